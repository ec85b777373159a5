#include "fvx/map/dense_grid.hpp"

#include <algorithm>
#include <cmath>

#include "fvx/core/error.hpp"

namespace fvx::map {

DenseGrid::DenseGrid(const OccupancyMap& map, const Eigen::AlignedBox3d& bounds_m) : resolution_m_(map.resolution_m()) {
  const double R = resolution_m_;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {  // cells whose centres (k + 0.5)·R lie in the bounds
    lo[a] = std::max(0, int(std::ceil(bounds_m.min()[a] / R - 0.5)) + 32768);
    hi[a] = std::min(0xFFFF, int(std::floor(bounds_m.max()[a] / R - 0.5)) + 32768);
    if (hi[a] < lo[a]) return;  // an empty grid
  }
  min_ = {std::uint16_t(lo[0]), std::uint16_t(lo[1]), std::uint16_t(lo[2])};
  size_ = Eigen::Vector3i(hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1);
  FVX_ASSERT(double(size_.x()) * size_.y() * size_.z() < 4e9, "dense grid too large");
  states_.assign(std::size_t(size_.x()) * size_.y() * size_.z(), std::uint8_t(VoxelState::Unknown));
  for (const Leaf& leaf : map.leaves()) {
    int from[3], to[3];
    const int k0[3] = {leaf.min_key.x, leaf.min_key.y, leaf.min_key.z};
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      from[a] = std::max(k0[a], lo[a]);
      to[a] = std::min(k0[a] + int(leaf.size_cells) - 1, hi[a]);
      empty |= to[a] < from[a];
    }
    if (empty) continue;
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y) {
        const std::size_t row = index({std::uint16_t(from[0]), std::uint16_t(y), std::uint16_t(z)});
        std::fill(states_.begin() + std::ptrdiff_t(row), states_.begin() + std::ptrdiff_t(row) + (to[0] - from[0] + 1),
                  std::uint8_t(leaf.state));
      }
  }
}

VoxelKey DenseGrid::key(std::size_t i) const {
  const std::size_t nx = std::size_t(size_.x()), ny = std::size_t(size_.y());
  return {std::uint16_t(min_.x + i % nx), std::uint16_t(min_.y + i / nx % ny), std::uint16_t(min_.z + i / (nx * ny))};
}

Eigen::Vector3d DenseGrid::center_of(const VoxelKey& k) const {
  return {(double(k.x) - 32768 + 0.5) * resolution_m_, (double(k.y) - 32768 + 0.5) * resolution_m_,
          (double(k.z) - 32768 + 0.5) * resolution_m_};
}

}  // namespace fvx::map
