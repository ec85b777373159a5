#pragma once
// What `fvx frontiers` and `fvx voids` share: loading a map into the incremental sets, the
// search-space option, and the outputs people look at.
#include <optional>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/io/visual.hpp"
#include "options.hpp"
#include "report.hpp"

namespace fvx::cli {

/// --bounds x0,y0,z0,x1,y1,z1 (metres; or another option of that form), or empty.
std::optional<Eigen::AlignedBox3d> parse_bounds(const Args& args, const std::string& name = "bounds");

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

}  // namespace fvx::cli
