#pragma once
/// \file
/// The options of the step's configs that several commands share, declared next to the
/// configs they set: their table rows (with default and range) and their parsing.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fvx/core/json.hpp"
#include "fvx/core/options.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/scan/load.hpp"

namespace fvx::pipeline {

/// The default cell edge of every command, metres: the paper's 2.5 cm.
inline const double kDefaultResolution_m = Config{}.resolution_m;

/// --resolution M in [0.001, 1] metres, default kDefaultResolution_m then `note`.
OptionSpec resolution_option(const std::string& echo, const char* help, const std::string& note);
/// --bounds x0,y0,z0,x1,y1,z1 (metres; or another option of that form), or empty;
/// UsageError unless the minimum is below the maximum on every axis.
std::optional<Eigen::AlignedBox3d> parse_bounds(const Args& args, const std::string& name = "bounds");
/// `fvx nbv`'s search options: strategy, sensor, rays, sampling, refinement, polish,
/// climb, near voids, view bounds, seed, threads and accumulation (the rest at defaults).
nbv::Config read_search_options(const Args& args);
/// --resolution's value, `fallback` when absent.
double parse_resolution(const Args& args, double fallback);
/// --discretize: Config::discretize (OctoMap's discretised insertion).
OptionSpec discretize_option(const std::string& echo);
/// --max-time-diff S: stamps matched within S seconds (scan::LoadConfig's default).
OptionSpec max_time_diff_option();
/// --trajectory FILE|DIR (for `fvx replay` or `fvx integrate`), --pose-format
/// auto|tum|redwood|kitti (io::PoseFormatChoice) and --max-time-diff.
std::vector<OptionSpec> trajectory_options(bool replay);
/// --trajectory, --pose-format and --max-time-diff into `load`; UsageError for a format
/// without a trajectory.
void read_trajectory_options(const Args& args, scan::LoadConfig& load);
/// --bag FILE, --topic NAME, --fixed-frame NAME, --frame NAME (io::BagQuery).
std::vector<OptionSpec> bag_options();
/// The bag's query when --bag is given (`intrinsics` override CameraInfo); UsageError for
/// --topic without --bag, --bag without --topic or --fixed-frame, or with a trajectory or --pose.
std::optional<io::BagQuery> read_bag_options(const Args& args, const std::optional<io::Intrinsics>& intrinsics);
/// {"bag", "topic", "fixed_frame", "frame"} of the report's inputs (nulls without a bag).
Json bag_inputs_json(const std::optional<io::BagQuery>& query);
/// --min-fit-score S in (0, 1], default voids::ClusterConfig's.
OptionSpec min_fit_score_option(const std::string& echo, const char* help);

/// --far-voids-only and --near-voids (the default of every command; kept for scripts).
std::vector<OptionSpec> near_voids_options(const std::string& echo);
/// nbv::Config::count_near_void_cells from them, `fallback` (a session's) when neither is
/// given; UsageError when both are.
bool parse_near_voids(const Args& args, bool fallback);

/// --target-size M: the searched object's smallest extent, metres; only void cells that
/// could hide it count (voids/width.hpp). 0 (the default): every void cell.
std::vector<OptionSpec> target_size_options(const std::string& echo);
/// The value of --target-size if given, else `fallback`.
double parse_target_size(const Args& args, double fallback);

/// --accumulation exact|sampled and --utility-vectors N (utility/utility.hpp), and
/// --coarse-rays COLSxROWS|off (nbv::Config::coarse_ray_cols): the search's speed settings.
std::vector<OptionSpec> accumulation_options(const std::string& echo);
/// Sets config.accumulation, max_utility_vectors and the coarse fan from them; UsageError
/// when bad.
void parse_accumulation(const Args& args, nbv::Config& config);
/// "COLSxROWS" (each 1 to 4096) as {cols, rows}; UsageError naming `option` otherwise.
std::pair<int, int> parse_cols_rows(const std::string& text, const std::string& option);

/// --void-hull map|search-space (pipeline::Config::hull_in_bounds), echoed at `echo`.
OptionSpec void_hull_option(const std::string& echo);
/// void_hull_option, --unknown-depth N (nbv::Config::unknown_depth_cells) and --near-unknown
/// MODE (nbv::Config::near_unknown): measured alternatives to the paper's void set and U
/// (README, "Exploration over a scene suite").
std::vector<OptionSpec> void_model_options(const std::string& pipeline_echo, const std::string& nbv_echo);
/// --void-hull's value as hull_in_bounds, `fallback` when absent; UsageError when bad.
bool parse_void_hull(const Args& args, bool fallback);
/// --near-unknown's value (nbv::Config::near_unknown), `fallback` when absent; UsageError
/// when bad.
viewpoints::NearUnknown parse_near_unknown(const Args& args, viewpoints::NearUnknown fallback);
/// --exterior's value (nbv::Config::exterior), `fallback` when absent; UsageError when bad.
nbv::Exterior parse_exterior(const Args& args, nbv::Exterior fallback);

/// What the search models, for commands that search: --far-voids-only/--near-voids,
/// --target-size, --accumulation/--utility-vectors and the depth camera; `pipeline_echo` and
/// `nbv_echo` point at the report's pipeline and search configs.
std::vector<OptionSpec> search_model_options(const std::string& pipeline_echo, const std::string& nbv_echo);

}  // namespace fvx::pipeline
