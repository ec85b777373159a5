// Frontier cells against a brute-force oracle; incremental updates against from-scratch
// recomputation; clusters.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "fvx/frontiers/frontiers.hpp"
#include "slambook.hpp"
#include "test_support.hpp"

namespace fvx::frontiers {
namespace {

/// Every cell of the box around the known cells, tested one by one with the definition.
std::vector<map::VoxelKey> brute_force(const map::OccupancyMap& map) {
  const map::Stats s = map.stats();
  std::vector<map::VoxelKey> out;
  if (s.empty) return out;
  const map::VoxelKey lo = *map.key_of(s.known_min_m + Eigen::Vector3d::Constant(map.resolution_m() / 2));
  const map::VoxelKey hi = *map.key_of(s.known_max_m - Eigen::Vector3d::Constant(map.resolution_m() / 2));
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const map::VoxelKey k{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
        if (is_frontier(map, k)) out.push_back(k);
      }
  return out;  // z, y, x loops: key order
}

std::vector<Eigen::Vector3f> random_scan(std::mt19937& rng, const Eigen::Vector3f& origin, int n) {
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_real_distribution<float> radius(0.2f, 1.2f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3f d(gauss(rng), gauss(rng), gauss(rng));
    points.push_back(origin + d.normalized() * radius(rng));
  }
  return points;
}

TEST(Frontiers, FromScratchEqualsBruteForceAndIncrementalOnRandomMaps) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    map::OccupancyMap map(0.1);
    FrontierSet incremental;
    for (int s = 0; s < 4; ++s) {
      const Eigen::Vector3f origin(0.3f * s, 0.2f * float(seed), -0.1f * s);
      const map::Integration change = map.integrate(random_scan(rng, origin, 300), origin, 1.0);
      incremental.update(map, change.changes);
      FrontierSet scratch;
      scratch.rebuild(map);
      const auto oracle = brute_force(map);
      ASSERT_FALSE(oracle.empty());
      EXPECT_EQ(scratch.cells(map), oracle) << "seed " << seed << " scan " << s;
      EXPECT_EQ(incremental.cells(map), oracle) << "seed " << seed << " scan " << s;
    }
  }
}

// Changes at keys 0 and 65535: their neighbours beyond the key space are no candidates (the
// update merges the shifted change lists and must skip them as the definition does).
TEST(Frontiers, IncrementalEqualsBruteForceAtTheEdgesOfTheKeySpace) {
  std::mt19937 rng(7);
  for (const float corner : {-3276.75f, 3276.75f}) {  // 0.1 m cells: keys 0 and 65535 there
    map::OccupancyMap map(0.1);
    FrontierSet incremental;
    std::size_t edge_changes = 0;
    for (int s = 0; s < 3; ++s) {
      const Eigen::Vector3f origin = Eigen::Vector3f::Constant(corner - std::copysign(0.3f * float(s), corner));
      const map::Integration change = map.integrate(random_scan(rng, origin, 300), origin, 1.0);
      ASSERT_GT(change.points_out_of_map, 0u) << "the scan must reach past the edge";
      for (const map::Change& c : change.changes)
        for (const int v : {c.key.x, c.key.y, c.key.z}) edge_changes += v == 0 || v == 0xFFFF;
      incremental.update(map, change.changes);
      const auto oracle = brute_force(map);
      ASSERT_FALSE(oracle.empty());
      EXPECT_EQ(incremental.cells(map), oracle) << "corner " << corner << " scan " << s;
    }
    EXPECT_GT(edge_changes, 0u) << "corner " << corner << ": no change at the key space's edge";
  }
}

TEST(Frontiers, APrunedFreeLeafContributesItsSurface) {
  map::OccupancyMap map(0.1);
  // An aligned 8³ block of free cells, pruned by OctoMap into one leaf, unknown all around.
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        map.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)},
                      map::VoxelState::Free);
  ASSERT_EQ(map.leaves().size(), 1u);
  EXPECT_EQ(map.leaves()[0].size_cells, 8u);
  FrontierSet set;
  set.rebuild(map);
  EXPECT_EQ(set.size(), 8u * 8 * 8 - 6u * 6 * 6);
  EXPECT_EQ(set.cells(map), brute_force(map));
}

TEST(Frontiers, BoundsFilterAtQueryTime) {
  map::OccupancyMap map(0.1);
  for (int x = 0; x < 10; ++x) map.set_state({std::uint16_t(32768 + x), 32768, 32768}, map::VoxelState::Free);
  FrontierSet set;
  set.rebuild(map);
  EXPECT_EQ(set.cells(map).size(), 10u);
  EXPECT_EQ(set.cells(map, Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.5, 0.1, 0.1))).size(), 5u);
}

