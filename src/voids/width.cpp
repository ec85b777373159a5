#include "fvx/voids/width.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fvx/core/error.hpp"

namespace fvx::voids {

int void_width_for_target(double target_size_m, double resolution_m) {
  FVX_ASSERT(target_size_m >= 0.0 && resolution_m > 0.0, "target size or resolution");
  // An interval of length L contains floor(L/R) − 1 whole cells at worst (its ends just
  // past grid lines); the 1e-9 keeps L = n·R from rounding down to n − 1.
  return std::max(1, int(std::floor(target_size_m / resolution_m + 1e-9)) - 1);
}

std::vector<map::VoxelKey> cells_in_full_cubes(const std::vector<map::VoxelKey>& cells, int width) {
  FVX_ASSERT(width >= 1, "cube width " + std::to_string(width));
  if (width == 1 || cells.empty()) return cells;
  // A flat bitmap over the cells' box: `in` marks the cells, `start` the cubes' lowest corners.
  int lo[3] = {0xFFFF, 0xFFFF, 0xFFFF}, hi[3] = {0, 0, 0};
  for (const map::VoxelKey& k : cells) {
    const int c[3] = {k.x, k.y, k.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  const auto index = [&](std::int64_t x, std::int64_t y, std::int64_t z) { return (z * ny + y) * nx + x; };
  std::vector<std::uint8_t> in(std::size_t(nx * ny * nz), 0), start(in.size(), 0);
  for (const map::VoxelKey& k : cells) in[std::size_t(index(k.x - lo[0], k.y - lo[1], k.z - lo[2]))] = 1;
  const auto full_from = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    if (x + width > nx || y + width > ny || z + width > nz) return false;
    for (int dz = 0; dz < width; ++dz)
      for (int dy = 0; dy < width; ++dy)
        for (int dx = 0; dx < width; ++dx)
          if (!in[std::size_t(index(x + dx, y + dy, z + dz))]) return false;
    return true;
  };
  for (const map::VoxelKey& k : cells) {
    const std::int64_t x = k.x - lo[0], y = k.y - lo[1], z = k.z - lo[2];
    start[std::size_t(index(x, y, z))] = full_from(x, y, z);
  }
  std::vector<map::VoxelKey> kept;
  for (const map::VoxelKey& k : cells) {
    const std::int64_t x = k.x - lo[0], y = k.y - lo[1], z = k.z - lo[2];
    bool covered = false;
    for (int dz = 0; dz < width && !covered; ++dz)
      for (int dy = 0; dy < width && !covered; ++dy)
        for (int dx = 0; dx < width && !covered; ++dx)
          covered = x >= dx && y >= dy && z >= dz && start[std::size_t(index(x - dx, y - dy, z - dz))];
    if (covered) kept.push_back(k);
  }
  return kept;
}

}  // namespace fvx::voids
