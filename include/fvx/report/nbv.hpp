#pragma once
/// \file
/// What `fvx nbv` shows of a search (nbv::Result), and what `fvx explore` and `fvx replay`
/// write for each view: the ranked views as JSON, the search's effective settings, and the
/// utility field as a cloud and a top view (the paper's Figure 4 colours).
#include <optional>
#include <string>
#include <vector>

#include "fvx/core/json.hpp"
#include "fvx/io/visual.hpp"
#include "fvx/nbv/loaded_arm.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/voids/clusters.hpp"

namespace fvx::report {

/// bounds, void and frontier counts, the pruning counts, the ranked views (R: the map's cell
/// edge, for dm³; joint names of the arm, or empty) and, with `timing`, the time split.
Json nbv_results_json(const nbv::Result& r, const frontier_voids::Analysis& a, double R,
                      const std::vector<std::string>& joint_names, nbv::Strategy strategy, bool timing);

/// The effective settings of `fvx nbv`: the search's, then the analysis's and where the arm
/// stands (null: free-flying).
Json search_config_json(const nbv::Config& config, double target_size_m, int void_width, bool hull_in_bounds,
                        const std::optional<Eigen::AlignedBox3d>& bounds, const voids::ClusterConfig& cluster_config,
                        const std::optional<Eigen::Isometry3d>& T_world_base);

/// The capability map as loaded (file, links, hash, voxel, directions), where its base stands
/// and the URDF (`urdf_path`, may be empty); null without one.
Json arm_json(const std::string& path, const std::string& urdf_path, const nbv::LoadedArm& in);

/// The utility colour of a rank in [0, 1]: red (low), yellow, green (high), as the paper's
/// Figure 4.
io::Rgb ramp(double rank);
/// Each field cell's utility as its rank among the kept cells, in [0, 1] (utility spans
/// orders of magnitude, so a linear scale would paint nearly all of it "low").
std::vector<double> utility_ranks(const nbv::Result& r);

/// The utility field (Result::utility_field) as a coloured cloud, .ply or .pcd: red (low),
/// yellow, green (high) by rank among the kept cells; pruned cells grey.
void write_utility_cloud(const std::string& path, const nbv::Result& r);
/// A top view of the occupied cells, the voids, the utility field in thirds and the best view.
void write_utility_picture(const std::string& path, const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                           const nbv::Result& r);

}  // namespace fvx::report
