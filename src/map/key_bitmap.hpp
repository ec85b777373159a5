#pragma once
// Private to the map stage: a set of octree keys inside a known key box, as bits in 8³-cell
// blocks. One scan's rays visit tens of millions of cells but only ~10⁵–10⁶ distinct ones;
// a bit per cell deduplicates them at memory speed where OctoMap's std::unordered_set spends
// most of insertPointCloud's time.
#include <cstdint>
#include <vector>

#include <octomap/OcTree.h>  // OcTreeKey.h alone is not self-contained

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "fvx/core/error.hpp"

namespace fvx::map {

/// A bit per cell of a key box, flat. Used when the box of one scan is small enough (a 4 m
/// Kinect frame at 2.5 cm: at most 320³ bits, 4 MiB): one add and one OR per visited cell.
class DenseKeyBitmap {
 public:
  static constexpr std::uint64_t kMaxBits = std::uint64_t(1) << 30;  // 128 MiB

  static std::uint64_t bits_for(const std::array<int, 3>& min_key, const std::array<int, 3>& max_key) {
    return std::uint64_t(max_key[0] - min_key[0] + 1) * std::uint64_t(max_key[1] - min_key[1] + 1) *
           std::uint64_t(max_key[2] - min_key[2] + 1);
  }

  DenseKeyBitmap(const std::array<int, 3>& min_key, const std::array<int, 3>& max_key)
      : min_(min_key),
        nx_(std::uint64_t(max_key[0] - min_key[0] + 1)),
        ny_(std::uint64_t(max_key[1] - min_key[1] + 1)),
        nz_(std::uint64_t(max_key[2] - min_key[2] + 1)),
        words_((nx_ * ny_ * nz_ + 63) / 64, 0),
        strides_{1, std::int64_t(nx_), std::int64_t(nx_ * ny_)} {
    FVX_ASSERT(nx_ * ny_ * nz_ <= kMaxBits, "dense bitmap too large");
  }

  void insert(const octomap::OcTreeKey& k) { set(index(k)); }
  void set(std::uint64_t i) { words_[i >> 6] |= std::uint64_t(1) << (i & 63); }

  /// Adds every key of `other`, which must cover the same box.
  void merge(const DenseKeyBitmap& other) {
    FVX_ASSERT(other.words_.size() == words_.size() && other.min_ == min_, "bitmaps of different boxes");
    for (std::size_t w = 0; w < words_.size(); ++w) words_[w] |= other.words_[w];
  }

  /// The bits, 64 to a word (bit i in word i / 64, at i % 64), for walks that set them directly.
  std::uint64_t* words() { return words_.data(); }

  /// Bit-index distance between neighbouring cells along x, y, z.
  const std::int64_t* strides() const { return strides_; }

  std::uint64_t index(const octomap::OcTreeKey& k) const {
    const std::uint64_t x = std::uint64_t(int(k[0]) - min_[0]), y = std::uint64_t(int(k[1]) - min_[1]),
                        z = std::uint64_t(int(k[2]) - min_[2]);
    FVX_ASSERT(x < nx_ && y < ny_ && z < nz_, "key outside the bitmap's box");
    return (z * ny_ + y) * nx_ + x;
  }
  bool contains(const octomap::OcTreeKey& k) const {
    const std::uint64_t i = index(k);
    return (words_[i >> 6] >> (i & 63)) & 1u;
  }

  /// Calls f(key) for every stored key, x fastest (memory order).
  template <typename F>
  void for_each(F f) const {
    for (std::size_t w = 0; w < words_.size(); ++w) {
      for (std::uint64_t word = words_[w]; word; word &= word - 1) {
        const std::uint64_t i = w * 64 + std::uint64_t(__builtin_ctzll(word));
        f(octomap::OcTreeKey(std::uint16_t(min_[0] + i % nx_), std::uint16_t(min_[1] + i / nx_ % ny_),
                             std::uint16_t(min_[2] + i / (nx_ * ny_))));
      }
    }
  }

