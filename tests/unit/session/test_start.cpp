// The first view of an exploration and the poses of an arm's capability map. Oracle: the
// capability map's poses enumerated directly; the default start is the farthest of those
// outside the search space that aim within 10° of the target.
#include <gtest/gtest.h>

#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/session/start.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "test_support.hpp"

namespace fvx::session {
namespace {

struct FvxArm {
  capmap::CapabilityMap cm = capmap::CapabilityMap::load(test::source("data/arms/fvx-arm.fcm"));
  nbv::Reach reach() const {
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    T_world_base.translation() = Eigen::Vector3d(0.2, 0.0, 0.0);
    return nbv::Reach{&cm, T_world_base, nullptr, {}};
  }
};

const Eigen::AlignedBox3d kSearchSpace(Eigen::Vector3d(0.35, -0.75, 0.0), Eigen::Vector3d(1.3, 0.9, 0.55));

TEST(Start, WithAnArmTheFarthestPoseAimedAtTheTargetOutsideTheSearchSpace) {
  const FvxArm arm;
  const nbv::Reach reach = arm.reach();
  const Eigen::Vector3d target = kSearchSpace.center() - Eigen::Vector3d(0, 0, 0.1);
  const Eigen::Isometry3d T = default_start(reach, reach.T_world_base, kSearchSpace, target);
  const Eigen::Vector3d eye = T.translation(), axis = T.linear().col(2);
  EXPECT_FALSE(kSearchSpace.contains(eye));
  EXPECT_TRUE(arm.cm.reachable(reach.T_world_base, eye, axis));
  const double aimed = std::cos(10.0 * M_PI / 180.0);
  EXPECT_GE(axis.dot((target - eye).normalized()), aimed);
  // Brute force over every pose of the map outside S.
  double farthest = 0.0;
  std::size_t aimed_poses = 0;
  for (const Eigen::Isometry3d& P :
       capmap_view_poses(reach, [](const Eigen::Vector3d& p) { return kSearchSpace.contains(p); })) {
    const Eigen::Vector3d to_target = target - P.translation();
    if (P.linear().col(2).dot(to_target.normalized()) < aimed) continue;
    ++aimed_poses;
    farthest = std::max(farthest, to_target.norm());
  }
  ASSERT_GT(aimed_poses, 0u);
  EXPECT_NEAR((target - eye).norm(), farthest, 1e-9);
}

TEST(Start, WithoutAnArmAboveAndBehindTheBaseLookingAtTheTarget) {
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
  T_world_base.translation() = Eigen::Vector3d(1.0, 2.0, 0.0);
  const Eigen::Vector3d target(2.0, 2.0, 0.2);
  const Eigen::Isometry3d T = default_start(std::nullopt, T_world_base, kSearchSpace, target);
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(0.85, 2.0, 0.95)));
  EXPECT_NEAR(T.linear().col(2).dot((target - T.translation()).normalized()), 1.0, 1e-12);
}

TEST(Start, AMapInsideTheSearchSpaceHasNoStart) {
  const FvxArm arm;
  const nbv::Reach reach = arm.reach();
  const Eigen::AlignedBox3d everywhere(Eigen::Vector3d::Constant(-100.0), Eigen::Vector3d::Constant(100.0));
  EXPECT_THROW(default_start(reach, reach.T_world_base, everywhere, Eigen::Vector3d::Zero()), Error);
}

TEST(Start, TheMapsPosesAreEveryReachableDirectionOfEveryFreeVoxel) {
  const FvxArm arm;
  const nbv::Reach reach = arm.reach();
  std::size_t expected = 0, below = 0;
  for (const auto& [voxel, bits] : arm.cm.voxels()) {
    const Eigen::Vector3d p = reach.T_world_base * arm.cm.center_of(voxel);
    const std::size_t n = arm.cm.reachable_directions(arm.cm.center_of(voxel)).size();
    expected += n;
    below += p.z() < 0.3 ? n : 0;
  }
  ASSERT_GT(below, 0u);
  const auto poses = capmap_view_poses(reach, [](const Eigen::Vector3d&) { return false; });
  EXPECT_EQ(poses.size(), expected);
  for (const Eigen::Isometry3d& P : poses)
    EXPECT_TRUE(arm.cm.reachable(reach.T_world_base, P.translation(), P.linear().col(2)));
  EXPECT_EQ(capmap_view_poses(reach, [](const Eigen::Vector3d& p) { return p.z() < 0.3; }).size(), expected - below);
}

TEST(Start, TheGroundTruthRegionHoldsTheSensorWithinTwoMetres) {
  const Eigen::AlignedBox3d region =
      sim::exploration_region(kSearchSpace, {Eigen::Vector3d(0.0, 0.0, 1.2), Eigen::Vector3d(10.0, 0.0, 0.0)});
  EXPECT_TRUE(region.contains(Eigen::Vector3d(0.0, 0.0, 1.2)));
  EXPECT_TRUE(region.contains(kSearchSpace.min() - Eigen::Vector3d::Constant(0.25)));
  EXPECT_DOUBLE_EQ(region.max().x(), kSearchSpace.max().x() + 2.0);
  EXPECT_DOUBLE_EQ(region.min().z(), kSearchSpace.min().z() - 0.25);
}

}  // namespace
}  // namespace fvx::session
