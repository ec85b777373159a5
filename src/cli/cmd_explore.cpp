// fvx explore — the closed loop of §IV on a simulated scene with a virtual Kinect: scan,
// integrate, frontiers and voids, next best view, move; a session directory and the per-view
// table with ground truth.
#include <filesystem>
#include <iostream>

#include "analysis_output.hpp"
#include "command_table.hpp"
#include "common_options.hpp"
#include "table.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/session/recorder.hpp"
#include "fvx/session/simulated_world.hpp"
#include "fvx/session/start.hpp"
#include "fvx/report/picture3d.hpp"
#include "fvx/report/session.hpp"

namespace fvx::cli {

const CommandSpec kExploreSpec = {
    "explore",
    "SCENE.ply|builtin:NAME (--capmap ARM.fcm [--base POSE] [--arm URDF] | --no-capmap) -o SESSION/ [options]",
    "the closed loop on a simulated scene: scan, integrate, voids, next best view, move; per-view table",
    options({{
                 {"output", 'o', "DIR", "the session directory to create (must not exist or be empty)", "-"},
             },
             arm_options(),
             {
                 {"strategy", 0, "NAME", "frontier-void (default, the paper's), frontier, random or exhaustive",
                  "/config/pipeline/nbv/strategy"},
                 {"planner", 0, "NAME", "the same as --strategy (its earlier name here)",
                  "/config/pipeline/nbv/strategy"},
                 {"start", 0, "ex,ey,ez,tx,ty,tz", "first view: sensor at eye E looking at T, metres (default, "
                                                   "with an arm: its farthest reachable pose aimed within 10 "
                                                   "degrees of the search space's centre)",
                  "/config/T_world_sensor_start"},
                 {"max-views", 0, "N", "stop after N scans", "/config/max_views",
                  dflt(session::ExploreConfig{}.max_views), in(1, 10000)},
                 {"pose-noise", 0, "M,DEG", "recorded poses after the first are off by Gaussian noise of sigma M "
                                            "metres and DEG degrees per axis; turns registration on",
                  "/config/pose_noise"},
                 {"register", 0, nullptr, "register every scan to the map (on with --pose-noise)",
                  "/config/pipeline/register_scans"},
                 resolution_option("/config/pipeline/resolution_m", "map cell edge, metres", ", the paper's"),
                 {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space S, metres (default: the scene's sidecar)",
                  "/config/pipeline/bounds_m"},
                 {"view-bounds", 0, "x0,y0,z0,x1,y1,z1", "the sensor stays in this box, metres (default: the "
                                                         "known cells' box)", "/config/pipeline/nbv/view_bounds_m"},
                 {"scene-info", 0, "FILE", "ground-truth sidecar JSON (default: SCENE with .json)",
                  "/inputs/scene_info"},
                 {"noise", 0, "MODEL", "depth noise of the virtual Kinect: none (default) or kinect",
                  "/config/depth_noise_m_per_m2"},
                 seed_option("/config/seed", "seed of the planner, the depth noise and the pose noise",
                             session::ExploreConfig{}.seed),
                 {"no-return", 0, "MODE", "a ray of the virtual Kinect that meets no surface within its depth "
                                          "limit: none (default: no measurement, as a Kinect) or free (a point "
                                          "beyond the limit that clears the ray up to it, as a laser's max-range "
                                          "return)", "/config/pipeline/clear_beyond_range"},
                 pipeline::discretize_option("/config/pipeline/discretize"),
                 {"format", 0, "NAME", "the table on stdout: markdown (default), csv or json", "-"},
                 threads_option("/config/pipeline/nbv/threads", "threads for rendering and the search"),
             },
             search_model_options("/config/pipeline", "/config/pipeline/nbv"),
             report::picture_options(true, nullptr, nullptr),
             session_report_options()})};

namespace {

const std::vector<std::string> kExploreColumns = {"view",           "integration_s", "search_s",       "void_cells",
                                                  "utility_dm3",    "map_void_cells", "void_known_pct", "known_pct",
                                                  "target_seen",    "revealed",      "u_in_solid"};

/// The loop's settings from the options (all but the scene's: bounds and start come later).
session::ExploreConfig parse_config(const Args& args) {
  session::ExploreConfig config;
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  nc.strategy = parse_strategy_option(args, "explore", nbv::Strategy::FrontierVoid);
  nc.sensor = parse_depth_camera(args, "explore");
  args.read("seed", nc.seed);
  args.read("threads", nc.threads);
  parse_accumulation(args, nc);
  nc.view_bounds_m = parse_bounds(args, "view-bounds");
  nc.count_near_void_cells = parse_near_voids(args, true);
  pc.resolution_m = parse_resolution(args, kDefaultResolution_m);
  pc.target_size_m = parse_target_size(args, 0.0);
  pc.hull_in_bounds = parse_void_hull(args, false);
  args.read("unknown-depth", nc.unknown_depth_cells);
  nc.near_unknown = pipeline::parse_near_unknown(args, nc.near_unknown);
  nc.exterior = pipeline::parse_exterior(args, nc.exterior);
  if (args.has("no-return")) {
    const std::string mode = args.get("no-return");
    if (mode != "none" && mode != "free") throw UsageError("--no-return '" + mode + "': expected none or free");
    pc.clear_beyond_range = mode == "free";
  }
  pc.discretize = args.has("discretize");
  pc.tie_to_search();
  config.seed = nc.seed;
  args.read("max-views", config.max_views);
  if (args.has("pose-noise")) {
    const std::vector<double> v = parse_double_list(args.get("pose-noise"), "--pose-noise (M,DEG)", 2);
    if (!(v[0] >= 0 && v[0] <= 1.0) || !(v[1] >= 0 && v[1] <= 45.0))
      throw UsageError("--pose-noise " + args.get("pose-noise") + ": expected 0 <= M <= 1 metres, 0 <= DEG <= 45");
    config.pose_noise_m = v[0];
    config.pose_noise_deg = v[1];
  }
  pc.register_scans = args.has("register") || config.pose_noise_m > 0 || config.pose_noise_deg > 0;
  if (nc.strategy == nbv::Strategy::Exhaustive && !args.has("capmap"))
    throw UsageError("fvx explore: --strategy exhaustive enumerates a capability map: give --capmap");
  return config;
}

/// The virtual Kinect of the run: the search's sensor, seeded, with the depth noise asked for
/// and, when the pipeline clears rays beyond the range, max-range points for rays without a
/// surface.
sim::SensorConfig render_config_of(const Args& args, const pipeline::Config& pc) {
  const nbv::Config& nc = pc.nbv;
  sim::SensorConfig render_config = sim::SensorConfig::of(nc.sensor, nc.seed, nc.threads);
  render_config.noise_m_per_m2 = parse_depth_noise(args);
  // Beyond the limit by a margin that float rounding of the recorded scan cannot undo.
  if (pc.clear_beyond_range) render_config.no_return_depth_m = 2.0 * nc.sensor.depth_max_m;
  return render_config;
}

/// The run's report (--format json): the effective settings, the inputs, every row and how
/// the loop ended.
Json run_report(const Args& args, const session::ExploreConfig& config, const sim::SensorConfig& render_config,
                const std::string& scene_info_path, const ArmInputs& arm_inputs, const std::string& dir,
                const session::ExploreResult& result,
                const sim::ExplorationScore& score, const std::vector<session::ViewRow>& rows) {
  Json report = new_report("explore");
  report["config"] = session::config_json(config);
  report["config"]["depth_noise_m_per_m2"] = render_config.noise_m_per_m2;
  report["inputs"] = {{"scene", args.positional[0]},
                      {"scene_info", scene_info_path.empty() ? Json(nullptr) : Json(scene_info_path)},
                      {"capmap", capmap_json(args, arm_inputs)},
                      {"arm", args.has("arm") ? Json(args.get("arm")) : Json(nullptr)}};
  report["results"] = explore_results_json(dir, result, score, rows, args.has("timing"));
  report["warnings"] = Json::array();
  return report;
}

/// One scene, an output folder that is new or empty, arm options that go together.
void check_inputs_and_output(const Args& args) {
  if (args.positional.size() != 1)
    throw UsageError("fvx explore: give one scene (a mesh file or builtin:NAME), got " +
                     std::to_string(args.positional.size()));
  if (!args.has("output")) throw UsageError("fvx explore: -o/--output SESSION_DIR is required");
  check_arm_options(args, "fvx explore");
  const std::filesystem::path dir = args.get("output");
  if (std::filesystem::exists(dir) && !(std::filesystem::is_directory(dir) && std::filesystem::is_empty(dir)))
    throw UsageError("fvx explore: -o " + dir.string() + " exists and is not an empty folder; nothing is overwritten");
}

}  // namespace

int run_explore(const Args& args) {
  check_inputs_and_output(args);
  const Format format = parse_format(args);
  const std::filesystem::path dir = args.get("output");
  session::ExploreConfig config = parse_config(args);
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  const sim::SensorConfig render_config = render_config_of(args, pc);
  // Inputs: the scene, the arm; then the start pose against both.
  const sim::Scene scene = scene_from(args.positional[0], args);
  ArmInputs arm_inputs;
  if (args.has("capmap") && !args.has("base") && !scene.info.bases.empty()) {  // where the scene puts the arm
    const auto& b = scene.info.bases.front();
    const double d = M_PI / 180.0;
    nbv::load_arm(args.get("capmap"), args.has("arm") ? args.get("arm") : "",
                  pose_from_xyz_rpy(b[0], b[1], b[2], b[3] * d, b[4] * d, b[5] * d), "fvx explore", arm_inputs);
  } else {
    load_arm_inputs(args, "fvx explore", arm_inputs);
  }
  pc.bounds_m = parse_bounds(args);
  if (!pc.bounds_m) pc.bounds_m = scene.info.search_space;
  if (!pc.bounds_m)
    throw UsageError("fvx explore: the scene has no search space (sidecar search_space); give --bounds");
  const Eigen::AlignedBox3d S = *pc.bounds_m;
  std::optional<Eigen::Isometry3d> start;
  if (args.has("start")) start = parse_look_at(args.get("start"), "--start");
  throw_if_problems("fvx explore", config.validate());
  const report::PictureRequest picture_request = report::read_picture_options(args);
  Progress progress(args.has("progress"));
  const session::SimulatedWorld world(scene, pc.resolution_m, S, start, arm_inputs.T_world_base,
                                      S.center() - Eigen::Vector3d(0, 0, 0.1), arm_inputs.reach, nc.sensor,
                                      nc.clearance_m, config.seed, nc.threads,
                                      [&](const std::string& stage) { progress.update("fvx explore: " + stage); });
  config.T_world_sensor_start = world.start();
  const sim::ExplorationScore& score = world.score();
  // The session directory: created only now that every input is good.
  session::Recorder recorder(dir.string(),
                             session::explore_manifest(config, args.positional[0], arm_inputs.reach,
                                                       args.has("capmap") ? args.get("capmap") : "",
                                                       args.has("arm") ? args.get("arm") : ""),
                             nc.sensor);
  const std::vector<std::string> joint_names = arm_inputs.joint_names();
  std::vector<session::ViewRow> rows;
  report::SessionPictures pictures(dir.string(), picture_request, nc.sensor,
                                   arm_inputs.reach ? std::optional(arm_inputs.T_world_base) : std::nullopt);
  const session::ExploreResult result = session::explore(
      world.kinect(render_config), arm_inputs.reach, config,
      [&](const session::ViewRecord& v, const pipeline::State& state) {
        session::append_row(rows, world.row_of(v, state.map), v.revealed_void_cells);
        pictures.add(v.view, state.map.occupied_centers(), pc.resolution_m, v.step, v.chosen);
        const session::ViewRow& row = rows.back();
        // The view's files, then the manifest that lists them.
        recorder.add(v, state.map,
                     report_text(explore_view_report(args.positional[0], v, recorder.files_of(v), row,
                                                     pc.resolution_m, joint_names, nc.strategy, args.has("timing"))));
        progress.update("fvx explore: view " + std::to_string(v.view + 1) + ": " + std::to_string(row.map_void_cells) +
                        " void cells, next view sees " + std::to_string(row.void_cells) + ", " +
                        fixed(100.0 * row.truth->void_known_fraction, 1) + " % of the void known" +
                        (row.truth->target_seen ? ", target seen" : ""));
      });
  progress.finish();
  pictures.finish("fvx explore " + args.positional[0]);

  if (format == Format::json) {
    write_report(
        run_report(args, config, render_config, scene.info_path, arm_inputs, dir.string(), result, score, rows), "");
  } else {
    print_rows(rows, kExploreColumns, format, std::cout);
    if (format == Format::markdown) std::cout << "\n" << result.end << " after " << result.views << " views.\n";
  }
  if (score.observable_target_cells() && *score.observable_target_cells() < sim::ExplorationScore::kTargetCellsSeen)
    std::cerr << "fvx explore: warning: from this base no pose of the arm sees the target (ground truth: "
              << *score.observable_target_cells() << " of its cells measurable); move --base\n";
  std::cerr << "fvx explore: " << result.end << "; session in " << dir.string() << "\n";
  return core::end_process(0);
}

}  // namespace fvx::cli
