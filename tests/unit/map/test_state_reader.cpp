// map::StateReader against OccupancyMap::state, the root-to-leaf search it shortcuts: a map
// with pruned free and occupied blocks and scattered cells with unknown ones between them,
// around key 32768 (32767 → 32768 differs in every bit), read in key order, in neighbour
// walks and at random.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {
namespace {

OccupancyMap mixed_map(std::mt19937& rng) {
  OccupancyMap map(0.1);
  // An aligned 8³ block of free cells (OctoMap prunes it into one leaf) and one of
  // occupied cells, both straddling nothing; then scattered cells around key 32768.
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        map.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)}, VoxelState::Free);
        map.set_state({std::uint16_t(32752 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)},
                      VoxelState::Occupied);
      }
  // Free or occupied (deleting cells from pruned leaves trips an assertion inside OctoMap);
  // the cells between them stay unknown.
  std::uniform_int_distribution<int> near(32760, 32780);
  std::bernoulli_distribution occupied(0.3);
  for (int i = 0; i < 3000; ++i)
    map.set_state({std::uint16_t(near(rng)), std::uint16_t(near(rng)), std::uint16_t(near(rng))},
                  occupied(rng) ? VoxelState::Occupied : VoxelState::Free);
  return map;
}

TEST(StateReader, EqualsTheTreeSearchInAnyOrder) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    const OccupancyMap map = mixed_map(rng);
    std::vector<VoxelKey> keys;  // the box around the cells, in key order
    for (int z = 32748; z <= 32784; ++z)
      for (int y = 32748; y <= 32784; ++y)
        for (int x = 32748; x <= 32784; ++x) keys.push_back({std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)});
    std::size_t known = 0;
    StateReader in_order(map);
    for (const VoxelKey& k : keys) {
      ASSERT_EQ(in_order(k), map.state(k)) << k.x << " " << k.y << " " << k.z;
      known += map.state(k) != VoxelState::Unknown;
    }
    EXPECT_GT(known, 3000u);  // two blocks of 512 and most of the 3000 scattered cells
    EXPECT_LT(known, keys.size() / 2);
    StateReader walks(map);   // each key, then its six face-neighbours
    for (std::size_t i = 0; i < keys.size(); i += 7) {
      const VoxelKey k = keys[i];
      ASSERT_EQ(walks(k), map.state(k));
      for (int a = 0; a < 3; ++a)
        for (int step : {-1, 1}) {
          VoxelKey n = k;
          (a == 0 ? n.x : a == 1 ? n.y : n.z) += std::uint16_t(step);
          ASSERT_EQ(walks(n), map.state(n));
        }
    }
    std::shuffle(keys.begin(), keys.end(), rng);
    StateReader shuffled(map);
    for (const VoxelKey& k : keys) ASSERT_EQ(shuffled(k), map.state(k));
  }
}

TEST(StateReader, AnEmptyMapIsUnknownEverywhere) {
  const OccupancyMap map(0.05);
  StateReader read(map);
  EXPECT_EQ(read({1, 2, 3}), VoxelState::Unknown);
  EXPECT_EQ(read({1, 2, 3}), VoxelState::Unknown);
}

}  // namespace
}  // namespace fvx::map
