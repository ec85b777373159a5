#pragma once
/// \file
/// A fixed set of packed voxel keys (x | y << 16 | z << 32), each with a 32-bit value, in
/// one flat open-addressing table. Built once, then only looked up: the neighbour look-ups
/// of clustering and frontier-void pairing (tens of millions on a real map) run several
/// times faster than in std::unordered_map, whose every look-up chases a node pointer.
#include <cstdint>
#include <utility>
#include <vector>

namespace fvx::map {

class KeyIndex {
 public:
  static constexpr std::uint32_t kMissing = 0xFFFFFFFFu;

  /// `entries`: (packed key, value) pairs with distinct keys; a repeated key keeps its
  /// first value.
  explicit KeyIndex(const std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries) {
    std::size_t capacity = 16;
    while (capacity < 2 * entries.size()) capacity *= 2;  // load factor at most 1/2
    mask_ = capacity - 1;
    slots_.assign(capacity, {kEmpty, kMissing});
    for (const auto& [key, value] : entries) {
      std::size_t i = slot(key);
      while (slots_[i].first != kEmpty && slots_[i].first != key) i = (i + 1) & mask_;
      if (slots_[i].first == kEmpty) slots_[i] = {key, value};
    }
  }

  /// The value stored for `key`, or kMissing.
  std::uint32_t find(std::uint64_t key) const {
    for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
      if (slots_[i].first == key) return slots_[i].second;
      if (slots_[i].first == kEmpty) return kMissing;
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);  // no packed key has bits above 47
  std::size_t slot(std::uint64_t key) const {
    return std::size_t((key * 0x9E3779B97F4A7C15ull) >> 17) & mask_;  // Fibonacci hashing
  }
  std::size_t mask_ = 0;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> slots_;
};

}  // namespace fvx::map
