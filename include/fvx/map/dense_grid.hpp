#pragma once
/// \file
/// A snapshot of the map's cell states inside a box, one byte per cell: the flat array the
/// hot loops (utility rays, field-of-view scoring) walk instead of octree searches
/// (ARCHITECTURE.md §2: a dense-grid DDA walks ~500 M cells/s, octree look-ups 20–30 M/s).
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <optional>
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
  /// Inline: the field-of-view scorer and Algorithm 1 ask it for cells along every ray.
  VoxelKey key(std::size_t index) const {
    const std::size_t nx = std::size_t(size_.x()), ny = std::size_t(size_.y());
    return {std::uint16_t(min_.x + index % nx), std::uint16_t(min_.y + index / nx % ny),
            std::uint16_t(min_.z + index / (nx * ny))};
  }
  /// The key of the grid cell holding p_m (OctoMap's coordToKey rounding, so it equals
  /// OccupancyMap::key_of), or nothing outside the grid: searches that run while the map
  /// changes (fvx replay) find cells without reading the map.
  std::optional<VoxelKey> cell_of(const Eigen::Vector3d& p_m) const {
    if (!p_m.allFinite()) return std::nullopt;
    int k[3];
    for (int a = 0; a < 3; ++a) {
      const double scaled = std::floor(inverse_resolution_ * p_m[a]);
      if (!(scaled >= -32768.0 && scaled < 32768.0)) return std::nullopt;
      k[a] = int(scaled) + 32768;
    }
    const VoxelKey key{std::uint16_t(k[0]), std::uint16_t(k[1]), std::uint16_t(k[2])};
    if (!contains(key)) return std::nullopt;
    return key;
  }
  /// Precondition: contains(k).
  VoxelState state(const VoxelKey& k) const { return VoxelState(states_[index(k)]); }
  VoxelState state_at(std::size_t index) const { return VoxelState(states_[index]); }
  /// Changes one cell's state in this copy (the map is not touched).
  void set_state_at(std::size_t index, VoxelState state) { states_[index] = std::uint8_t(state); }
  Eigen::Vector3d center_of(const VoxelKey& k) const {
    return {(double(k.x) - 32768 + 0.5) * resolution_m_, (double(k.y) - 32768 + 0.5) * resolution_m_,
            (double(k.z) - 32768 + 0.5) * resolution_m_};
  }

  /// Walks the cells along a ray from `origin_m` (Amanatides–Woo, the same stepping as
  /// OccupancyMap::cast_ray), calling visit(index, state) for each cell from the origin's
  /// on; stops when visit returns false (outcome Hit or Unknown, by the state), at
  /// `max_range_m` (MaxRange) or at the edge of the box (OutOfBounds).
  template <typename Visit>
  RayOutcome walk(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& direction, double max_range_m,
                  Visit&& visit) const {
    return walk_cells(states_.data(), origin_m, direction, max_range_m,
                      [&](std::size_t i, std::uint8_t cell) { return visit(i, VoxelState(cell)); });
  }
  /// The same walk over `cells`, an array laid out like the grid whose low two bits are the
  /// VoxelState (the outcome reads them) and whose other bits the caller keeps its own flags
  /// in: visit(index, cell byte). One load per cell where state and flags sit in one array.
  template <typename Visit>
  RayOutcome walk_cells(const std::uint8_t* cells, const Eigen::Vector3d& origin_m, const Eigen::Vector3d& direction,
                        double max_range_m, Visit&& visit) const;
  /// walk_cells from `origin_m` in cell `k` (contains(k); the cell walk_cells would find)
  /// along a unit direction `d`, the same walk step for step. Algorithm 1 (rays from a
  /// frontier cell) and the field-of-view scorer (rays from a pose) know the origin's cell
  /// and have the unit direction for their box tests: this skips the cell look-up and the
  /// second normalisation, per ray.
  template <typename Visit>
  RayOutcome walk_unit(const std::uint8_t* cells, const VoxelKey& k, const Eigen::Vector3d& origin_m,
                       const Eigen::Vector3d& d, double max_range_m, Visit&& visit) const;
  /// The raw states (a VoxelState per byte), in index order.
  const std::uint8_t* states() const { return states_.data(); }

 private:
  double resolution_m_;
  double inverse_resolution_;  ///< OctoMap's resolution_factor (1 / resolution), for cell_of
  VoxelKey min_;
  Eigen::Vector3i size_ = Eigen::Vector3i::Zero();
  core::LargeVector<std::uint8_t> states_;
};

