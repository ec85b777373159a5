// Ground truth for explorations: the sealed crate's air is not observable, the open crate's
// is; the ground truth itself knows everything and an empty map nothing; a pose looking
// into the open crate keeps only what it reveals, and one that sees the victim says so; the
// ground truth tells which predicted void cells and which free map cells lie inside material.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "fvx/map/dense_grid.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
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

// The observable void cells: inside the convex hull of the solid cells in S. Here S holds an
// open crate and, beyond a gap, a low block, so the hull is a prism along y whose x-z section
// is known: the solids' bottom layer, the crate's near and top faces, the block's far face,
// and the slope from the crate's far top edge down to the block's far top edge. (The floor's
// surface at z = 0 belongs to the cell below, outside S.) Brute force: every free cell tested
// against that section.
TEST(ExplorationScore, ObservableVoidCellsAreTheFreeCellsInsideTheHullOfTheSurfaces) {
  Scene scene;
  scene.mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-0.5f, -1.0f, -0.05f), Eigen::Vector3f(2.0f, 1.0f, 0.0f)));
  Face faces[6];
  faces[5] = {Face::Open};
  scene.mesh.append(hollow_box(Eigen::AlignedBox3f(Eigen::Vector3f(0.5f, -0.2f, 0.0f), Eigen::Vector3f(0.9f, 0.2f, 0.3f)),
                               0.02f, faces));
  scene.mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(1.0f, -0.2f, 0.0f), Eigen::Vector3f(1.1f, 0.2f, 0.1f)));
  const auto caster = make_ray_caster(scene.mesh);
  const Eigen::AlignedBox3d S(Eigen::Vector3d(0.5, -0.2, 0.0), Eigen::Vector3d(1.1, 0.2, 0.3));
  const GroundTruth gt(scene.mesh, *caster, 0.025,
                       Eigen::AlignedBox3d(S.min() - Eigen::Vector3d::Constant(0.25), S.max() + Eigen::Vector3d::Constant(0.25)));
  auto in_section = [](const Eigen::Vector3d& p) {
    const double e = 1e-6, top = 0.2875 - (p.x() - 0.8875);  // from (0.8875, 0.2875) to (1.0875, 0.0875)
    return p.x() >= 0.5125 - e && p.x() <= 1.0875 + e && p.y() >= -0.1875 - e && p.y() <= 0.1875 + e &&
           p.z() >= 0.0125 - e && p.z() <= std::min(0.2875, top) + e;
  };
  std::size_t expected = 0, inside_crate = 0;
  std::vector<Eigen::Vector3d> centres;  // in the constructor's order: z, then y, then x
  for (int z = 0; z < gt.size().z(); ++z)
    for (int y = 0; y < gt.size().y(); ++y)
      for (int x = 0; x < gt.size().x(); ++x) {
        const Eigen::Vector3i cell = gt.first_cell() + Eigen::Vector3i(x, y, z);
        const Eigen::Vector3d p = gt.center_of(cell);
        if (gt.solid(cell) || !S.contains(p) || !in_section(p)) continue;
        ++expected;  // every free cell here is open to the air: the crate has no lid
        inside_crate += p.x() < 0.88;
        centres.push_back(p);
      }
  const ExplorationScore score(gt, S, std::nullopt);
  ASSERT_GT(inside_crate, 1000u);
  ASSERT_GT(expected, inside_crate + 200);  // the gap under the slope holds void air too
  EXPECT_EQ(score.observable_void_cells(), expected);
  EXPECT_EQ(score.observable_void_centres_m(), centres);
  EXPECT_LT(score.observable_void_cells(), score.observable_cells());  // the air above the slope is not void
  // The share known: nothing, everything, and a map that knows only the crate's upper half.
  EXPECT_DOUBLE_EQ(score.void_known_fraction(map::OccupancyMap(0.025)), 0.0);
  const map::OccupancyMap truth = gt.to_map();
  EXPECT_DOUBLE_EQ(score.void_known_fraction(truth), 1.0);
  map::OccupancyMap half(0.025);
  std::size_t upper = 0;
  for (int z = 0; z < gt.size().z(); ++z)
    for (int y = 0; y < gt.size().y(); ++y)
      for (int x = 0; x < gt.size().x(); ++x) {
        const Eigen::Vector3i cell = gt.first_cell() + Eigen::Vector3i(x, y, z);
        const Eigen::Vector3d p = gt.center_of(cell);
        if (gt.solid(cell) || !S.contains(p) || !in_section(p) || p.z() < 0.15) continue;
        half.set_state(*half.key_of(p), map::VoxelState::Free);
        ++upper;
      }
  EXPECT_NEAR(score.void_known_fraction(half), double(upper) / double(expected), 1e-12);
}

