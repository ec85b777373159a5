// fvx explore — the closed loop of §IV on a simulated scene with a virtual Kinect: scan,
// integrate, frontiers and voids, next best view, move; a session directory and the per-view
// table with ground truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "analysis_output.hpp"
#include "command_table.hpp"
#include "common_options.hpp"
#include "table.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/session/recorder.hpp"
#include "fvx/session/rows.hpp"
#include "fvx/session/session.hpp"
#include "fvx/session/start.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/exploration_score.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "fvx/voids/width.hpp"
#include "session_output.hpp"

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
                 {"max-views", 0, "N", "stop after N scans (default 15)", "/config/max_views"},
                 {"pose-noise", 0, "M,DEG", "recorded poses after the first are off by Gaussian noise of sigma M "
                                            "metres and DEG degrees per axis; turns registration on",
                  "/config/pose_noise"},
                 {"register", 0, nullptr, "register every scan to the map (on with --pose-noise)",
                  "/config/pipeline/register_scans"},
                 {"resolution", 'r', "M", "map cell edge, metres (default 0.025, the paper's)",
                  "/config/pipeline/resolution_m"},
                 {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space S, metres (default: the scene's sidecar)",
                  "/config/pipeline/bounds_m"},
                 {"view-bounds", 0, "x0,y0,z0,x1,y1,z1", "the sensor stays in this box, metres (default: the "
                                                         "known cells' box)", "/config/pipeline/nbv/view_bounds_m"},
                 {"scene-info", 0, "FILE", "ground-truth sidecar JSON (default: SCENE with .json)",
                  "/inputs/scene_info"},
                 {"noise", 0, "MODEL", "depth noise of the virtual Kinect: none (default) or kinect",
                  "/config/depth_noise_m_per_m2"},
                 {"seed", 0, "N", "seed of the planner, the depth noise and the pose noise (default 1)",
                  "/config/seed"},
                 {"format", 0, "NAME", "the table on stdout: markdown (default), csv or json", "-"},
                 {"threads", 0, "N", "threads for rendering and the search (default 0: all cores)",
                  "/config/pipeline/nbv/threads"},
             },
             search_model_options("/config/pipeline", "/config/pipeline/nbv"),
             session_report_options()})};

