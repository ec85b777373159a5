#pragma once
/// \file
/// A fixed set of packed voxel keys (x | y << 16 | z << 32), each with a 32-bit value. Built
/// once, then only looked up: the neighbour look-ups of clustering and frontier-void pairing
/// (tens of millions on a real map). Keys that fill a fair part of their bounding box (void
/// cells, frontier cells) go in a dense array over that box, where a look-up is one load and
/// neighbours are near in memory; sparse ones in a flat open-addressing table. Either runs
/// several times faster than std::unordered_map, whose every look-up chases a node pointer.
#include <algorithm>
#include <cstdint>

#include <utility>
#include <vector>

#include "fvx/core/large_vector.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {

/// A key packed into one integer (x | y << 16 | z << 32), for hashing and KeyIndex.
inline std::uint64_t pack(const VoxelKey& k) {
  return std::uint64_t(k.x) | std::uint64_t(k.y) << 16 | std::uint64_t(k.z) << 32;
}
inline VoxelKey unpack(std::uint64_t p) {
  return {std::uint16_t(p & 0xFFFF), std::uint16_t(p >> 16 & 0xFFFF), std::uint16_t(p >> 32 & 0xFFFF)};
}

class KeyIndex {
 public:
  static constexpr std::uint32_t kMissing = 0xFFFFFFFFu;

  /// `entries`: (packed key, value) pairs with distinct keys; a repeated key keeps its
  /// first value.
  explicit KeyIndex(const std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries)
      : KeyIndex(entries.size(), [&](auto&& visit) {
          for (const auto& [key, value] : entries) visit(key, value);
        }) {}

  /// `count` entries, given by for_each(visit), which calls visit(packed key, value) for each
  /// entry in the same order every time: no list of pairs to build.
  template <typename ForEach>
  KeyIndex(std::size_t count, ForEach&& for_each) {
    if (count > 0 && fits_dense(count, for_each)) {
      dense_.assign(std::size_t(size_[0]) * size_[1] * size_[2], kMissing);
      for_each([&](std::uint64_t key, std::uint32_t value) {
        std::uint32_t& slot = dense_[dense_index(key)];
        if (slot == kMissing) slot = value;  // a repeated key keeps its first value
      });
      return;
    }
    std::size_t capacity = 16;
    while (capacity < 2 * count) capacity *= 2;  // load factor at most 1/2
    mask_ = capacity - 1;
    slots_.assign(capacity, {kEmpty, kMissing});
    for_each([&](std::uint64_t key, std::uint32_t value) {
      std::size_t i = slot(key);
      while (slots_[i].first != kEmpty && slots_[i].first != key) i = (i + 1) & mask_;
      if (slots_[i].first == kEmpty) slots_[i] = {key, value};
    });
  }

  /// Whether `keys` keys filling a box of `box_cells` cells go in a dense array over the box
  /// (4 bytes per cell) rather than the hashed table (32 bytes per key, slower to probe).
  /// Region growing (voids::cluster_voids) labels its cells the same way.
  static bool dense_fits(std::size_t keys, double box_cells) {
    return box_cells <= double(kDenseCellsPerKey) * double(keys) + double(kDenseFreeCells);
  }

  /// The value stored for `key`, or kMissing.
  std::uint32_t find(std::uint64_t key) const {
    if (!dense_.empty()) {
      const std::uint32_t x = std::uint32_t(key & 0xFFFF) - min_[0], y = std::uint32_t(key >> 16 & 0xFFFF) - min_[1],
                          z = std::uint32_t(key >> 32 & 0xFFFF) - min_[2];
      if (x >= size_[0] || y >= size_[1] || z >= size_[2]) return kMissing;  // wraps below the box too
      return dense_[(std::size_t(z) * size_[1] + y) * size_[0] + x];
    }
    for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
      if (slots_[i].first == key) return slots_[i].second;
      if (slots_[i].first == kEmpty) return kMissing;
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);  // no packed key has bits above 47
  /// Dense when the box has at most this many cells per key (4 bytes each), plus a small
  /// box for free: the hashed table costs 32 bytes per key and is slower to probe.
  static constexpr std::size_t kDenseCellsPerKey = 32, kDenseFreeCells = std::size_t(1) << 16;

  template <typename ForEach>
  bool fits_dense(std::size_t count, ForEach& for_each) {
    std::uint32_t hi[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) min_[a] = 0xFFFF;
    for_each([&](std::uint64_t key, std::uint32_t) {
      for (int a = 0; a < 3; ++a) {
        const std::uint32_t c = std::uint32_t(key >> (16 * a) & 0xFFFF);
        min_[a] = std::min(min_[a], c);
        hi[a] = std::max(hi[a], c);
      }
    });
    for (int a = 0; a < 3; ++a) size_[a] = hi[a] - min_[a] + 1;
    return dense_fits(count, double(size_[0]) * size_[1] * size_[2]);
  }
  std::size_t dense_index(std::uint64_t key) const {
    return (std::size_t((key >> 32 & 0xFFFF) - min_[2]) * size_[1] + ((key >> 16 & 0xFFFF) - min_[1])) * size_[0] +
           ((key & 0xFFFF) - min_[0]);
  }
  std::size_t slot(std::uint64_t key) const {
    return std::size_t((key * 0x9E3779B97F4A7C15ull) >> 17) & mask_;  // Fibonacci hashing
  }
  std::size_t mask_ = 0;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> slots_;
  std::uint32_t min_[3] = {0, 0, 0}, size_[3] = {0, 0, 0};
  core::LargeVector<std::uint32_t> dense_;  ///< over the keys' box, x fastest; empty: hashed
};

}  // namespace fvx::map
