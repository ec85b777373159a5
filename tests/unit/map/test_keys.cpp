// Voxel keys at and around cell borders, for negative coordinates and at the key-space edge.
#include <gtest/gtest.h>

#include <cmath>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {
namespace {

constexpr std::uint16_t kOrigin = 32768;  // key of the cell [0, R)

TEST(VoxelKey, CellBordersWithExactResolution) {
  const OccupancyMap map(0.25);  // exact in binary: borders are exact
  EXPECT_EQ(map.key_of({0.0, 0.0, 0.0})->x, kOrigin);
  EXPECT_EQ(map.key_of({0.2499999, 0, 0})->x, kOrigin);
  EXPECT_EQ(map.key_of({0.25, 0, 0})->x, kOrigin + 1);   // a border belongs to the upper cell
  EXPECT_EQ(map.key_of({-1e-9, 0, 0})->x, kOrigin - 1);  // just below zero
  EXPECT_EQ(map.key_of({-0.25, 0, 0})->x, kOrigin - 1);
  EXPECT_EQ(map.key_of({-0.2500001, 0, 0})->x, kOrigin - 2);
  EXPECT_EQ(map.key_of({0, -3.9, 0})->y, kOrigin - 16);  // floor(-15.6) = -16
  EXPECT_EQ(map.key_of({0, 0, 3.9})->z, kOrigin + 15);
}

TEST(VoxelKey, CentersRoundTrip) {
  for (double R : {0.025, 0.05, 0.1, 0.25}) {
    const OccupancyMap map(R);
    for (int i = -50; i <= 50; ++i) {
      const VoxelKey key{std::uint16_t(kOrigin + i), std::uint16_t(kOrigin - i), std::uint16_t(kOrigin + 2 * i)};
      const Eigen::Vector3d c = map.center_of(key);
      EXPECT_NEAR(c.x(), (i + 0.5) * R, 1e-9);
      EXPECT_NEAR(c.y(), (-i + 0.5) * R, 1e-9);
      EXPECT_EQ(map.key_of(c), key) << "R=" << R << " i=" << i;
      // A point a hair inside either border of the cell maps to the same key.
      EXPECT_EQ(map.key_of(c + Eigen::Vector3d::Constant(0.4999 * R)), key);
      EXPECT_EQ(map.key_of(c - Eigen::Vector3d::Constant(0.4999 * R)), key);
    }
  }
}

TEST(VoxelKey, OutsideTheKeySpaceHasNoKey) {
  const OccupancyMap map(0.05);
  const double half_extent_m = 32768 * 0.05;
  EXPECT_TRUE(map.key_of({half_extent_m - 0.06, 0, 0}).has_value());
  EXPECT_FALSE(map.key_of({half_extent_m + 0.01, 0, 0}).has_value());
  EXPECT_FALSE(map.key_of({0, -half_extent_m - 0.01, 0}).has_value());
  EXPECT_FALSE(map.key_of({NAN, 0, 0}).has_value());
}

TEST(VoxelKey, OrderIsZThenYThenX) {
  EXPECT_LT((VoxelKey{9, 9, 1}), (VoxelKey{0, 0, 2}));
  EXPECT_LT((VoxelKey{9, 1, 2}), (VoxelKey{0, 2, 2}));
  EXPECT_LT((VoxelKey{1, 2, 2}), (VoxelKey{2, 2, 2}));
  EXPECT_FALSE((VoxelKey{2, 2, 2}) < (VoxelKey{2, 2, 2}));
}

}  // namespace
}  // namespace fvx::map
