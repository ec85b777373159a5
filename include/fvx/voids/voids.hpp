#pragma once
/// \file
/// Stage `voids` (paper §IV-B): void cells are the unknown cells inside the convex hull of
/// the map's occupied cell centres (ARCHITECTURE.md §3: a .bt alone is enough), maintained
/// incrementally. The hull is that of the cells occupied now, so the incremental set equals
/// a from-scratch computation exactly; it grows with each scan in practice.
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <unordered_set>
#include <vector>

#include "fvx/map/dense_grid.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::voids {

/// The convex hull as half-spaces n·p + d <= 0 (outward unit normals n), or none when the
/// points span no volume (fewer than four, or all in a plane).
struct Hull {
  std::vector<Eigen::Vector4d> planes;     ///< (n, d)
  std::vector<Eigen::Vector3d> vertices;   ///< the extreme points
  Eigen::AlignedBox3d bounds_m;
  bool empty() const { return planes.empty(); }
  /// Inside or on the hull, within 1 µm.
  bool contains(const Eigen::Vector3d& p) const;
  /// The z-range of the hull along the vertical line through (x, y), if it meets the hull.
  std::optional<std::pair<double, double>> z_range(double x, double y) const;
};

/// The hull of `points` (CGAL's convex_hull_3).
Hull convex_hull(const std::vector<Eigen::Vector3d>& points);

/// Per cell of `grid`: 1 when its centre lies inside `hull` (the test void_cells applies).
core::LargeVector<std::uint8_t> inside_hull(const map::DenseGrid& grid, const Hull& hull);

/// The void cells of `grid` (unknown cells inside the hull of its occupied cell centres), in
/// key order, from scratch, and that hull: what VoidSet::rebuild finds when the grid holds
/// every known cell of the map. The hull is built from each column's lowest and highest
/// occupied cell only (the others lie between them), and the cells are read from the flat
/// array, not the octree. With `hull_box_m`, only occupied cells whose centres lie in it
/// build the hull (VoidSet::rebuild's hull_box_m).
std::vector<map::VoxelKey> void_cells(const map::DenseGrid& grid, Hull& hull,
                                      const std::optional<Eigen::AlignedBox3d>& hull_box_m = std::nullopt);

/// The hull void_cells finds on a grid over every known cell of `map`, read from the map's
/// occupied leaves instead (each column's lowest and highest occupied cell, in the same
/// order): the hull for a grid that covers only the search space of a large map.
Hull hull_of_map(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& hull_box_m = std::nullopt);

/// The void cells of `grid` inside `hull`, in key order.
std::vector<map::VoxelKey> void_cells_in(const map::DenseGrid& grid, const Hull& hull);

class VoidSet {
 public:
  VoidSet();
  ~VoidSet();
  VoidSet(VoidSet&&) noexcept;
  VoidSet& operator=(VoidSet&&) noexcept;

  /// All void cells of `map`, from scratch. With `hull_box_m`, the hull is that of the
  /// occupied cells whose centres lie in the box (the search space: surfaces outside it, a
  /// room's walls, do not make the air inside it a void); update() keeps the box.
  void rebuild(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& hull_box_m = std::nullopt);
  /// After `map` integrated a scan with these changes: cells that became known leave; when
  /// the occupied cells change the hull, only the cells between the old and the new hull,
  /// column by column, are examined.
  void update(const map::OccupancyMap& map, const std::vector<map::Change>& changes);

  const Hull& hull() const;
  std::size_t size() const;
  bool contains(const map::VoxelKey& key) const;
  /// The void cells whose centres lie in `bounds_m` (all when empty), in key order.
  std::vector<map::VoxelKey> cells(const map::OccupancyMap& map,
                                   const std::optional<Eigen::AlignedBox3d>& bounds_m = std::nullopt) const;

  struct State;

 private:
  std::unique_ptr<State> state_;
};

}  // namespace fvx::voids
