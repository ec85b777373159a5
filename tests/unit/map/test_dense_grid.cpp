// The dense grid against the octree it snapshots: states cell by cell, and ray walks
// against OccupancyMap::cast_ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fvx/map/dense_grid.hpp"

namespace fvx::map {
namespace {

OccupancyMap random_map(std::mt19937& rng) {
  OccupancyMap map(0.1);
  std::normal_distribution<float> g(0, 1);
  for (int s = 0; s < 3; ++s) {
    const Eigen::Vector3f origin(0.3f * s, -0.2f * s, 0.1f);
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i < 400; ++i) points.push_back(origin + Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized() * 1.5f);
    map.integrate(points, origin, 1.2);
  }
  return map;
}

TEST(DenseGrid, StatesEqualTheOctreeCellByCell) {
  std::mt19937 rng(2);
  const OccupancyMap map = random_map(rng);
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-1.5, -1.5, -1.2), Eigen::Vector3d(1.6, 1.1, 1.3));
  const DenseGrid grid(map, bounds);
  ASSERT_GT(grid.cell_count(), 10000u);
  std::size_t known = 0;
  for (std::size_t i = 0; i < grid.cell_count(); ++i) {
    const VoxelKey k = grid.key(i);
    ASSERT_EQ(grid.index(k), i);
    ASSERT_TRUE(bounds.contains(grid.center_of(k)));
    ASSERT_EQ(grid.state_at(i), map.state(k));
    known += grid.state_at(i) != VoxelState::Unknown;
  }
  EXPECT_GT(known, 1000u);
}

TEST(DenseGrid, ASmallBoxReadsOnlyItsLeavesAndEqualsTheOctree) {
  std::mt19937 rng(3);
  OccupancyMap map = random_map(rng);
  for (int z = 0; z < 8; ++z)  // an aligned free block: leaves of 8 cells that the boxes cut
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        map.set_state({std::uint16_t(32784 + x), std::uint16_t(32784 + y), std::uint16_t(32784 + z)}, VoxelState::Free);
  const auto all = map.leaves();
  ASSERT_TRUE(std::any_of(all.begin(), all.end(), [](const Leaf& l) { return l.size_cells >= 8; }));
  for (const Eigen::AlignedBox3d& box :
       {Eigen::AlignedBox3d(Eigen::Vector3d(1.72, 1.63, 1.61), Eigen::Vector3d(1.93, 2.1, 1.7)),
        Eigen::AlignedBox3d(Eigen::Vector3d(-0.31, -0.2, -0.05), Eigen::Vector3d(0.12, 0.33, 0.41)),
        Eigen::AlignedBox3d(Eigen::Vector3d(1.0, -2.0, -0.5), Eigen::Vector3d(9.0, 0.0, 0.5)),
        // starts on the cell just above the block's leaf, which OctoMap's bbx iterator also yields
        Eigen::AlignedBox3d(Eigen::Vector3d(2.41, 1.61, 1.61), Eigen::Vector3d(2.6, 2.3, 2.3))}) {
    const DenseGrid grid(map, box);
    ASSERT_GT(grid.cell_count(), 0u);
    for (std::size_t i = 0; i < grid.cell_count(); ++i) ASSERT_EQ(grid.state_at(i), map.state(grid.key(i)));
    // The leaves in the box's keys are the leaves that reach into it, each once.
    const VoxelKey lo = grid.min_key();
    const VoxelKey hi{std::uint16_t(lo.x + grid.size().x() - 1), std::uint16_t(lo.y + grid.size().y() - 1),
                      std::uint16_t(lo.z + grid.size().z() - 1)};
    std::vector<Leaf> expected;
    for (const Leaf& l : all) {
      const int k0[3] = {l.min_key.x, l.min_key.y, l.min_key.z}, a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
      bool overlaps = true;
      for (int d = 0; d < 3; ++d) overlaps &= k0[d] <= b[d] && k0[d] + int(l.size_cells) - 1 >= a[d];
      if (overlaps) expected.push_back(l);
    }
    const std::vector<Leaf> in_box = map.leaves(lo, hi);
    ASSERT_EQ(in_box.size(), expected.size());
    for (std::size_t i = 0; i < in_box.size(); ++i) {
      EXPECT_EQ(in_box[i].min_key, expected[i].min_key);
      EXPECT_EQ(in_box[i].size_cells, expected[i].size_cells);
      EXPECT_EQ(in_box[i].state, expected[i].state);
    }
  }
}

