#include <gtest/gtest.h>

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"

namespace fvx {
namespace {

TEST(Pose, ScalarLastQuaternionAndTranslation) {
  // 90° about z: x → y.
  const double s = std::sqrt(0.5);
  const Eigen::Isometry3d T = parse_pose("1,2,3,0,0," + std::to_string(s) + "," + std::to_string(s), "--pose");
  const Eigen::Vector3d p = T * Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR((p - Eigen::Vector3d(1, 3, 3)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(rotation_angle_deg(T), 90.0, 1e-4);
}

TEST(Pose, SignFlipIsTheSameRotationAndScaleIsRemoved) {
  const Eigen::Isometry3d a = pose_from_translation_quaternion({0, 0, 0}, 0.1, 0.2, 0.3, 0.9, "a");
  const Eigen::Isometry3d b = pose_from_translation_quaternion({0, 0, 0}, -0.1, -0.2, -0.3, -0.9, "b");
  const Eigen::Isometry3d c = pose_from_translation_quaternion({0, 0, 0}, 0.2, 0.4, 0.6, 1.8, "c");
  EXPECT_TRUE(a.isApprox(b, 1e-12));
  EXPECT_TRUE(a.isApprox(c, 1e-12));
  const Eigen::Matrix3d R = a.linear();
  EXPECT_TRUE((R * R.transpose()).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(Pose, BadQuaternionsAreUsageErrors) {
  EXPECT_THROW(parse_pose("0,0,0,0,0,0,0", "--pose"), UsageError);
  EXPECT_THROW(parse_pose("0,0,0,0,0,1", "--pose"), UsageError);
  EXPECT_THROW(parse_pose("0,0,nan,0,0,0,1", "--pose"), UsageError);
}

}  // namespace
}  // namespace fvx
