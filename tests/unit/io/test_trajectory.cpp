// Trajectory files: the real TUM-like and Redwood samples, a TUM file with stamps, bad files.
#include <gtest/gtest.h>

#include <fstream>

#include "fvx/core/error.hpp"
#include "fvx/io/trajectory.hpp"
#include "test_support.hpp"

namespace fvx::io {
namespace {

TEST(TrajectoryRealData, SlambookPosesWithoutStampsOrTrailingNewline) {
  FVX_REAL_DATA_OR_SKIP(path, "slambook-joinmap-5kf/pose.txt");
  const Trajectory t = read_trajectory(path);
  EXPECT_EQ(t.format, TrajectoryFormat::TumNoStamp);
  ASSERT_EQ(t.entries.size(), 5u);
  EXPECT_FALSE(t.entries[0].stamp_s.has_value());
  for (const auto& e : t.entries) {
    // Written with 6-7 digits: unit within 1e-6, used as given (see pose.cpp).
    EXPECT_NEAR(Eigen::Quaterniond(e.T_world_sensor.rotation()).norm(), 1.0, 1e-6);
  }
}

TEST(TrajectoryRealData, IclNuimFirstPose) {
  FVX_REAL_DATA_OR_SKIP(path, "icl-nuim-slambook2-5f/pose.txt");
  const Trajectory t = read_trajectory(path);
  ASSERT_EQ(t.entries.size(), 5u);
  // Line 1: 0.000466347 0.00895357 -2.24935 -0.00101358 0.00052453 -0.000231475 0.999999
  EXPECT_NEAR((t.entries[0].T_world_sensor.translation() - Eigen::Vector3d(0.000466347, 0.00895357, -2.24935)).norm(), 0, 1e-9);
}

TEST(TrajectoryRealData, RedwoodLogsStartWhereTheyStart) {
  FVX_REAL_DATA_OR_SKIP(odometry, "open3d-redwood-testdata/RGBD/odometry.log");
  FVX_REAL_DATA_OR_SKIP(livingroom, "redwood-livingroom1-micro/trajectory_open3d_estimated.log");
  const Trajectory a = read_trajectory(odometry);
  EXPECT_EQ(a.format, TrajectoryFormat::RedwoodLog);
  ASSERT_EQ(a.entries.size(), 5u);
  EXPECT_EQ(a.entries[0].frame_id, 0);
  EXPECT_NEAR((a.entries[0].T_world_sensor.translation() - Eigen::Vector3d(2, 2, -0.3)).norm(), 0, 1e-9);
  const Trajectory b = read_trajectory(livingroom);
  ASSERT_EQ(b.entries.size(), 211u);
  EXPECT_EQ(b.entries[210].frame_id, 210);
  EXPECT_TRUE(b.entries[0].T_world_sensor.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
}

TEST(Trajectory, TumWithStampsAndComments) {
  const test::TempDir dir;
  std::ofstream(dir / "t.txt") << "# timestamp tx ty tz qx qy qz qw\n"
                                  "1305031102.1753 1 2 3 0 0 0 1\n\n"
                                  "1305031102.2112 1 2 3 0 0 0 -1  # sign flip\n";
  const Trajectory t = read_trajectory(dir / "t.txt");
  EXPECT_EQ(t.format, TrajectoryFormat::Tum);
  ASSERT_EQ(t.entries.size(), 2u);
  EXPECT_DOUBLE_EQ(*t.entries[1].stamp_s, 1305031102.2112);
  EXPECT_TRUE(t.entries[0].T_world_sensor.isApprox(t.entries[1].T_world_sensor, 1e-12));
}

TEST(Trajectory, BadFilesNameTheFileAndLine) {
  const test::TempDir dir;
  std::ofstream(dir / "fields.txt") << "1 2 3 0 0 0 1\n1 2 3 0 0 1\n";
  std::ofstream(dir / "text.txt") << "1 2 3 0 0 0 1\n1 2 x 0 0 0 1\n";
  std::ofstream(dir / "zero.txt") << "1 2 3 0 0 0 0\n";
  std::ofstream(dir / "empty.txt") << "# nothing\n";
  std::ofstream(dir / "shear.log") << "0 0 1\n1 0.5 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  std::ofstream(dir / "short.log") << "0 0 1\n1 0 0 0\n0 1 0 0\n";
  for (const char* name : {"fields.txt", "text.txt", "zero.txt", "empty.txt", "shear.log", "short.log", "missing.txt"}) {
    try {
      read_trajectory(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  try {
    read_trajectory(dir / "text.txt");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("text.txt:2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fvx::io
