// fvx integrate — recorded scans with pose priors → registered → an OctoMap (paper §IV
// steps 1–3). Parse, validate, call the library, report; nothing else.
#include <cmath>
#include <filesystem>
#include <limits>

#include "command_table.hpp"
#include "fvx/core/atomic_file.hpp"  // lowercase_extension
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/pipeline/integrate_files.hpp"
#include "fvx/registration/registration.hpp"
#include "fvx/report/integrate.hpp"
#include "common_options.hpp"
#include "report.hpp"

namespace fvx::cli {

namespace {
const scan::FilterConfig kFilter;  ///< the defaults --help shows
const registration::Config kReg;
}  // namespace

const CommandSpec kIntegrateSpec = {
    "integrate",
    "-o MAP.bt|MAP.ot [options] SCAN... | --bag FILE --topic T --fixed-frame F",
    "integrate recorded scans (PCD, PLY, depth images) into an OctoMap",
    options({{
        {"output", 'o', "FILE", "map to write, .bt or .ot (required; written atomically)", "-"},
        {"map", 0, "FILE", "start from this map (.bt/.ot) instead of an empty one", "/inputs/map"},
        {"report", 0, "FILE", "write the JSON report to FILE instead of stdout", "-"},
        resolution_option("/config/resolution_m", "cell edge of a new map, metres", ", the paper's"),
        {"max-range", 0, "M", "cut rays longer than this, metres; their ends are not marked "
                              "occupied (default: no limit)", "/config/max_range_m", "", above(0, 1e6)},
        pipeline::discretize_option("/config/discretize"),
        {"depth-min", 0, "M", "drop points closer than this along the optical axis, metres",
         "/config/filter/depth_min_m", dflt(kFilter.depth_min_m), in(0, 1e6)},
        {"depth-max", 0, "M", "drop points at or beyond this depth, metres (default: no limit)",
         "/config/filter/depth_max_m", "", above(0, 1e6)},
        {"downsample", 0, "M", "voxel-downsample each scan with this edge, metres", "/config/filter/voxel_m",
         dflt(kFilter.voxel_m) + ": off", in(0, 10)},
        {"pose", 0, "x,y,z,qx,qy,qz,qw", "pose prior T_world_sensor for every scan (metres, "
                                         "quaternion scalar-last)", "/config/pose"},
        {"ignore-viewpoint", 0, nullptr, "do not use the PCD VIEWPOINT as pose (legacy OpenNI "
                                         "captures): without a trajectory the points are in the world frame",
         "/config/use_viewpoint"},
    }, trajectory_options(false), bag_options(), intrinsics_options(false, "/config/intrinsics"), {
        {"register", 0, nullptr, "align each scan to the map before integrating it (default)",
         "/config/register_scans"},
        {"no-register", 0, nullptr, "integrate scans at their pose priors, without registration",
         "/config/register_scans"},
        {"reg-method", 0, "NAME", "registration method: gicp (default) or icp", "/config/registration/method"},
        {"reg-voxel", 0, "M", "downsampling voxel for registration, metres", "/config/registration/voxel_m",
         dflt(kReg.voxel_m), in(0, 10)},
        {"reg-max-corr", 0, "M", "largest correspondence distance of the coarse pass, metres",
         "/config/registration/max_correspondence_m", dflt(kReg.max_correspondence_m), above(0, 100)},
        {"reg-fine-corr", 0, "M", "largest correspondence distance of the fine pass, metres",
         "/config/registration/fine_correspondence_m", dflt(kReg.fine_correspondence_m), above(0, 100)},
        {"reg-max-iter", 0, "N", "iteration cap; reaching it counts as not converged",
         "/config/registration/max_iterations", dflt(kReg.max_iterations), in(1, 10000)},
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
  bool timing = false, progress = false, discretize = false;
  std::vector<std::string> scans;
  std::optional<io::BagQuery> bag;
};

Options parse(const Args& args) {
  Options o;
  if (!args.has("output")) throw UsageError("fvx integrate: -o/--output MAP.bt|MAP.ot is required");
  o.output_path = args.get("output");
  if (args.has("map")) o.map_path = args.get("map");
  if (args.has("report")) o.report_path = args.get("report");
  o.resolution_given = args.has("resolution");
  o.resolution_m = parse_resolution(args, kDefaultResolution_m);
  args.read("max-range", o.max_range_m);
  o.discretize = args.has("discretize");
  args.read("depth-min", o.filter.depth_min_m);
  args.read("depth-max", o.filter.depth_max_m);
  args.read("downsample", o.filter.voxel_m);
  if (!(o.filter.depth_max_m > o.filter.depth_min_m))
    throw UsageError("fvx integrate: --depth-max must be greater than --depth-min");
  FVX_ASSERT(o.filter.validate().empty(), "filter options were checked above");

  if (args.has("pose") && args.has("trajectory"))
    throw UsageError("fvx integrate: give --pose or --trajectory, not both");
  if (args.has("pose")) o.load.pose = parse_pose(args.get("pose"), "--pose");
  read_trajectory_options(args, o.load);
  o.load.use_viewpoint = !args.has("ignore-viewpoint");

  o.load.intrinsics = parse_intrinsics(args, "integrate");

  if (args.has("register") && args.has("no-register"))
    throw UsageError("fvx integrate: --register and --no-register contradict each other");
  o.do_register = !args.has("no-register");
  if (args.has("reg-method")) o.reg.method = registration::parse_method(args.get("reg-method"), "--reg-method");
  args.read("reg-voxel", o.reg.voxel_m);
  args.read("reg-max-corr", o.reg.max_correspondence_m);
  args.read("reg-fine-corr", o.reg.fine_correspondence_m);
  args.read("reg-max-iter", o.reg.max_iterations);
  o.timing = args.has("timing");
  o.progress = args.has("progress");
  o.scans = args.positional;
  o.bag = read_bag_options(args, o.load.intrinsics);
  if (o.scans.empty() && !o.bag) throw UsageError("fvx integrate: no scans given (see 'fvx integrate --help')");
  return o;
}

/// Paper §IV steps 1–3 of the pipeline's step: no frontiers, voids or search.
pipeline::Config step_config(const Options& o, double resolution_m) {
  pipeline::Config c;
  c.resolution_m = resolution_m;
  c.filter = o.filter;
  c.max_range_m = o.max_range_m;
  c.discretize = o.discretize;
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
  report["config"] = integrate_config_json(config, o.load, map);
  report["inputs"] = {{"map", o.map_path.empty() ? Json(nullptr) : Json(o.map_path)},
                      {"trajectory", o.load.trajectory_path.empty() ? Json(nullptr) : Json(o.load.trajectory_path)},
                      {"scans", o.scans}};
  report["inputs"].update(bag_inputs_json(o.bag));

  scan::ScanPlan plan = o.bag ? scan::plan_bag(*o.bag) : scan::plan_scans(o.scans, o.load);
  std::vector<std::string> warnings = plan.warnings;
  report["inputs"]["pose_match"] = scan::to_string(plan.match);

  pipeline::Pipeline pipeline(config, std::nullopt, std::move(map));
  Progress progress(o.progress);
  Json scans_json = Json::array();
  const std::string total = std::to_string(plan.scans.size());
  progress.update("fvx integrate: " + total + " scans");
  pipeline::integrate_files(pipeline, plan, o.load, warnings, [&](std::size_t i, const pipeline::IntegratedScan& s) {
    progress.update("fvx integrate: scan " + std::to_string(i + 1) + "/" + total + " integrated: " + s.path);
    scans_json.push_back(integrated_scan_json(s, o.do_register, o.timing));
  });
  progress.finish();

  pipeline.map().save(o.output_path);
  report["results"] = {{"output", o.output_path}, {"scans", scans_json}, {"map", map_json(pipeline.map().stats())}};
  report["warnings"] = warnings;
  write_report(report, o.report_path);
  return core::end_process(0);
}

}  // namespace fvx::cli
