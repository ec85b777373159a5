// Ground truth for explorations: the sealed crate's air is not observable, the open crate's
// is; the ground truth itself knows everything and an empty map nothing; a pose looking
// into the open crate keeps only what it reveals, and one that sees the victim says so; the
// ground truth tells which predicted void cells and which free map cells lie inside material.
#include <gtest/gtest.h>

#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/exploration_score.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::sim {
namespace {

struct Crates {
  Scene scene = builtin_scene("crates");
  std::unique_ptr<RayCaster> caster = make_ray_caster(scene.mesh);
  Eigen::AlignedBox3d S = *scene.info.search_space;
  GroundTruth gt{scene.mesh, *caster, 0.025,
                 Eigen::AlignedBox3d(S.min() - Eigen::Vector3d::Constant(0.25), S.max() + Eigen::Vector3d(0.25, 0.25, 0.7))};
};

bool observable(const Crates& c, const Eigen::Vector3d& p) {
  // A one-cell search space around p: observable iff that cell is.
  const Eigen::Vector3d centre = c.gt.center_of(c.gt.cell_of(p));
  const ExplorationScore one(c.gt, Eigen::AlignedBox3d(centre, centre), std::nullopt);
  return one.observable_cells() == 1;
}

TEST(ExplorationScore, SealedAirIsNotObservable) {
  const Crates c;
  EXPECT_FALSE(observable(c, {0.75, 0.40, 0.17}));  // inside the closed crate
  EXPECT_TRUE(observable(c, {0.67, -0.50, 0.12}));  // inside the open crate
  EXPECT_TRUE(observable(c, {0.45, 0.0, 0.45}));    // the air above the floor
  const ExplorationScore score(c.gt, c.S, c.scene.info.target->box);
  ASSERT_GT(score.observable_cells(), 10000u);
  EXPECT_DOUBLE_EQ(score.known_fraction(map::OccupancyMap(0.025)), 0.0);
  const map::OccupancyMap truth = c.gt.to_map();
  EXPECT_DOUBLE_EQ(score.known_fraction(truth), 1.0);
  EXPECT_TRUE(score.target_seen(truth));
  EXPECT_FALSE(score.target_seen(map::OccupancyMap(0.025)));
}

TEST(ExplorationScore, ViewsKeepWhatTheyReveal) {
  const Crates c;
  ExplorationScore score(c.gt, c.S, c.scene.info.target->box);
  const std::size_t all = score.observable_cells();
  // One pose above the open crate, looking straight down into it (inside the ground truth's
  // region: a ray starts where the ground truth is known).
  Eigen::Isometry3d above = Eigen::Isometry3d::Identity();
  above.translation() = Eigen::Vector3d(0.67, -0.5, 1.1);
  above.linear() = viewpoints::look_along(Eigen::Vector3d(0, 0, -1), 0.0);
  const auto rays = viewpoints::ray_fan(io::Intrinsics{}, 40, 30);
  score.restrict_to_views(c.gt, {above}, rays, 0.5, 4.0);
  EXPECT_LT(score.observable_cells(), all);
  EXPECT_GT(score.observable_cells(), 100u);
  ASSERT_TRUE(score.observable_target_cells().has_value());
  // The victim (0.8…0.9, −0.1…0) lies in the crate with the side opening: this pose does
  // not see it; one inside that crate looking at it does (a near-sighted sensor).
  EXPECT_EQ(*score.observable_target_cells(), 0u);
  ExplorationScore victim(c.gt, c.S, c.scene.info.target->box);
  Eigen::Isometry3d inside = Eigen::Isometry3d::Identity();
  inside.translation() = Eigen::Vector3d(0.66, -0.05, 0.22);
  inside.linear() = viewpoints::look_along(Eigen::Vector3d(0.85, -0.05, 0.06) - inside.translation(), 0.0);
  victim.restrict_to_views(c.gt, {inside}, rays, 0.05, 4.0);
  EXPECT_GT(*victim.observable_target_cells(), 0u);
}

TEST(GroundTruth, CountsPredictionsAndFreeCellsInsideSolids) {
  const Crates c;
  map::OccupancyMap truth = c.gt.to_map();
  EXPECT_EQ(c.gt.free_in_solid(truth, c.S), 0u);
  EXPECT_EQ(c.gt.free_in_solid(map::OccupancyMap(0.025), c.S), 0u);
  // A cell of the closed crate's wall (x 0.55…0.565) and one of the air inside it.
  const auto wall = truth.key_of({0.56, 0.4, 0.2});
  const auto air = truth.key_of({0.75, 0.4, 0.17});
  ASSERT_TRUE(wall && air);
  ASSERT_TRUE(c.gt.solid(c.gt.cell_of({0.56, 0.4, 0.2})));
  ASSERT_FALSE(c.gt.solid(c.gt.cell_of({0.75, 0.4, 0.17})));
  EXPECT_EQ(c.gt.solid_among({*wall, *air}), 1u);
  EXPECT_EQ(c.gt.solid_among({*air}), 0u);
  // A key far outside the ground truth's region does not count.
  EXPECT_EQ(c.gt.solid_among({map::VoxelKey{100, 100, 100}}), 0u);
  truth.set_state(*wall, map::VoxelState::Free);
  EXPECT_EQ(c.gt.free_in_solid(truth, c.S), 1u);
  // Outside the box it does not count.
  EXPECT_EQ(c.gt.free_in_solid(truth, Eigen::AlignedBox3d(Eigen::Vector3d(0.7, 0.3, 0.1), Eigen::Vector3d(0.8, 0.5, 0.3))), 0u);
}

}  // namespace
}  // namespace fvx::sim