TEST(DenseGrid, CellOfEqualsTheMapsKeyInsideTheGridAndIsEmptyOutside) {
  std::mt19937 rng(3);
  const OccupancyMap map = random_map(rng);
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-1.5, -1.5, -1.2), Eigen::Vector3d(1.6, 1.1, 1.3));
  const DenseGrid grid(map, bounds);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  std::size_t inside = 0;
  for (int i = 0; i < 200000; ++i) {
    // Points on cell faces too (multiples of the resolution), where rounding decides.
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    if (i % 4 == 0) p = (p / 0.1).array().round().matrix() * 0.1;
    const std::optional<VoxelKey> key = map.key_of(p), cell = grid.cell_of(p);
    ASSERT_TRUE(key);
    if (grid.contains(*key)) {
      ASSERT_TRUE(cell) << p.transpose();
      ASSERT_EQ(*cell, *key) << p.transpose();
      ++inside;
    } else {
      ASSERT_FALSE(cell) << p.transpose();
    }
  }
  EXPECT_GT(inside, 30000u);
  EXPECT_FALSE(grid.cell_of(Eigen::Vector3d(std::nan(""), 0, 0)));
  EXPECT_FALSE(grid.cell_of(Eigen::Vector3d(1e300, 0, 0)));
}

TEST(DenseGrid, WalksEqualTheOctreeRayCast) {
  std::mt19937 rng(4);
  const OccupancyMap map = random_map(rng);
  const DenseGrid grid(map, Eigen::AlignedBox3d(Eigen::Vector3d(-3, -3, -3), Eigen::Vector3d(3, 3, 3)));
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  std::normal_distribution<double> g(0, 1);
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d origin(u(rng), u(rng), u(rng));
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const RayCast octree = map.cast_ray({origin, dir, 1.5, false});
    VoxelKey last;
    const RayOutcome outcome = grid.walk(origin, dir, 1.5, [&](std::size_t index, VoxelState s) {
      last = grid.key(index);
      return s == VoxelState::Free;
    });
    if (octree.outcome == RayOutcome::OutOfBounds) continue;  // the octree starts outside its key space
    ASSERT_EQ(outcome, octree.outcome) << i;
    if (outcome == RayOutcome::Hit || outcome == RayOutcome::Unknown) {
      EXPECT_EQ(last, octree.key) << i;
    }
    ++compared;
  }
  EXPECT_GT(compared, 1900);
}

}  // namespace
}  // namespace fvx::map

namespace fvx::map {
namespace {

// The separable distance transform against the brute-force minimum over every occupied cell.
TEST(DenseGrid, SquaredDistanceToOccupiedEqualsBruteForce) {
  std::mt19937 rng(5);
  OccupancyMap map(0.1);
  std::uniform_int_distribution<int> cell(-12, 12);
  for (int i = 0; i < 60; ++i)
    map.set_state({std::uint16_t(32768 + cell(rng)), std::uint16_t(32768 + cell(rng)), std::uint16_t(32768 + cell(rng))},
                  VoxelState::Occupied);
  const DenseGrid grid(map, Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -1.3, -0.9), Eigen::Vector3d(1.1, 0.9, 1.2)));
  std::vector<Eigen::Vector3i> occupied;
  for (std::size_t i = 0; i < grid.cell_count(); ++i)
    if (grid.state_at(i) == VoxelState::Occupied) {
      const VoxelKey k = grid.key(i);
      occupied.emplace_back(k.x, k.y, k.z);
    }
  ASSERT_GT(occupied.size(), 20u);
  // Any split of the lines over threads (more threads than some axes have lines) gives it.
  for (const unsigned threads : {1u, 2u, 5u, 64u}) {
    const auto d = squared_distance_to(grid, VoxelState::Occupied, threads);
    for (std::size_t i = 0; i < grid.cell_count(); ++i) {
      const VoxelKey k = grid.key(i);
      int best = std::numeric_limits<int>::max();
      for (const auto& o : occupied) best = std::min(best, (o - Eigen::Vector3i(k.x, k.y, k.z)).squaredNorm());
      ASSERT_EQ(d[i], float(best)) << "cell " << i << ", threads " << threads;
    }
  }
  // With a largest distance: the exact value up to it, +infinity beyond (the passes drop
  // values above it as they go).
  const auto exact = squared_distance_to(grid, VoxelState::Occupied, 1);
  for (const float max_sq : {0.0f, 2.0f, 5.0f, 30.0f})
    for (const unsigned threads : {1u, 3u}) {
      const auto capped = squared_distance_to(grid, VoxelState::Occupied, threads, max_sq);
      for (std::size_t i = 0; i < grid.cell_count(); ++i)
        ASSERT_EQ(capped[i], exact[i] <= max_sq ? exact[i] : INFINITY) << "cell " << i << ", max " << max_sq;
    }
  // No cell in that state: infinity everywhere.
  OccupancyMap free_only(0.1);
  free_only.set_state({32768, 32768, 32768}, VoxelState::Free);
  const DenseGrid g2(free_only, Eigen::AlignedBox3d(Eigen::Vector3d(-0.3, -0.3, -0.3), Eigen::Vector3d(0.3, 0.3, 0.3)));
  for (const float v : squared_distance_to(g2, VoxelState::Occupied)) ASSERT_TRUE(std::isinf(v));
}

}  // namespace
}  // namespace fvx::map
