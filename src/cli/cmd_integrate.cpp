// fvx integrate — recorded scans with pose priors → registered → an OctoMap (paper §IV
// steps 1–3). Parse, validate, call the library, report; nothing else.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include "command_table.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/registration/registration.hpp"
#include "fvx/scan/load.hpp"
#include "common_options.hpp"
#include "report.hpp"

namespace fvx::cli {

const CommandSpec kIntegrateSpec = {
    "integrate",
    "-o MAP.bt|MAP.ot [options] SCAN...",
    "integrate recorded scans (PCD, PLY, depth images) into an OctoMap",
    options({{
        {"output", 'o', "FILE", "map to write, .bt or .ot (required; written atomically)", "-"},
        {"map", 0, "FILE", "start from this map (.bt/.ot) instead of an empty one", "/inputs/map"},
        {"report", 0, "FILE", "write the JSON report to FILE instead of stdout", "-"},
        {"resolution", 'r', "M", "cell edge of a new map, metres (default 0.025, the paper's)", "/config/resolution_m"},
        {"max-range", 0, "M", "cut rays longer than this, metres; their ends are not marked "
                              "occupied (default: no limit)", "/config/max_range_m"},
        {"depth-min", 0, "M", "drop points closer than this along the optical axis, metres (default 0)",
         "/config/filter/depth_min_m"},
        {"depth-max", 0, "M", "drop points at or beyond this depth, metres (default: no limit)",
         "/config/filter/depth_max_m"},
        {"downsample", 0, "M", "voxel-downsample each scan with this edge, metres (default 0: off)",
         "/config/filter/voxel_m"},
        {"pose", 0, "x,y,z,qx,qy,qz,qw", "pose prior T_world_sensor for every scan (metres, "
                                         "quaternion scalar-last)", "/config/pose"},
        {"trajectory", 't', "FILE", "pose priors from a TUM (stamp tx ty tz qx qy qz qw, or "
                                    "without stamp) or Redwood .log file", "/inputs/trajectory"},
        {"max-time-diff", 0, "S", "largest stamp difference when matching by timestamp, "
                                  "seconds (default 0.02)", "/config/max_time_diff_s"},
        {"ignore-viewpoint", 0, nullptr, "do not use the PCD VIEWPOINT as pose (legacy OpenNI "
                                         "captures)", "/config/use_viewpoint"},
    }, intrinsics_options(false, "/config/intrinsics"), {
        {"register", 0, nullptr, "align each scan to the map before integrating it (default)",
         "/config/register_scans"},
        {"no-register", 0, nullptr, "integrate scans at their pose priors, without registration",
         "/config/register_scans"},
        {"reg-method", 0, "NAME", "registration method: gicp (default) or icp", "/config/registration/method"},
        {"reg-voxel", 0, "M", "downsampling voxel for registration, metres (default 0.05)",
         "/config/registration/voxel_m"},
        {"reg-max-corr", 0, "M", "largest correspondence distance of the coarse pass, metres "
                                 "(default 0.3)", "/config/registration/max_correspondence_m"},
        {"reg-fine-corr", 0, "M", "largest correspondence distance of the fine pass, metres "
                                  "(default 0.1)", "/config/registration/fine_correspondence_m"},
        {"reg-max-iter", 0, "N", "iteration cap; reaching it counts as not converged (default 60)",
         "/config/registration/max_iterations"},
        {"timing", 0, nullptr, "add per-stage times (seconds) to the report", "-"},
        {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
        {"help", 'h', nullptr, "show this help", "-"},
    }})};

namespace {

struct Options {
  std::string output_path, map_path, report_path;
  double resolution_m = kDefaultResolution_m;
  double max_range_m = std::numeric_limits<double>::infinity();
  bool resolution_given = false;
  scan::FilterConfig filter;
  scan::LoadConfig load;
  bool do_register = true;
  registration::Config reg;
  bool timing = false, progress = false;
  std::vector<std::string> scans;
};

Options parse(const Args& args) {
  Options o;
  if (!args.has("output")) throw UsageError("fvx integrate: -o/--output MAP.bt|MAP.ot is required");
  o.output_path = args.get("output");
  if (args.has("map")) o.map_path = args.get("map");
  if (args.has("report")) o.report_path = args.get("report");
  const double inf = std::numeric_limits<double>::infinity();
  const double big = 1e6;
  o.resolution_given = args.has("resolution");
  o.resolution_m = parse_resolution(args, kDefaultResolution_m);
  o.max_range_m = args.number("max-range", inf, 0.0, big, true);
  o.filter.depth_min_m = args.number("depth-min", 0.0, 0.0, big);
  o.filter.depth_max_m = args.number("depth-max", inf, 0.0, big, true);
  o.filter.voxel_m = args.number("downsample", 0.0, 0.0, 10.0);
  if (!(o.filter.depth_max_m > o.filter.depth_min_m))
    throw UsageError("fvx integrate: --depth-max must be greater than --depth-min");
  FVX_ASSERT(o.filter.validate().empty(), "filter options were checked above");

  if (args.has("pose") && args.has("trajectory"))
    throw UsageError("fvx integrate: give --pose or --trajectory, not both");
  if (args.has("pose")) o.load.pose = parse_pose(args.get("pose"), "--pose");
  if (args.has("trajectory")) o.load.trajectory_path = args.get("trajectory");
  o.load.max_time_diff_s = args.number("max-time-diff", 0.02, 0.0, big);
  o.load.use_viewpoint = !args.has("ignore-viewpoint");

  o.load.intrinsics = parse_intrinsics(args, "integrate");

  if (args.has("register") && args.has("no-register"))
    throw UsageError("fvx integrate: --register and --no-register contradict each other");
  o.do_register = !args.has("no-register");
  if (args.has("reg-method")) o.reg.method = registration::parse_method(args.get("reg-method"), "--reg-method");
  o.reg.voxel_m = args.number("reg-voxel", o.reg.voxel_m, 0.0, 10.0);
  o.reg.max_correspondence_m = args.number("reg-max-corr", o.reg.max_correspondence_m, 0.0, 100.0, true);
  o.reg.fine_correspondence_m = args.number("reg-fine-corr", o.reg.fine_correspondence_m, 0.0, 100.0, true);
  o.reg.max_iterations = int(args.integer("reg-max-iter", o.reg.max_iterations, 1, 10000));
  o.timing = args.has("timing");
  o.progress = args.has("progress");
  o.scans = args.positional;
  if (o.scans.empty()) throw UsageError("fvx integrate: no scans given (see 'fvx integrate --help')");
  return o;
}

/// The step's settings, then how scans are read and the map's sensor model.
Json config_json(const Options& o, const pipeline::Config& config, const map::OccupancyMap& map) {
  Json c = pipeline::config_json(config);
  c["pose"] = o.load.pose ? pose_json(*o.load.pose) : Json(nullptr);
  c["use_viewpoint"] = o.load.use_viewpoint;
  c["max_time_diff_s"] = o.load.max_time_diff_s;
  c["intrinsics"] = o.load.intrinsics ? io::intrinsics_json(*o.load.intrinsics) : Json(nullptr);
  const map::SensorModel model = map.sensor_model();
  c["sensor_model"] = {{"prob_hit", model.prob_hit},
                       {"prob_miss", model.prob_miss},
                       {"clamp_min", model.clamp_min},
                       {"clamp_max", model.clamp_max},
                       {"occupancy_threshold", model.occupancy_threshold}};
  return c;
}

Json map_json(const map::Stats& s) {
  Json j = {{"resolution_m", s.resolution_m},
            {"nodes", s.nodes},
            {"free_leaves", s.free_leaves},
            {"occupied_leaves", s.occupied_leaves},
            {"free_volume_m3", s.free_volume_m3},
            {"occupied_volume_m3", s.occupied_volume_m3}};
  j["known_bounds_m"] = s.empty ? Json(nullptr)
                                : Json{{"min", vec_json(s.known_min_m)}, {"max", vec_json(s.known_max_m)}};
  return j;
}

Json registration_json(const registration::Result& r) {
  Json j = {{"attempted", true},
            {"converged", r.converged},
            {"iterations", r.iterations},
            {"fitness_rmse_m", r.fitness_rmse_m},
            {"inlier_fraction", r.inlier_fraction},
            {"source_points", r.source_points},
            {"target_points", r.target_points},
            {"correction", {{"translation_m", r.correction_translation_m},
                            {"rotation_deg", r.correction_rotation_deg}}}};
  j["weak_directions"] = r.weak_directions;
  if (!r.fine_start.empty()) j["fine_start"] = r.fine_start;
  if (!r.problem.empty()) j["problem"] = r.problem;
  return j;
}

Json integration_json(const map::IntegrationCounts& c) {
  return {{"changed_cells", c.changed_cells},
          {"became_free", c.became_free},
          {"became_occupied", c.became_occupied},
          {"free_updates", c.free_updates},
          {"occupied_updates", c.occupied_updates},
          {"points_beyond_range", c.points_beyond_range},
          {"points_out_of_map", c.points_out_of_map}};
}

/// Paper §IV steps 1–3 of the pipeline's step: no frontiers, voids or search.
pipeline::Config step_config(const Options& o, double resolution_m) {
  pipeline::Config c;
  c.resolution_m = resolution_m;
  c.filter = o.filter;
  c.max_range_m = o.max_range_m;
  c.register_scans = o.do_register;
  c.registration = o.reg;
  c.analyse = false;
  c.search = false;
  return c;
}

/// Fails before any work if the map cannot be written there, or is not a .bt or .ot name.
void check_output(const std::string& output_path) {
  const auto output_dir = std::filesystem::path(output_path).parent_path();
  if (!output_dir.empty() && !std::filesystem::is_directory(output_dir))
    throw FileError(output_path, "cannot write: folder '" + output_dir.string() + "' does not exist");
  const std::string ext = lowercase_extension(output_path);
  if (ext != ".bt" && ext != ".ot")
    throw UsageError("fvx integrate: --output " + output_path + ": expected a .bt or .ot file name");
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int run_integrate(const Args& args) {
  const Options o = parse(args);

  map::OccupancyMap map = o.map_path.empty() ? map::OccupancyMap(o.resolution_m)
                                             : map::OccupancyMap::load(o.map_path);
  if (!o.map_path.empty() && o.resolution_given && std::abs(map.resolution_m() - o.resolution_m) > 1e-9)
    throw UsageError("fvx integrate: --resolution " + std::to_string(o.resolution_m) +
                     " differs from the resolution of --map " + o.map_path + " (" +
                     std::to_string(map.resolution_m()) + "); leave --resolution out");
  check_output(o.output_path);

  // With --map, registration starts from the map's occupied cell centres (pipeline::State).
  const pipeline::Config config = step_config(o, map.resolution_m());
  Json report = new_report("integrate");
  report["config"] = config_json(o, config, map);
  report["inputs"] = {{"map", o.map_path.empty() ? Json(nullptr) : Json(o.map_path)},
                      {"trajectory", o.load.trajectory_path.empty() ? Json(nullptr) : Json(o.load.trajectory_path)},
                      {"scans", o.scans}};

  scan::ScanPlan plan = scan::plan_scans(o.scans, o.load);
  std::vector<std::string> warnings = plan.warnings;
  report["inputs"]["pose_match"] = scan::to_string(plan.match);

  pipeline::State state(std::move(map), config);

  Progress progress(o.progress);
  Json scans_json = Json::array();
  for (std::size_t i = 0; i < plan.scans.size(); ++i) {
    const auto& source = plan.scans[i];
    progress.update("fvx integrate: scan " + std::to_string(i + 1) + "/" +
                    std::to_string(plan.scans.size()) + " " + source.path);
    const auto t_load = std::chrono::steady_clock::now();
    scan::Scan s = scan::load_scan(source, o.load, warnings);
    const double load_s = seconds_since(t_load);
    const Eigen::Isometry3d prior = s.T_world_sensor;
    const scan::PoseSource pose_source = s.pose_source;
    const pipeline::StepResult r = pipeline::integrate_step(state, std::move(s), config);
    const scan::FilterStats& filtered = r.filtered;
    if (filtered.input == 0) throw Error(source.path + ": the scan holds no points");
    if (filtered.non_finite == filtered.input)
      throw Error(source.path + ": the scan holds no finite points (all NaN)");
    if (filtered.kept == 0)
      throw Error(source.path + ": no point is left after the depth limits (--depth-min/--depth-max)");

    Json entry = {{"file", source.path}, {"pose_source", scan::to_string(pose_source)}};
    entry["points"] = {{"input", filtered.input}, {"non_finite", filtered.non_finite},
                       {"out_of_depth", filtered.out_of_depth}, {"merged", filtered.merged},
                       {"kept", filtered.kept}};
    entry["prior"] = pose_json(prior);
    if (r.registration) {
      entry["registration"] = registration_json(*r.registration);
      if (!r.registration->converged)
        warnings.push_back(source.path + ": registration did not converge (" + r.registration->problem +
                           "); the scan is integrated at its pose prior");
    } else {
      entry["registration"] = {{"attempted", false},
                               {"reason", o.do_register ? "nothing to register to yet (first scan of an empty map)" : "--no-register"}};
    }
    entry["T_world_sensor"] = pose_json(r.T_world_sensor);
    entry["integration"] = integration_json(r.integration);
    if (o.timing)
      entry["timing_s"] = {{"load", load_s}, {"registration", r.timing.registration_s},
                           {"integration", r.timing.integration_s}};
    scans_json.push_back(entry);
  }
  progress.finish();

  state.map.save(o.output_path);
  report["results"] = {{"output", o.output_path}, {"scans", scans_json}, {"map", map_json(state.map.stats())}};
  report["warnings"] = warnings;
  write_report(report, o.report_path);
  return 0;
}

}  // namespace fvx::cli
