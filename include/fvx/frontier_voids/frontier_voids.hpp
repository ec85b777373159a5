#pragma once
/// \file
/// Stage `frontier_voids` (paper §IV-B): each void cluster paired with the frontier clusters
/// that touch it — a frontier cell face- or edge-adjacent (18-neighbourhood) to one of the
/// void's cells — with utility u_i = N_i·R³, the void's volume. A void no frontier touches is
/// enclosed: nothing can be seen into it yet.
#include <optional>
#include <string>
#include <vector>

#include "fvx/frontiers/frontiers.hpp"
#include "fvx/voids/clusters.hpp"
#include "fvx/voids/voids.hpp"

namespace fvx::frontier_voids {

struct FrontierVoid {
  int void_id = 0;
  std::vector<int> frontier_ids;  ///< ascending
  double utility_m3 = 0;          ///< u_i = N_i·R³
  bool enclosed() const { return frontier_ids.empty(); }
};

/// One entry per void cluster, in void id order.
std::vector<FrontierVoid> pair_frontier_voids(const std::vector<voids::VoidCluster>& voids,
                                              const std::vector<frontiers::Cluster>& frontier_clusters);

/// Everything §IV-A/B computes from a map, within the search space S.
struct Analysis {
  Eigen::AlignedBox3d bounds_m;                       ///< S
  std::vector<map::VoxelKey> frontier_cells;          ///< in S, key order
  std::vector<frontiers::Cluster> frontier_clusters;
  std::vector<map::VoxelKey> void_cells;              ///< in S, key order
  /// Void cells left out of void_cells: in no all-void cube of min_void_width_cells (they
  /// cannot hide a target that size; voids/width.hpp). 0 when the width is 1.
  std::size_t thin_void_cells = 0;
  std::vector<voids::VoidCluster> void_clusters;
  std::vector<FrontierVoid> frontier_voids;           ///< one per void cluster
  std::size_t hull_faces = 0;                         ///< planes of the hull the voids lie in
  voids::Hull hull;                                   ///< that hull (empty without voids)
  std::vector<std::string> warnings;                  ///< why a result is empty
};

/// Clusters and pairs the current frontier and void sets within `bounds_m` (default: the
/// box of the map's known cells); without a void set (nullptr), frontiers only. Empty
/// results come with a warning saying why (no free cells, no occupied cells, a flat hull,
/// bounds without known cells). `min_void_width_cells` > 1 keeps only the void cells that
/// could hide a target that wide (voids::cells_in_full_cubes); 1 is the paper's void set.
Analysis analyse(const map::OccupancyMap& map, const frontiers::FrontierSet& frontier_set,
                 const voids::VoidSet* void_set, const std::optional<Eigen::AlignedBox3d>& bounds_m,
                 const voids::ClusterConfig& config, int min_void_width_cells = 1);

/// The same analysis from scratch, with no incremental state to keep: frontier and void cells
/// from one dense grid over the map's known cells (frontiers::frontier_cells,
/// voids::void_cells). Equal to analyse() with freshly rebuilt sets, and several times faster
/// on a real map — the path of the one-shot commands (`fvx frontiers`, `voids`, `nbv`).
/// `with_voids` false: frontiers only, as analyse() without a void set. With `bounds_m` the
/// grid covers only the known cells in and next to it (the hull still comes from every
/// occupied cell, voids::hull_of_map), so a small search space of a large map stays cheap.
/// A grid of more than 2^28 cells (a few cells far apart) goes through the sets instead.
/// `hull_in_bounds`: the voids' hull from the occupied cells in bounds_m only
/// (VoidSet::rebuild's hull_box_m), as `fvx explore` and `replay` keep it.
Analysis analyse_map(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& bounds_m,
                     const voids::ClusterConfig& config, int min_void_width_cells = 1, bool with_voids = true,
                     bool hull_in_bounds = false);

/// Utility in dm³ (1 dm³ = 10⁻³ m³): the unit of the paper's tables.
inline double to_dm3(double m3) { return m3 * 1000.0; }

}  // namespace fvx::frontier_voids
