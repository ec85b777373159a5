#pragma once
/// \file
/// Voxel ground truth of a scene, on the map's grid (cell k covers [k·R, (k+1)·R) on each
/// axis, as OctoMap keys do): which cells hold material (solid) and which are empty (free),
/// so that maps and explorations can be scored cell by cell.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "fvx/map/occupancy_map.hpp"
#include "fvx/sim/mesh.hpp"
#include "fvx/sim/ray_caster.hpp"

namespace fvx::sim {

class GroundTruth {
 public:
  /// A cell is solid if the mesh surface passes through it (triangles sampled every R/4, so
  /// walls thinner than a cell count) or its centre lies inside a closed part of the mesh
  /// (odd number of crossings along +x); otherwise free. Cells are those whose centres lie
  /// in `region`. Assumes closed solids do not overlap (their crossings would cancel).
  GroundTruth(const Mesh& mesh, const RayCaster& caster, double resolution_m,
              const Eigen::AlignedBox3d& region);

  double resolution_m() const { return resolution_m_; }
  /// Integer cell of a point: floor(p / R) per axis (the map key minus 32768).
  Eigen::Vector3i cell_of(const Eigen::Vector3d& p_world) const;
  Eigen::Vector3d center_of(const Eigen::Vector3i& cell) const;
  bool contains(const Eigen::Vector3i& cell) const;
  /// Precondition: contains(cell).
  bool solid(const Eigen::Vector3i& cell) const;

  const Eigen::Vector3i& first_cell() const { return first_; }
  const Eigen::Vector3i& size() const { return size_; }
  std::size_t solid_cells() const { return solid_count_; }
  std::size_t free_cells() const { return solid_.size() - solid_count_; }
  /// Free cells whose centres lie in `box`, times R³.
  double free_volume_m3(const Eigen::AlignedBox3d& box) const;

  /// Of `keys` (cells of a map with this resolution), those solid here: predicted void
  /// cells that no scan can reveal as free. Keys outside the region do not count.
  std::size_t solid_among(const std::vector<map::VoxelKey>& keys) const;
  /// Cells whose centres lie in `box` that are solid here but free in `map` (same
  /// resolution): a surface seen only edge-on, whose cell the rays through its empty part
  /// cleared. Behind such a cell the map shows a solid's unknown inside as open to view.
  std::size_t free_in_solid(const map::OccupancyMap& map, const Eigen::AlignedBox3d& box) const;

  /// The ground truth as a map: solid cells occupied, free cells free (both at the clamping
  /// bounds), everything else unknown. Open it in octovis, or compare it with a built map.
  map::OccupancyMap to_map() const;

 private:
  std::size_t index(const Eigen::Vector3i& cell) const;
  double resolution_m_;
  Eigen::Vector3i first_, size_;
  std::vector<std::uint8_t> solid_;
  std::size_t solid_count_ = 0;
};

/// The box an exploration's ground truth covers: the search space `S` grown by 0.25 m (so the
/// air around the containers reaches its border) and every place the sensor can be
/// (`sensor_positions_m`: rays of the observability check start there), within S grown by 2 m.
Eigen::AlignedBox3d exploration_region(const Eigen::AlignedBox3d& S,
                                       const std::vector<Eigen::Vector3d>& sensor_positions_m);

}  // namespace fvx::sim