namespace {

const std::vector<std::string> kColumns = {"view",       "integration_s",  "search_s",  "void_cells",
                                           "utility_dm3", "map_void_cells", "known_pct", "target_seen",
                                           "revealed",   "u_in_solid"};

/// The loop's settings from the options (all but the scene's: bounds and start come later).
session::ExploreConfig parse_config(const Args& args) {
  session::ExploreConfig config;
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  nc.strategy = parse_strategy_option(args, "explore", nbv::Strategy::FrontierVoid);
  nc.sensor = parse_depth_camera(args, "explore");
  nc.seed = std::uint64_t(args.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
  nc.threads = unsigned(args.integer("threads", 0, 0, 1024));
  parse_accumulation(args, nc);
  nc.view_bounds_m = parse_bounds(args, "view-bounds");
  nc.count_near_void_cells = parse_near_voids(args, true);
  pc.clusters.seed = nc.seed;
  pc.resolution_m = parse_resolution(args, kDefaultResolution_m);
  pc.target_size_m = parse_target_size(args, 0.0);
  pc.filter.depth_min_m = nc.sensor.depth_min_m;
  pc.filter.depth_max_m = nc.sensor.depth_max_m;
  config.seed = nc.seed;
  config.max_views = int(args.integer("max-views", config.max_views, 1, 10000));
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

/// The virtual Kinect of the run: the search's sensor, seeded, with the depth noise asked for.
sim::SensorConfig render_config_of(const Args& args, const nbv::Config& nc) {
  sim::SensorConfig render_config;
  render_config.intrinsics = nc.sensor.intrinsics;
  render_config.depth_min_m = nc.sensor.depth_min_m;
  render_config.depth_max_m = nc.sensor.depth_max_m;
  render_config.seed = nc.seed;
  render_config.threads = nc.threads;
  render_config.noise_m_per_m2 = parse_depth_noise(args);

  return render_config;
}

/// What the session's manifest records of the run.
session::Manifest manifest_of(const Args& args, const session::ExploreConfig& config, const ArmInputs& arm_inputs) {
  const pipeline::Config& pc = config.pipeline;
  const nbv::Config& nc = pc.nbv;
  session::Manifest manifest;
  manifest.created_by = std::string("fvx explore ") + version();
  manifest.scene = args.positional[0];
  manifest.resolution_m = pc.resolution_m;
  manifest.search_space_m = pc.bounds_m;
  manifest.view_bounds_m = nc.view_bounds_m;
  if (arm_inputs.reach) {
    manifest.T_world_base = arm_inputs.T_world_base;
    manifest.capmap = args.get("capmap");
    manifest.capmap_urdf_hash = arm_inputs.capability_map->header().urdf_hash;
  }
  if (args.has("arm")) manifest.arm = args.get("arm");
  manifest.strategy = nbv::to_string(nc.strategy);
  manifest.seed = config.seed;
  manifest.pose_noise_m = config.pose_noise_m;
  manifest.pose_noise_deg = config.pose_noise_deg;
  manifest.registration = pc.register_scans;
  manifest.near_voids = nc.count_near_void_cells;
  manifest.target_size_m = pc.target_size_m;
  manifest.accumulation = utility::to_string(nc.accumulation);
  manifest.max_utility_vectors = nc.max_utility_vectors;
  return manifest;
}

/// The table row of a view, judged against the ground truth (revealed comes with the next).
session::ViewRow row_of(const session::ViewRecord& v, const map::OccupancyMap& map, const sim::GroundTruth& gt,
                        const sim::ExplorationScore& score, const Eigen::AlignedBox3d& S) {
  session::ViewRow row = session::row_of(v, map, S);
  session::TruthColumns truth;
  truth.known_fraction = score.known_fraction(map);
  truth.target_cells = score.target_cells_seen(map);
  truth.target_seen = truth.target_cells >= sim::ExplorationScore::kTargetCellsSeen;
  if (v.chosen) truth.u_in_solid = gt.solid_among(v.step.nbv.views[*v.chosen].seen_void_cells);
  truth.free_in_solid = gt.free_in_solid(map, S);
  row.truth = truth;
  return row;
}

/// A view's report: its analysis, next best views, poses and table row.
Json explore_view_report(const std::string& scene, const session::ViewRecord& v, const session::ManifestView& files,
                         const session::ViewRow& row, double R, const std::vector<std::string>& joint_names,
                         nbv::Strategy strategy, bool timing) {
  Json report = view_report("explore", {{"scene", scene}, {"view", v.view}, {"scan", files.scan}, {"map", files.map}},
                            v.step, v.chosen, row, R, joint_names, strategy, timing);
  report["results"]["T_world_sensor_prior"] = pose_json(v.T_world_sensor_prior);
  report["results"]["T_world_sensor_true"] = pose_json(v.T_world_sensor_true);
  return report;
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
  report["results"] = {{"session", dir}, {"views", result.views}, {"end", result.end},
                       {"utility_exhausted", result.utility_exhausted},
                       {"observable_cells", score.observable_cells()},
                       {"observable_target_cells",
                        score.observable_target_cells() ? Json(*score.observable_target_cells()) : Json(nullptr)},
                       {"rows", rows_json(rows, args.has("timing"))}};
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

/// Every place the sensor can be: the start and, with an arm, its capability map's voxels.
std::vector<Eigen::Vector3d> sensor_positions(const Eigen::Vector3d& start, const ArmInputs& arm_inputs) {
  std::vector<Eigen::Vector3d> positions = {start};
  if (arm_inputs.reach)
    for (const auto& entry : arm_inputs.capability_map->voxels())
      positions.push_back(arm_inputs.T_world_base * arm_inputs.capability_map->center_of(entry.first));
  return positions;
}

/// The virtual Kinect: a frame rendered at the true pose, seeded by the view.
session::Sensor kinect_of(const sim::RayCaster& caster, const sim::SensorConfig& render_config) {
  return [&caster, render_config](const Eigen::Isometry3d& T_world_sensor, int view) {
    const sim::Frame frame = sim::render(caster, T_world_sensor, render_config, std::uint64_t(view));
    std::vector<Eigen::Vector3d> points;
    points.reserve(frame.points_sensor.size());
    for (const auto& p : frame.points_sensor) points.push_back(p.cast<double>());
    return points;
  };
}

/// Observable = what some pose of the arm's capability map would reveal (coarse rays: the
/// union over thousands of poses fills their gaps).
void restrict_to_arm(const nbv::Reach& reach, const sim::GroundTruth& gt, const nbv::Config& nc,
                     sim::ExplorationScore& score) {
  const std::vector<Eigen::Isometry3d> poses = session::capmap_view_poses(reach, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3i cell = gt.cell_of(p);
    return gt.contains(cell) && gt.solid(cell);
  });
  score.restrict_to_views(gt, poses, viewpoints::ray_fan(nc.sensor.intrinsics, 20, 15), nc.sensor.depth_min_m,
                          nc.sensor.depth_max_m, nc.threads);
}

}  // namespace

int run_explore(const Args& args) {
  check_inputs_and_output(args);
  const Format format = parse_format(args);
  const std::filesystem::path dir = args.get("output");
  session::ExploreConfig config = parse_config(args);
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  const sim::SensorConfig render_config = render_config_of(args, nc);
  // Inputs: the scene, the arm; then the start pose against both.
  const sim::Scene scene = scene_from(args.positional[0], args);
  ArmInputs arm_inputs;
  load_arm_inputs(args, "fvx explore", arm_inputs);
  pc.bounds_m = parse_bounds(args);
  if (!pc.bounds_m) pc.bounds_m = scene.info.search_space;
  if (!pc.bounds_m)
    throw UsageError("fvx explore: the scene has no search space (sidecar search_space); give --bounds");
  const Eigen::AlignedBox3d S = *pc.bounds_m;
  config.T_world_sensor_start =
      args.has("start") ? parse_look_at(args.get("start"), "--start")
                        : session::default_start(arm_inputs.reach, arm_inputs.T_world_base, S,
                                                 S.center() - Eigen::Vector3d(0, 0, 0.1));
  throw_if_problems("fvx explore", config.validate());
  const auto caster = sim::make_ray_caster(scene.mesh);
  const double R = pc.resolution_m;
  const Eigen::Vector3d eye = config.T_world_sensor_start.translation();
  if (sim::inside_solid(*caster, eye.cast<float>()))
    throw Error("fvx explore: the start pose (" + fixed(eye.x(), 3) + ", " + fixed(eye.y(), 3) + ", " +
                fixed(eye.z(), 3) + ") is inside an obstacle of the scene");
  // Ground truth around S and over every place the sensor can be (the start, the arm's
  // capability map): rays of the observability check start there.
  session::start_configuration(arm_inputs.reach, config.T_world_sensor_start, config.seed);  // throws if unreachable
  Progress progress(args.has("progress"));
  progress.update("fvx explore: ground truth of the search space");
  const sim::GroundTruth gt(scene.mesh, *caster, R, sim::exploration_region(S, sensor_positions(eye, arm_inputs)));
  std::optional<Eigen::AlignedBox3d> target;
  if (scene.info.target) target = scene.info.target->box;
  sim::ExplorationScore score(gt, S, target);
  if (arm_inputs.reach) {
    progress.update("fvx explore: the space the arm can observe at all (ground truth)");
    restrict_to_arm(*arm_inputs.reach, gt, nc, score);
  }
  // The session directory: created only now that every input is good.
  session::Recorder recorder(dir.string(), manifest_of(args, config, arm_inputs), nc.sensor);

  const std::vector<std::string> joint_names =
      arm_inputs.arm ? arm_inputs.arm->joint_names() : std::vector<std::string>{};
  const session::Sensor kinect = kinect_of(*caster, render_config);
  std::vector<session::ViewRow> rows;
  const session::ExploreResult result = session::explore(
      kinect, arm_inputs.reach, config, [&](const session::ViewRecord& v, const pipeline::State& state) {
        session::append_row(rows, row_of(v, state.map, gt, score, S), v.revealed_void_cells);
        const session::ViewRow& row = rows.back();

        // The view's files, then the manifest that lists them.
        recorder.add(v, state.map,
                     report_text(explore_view_report(args.positional[0], v, recorder.files_of(v), row, R, joint_names,
                                                 nc.strategy, args.has("timing"))));
        progress.update("fvx explore: view " + std::to_string(v.view + 1) + ": " + std::to_string(row.map_void_cells) +
                        " void cells, next view sees " + std::to_string(row.void_cells) + ", " +
                        fixed(100.0 * row.truth->known_fraction, 1) + " % known" +
                        (row.truth->target_seen ? ", target seen" : ""));
      });
  progress.finish();

  if (format == Format::json) {
    write_report(
        run_report(args, config, render_config, scene.info_path, arm_inputs, dir.string(), result, score, rows), "");
  } else {
    print_rows(rows, kColumns, format, std::cout);
    if (format == Format::markdown) std::cout << "\n" << result.end << " after " << result.views << " views.\n";
  }
  if (score.observable_target_cells() && *score.observable_target_cells() < sim::ExplorationScore::kTargetCellsSeen)
    std::cerr << "fvx explore: warning: from this base no pose of the arm sees the target (ground truth: "
              << *score.observable_target_cells() << " of its cells measurable); move --base\n";
  std::cerr << "fvx explore: " << result.end << "; session in " << dir.string() << "\n";
  return 0;
}

}  // namespace fvx::cli