// The target seen through the full image: from 3.4 m a 10 cm block covers about 15 pixels, so
// every pixel of its image is cast. Oracle: the renderer's full frame from the same pose,
// the cells holding its points inside the target box (above its lowest cell).
TEST(ExplorationScore, TheTargetIsJudgedByTheRaysThroughItsImage) {
  Scene scene;
  scene.mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-1.0f, -1.0f, -0.05f), Eigen::Vector3f(5.0f, 1.0f, 0.0f)));
  // Faces off the 2.5 cm cell boundaries: a face on one puts its hits where the last bit of a
  // ray's distance decides the cell, and Embree's bits differ between CPUs (AMD, Intel).
  const Eigen::AlignedBox3f block(Eigen::Vector3f(3.01f, -0.04f, 0.0f), Eigen::Vector3f(3.11f, 0.06f, 0.11f));
  scene.mesh.add_box(block);
  const auto caster = make_ray_caster(scene.mesh);
  const Eigen::AlignedBox3d S(Eigen::Vector3d(2.5, -0.5, 0.0), Eigen::Vector3d(3.5, 0.5, 0.5));
  const GroundTruth gt(scene.mesh, *caster, 0.025, Eigen::AlignedBox3d(S.min() - Eigen::Vector3d(3, 1, 0.25), S.max() + Eigen::Vector3d::Constant(0.25)));
  const Eigen::AlignedBox3d target(block.min().cast<double>(), block.max().cast<double>());
  Eigen::Isometry3d eye = Eigen::Isometry3d::Identity();
  eye.translation() = Eigen::Vector3d(-0.35, 0.0, 0.9);
  eye.linear() = viewpoints::look_along(target.center() - eye.translation(), 0.0);
  SensorConfig sensor;
  const Frame frame = render(*caster, eye, sensor);
  std::set<std::tuple<int, int, int>> cells;
  Eigen::AlignedBox3d above_floor = target;
  above_floor.min().z() += 0.025;
  for (const Eigen::Vector3f& p : frame.points_sensor) {
    if (!p.allFinite()) continue;
    const Eigen::Vector3i k = ((eye * p.cast<double>()).array() / 0.025).floor().cast<int>();
    const Eigen::Vector3d centre = (k.cast<double>().array() + 0.5).matrix() * 0.025;
    if (above_floor.contains(centre)) cells.insert({k.x(), k.y(), k.z()});
  }
  ASSERT_GE(cells.size(), 3u);
  ExplorationScore fan(gt, S, target), image(gt, S, target);
  fan.restrict_to_views(gt, {eye}, viewpoints::ray_fan(sensor.intrinsics, 20, 15), 0.5, 4.0);
  image.restrict_to_views(gt, {eye}, viewpoints::ray_fan(sensor.intrinsics, 20, 15), 0.5, 4.0);
  image.restrict_target_to_views(*caster, {eye}, sensor.intrinsics, 0.5, 4.0, 0.025);
  EXPECT_LT(*fan.observable_target_cells(), cells.size());  // the coarse fan misses cells
  EXPECT_EQ(*image.observable_target_cells(), cells.size());
  // Beyond the sensor's range, or behind it, nothing.
  ExplorationScore near(gt, S, target);
  near.restrict_target_to_views(*caster, {eye}, sensor.intrinsics, 0.5, 3.0, 0.025);
  EXPECT_EQ(*near.observable_target_cells(), 0u);
  Eigen::Isometry3d away = eye;
  away.linear() = viewpoints::look_along(eye.translation() - target.center(), 0.0);
  ExplorationScore behind(gt, S, target);
  behind.restrict_target_to_views(*caster, {away}, sensor.intrinsics, 0.5, 4.0, 0.025);
  EXPECT_EQ(*behind.observable_target_cells(), 0u);
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
  const std::size_t all_void = score.observable_void_cells();
  score.restrict_to_views(c.gt, {above}, rays, 0.5, 4.0);
  EXPECT_LT(score.observable_cells(), all);
  EXPECT_LT(score.observable_void_cells(), all_void);
  EXPECT_GT(score.observable_void_cells(), 50u);  // the open crate's inside, seen from above
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