/// Per grid cell, the squared distance in cells to the centre of the nearest cell in `state`
/// within the grid (an exact Euclidean distance transform, Felzenszwalb & Huttenlocher 2012,
/// three separable passes); +infinity when the grid holds no such cell. The lines of each
/// pass are split over `threads` threads (0: all cores); the result does not depend on it.
/// Distances above `max_sq` come out as +infinity: a pass drops every value above it, which
/// no later pass can bring back under it, so what stays is exact and the later passes skip
/// the dropped cells (a clearance check needs a few cells, not the whole range).
core::LargeVector<float> squared_distance_to(const DenseGrid& grid, VoxelState state, unsigned threads = 0,
                                             float max_sq = INFINITY);

template <typename Visit>
RayOutcome DenseGrid::walk_cells(const std::uint8_t* cells, const Eigen::Vector3d& origin_m,
                                 const Eigen::Vector3d& direction, double max_range_m, Visit&& visit) const {
  // Cell of the origin on the map's key grid (as OctoMap: floor(coordinate / R) + 32768).
  int cell[3];
  for (int a = 0; a < 3; ++a) cell[a] = int(std::floor(origin_m[a] * (1.0 / resolution_m_))) + 32768;
  const int lo[3] = {min_.x, min_.y, min_.z};
  for (int a = 0; a < 3; ++a)
    if (cell[a] < lo[a] || cell[a] - lo[a] >= size_[a]) return RayOutcome::OutOfBounds;
  const VoxelKey k{std::uint16_t(cell[0]), std::uint16_t(cell[1]), std::uint16_t(cell[2])};
  return walk_unit(cells, k, origin_m, direction.normalized(), max_range_m, visit);
}

template <typename Visit>
RayOutcome DenseGrid::walk_unit(const std::uint8_t* cells, const VoxelKey& k, const Eigen::Vector3d& origin_m,
                                const Eigen::Vector3d& d, double max_range_m, Visit&& visit) const {
  const double R = resolution_m_;
  const int cell[3] = {k.x, k.y, k.z};
  const int lo[3] = {min_.x, min_.y, min_.z};
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
  // Steps left along each axis before the ray leaves the box; the walk state in scalars, so
  // that it stays in registers (arrays indexed by the axis went through memory every cell).
  std::int64_t left[3];
  for (int a = 0; a < 3; ++a)
    left[a] = step[a] > 0 ? size_[a] - 1 - (cell[a] - lo[a]) : step[a] < 0 ? cell[a] - lo[a] : INT64_MAX;
  double tx = t_max[0], ty = t_max[1], tz = t_max[2];
  std::int64_t left_x = left[0], left_y = left[1], left_z = left[2];
  const std::int64_t sx = step[0] * stride[0], sy = step[1] * stride[1], sz = step[2] * stride[2];
  while (true) {
    const std::uint8_t byte = cells[std::size_t(index)];
    if (!visit(std::size_t(index), byte))
      return VoxelState(byte & 3) == VoxelState::Occupied ? RayOutcome::Hit : RayOutcome::Unknown;

    if (tx < ty) {
      if (tx < tz) {
        if (tx > max_range_m) return RayOutcome::MaxRange;
        if (left_x-- == 0) return RayOutcome::OutOfBounds;
        index += sx;
        tx += t_delta[0];
        continue;
      }
    } else if (ty < tz) {
      if (ty > max_range_m) return RayOutcome::MaxRange;
      if (left_y-- == 0) return RayOutcome::OutOfBounds;
      index += sy;
      ty += t_delta[1];
      continue;
    }
    if (tz > max_range_m) return RayOutcome::MaxRange;
    if (left_z-- == 0) return RayOutcome::OutOfBounds;
    index += sz;
    tz += t_delta[2];
  }
}

}  // namespace fvx::map