TEST(Frontiers, ClustersAre26ConnectedAndNumberedByTheirSmallestKey) {
  map::OccupancyMap map(0.1);
  const std::vector<map::VoxelKey> cells = {
      {10, 10, 10}, {11, 11, 11},  // diagonal neighbours: one cluster
      {20, 10, 10},                // alone
      {5, 10, 12},  {5, 11, 12}};  // two face neighbours, lower x
  std::vector<map::VoxelKey> sorted = cells;
  std::sort(sorted.begin(), sorted.end());
  const auto clusters = cluster(map, sorted);
  ASSERT_EQ(clusters.size(), 3u);
  EXPECT_EQ(clusters[0].cells.size(), 2u);  // {10,10,10} has the smallest key (z = 10)
  EXPECT_EQ(clusters[0].cells[0], (map::VoxelKey{10, 10, 10}));
  EXPECT_EQ(clusters[1].cells.size(), 1u);
  EXPECT_EQ(clusters[2].cells.size(), 2u);
  EXPECT_EQ(cluster(map, sorted).size(), 3u);
  for (std::size_t i = 0; i < clusters.size(); ++i) EXPECT_EQ(clusters[i].id, int(i));
}

/// Clusters by breadth-first search over a std::set, 26-neighbours by definition, in order
/// of each cluster's smallest key.
std::vector<std::vector<map::VoxelKey>> brute_force_clusters(const std::vector<map::VoxelKey>& cells) {
  const std::set<map::VoxelKey> all(cells.begin(), cells.end());
  std::set<map::VoxelKey> done;
  std::vector<std::vector<map::VoxelKey>> out;
  for (const map::VoxelKey& start : all) {
    if (!done.insert(start).second) continue;
    std::vector<map::VoxelKey> members{start};
    for (std::size_t head = 0; head < members.size(); ++head)
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const map::VoxelKey k = members[head];
            const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
            if (x < 0 || y < 0 || z < 0 || x > 0xFFFF || y > 0xFFFF || z > 0xFFFF) continue;
            const map::VoxelKey n{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
            if (all.count(n) && done.insert(n).second) members.push_back(n);
          }
    std::sort(members.begin(), members.end());
    out.push_back(members);
  }
  return out;
}

// Random cells at three densities, in the middle and at both ends of the key space (where a
// neighbour row would wrap): the row-walking clustering equals breadth-first search.
TEST(Frontiers, ClustersEqualBreadthFirstSearchOnRandomCells) {
  const map::OccupancyMap map(0.1);
  for (unsigned seed : {1u, 2u}) {
    for (double density : {0.05, 0.2, 0.5}) {
      for (int origin : {0, 30000, 0xFFFF - 11}) {
        std::mt19937 rng(seed);
        std::bernoulli_distribution keep(density);
        std::vector<map::VoxelKey> cells;
        for (int z = 0; z < 12; ++z)
          for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 12; ++x)
              if (keep(rng))
                cells.push_back({std::uint16_t(origin + x), std::uint16_t(origin + y), std::uint16_t(origin + z)});
        const auto oracle = brute_force_clusters(cells);
        const auto clusters = cluster(map, cells);
        ASSERT_EQ(clusters.size(), oracle.size()) << seed << " " << density << " " << origin;
        for (std::size_t i = 0; i < clusters.size(); ++i) {
          EXPECT_EQ(clusters[i].id, int(i));
          EXPECT_EQ(clusters[i].cells, oracle[i]) << seed << " " << density << " " << origin << " cluster " << i;
        }
      }
    }
  }
}

// Integrating the five slambook frames one by one, the incremental set equals a from-scratch
// computation after every frame.
TEST(FrontiersRealData, SlambookIncrementalEqualsFromScratchAfterEveryFrame) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  map::OccupancyMap map(0.05);
  FrontierSet incremental;
  test::for_each_slambook_frame(frames, [&](const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& origin,
                                            const std::string& path) {
    incremental.update(map, map.integrate(points, origin).changes);
    FrontierSet scratch;
    scratch.rebuild(map);
    ASSERT_GT(scratch.size(), 1000u);
    EXPECT_EQ(incremental.cells(map), scratch.cells(map)) << path;
  });
}

}  // namespace
}  // namespace fvx::frontiers