 private:
  std::array<int, 3> min_;
  std::uint64_t nx_, ny_, nz_;
  std::vector<std::uint64_t> words_;
  std::int64_t strides_[3];
};

/// A sparse set of keys for boxes too large for DenseKeyBitmap: bits in 8³-cell blocks.
class KeyBitmap {
 public:
  /// Keys with min_key[i] <= k[i] <= max_key[i] may be stored.
  KeyBitmap(const std::array<int, 3>& min_key, const std::array<int, 3>& max_key) {
    for (int i = 0; i < 3; ++i) {
      FVX_ASSERT(min_key[i] <= max_key[i], "empty key box");
      origin_[i] = min_key[i];
      blocks_[i] = (max_key[i] - min_key[i]) / 8 + 1;
    }
    const std::uint64_t total = std::uint64_t(blocks_[0]) * blocks_[1] * blocks_[2];
    if (total <= kMaxDenseSlots) dense_.assign(total, kNone);
  }

  bool insert(const octomap::OcTreeKey& k) {
    const auto [block, bit] = locate(k);
    std::uint64_t& word = bits_[block][bit >> 6];
    const std::uint64_t mask = std::uint64_t(1) << (bit & 63);
    const bool added = !(word & mask);
    word |= mask;
    return added;
  }

  bool contains(const octomap::OcTreeKey& k) const {
    const Address a = address(k);
    std::uint32_t block = kNone;
    if (!dense_.empty()) {
      block = dense_[a.slot];
    } else if (const auto it = sparse_.find(a.slot); it != sparse_.end()) {
      block = it->second;
    }
    return block != kNone && (bits_[block][a.bit >> 6] >> (a.bit & 63)) & 1u;
  }

  /// Calls f(key) for every stored key, block by block in order of first insertion.
  template <typename F>
  void for_each(F f) const {
    for (std::size_t b = 0; b < bits_.size(); ++b) {
      for (unsigned w = 0; w < 8; ++w) {
        for (std::uint64_t word = bits_[b][w]; word; word &= word - 1) {
          const unsigned bit = w * 64 + unsigned(__builtin_ctzll(word));
          const auto& c = block_corner_[b];
          f(octomap::OcTreeKey(std::uint16_t(c[0] + (bit & 7)), std::uint16_t(c[1] + ((bit >> 3) & 7)),
                               std::uint16_t(c[2] + (bit >> 6))));
        }
      }
    }
  }

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  static constexpr std::uint64_t kMaxDenseSlots = std::uint64_t(1) << 24;  // 64 MiB of slots

  /// Where a key lives: its block slot in the box, its bit in the block, its block's corner.
  struct Address {
    std::uint64_t slot;
    unsigned bit;
    std::array<int, 3> corner;
  };

  Address address(const octomap::OcTreeKey& k) const {
    int local[3];
    for (int i = 0; i < 3; ++i) {
      local[i] = int(k[i]) - origin_[i];
      FVX_ASSERT(local[i] >= 0 && local[i] / 8 < blocks_[i], "key outside the bitmap's box");
    }
    return {(std::uint64_t(local[2] / 8) * blocks_[1] + local[1] / 8) * blocks_[0] + local[0] / 8,
            unsigned((local[2] & 7) * 64 + (local[1] & 7) * 8 + (local[0] & 7)),
            {origin_[0] + local[0] / 8 * 8, origin_[1] + local[1] / 8 * 8, origin_[2] + local[2] / 8 * 8}};
  }

  /// The block and bit of a key, creating its block if needed.
  std::pair<std::uint32_t, unsigned> locate(const octomap::OcTreeKey& k) {
    const Address a = address(k);
    std::uint32_t& index = dense_.empty() ? sparse_.try_emplace(a.slot, kNone).first->second : dense_[a.slot];
    if (index == kNone) {
      index = std::uint32_t(bits_.size());
      bits_.push_back({});
      block_corner_.push_back(a.corner);
    }
    return {index, a.bit};
  }

  int origin_[3];
  int blocks_[3];
  std::vector<std::uint32_t> dense_;                        // slot → block, when small enough
  std::unordered_map<std::uint64_t, std::uint32_t> sparse_; // otherwise
  std::vector<std::array<std::uint64_t, 8>> bits_;          // 512 bits per block
  std::vector<std::array<int, 3>> block_corner_;
};

}  // namespace fvx::map
