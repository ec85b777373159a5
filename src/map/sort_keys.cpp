#include "fvx/map/sort_keys.hpp"

#include <algorithm>
#include <cstdint>

namespace fvx::map {

namespace {

/// Below this many keys a comparison sort is as fast and needs no counting array.
constexpr std::size_t kCountingFrom = 4096;

std::uint16_t axis(const VoxelKey& k, int a) { return a == 0 ? k.x : a == 1 ? k.y : k.z; }

/// One stable counting pass: `from` ordered by axis `a` into `to`.
void count_by_axis(const std::vector<VoxelKey>& from, std::vector<VoxelKey>& to, int a) {
  std::uint16_t lo = 0xFFFF, hi = 0;
  for (const VoxelKey& k : from) lo = std::min(lo, axis(k, a)), hi = std::max(hi, axis(k, a));
  std::vector<std::size_t> start(std::size_t(hi - lo) + 2, 0);  // start[v − lo + 1] counts v
  for (const VoxelKey& k : from) ++start[std::size_t(axis(k, a) - lo) + 1];
  for (std::size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
  for (const VoxelKey& k : from) to[start[std::size_t(axis(k, a) - lo)]++] = k;
}

}  // namespace

void sort_keys(std::vector<VoxelKey>& keys) {
  if (keys.size() < kCountingFrom) {
    std::stable_sort(keys.begin(), keys.end());
    return;
  }
  std::vector<VoxelKey> other(keys.size());
  count_by_axis(keys, other, 0);  // least significant first: x, y, then z
  count_by_axis(other, keys, 1);
  count_by_axis(keys, other, 2);
  keys.swap(other);
}

}  // namespace fvx::map
