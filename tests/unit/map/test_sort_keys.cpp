// map::sort_keys against std::sort: both sides of the counting threshold, narrow and full
// axis ranges, repeated keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fvx/map/sort_keys.hpp"

namespace fvx::map {
namespace {

std::vector<VoxelKey> random_keys(std::size_t n, int lo, int hi, std::mt19937& rng) {
  std::uniform_int_distribution<int> value(lo, hi);
  std::vector<VoxelKey> keys(n);
  for (VoxelKey& k : keys) k = {std::uint16_t(value(rng)), std::uint16_t(value(rng)), std::uint16_t(value(rng))};
  return keys;
}

TEST(SortKeys, EqualsAComparisonSort) {
  std::mt19937 rng(7);
  for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(100), std::size_t(4095),
                              std::size_t(4096), std::size_t(200000)}) {
    for (const auto& [lo, hi] : {std::pair{32760, 32780}, std::pair{0, 0xFFFF}, std::pair{5, 5}}) {
      std::vector<VoxelKey> keys = random_keys(n, lo, hi, rng), oracle = keys;
      std::sort(oracle.begin(), oracle.end());
      sort_keys(keys);
      EXPECT_EQ(keys, oracle) << n << " keys in [" << lo << ", " << hi << "]";
    }
  }
}

}  // namespace
}  // namespace fvx::map
