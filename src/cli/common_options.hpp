#pragma once
// Options that several commands share. Those of a library config are declared beside it
// (io/camera_options.hpp, pipeline/options.hpp, nbv/loaded_arm.hpp) and named here; the
// rest belong to the command line.
#include <string>
#include <vector>

#include "fvx/io/camera_options.hpp"
#include "fvx/nbv/loaded_arm.hpp"
#include "fvx/pipeline/options.hpp"
#include "fvx/sim/scene.hpp"
#include "options.hpp"
#include "report.hpp"

namespace fvx::cli {

using fvx::kMaxInt;
using fvx::options;
using fvx::seed_option;
using fvx::threads_option;
using io::depth_camera_options;
using io::intrinsics_options;
using io::parse_depth_camera;
using io::parse_intrinsics;
using nbv::arm_options;
using nbv::check_arm_options;
using nbv::load_arm_inputs;
using pipeline::accumulation_options;
using pipeline::kDefaultResolution_m;
using pipeline::max_time_diff_option;
using pipeline::trajectory_options;
using pipeline::bag_options;
using pipeline::bag_inputs_json;
using pipeline::read_bag_options;
using pipeline::read_trajectory_options;
using pipeline::min_fit_score_option;
using pipeline::near_voids_options;
using pipeline::parse_accumulation;
using pipeline::parse_near_voids;
using pipeline::parse_resolution;
using pipeline::parse_target_size;
using pipeline::parse_void_hull;
using pipeline::resolution_option;
using pipeline::search_model_options;
using pipeline::target_size_options;
using pipeline::void_hull_option;

/// What arm_options() loaded (nbv::load_arm); `reach` points into it, so keep it alive
/// while using reach.
using ArmInputs = nbv::LoadedArm;
/// report::arm_json with the paths given as --capmap and --arm.
Json capmap_json(const Args& args, const ArmInputs& in);

/// --timing, --progress and --help of the session commands (explore, replay).
std::vector<OptionSpec> session_report_options();

/// --noise none|kinect: the virtual Kinect's depth noise coefficient (σ = k·z², metres):
/// 0, or 1.4e-3 (Khoshelham & Elberink 2012). UsageError for another model.
double parse_depth_noise(const Args& args);

/// The planner: --strategy NAME, or its alias --planner (explore's and replay's name before
/// one name served every command); `fallback` when neither is given.
nbv::Strategy parse_strategy_option(const Args& args, const std::string& command, nbv::Strategy fallback);

/// sim::scene_from with --scene-info.
sim::Scene scene_from(const std::string& source, const Args& args);

}  // namespace fvx::cli
