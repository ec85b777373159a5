// Void cells that could hide a target: the opening by a cube against a brute-force oracle
// on random sets, on shapes whose answer is known, and the width a target always fills.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "fvx/voids/width.hpp"

namespace fvx::voids {
namespace {

using Key = map::VoxelKey;

Key key(int x, int y, int z) { return {std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)}; }

/// The definition, cell by cell: some cube of width³ cells of the set contains the cell.
std::vector<Key> oracle(const std::vector<Key>& cells, int width) {
  const std::set<Key> in(cells.begin(), cells.end());
  std::vector<Key> kept;
  for (const Key& c : cells) {
    bool covered = false;
    for (int ox = 0; ox < width && !covered; ++ox)
      for (int oy = 0; oy < width && !covered; ++oy)
        for (int oz = 0; oz < width && !covered; ++oz) {
          bool full = true;
          for (int i = 0; i < width && full; ++i)
            for (int j = 0; j < width && full; ++j)
              for (int l = 0; l < width && full; ++l)
                full = in.count({std::uint16_t(c.x - ox + i), std::uint16_t(c.y - oy + j), std::uint16_t(c.z - oz + l)}) != 0;
          covered = full;
        }
    if (covered) kept.push_back(c);
  }
  return kept;
}

TEST(VoidWidth, MatchesTheDefinitionOnRandomSets) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::bernoulli_distribution dense(0.55 + 0.02 * trial);
    std::set<Key> set;
    for (int z = 0; z < 9; ++z)
      for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 11; ++x)
          if (dense(rng)) set.insert(key(x, y, z));
    const std::vector<Key> cells(set.begin(), set.end());
    for (int width = 1; width <= 3; ++width)
      EXPECT_EQ(cells_in_full_cubes(cells, width), oracle(cells, width)) << "trial " << trial << ", width " << width;
  }
}

TEST(VoidWidth, ASliverGoesAndABlockStays) {
  std::vector<Key> cells;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) cells.push_back(key(x, y, 0));  // a sheet one cell thick
  EXPECT_TRUE(cells_in_full_cubes(cells, 2).empty());
  EXPECT_EQ(cells_in_full_cubes(cells, 1).size(), cells.size());
  std::vector<Key> block;
  for (int z = 10; z < 13; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) block.push_back(key(x, y, z));
  std::vector<Key> both = block;
  both.push_back(key(3, 1, 11));  // a one-cell spur off the block
  std::sort(both.begin(), both.end());
  std::sort(block.begin(), block.end());
  EXPECT_EQ(cells_in_full_cubes(both, 2), block);
  EXPECT_EQ(cells_in_full_cubes(both, 3), block);
  EXPECT_TRUE(cells_in_full_cubes(both, 4).empty());
}

TEST(VoidWidth, ATargetAlwaysFillsACubeOfThatWidth) {
  const double R = 0.025;
  EXPECT_EQ(void_width_for_target(0.0, R), 1);
  EXPECT_EQ(void_width_for_target(0.06, R), 1);
  EXPECT_EQ(void_width_for_target(0.075, R), 2);
  EXPECT_EQ(void_width_for_target(0.08, R), 2);
  EXPECT_EQ(void_width_for_target(0.1, R), 3);
  // A cube of edge L anywhere on the grid: the cells it wholly covers hold a cube of the
  // width, and for some placement no wider one.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> offset(0.0, R);
  for (const double L : {0.06, 0.07, 0.08, 0.1, 0.12}) {
    const int width = void_width_for_target(L, R);
    bool tight = false;
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d lo(offset(rng), offset(rng), offset(rng));
      std::vector<Key> covered;
      for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
          for (int x = 0; x < 8; ++x) {
            const Eigen::Vector3d a = Eigen::Vector3d(x, y, z) * R, b = a + Eigen::Vector3d::Constant(R);
            if ((a.array() >= lo.array()).all() && (b.array() <= (lo.array() + L)).all()) covered.push_back(key(x, y, z));
          }
      std::sort(covered.begin(), covered.end());
      EXPECT_FALSE(cells_in_full_cubes(covered, width).empty()) << "L " << L << ", trial " << trial;
      tight |= cells_in_full_cubes(covered, width + 1).empty();
    }
    EXPECT_TRUE(tight) << "L " << L << ": a wider cube always fitted";
  }
}

}  // namespace
}  // namespace fvx::voids
