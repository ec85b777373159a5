#pragma once
// Options that several commands share, declared once: their table rows, their parsing and
// their report form.
#include <optional>
#include <vector>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/sim/scene.hpp"
#include "options.hpp"
#include "report.hpp"

namespace fvx::cli {

/// Concatenates option tables.
std::vector<OptionSpec> options(std::initializer_list<std::vector<OptionSpec>> tables);

/// --intrinsics, --fx, --fy, --cx, --cy, --depth-scale; with `with_size` also --width and
/// --height (for commands that render images). `echo`: the report's pointer to the
/// intrinsics object (the option groups below take their config object's pointer).
std::vector<OptionSpec> intrinsics_options(bool with_size, const std::string& echo);

/// The intrinsics the user gave (file, then flags on top), or empty when none was given.
/// Throws UsageError naming `command` when the result is invalid.
std::optional<io::Intrinsics> parse_intrinsics(const Args& args, const std::string& command);


/// --sensor FILE, --depth-min, --depth-max and the intrinsics options with the image size:
/// a depth camera for planning.
std::vector<OptionSpec> depth_camera_options(const std::string& echo);
/// The sensor file (default Kinect v1), then the flags on top. UsageError when invalid.
io::DepthCamera parse_depth_camera(const Args& args, const std::string& command);

/// --capmap, --base, --no-capmap, --arm: where the arm stands and what it reaches.
std::vector<OptionSpec> arm_options();
/// What arm_options() loaded; `reach` points into it, so keep it alive while using reach.
struct ArmInputs {
  std::optional<capmap::CapabilityMap> capability_map;
  std::optional<capmap::Arm> arm;
  std::optional<nbv::Reach> reach;  ///< empty with --no-capmap
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
};
/// UsageError unless exactly one of --capmap and --no-capmap is given (--base and --arm
/// only with --capmap). Cheap: call it before reading other inputs.
void check_arm_options(const Args& args, const std::string& command);
/// check_arm_options(), then loads the map
/// and the arm (FileError; Error when the URDF is not the one the map was built from).
/// Call it before any long work.
void load_arm_inputs(const Args& args, const std::string& command, ArmInputs& out);
/// The capability map as loaded (file, links, hash, voxel, directions), where its base stands
/// and the URDF; null without one.
Json capmap_json(const std::string& path, const std::string& urdf_path, const ArmInputs& in);
/// The same with the paths given as --capmap and --arm.
Json capmap_json(const Args& args, const ArmInputs& in);
/// The same from paths (a session's manifest): the capability map, the URDF (may be empty)
/// and the base pose. FileError, or Error when the URDF is not the map's.
void load_arm_files(const std::string& capmap_path, const std::string& urdf_path,
                    const Eigen::Isometry3d& T_world_base, const std::string& command, ArmInputs& out);

/// --noise none|kinect: the virtual Kinect's depth noise coefficient (σ = k·z², metres):
/// 0, or 1.4e-3 (Khoshelham & Elberink 2012). UsageError for another model.
double parse_depth_noise(const Args& args);

/// --resolution M, metres in [0.001, 1]; `fallback` when absent. One range and, through
/// kDefaultResolution_m, one default for every command.
double parse_resolution(const Args& args, double fallback);
inline const double kDefaultResolution_m = pipeline::Config{}.resolution_m;  ///< the paper's 2.5 cm

/// --far-voids-only and --near-voids (the default of every command; kept for scripts).
std::vector<OptionSpec> near_voids_options(const std::string& echo);
/// nbv::Config::count_near_void_cells from them, `fallback` (a session's) when neither is
/// given; UsageError when both are.
bool parse_near_voids(const Args& args, bool fallback);

/// What the search models, for commands that search: --far-voids-only/--near-voids,
/// --target-size, --accumulation/--utility-vectors and the depth camera; `pipeline_echo` and
/// `nbv_echo` point at the report's pipeline and search configs.
std::vector<OptionSpec> search_model_options(const std::string& pipeline_echo, const std::string& nbv_echo);

/// --timing, --progress and --help of the session commands (explore, replay).
std::vector<OptionSpec> session_report_options();

/// --target-size M: the searched object's smallest extent, metres; only void cells that
/// could hide it count (voids/width.hpp). 0 (the default): every void cell.
std::vector<OptionSpec> target_size_options(const std::string& echo);
/// --accumulation exact|sampled and --utility-vectors N (utility/utility.hpp).
/// The planner: --strategy NAME, or its alias --planner (explore's and replay's name before
/// one name served every command); `fallback` when neither is given.
nbv::Strategy parse_strategy_option(const Args& args, const std::string& command, nbv::Strategy fallback);

std::vector<OptionSpec> accumulation_options(const std::string& echo);
/// Sets config.accumulation and config.max_utility_vectors from them; UsageError when bad.
void parse_accumulation(const Args& args, nbv::Config& config);
/// The value of --target-size if given, else `fallback`; UsageError outside [0, 10] m.
double parse_target_size(const Args& args, double fallback);

/// "ex,ey,ez,tx,ty,tz": a sensor at eye E looking at target T, world z up (optical frame:
/// x right, y down). UsageError naming `what`.
Eigen::Isometry3d parse_look_at(const std::string& text, const std::string& what);

/// A scene argument: a mesh file (with its sidecar, or --scene-info) or builtin:NAME.
sim::Scene scene_from(const std::string& source, const Args& args);

}  // namespace fvx::cli
