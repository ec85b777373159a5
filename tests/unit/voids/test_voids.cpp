// Void cells against a brute-force oracle; incremental updates against from-scratch;
// degenerate clouds.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "fvx/voids/voids.hpp"
#include "slambook.hpp"
#include "test_support.hpp"

namespace fvx::voids {
namespace {

/// Every cell of the hull's box, tested one by one: unknown and inside the hull.
std::vector<map::VoxelKey> brute_force(const map::OccupancyMap& map, const Hull& hull) {
  std::vector<map::VoxelKey> out;
  if (hull.empty()) return out;
  const double R = map.resolution_m();
  const map::VoxelKey lo = *map.key_of(hull.bounds_m.min() - Eigen::Vector3d::Constant(R));
  const map::VoxelKey hi = *map.key_of(hull.bounds_m.max() + Eigen::Vector3d::Constant(R));
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const map::VoxelKey k{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
        if (map.state(k) == map::VoxelState::Unknown && hull.contains(map.center_of(k))) out.push_back(k);
      }
  return out;
}

std::vector<Eigen::Vector3d> occupied_centres(const map::OccupancyMap& map) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& c : map.occupied_centers()) out.push_back(c.cast<double>());
  return out;
}

std::vector<Eigen::Vector3f> random_scan(std::mt19937& rng, const Eigen::Vector3f& origin, int n) {
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_real_distribution<float> radius(0.3f, 1.0f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3f d(gauss(rng), gauss(rng), gauss(rng));
    points.push_back(origin + d.normalized() * radius(rng));
  }
  return points;
}

TEST(Hull, ContainsEveryPointAndEveryFaceTouchesThem) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 500; ++i) points.emplace_back(u(rng), u(rng), 0.5 * u(rng));
  const Hull hull = convex_hull(points);
  ASSERT_FALSE(hull.empty());
  for (const auto& p : points) EXPECT_TRUE(hull.contains(p));
  EXPECT_FALSE(hull.contains({1.1, 0, 0}));
  for (const Eigen::Vector4d& plane : hull.planes) {
    int touching = 0;
    for (const auto& p : points) touching += std::abs(plane.head<3>().dot(p) + plane.w()) < 1e-9;
    EXPECT_GE(touching, 3);
  }
}

TEST(Hull, FlatOrTinyCloudsHaveNoInterior) {
  EXPECT_TRUE(convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).empty());
  EXPECT_TRUE(convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}}).empty());  // a plane
  EXPECT_FALSE(convex_hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}).empty());
}

TEST(Voids, FromScratchEqualsBruteForceAndIncrementalOnRandomMaps) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    map::OccupancyMap map(0.1);
    VoidSet incremental;
    for (int s = 0; s < 4; ++s) {
      const Eigen::Vector3f origin(0.25f * s, 0.1f * float(seed), 0.05f * s);
      incremental.update(map, map.integrate(random_scan(rng, origin, 200), origin, 0.9).changes);
      VoidSet scratch;
      scratch.rebuild(map);
      const auto oracle = brute_force(map, convex_hull(occupied_centres(map)));
      ASSERT_FALSE(oracle.empty()) << "seed " << seed << " scan " << s;
      EXPECT_EQ(scratch.cells(map), oracle) << "seed " << seed << " scan " << s;
      EXPECT_EQ(incremental.cells(map), oracle) << "seed " << seed << " scan " << s;
    }
  }
}

TEST(Voids, AHullBoxBuildsTheHullFromTheOccupiedCellsInItOnly) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.45, -0.45, -0.45), Eigen::Vector3d(0.45, 0.45, 0.45));
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    map::OccupancyMap map(0.1);
    VoidSet incremental;
    incremental.rebuild(map, box);
    for (int s = 0; s < 4; ++s) {
      const Eigen::Vector3f origin(0.25f * s, 0.1f * float(seed), 0.05f * s);
      incremental.update(map, map.integrate(random_scan(rng, origin, 200), origin, 0.9).changes);
      std::vector<Eigen::Vector3d> in_box;
      for (const Eigen::Vector3d& c : occupied_centres(map))
        if (box.contains(c)) in_box.push_back(c);
      const auto oracle = brute_force(map, convex_hull(in_box));
      ASSERT_FALSE(oracle.empty()) << "seed " << seed << " scan " << s;
      // Surfaces outside the box do not widen it: fewer cells than the whole map's hull.
      EXPECT_LT(oracle.size(), brute_force(map, convex_hull(occupied_centres(map))).size());
      VoidSet scratch;
      scratch.rebuild(map, box);
      EXPECT_EQ(scratch.cells(map), oracle) << "seed " << seed << " scan " << s;
      EXPECT_EQ(incremental.cells(map), oracle) << "seed " << seed << " scan " << s;
      Hull hull;
      const map::DenseGrid grid(map, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-2), Eigen::Vector3d::Constant(2)));
      EXPECT_EQ(void_cells(grid, hull, box), oracle) << "seed " << seed << " scan " << s;
    }
  }
}