// restrict_to_views walks only the rays that can reach the search space or the target. Oracle:
// every ray of every pose walked on the ground truth's grid to its first solid cell (the
// class's rule, written out), from poses all around the crates, most looking away from them.
TEST(ExplorationScore, RestrictingToViewsKeepsWhatWalkingEveryRayKeeps) {
  const Crates c;
  const ExplorationScore all(c.gt, c.S, c.scene.info.target->box);
  ExplorationScore restricted = all;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double R = c.gt.resolution_m();
  const Eigen::Vector3d lo = c.gt.center_of(c.gt.first_cell()) - Eigen::Vector3d::Constant(R / 2);
  const Eigen::AlignedBox3d region(lo, lo + c.gt.size().cast<double>() * R);
  std::vector<Eigen::Isometry3d> poses;
  while (poses.size() < 300) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int a = 0; a < 3; ++a)
      T.translation()[a] = region.min()[a] + unit(rng) * (region.max()[a] - region.min()[a]);
    const Eigen::Vector3i cell = c.gt.cell_of(T.translation());
    if (!c.gt.contains(cell) || c.gt.solid(cell)) continue;
    const Eigen::Vector3d d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
    if (d.norm() < 1e-3) continue;
    T.linear() = viewpoints::look_along(d, 2 * M_PI * unit(rng));
    poses.push_back(T);
  }
  // And the pose in the victim's crate that sees it (ViewsKeepWhatTheyReveal).
  Eigen::Isometry3d inside = Eigen::Isometry3d::Identity();
  inside.translation() = Eigen::Vector3d(0.66, -0.05, 0.22);
  inside.linear() = viewpoints::look_along(Eigen::Vector3d(0.85, -0.05, 0.06) - inside.translation(), 0.0);
  poses.push_back(inside);
  const auto rays = viewpoints::ray_fan(io::Intrinsics{}, 20, 15);
  const double depth_min_m = 0.05, depth_max_m = 4.0;
  restricted.restrict_to_views(c.gt, poses, rays, depth_min_m, depth_max_m, 2);

  const map::OccupancyMap truth = c.gt.to_map();
  const map::DenseGrid grid(truth, region);
  std::vector<std::uint8_t> revealed(grid.cell_count(), 0);
  std::size_t walked = 0;
  for (const Eigen::Isometry3d& T : poses)
    for (const Eigen::Vector3d& ray : rays) {
      std::vector<std::size_t> crossed;
      std::optional<std::size_t> hit;
      grid.walk(T.translation(), T.linear() * ray, depth_max_m * ray.norm(), [&](std::size_t i, map::VoxelState s) {
        if (s == map::VoxelState::Occupied) hit = i;
        else crossed.push_back(i);
        return !hit;
      });
      if (!hit) continue;
      const double depth = (grid.center_of(grid.key(*hit)) - T.translation()).dot(T.linear().col(2));
      if (depth < depth_min_m || depth > depth_max_m) continue;
      ++walked;
      for (const std::size_t i : crossed) revealed[i] |= 1;
      revealed[*hit] |= 2;
    }
  ASSERT_GT(walked, 1000u);
  std::vector<Eigen::Vector3d> expected;
  for (const Eigen::Vector3d& p : all.observable_centres_m())
    if (revealed[grid.index(*truth.key_of(p))] & 1) expected.push_back(p);
  ASSERT_GT(expected.size(), 100u);
  EXPECT_EQ(restricted.observable_centres_m(), expected);
  Eigen::AlignedBox3d above_floor = c.scene.info.target->box;
  above_floor.min().z() += R;
  std::size_t target_cells = 0;
  for (std::size_t i = 0; i < grid.cell_count(); ++i)
    target_cells += (revealed[i] & 2) && above_floor.contains(grid.center_of(grid.key(i)));
  ASSERT_GT(target_cells, 0u);
  EXPECT_EQ(*restricted.observable_target_cells(), target_cells);
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
