// Algorithm 1 on a hand-built frontier-void with known rays, and on the closed-box scene.
#include <gtest/gtest.h>

#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/utility/utility.hpp"
#include "scan_scene.hpp"

namespace fvx::utility {
namespace {

map::VoxelKey key(int x, int y, int z) {
  return {std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)};
}

/// A line of free cells along +x from x = 0 to `wall` − 1, an occupied cell at x = `wall`,
/// unknown elsewhere. One void cluster: a single cell at x = −1 (so all its corners lie at the
/// void, −x of the frontier); one frontier cluster: the cells x = 0 … `frontier` − 1.
struct Line {
  map::OccupancyMap map{0.1};
  frontier_voids::Analysis a;
  Line(int wall, int frontier) {
    for (int x = 0; x < wall; ++x) map.set_state(key(x, 0, 0), map::VoxelState::Free);
    map.set_state(key(wall, 0, 0), map::VoxelState::Occupied);
    a.bounds_m = Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(0.1 * wall + 1, 1, 1));
    voids::VoidCluster v;
    v.cells = {key(-1, 0, 0)};
    v.mean_m = map.center_of(key(-1, 0, 0));
    v.semi_axes_m = Eigen::Vector3d::Constant(1e-4);  // corners within the void cell
    v.volume_m3 = 0.001;
    a.void_clusters = {v};
    frontiers::Cluster f;
    for (int x = 0; x < frontier; ++x) f.cells.push_back(key(x, 0, 0));
    a.frontier_clusters = {f};
    a.frontier_voids = {{0, {0}, v.volume_m3}};
  }
};

// The line with a wall at x = 10 and one frontier cell, x = 0.
TEST(Utility, RaysLeaveTheVoidThroughTheFrontierAndStopAtTheFirstNonFreeCell) {
  const Line line(10, 1);
  const frontier_voids::Analysis& a = line.a;
  const map::DenseGrid grid(line.map, a.bounds_m);
  Config config;
  config.sensor_range_m = 4.0;
  const Field field = accumulate(grid, a, config);
  EXPECT_EQ(field.vectors, 7u);  // 7 corners, one frontier cell
  for (int x = -5; x < 15; ++x) {
    const map::VoxelKey k = key(x, 0, 0);
    if (!grid.contains(k)) continue;
    const double expected = (x >= 0 && x < 10) ? 7 * 0.001 : 0.0;  // every ray runs +x to the wall
    EXPECT_NEAR(field.util_m3[grid.index(k)], expected, 1e-12) << "x = " << x;
  }
  EXPECT_EQ(field.cells, 10u);
  config.sensor_range_m = 0.44;  // s_r cuts the rays: cell k is entered at (k − 0.5)·0.1 m, so x = 0…4
  const Field short_range = accumulate(grid, a, config);
  EXPECT_EQ(short_range.cells, 5u);

  // The sensor's minimum depth: only cells whose centre is at least 0.35 m from the frontier
  // cell's (x ≥ 4) gain utility, the same amount; the ray still stops at the wall.
  config.sensor_range_m = 4.0;
  config.min_range_m = 0.35;
  const Field far = accumulate(grid, a, config);
  for (int x = 0; x < 10; ++x)
    EXPECT_NEAR(far.util_m3[grid.index(key(x, 0, 0))], x >= 4 ? 7 * 0.001 : 0.0, 1e-12) << "x = " << x;
  EXPECT_EQ(far.cells, 6u);
  EXPECT_EQ(far.vectors, 7u);
  config.min_range_m = 4.0;  // not below s_r
  EXPECT_FALSE(config.validate().empty());
}

// The same line with sixty frontier cells, x = 0…59, and the wall at x = 70: the rays from
// every frontier cell run +x to the wall, so cell x is passed 7·min(x + 1, 60) times by the
// one frontier-void, up to 420. The accumulation counts a frontier-void's passes per cell in
// a byte that spills past 255; the field must still be the full count, and the frontier-void
// a cell's one contributor.
TEST(Utility, ACellPassedMoreThan255TimesByOneFrontierVoidGetsEveryPass) {
  const Line line(70, 60);
  const map::DenseGrid grid(line.map, line.a.bounds_m);
  Config config;
  config.accumulation = Accumulation::Exact;
  config.sensor_range_m = 10.0;
  for (const unsigned threads : {1u, 2u}) {
    config.threads = threads;
    const Field field = accumulate(grid, line.a, config);
    EXPECT_EQ(field.vectors, 7u * 60u);
    for (int x = 0; x < 70; ++x) {
      const std::size_t i = grid.index(key(x, 0, 0));
      EXPECT_NEAR(field.util_m3[i], 7 * std::min(x + 1, 60) * 0.001, 1e-12) << "x = " << x;
      EXPECT_EQ(field.contributors[i], (std::array<std::int32_t, kContributors>{0, -1, -1, -1})) << "x = " << x;
    }
    EXPECT_EQ(field.cells, 70u);
  }
}

// Within the box's column (its footprint, floor to 1.2 m) the only void is the interior. Its
// utility rays cross the cone seen through the opening (inside the box, where pruning will
// later remove viewpoints) and leave through the opening: above the lid, the most useful
// cells lie over the opening.
TEST(Utility, OnTheClosedBoxTheBestCellsLookThroughTheOpening) {
  // A scan from the side and above: the lid and its opening are seen, the interior is not.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d eye(0.1, -0.02, 1.0), target(0.77, -0.02, 0.2);
  const Eigen::Vector3d z = (target - eye).normalized(), x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  T.linear() << x, z.cross(x), z;
  T.translation() = eye;
  map::OccupancyMap map(0.02);
  test::integrate_views(map, sim::builtin_scene("closed-box"), {T});
  frontiers::FrontierSet frontier_set;
  frontier_set.rebuild(map);
  voids::VoidSet void_set;
  void_set.rebuild(map);
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(0.52, -0.27, 0.0), Eigen::Vector3d(1.02, 0.23, 1.2));
  const auto a = frontier_voids::analyse(map, frontier_set, &void_set, bounds, voids::ClusterConfig{});
  const map::DenseGrid grid(map, bounds);
  Config one_thread;
  one_thread.threads = 1;
  const Field field = accumulate(grid, a, one_thread);
  ASSERT_GT(field.cells, 100u);
  // Threads split the frontier-voids; the field and the contributors do not change.
  Config three;
  three.threads = 3;
  const Field threaded = accumulate(grid, a, three);
  EXPECT_EQ(threaded.util_m3, field.util_m3);
  EXPECT_EQ(threaded.contributors, field.contributors);
  EXPECT_EQ(threaded.vectors, field.vectors);
  std::size_t best = 0;
  double best_above_lid = 0.0;
  for (std::size_t i = 0; i < field.util_m3.size(); ++i) {
    if (field.util_m3[i] > 0) {
      ASSERT_EQ(grid.state_at(i), map::VoxelState::Free);
    }
    if (grid.center_of(grid.key(i)).z() > 0.42 && field.util_m3[i] > best_above_lid) {
      best_above_lid = field.util_m3[i];
      best = i;
    }
  }
  ASSERT_GT(best_above_lid, 0.0) << "utility rays leave through the opening";
  // Over the opening: centre (0.77, −0.02), 16 cm wide.
  const Eigen::Vector3d c = grid.center_of(grid.key(best));
  EXPECT_LT(std::abs(c.x() - 0.77), 0.1) << c.transpose();
  EXPECT_LT(std::abs(c.y() + 0.02), 0.1) << c.transpose();
}

}  // namespace
}  // namespace fvx::utility