std::vector<std::array<double, 3>> sorted(const std::vector<Eigen::Vector3d>& points) {
  std::vector<std::array<double, 3>> out;
  for (const Eigen::Vector3d& p : points) out.push_back({p.x(), p.y(), p.z()});
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Voids, TheHullFromTheMapsLeavesIsTheGridsHull) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.45, -0.45, -0.45), Eigen::Vector3d(0.45, 0.45, 0.45));
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    map::OccupancyMap map(0.1);
    for (int s = 0; s < 3; ++s) {
      const Eigen::Vector3f origin(0.25f * s, 0.1f * float(seed), 0.05f * s);
      map.integrate(random_scan(rng, origin, 200), origin, 0.9);
    }
    for (int z = 0; z < 4; ++z)  // an aligned solid block: occupied leaves of several cells
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
          map.set_state({std::uint16_t(32776 + x), std::uint16_t(32768 + y), std::uint16_t(32764 + z)},
                        map::VoxelState::Occupied);
    const auto leaves = map.leaves();
    ASSERT_TRUE(std::any_of(leaves.begin(), leaves.end(), [](const map::Leaf& l) {
      return l.state == map::VoxelState::Occupied && l.size_cells > 1;
    }));
    const map::Stats st = map.stats();
    const map::DenseGrid grid(map, Eigen::AlignedBox3d(st.known_min_m, st.known_max_m));
    for (const auto& hull_box : {std::optional<Eigen::AlignedBox3d>(), std::optional<Eigen::AlignedBox3d>(box)}) {
      Hull from_grid;
      const auto cells = void_cells(grid, from_grid, hull_box);
      const Hull from_map = hull_of_map(map, hull_box);
      // CGAL lists a hull's faces and vertices in an order that changes from call to call
      // (the same points, hulled twice, give another order), so the hulls compare as sets.
      ASSERT_FALSE(from_map.empty()) << "seed " << seed;
      EXPECT_EQ(sorted(from_map.vertices), sorted(from_grid.vertices)) << "seed " << seed;
      EXPECT_EQ(from_map.planes.size(), from_grid.planes.size()) << "seed " << seed;
      EXPECT_TRUE(from_map.bounds_m.isApprox(from_grid.bounds_m, 0.0)) << "seed " << seed;
      EXPECT_EQ(void_cells_in(grid, from_map), cells) << "seed " << seed;
    }
  }
}

TEST(Voids, AMapWithoutVolumeHasNoVoids) {
  map::OccupancyMap map(0.1);
  VoidSet set;
  set.rebuild(map);
  EXPECT_EQ(set.size(), 0u);  // no occupied cells
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y) map.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), 32768},
                                                map::VoxelState::Occupied);
  set.rebuild(map);
  EXPECT_TRUE(set.hull().empty());  // one flat wall
  EXPECT_EQ(set.size(), 0u);
}

TEST(VoidsRealData, SlambookIncrementalEqualsFromScratchAfterEveryFrame) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  map::OccupancyMap map(0.05);
  VoidSet incremental;
  test::for_each_slambook_frame(frames, [&](const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& origin,
                                            const std::string& path) {
    incremental.update(map, map.integrate(points, origin).changes);
    VoidSet scratch;
    scratch.rebuild(map);
    ASSERT_GT(scratch.size(), 10000u);
    EXPECT_EQ(incremental.cells(map), scratch.cells(map)) << path;
  });
}

}  // namespace
}  // namespace fvx::voids
