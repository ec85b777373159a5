// map::KeyIndex against std::map as the oracle: dense boxes and sparse sets, repeated keys,
// and look-ups around and beyond the keys' box (below it the unsigned offsets wrap).
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "fvx/map/key_index.hpp"

namespace fvx::map {
namespace {

std::uint64_t packed(int x, int y, int z) {
  return std::uint64_t(x) | std::uint64_t(y) << 16 | std::uint64_t(z) << 32;
}

/// Every key of the box [lo − 2, hi + 2]³ and of random far keys is looked up in both.
void expect_same_as_map(const std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries, int lo, int hi,
                        std::mt19937& rng) {
  std::map<std::uint64_t, std::uint32_t> oracle;
  for (const auto& [k, v] : entries) oracle.emplace(k, v);  // the first value stays
  const KeyIndex index(entries);
  auto expect = [&](std::uint64_t k) {
    const auto it = oracle.find(k);
    EXPECT_EQ(index.find(k), it == oracle.end() ? KeyIndex::kMissing : it->second) << k;
  };
  for (int z = lo - 2; z <= hi + 2; ++z)
    for (int y = lo - 2; y <= hi + 2; ++y)
      for (int x = lo - 2; x <= hi + 2; ++x) expect(packed(x, y, z));
  std::uniform_int_distribution<int> any(0, 0xFFFF);
  for (int i = 0; i < 1000; ++i) expect(packed(any(rng), any(rng), any(rng)));
  expect(packed(0, 0, 0));
  expect(packed(0xFFFF, 0xFFFF, 0xFFFF));
}

TEST(KeyIndex, DenseBoxEqualsTheMap) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coord(1000, 1020);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  for (std::uint32_t i = 0; i < 4000; ++i) entries.emplace_back(packed(coord(rng), coord(rng), coord(rng)), i);
  expect_same_as_map(entries, 1000, 1020, rng);  // repeats included: 4000 draws in 9261 cells
}

TEST(KeyIndex, SparseKeysEqualTheMap) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> coord(0, 0xFFFF);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  for (std::uint32_t i = 0; i < 300; ++i) entries.emplace_back(packed(coord(rng), coord(rng), coord(rng)), i);
  entries.emplace_back(packed(5, 5, 5), 7);
  entries.emplace_back(packed(5, 5, 5), 8);  // a repeat keeps 7
  expect_same_as_map(entries, 3, 7, rng);
}

TEST(KeyIndex, KeysAtTheEdgesOfTheKeySpace) {
  std::mt19937 rng(5);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries = {
      {packed(0, 0, 0), 1}, {packed(1, 0, 2), 2}, {packed(0xFFFF, 0, 0), 3}, {packed(2, 2, 2), 4}};
  expect_same_as_map(entries, 0, 3, rng);
  expect_same_as_map({}, 0, 1, rng);
}

}  // namespace
}  // namespace fvx::map
