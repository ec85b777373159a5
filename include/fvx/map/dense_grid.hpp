#pragma once
/// \file
/// A snapshot of the map's cell states inside a box, one byte per cell: the flat array the
/// hot loops (utility rays, field-of-view scoring) walk instead of octree searches
/// (ARCHITECTURE.md §2: a dense-grid DDA walks ~500 M cells/s, octree look-ups 20–30 M/s).
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "fvx/core/large_vector.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {

class DenseGrid {
 public:
  /// The cells whose centres lie in `bounds_m` (on the map's key grid); cells the map does
  /// not know are Unknown.
  DenseGrid(const OccupancyMap& map, const Eigen::AlignedBox3d& bounds_m);

  double resolution_m() const { return resolution_m_; }
  std::size_t cell_count() const { return states_.size(); }
  const VoxelKey& min_key() const { return min_; }
  const Eigen::Vector3i& size() const { return size_; }

  bool contains(const VoxelKey& k) const {
    return k.x >= min_.x && k.y >= min_.y && k.z >= min_.z && k.x - min_.x < size_.x() && k.y - min_.y < size_.y() &&
           k.z - min_.z < size_.z();
  }
  std::size_t index(const VoxelKey& k) const {
    return (std::size_t(k.z - min_.z) * std::size_t(size_.y()) + std::size_t(k.y - min_.y)) * std::size_t(size_.x()) +
           std::size_t(k.x - min_.x);
  }
  VoxelKey key(std::size_t index) const;
  /// Precondition: contains(k).
  VoxelState state(const VoxelKey& k) const { return VoxelState(states_[index(k)]); }
  VoxelState state_at(std::size_t index) const { return VoxelState(states_[index]); }
  Eigen::Vector3d center_of(const VoxelKey& k) const;

  /// Walks the cells along a ray from `origin_m` (Amanatides–Woo, the same stepping as
  /// OccupancyMap::cast_ray), calling visit(index, state) for each cell from the origin's
  /// on; stops when visit returns false (outcome Hit or Unknown, by the state), at
  /// `max_range_m` (MaxRange) or at the edge of the box (OutOfBounds).
  template <typename Visit>
  RayOutcome walk(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& direction, double max_range_m,
                  Visit&& visit) const;

 private:
  double resolution_m_;
  VoxelKey min_;
  Eigen::Vector3i size_ = Eigen::Vector3i::Zero();
  core::LargeVector<std::uint8_t> states_;
};

/// Per grid cell, the squared distance in cells to the centre of the nearest cell in `state`
/// within the grid (an exact Euclidean distance transform, Felzenszwalb & Huttenlocher 2012,
/// three separable passes); +infinity when the grid holds no such cell.
core::LargeVector<float> squared_distance_to(const DenseGrid& grid, VoxelState state);

template <typename Visit>
RayOutcome DenseGrid::walk(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& direction, double max_range_m,
                           Visit&& visit) const {
  const double R = resolution_m_;
  // Cell of the origin on the map's key grid (as OctoMap: floor(coordinate / R) + 32768).
  int cell[3];
  for (int a = 0; a < 3; ++a) cell[a] = int(std::floor(origin_m[a] * (1.0 / R))) + 32768;
  const int lo[3] = {min_.x, min_.y, min_.z};
  for (int a = 0; a < 3; ++a)
    if (cell[a] < lo[a] || cell[a] - lo[a] >= size_[a]) return RayOutcome::OutOfBounds;
  const Eigen::Vector3d d = direction.normalized();
  int step[3];
  double t_max[3], t_delta[3];
  std::int64_t stride[3] = {1, size_.x(), std::int64_t(size_.x()) * size_.y()};
  std::int64_t index = 0;
  for (int a = 0; a < 3; ++a) {
    index += (cell[a] - lo[a]) * stride[a];
    step[a] = d[a] > 0 ? 1 : (d[a] < 0 ? -1 : 0);
    if (step[a] == 0) {
      t_max[a] = t_delta[a] = INFINITY;
    } else {
      const double center = (double(cell[a] - 32768) + 0.5) * R;
      t_max[a] = (center + 0.5 * R * step[a] - origin_m[a]) / d[a];
      t_delta[a] = R / std::abs(d[a]);
    }
  }
  while (true) {
    const VoxelState s = VoxelState(states_[std::size_t(index)]);
    if (!visit(std::size_t(index), s)) return s == VoxelState::Occupied ? RayOutcome::Hit : RayOutcome::Unknown;
    const int a = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    if (t_max[a] > max_range_m) return RayOutcome::MaxRange;
    cell[a] += step[a];
    if (cell[a] < lo[a] || cell[a] - lo[a] >= size_[a]) return RayOutcome::OutOfBounds;
    index += step[a] * stride[a];
    t_max[a] += t_delta[a];
  }
}

}  // namespace fvx::map
