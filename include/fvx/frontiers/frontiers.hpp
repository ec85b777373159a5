#pragma once
/// \file
/// Stage `frontiers` (paper §IV-A): free cells with at least one unknown face-neighbour
/// (6-connectivity; ARCHITECTURE.md §3), maintained incrementally from the map's change sets,
/// and their clusters (union-find over 26-connected frontier cells).
///
/// The set holds every frontier cell of the map; the search space S filters at query time,
/// so a search space that grows with the map (the default: the box of the known cells) does
/// not invalidate the incremental state.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "fvx/map/dense_grid.hpp"
#include "fvx/map/key_index.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::frontiers {

using map::pack;  // keys packed for hashing (map/key_index.hpp)
using map::unpack;

/// True when `key` is free and has an unknown face-neighbour (the definition, cell by cell).
bool is_frontier(const map::OccupancyMap& map, const map::VoxelKey& key);

/// The frontier cells of `grid`, in key order, from scratch: what FrontierSet::rebuild finds
/// when the grid holds every known cell of the map (a neighbour beyond the grid is then
/// unknown). One pass over a flat array instead of octree searches.
std::vector<map::VoxelKey> frontier_cells(const map::DenseGrid& grid);

class FrontierSet {
 public:
  /// All frontier cells of `map`, from scratch. A pruned free leaf contributes only cells on
  /// its surface: inside it every neighbour is free.
  void rebuild(const map::OccupancyMap& map);
  /// After `map` integrated a scan with these changes: re-examines each changed cell and its
  /// six face-neighbours, the only cells whose status a change can alter. `changes` in key
  /// order, as OccupancyMap::integrate returns them.
  void update(const map::OccupancyMap& map, const std::vector<map::Change>& changes);

  std::size_t size() const { return cells_.size(); }
  bool contains(const map::VoxelKey& key) const;
  /// The frontier cells whose centres lie in `bounds_m` (all when empty), in key order.
  std::vector<map::VoxelKey> cells(const map::OccupancyMap& map,
                                   const std::optional<Eigen::AlignedBox3d>& bounds_m = std::nullopt) const;

 private:
  std::vector<map::VoxelKey> cells_;  ///< in key order
};

struct Cluster {
  int id = 0;                        ///< 0, 1, … in order of each cluster's smallest key
  std::vector<map::VoxelKey> cells;  ///< in key order
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d bounds_m;      ///< of the cells' extents
};

/// Clusters of `cells` (key order) by union-find over 26-connectivity. Deterministic: the
/// same cells give the same clusters with the same ids.
std::vector<Cluster> cluster(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells);

}  // namespace fvx::frontiers
