#pragma once
/// \file
/// What `fvx frontiers` and `fvx voids` show of an analysis (frontier_voids::Analysis): its
/// clusters and frontier-voids as JSON, clouds of the cells, the void ellipsoids as a mesh,
/// and a top view; the picture layers other commands draw beneath their own.
#include <string>
#include <vector>

#include "fvx/core/json.hpp"
#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/io/visual.hpp"

namespace fvx::report {

/// `fvx frontiers`' results: the search space, the frontier cells and their clusters.
Json frontiers_results_json(const frontier_voids::Analysis& a);
/// `fvx voids`' results (R: the map's cell edge): the search space, the hull, void cells and
/// clusters, frontier clusters, frontier-voids and the void cells that frontiers touch.
Json voids_results_json(const frontier_voids::Analysis& a, double R);

Json frontier_clusters_json(const std::vector<frontiers::Cluster>& clusters);
Json void_clusters_json(const std::vector<voids::VoidCluster>& clusters);
Json frontier_voids_json(const std::vector<frontier_voids::FrontierVoid>& pairs,
                         const std::vector<voids::VoidCluster>& clusters);

/// Frontier cells red and void cells violet, or one colour per cluster (`by_cluster`).
void write_cells_cloud(const std::string& path, const map::OccupancyMap& map,
                       const frontier_voids::Analysis& a, bool with_voids, bool by_cluster);
/// The void ellipsoids (semi-axes a_j along e_j around μ) as one PLY mesh.
void write_ellipsoids(const std::string& path, const std::vector<voids::VoidCluster>& clusters);
/// The colours every picture and cloud of cells uses.
inline const io::Rgb kFrontierRed = {220, 30, 30};
inline const io::Rgb kVoidViolet = {140, 60, 200};
inline const io::Rgb kOccupiedGrey = {150, 150, 150};

/// Picture layers: the occupied cells within `bounds_m`, shaded by height; the void cells.
io::PictureLayer occupied_layer(const map::OccupancyMap& map, const Eigen::AlignedBox3d& bounds_m);
io::PictureLayer void_layer(const map::OccupancyMap& map, const frontier_voids::Analysis& a);

/// Occupied cells grey, frontier cells red, void cells violet, seen from above.
void write_picture(const std::string& path, const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                   bool with_voids);

}  // namespace fvx::report
