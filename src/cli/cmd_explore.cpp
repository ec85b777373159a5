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
#include "fvx/session/session.hpp"
#include "fvx/session/start.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/exploration_score.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "fvx/voids/width.hpp"
#include "nbv_output.hpp"

namespace fvx::cli {

const CommandSpec kExploreSpec = {
    "explore",
    "SCENE.ply|builtin:NAME (--capmap ARM.fcm [--base POSE] [--arm URDF] | --no-capmap) -o SESSION/ [options]",
    "the closed loop on a simulated scene: scan, integrate, voids, next best view, move; per-view table",
    options({{
                 {"output", 'o', "DIR", "the session directory to create (must not exist or be empty)"},
             },
             arm_options(),
             {
                 {"strategy", 0, "NAME", "frontier-void (default, the paper's), frontier, random or exhaustive"},
                 {"planner", 0, "NAME", "the same as --strategy (its earlier name here)"},
                 {"start", 0, "ex,ey,ez,tx,ty,tz", "first view: sensor at eye E looking at T, metres (default, "
                                                   "with an arm: its farthest reachable pose aimed within 10 "
                                                   "degrees of the search space's centre)"},
                 {"max-views", 0, "N", "stop after N scans (default 15)"},
                 {"pose-noise", 0, "M,DEG", "recorded poses after the first are off by Gaussian noise of sigma M "
                                            "metres and DEG degrees per axis; turns registration on"},
                 {"near-voids", 0, nullptr, "count every void cell a ray crosses in U, and Algorithm 1's utility "
                                            "from the frontier on (fvx nbv's default; default here: only what the "
                                            "sensor can measure, beyond its minimum depth)"},
                 {"far-voids-only", 0, nullptr, "only what the sensor can measure (the default; kept for scripts)"},
                 {"register", 0, nullptr, "register every scan to the map (on with --pose-noise)"},
                 {"resolution", 'r', "M", "map cell edge, metres (default 0.025, the paper's)"},
                 {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space S, metres (default: the scene's sidecar)"},
                 {"view-bounds", 0, "x0,y0,z0,x1,y1,z1", "the sensor stays in this box, metres (default: the "
                                                         "known cells' box)"},
                 {"scene-info", 0, "FILE", "ground-truth sidecar JSON (default: SCENE with .json)"},
                 {"noise", 0, "MODEL", "depth noise of the virtual Kinect: none (default) or kinect"},
                 {"seed", 0, "N", "seed of the planner, the depth noise and the pose noise (default 1)"},
                 {"format", 0, "NAME", "the table on stdout: markdown (default), csv or json"},
                 {"threads", 0, "N", "threads for rendering and the search (default 0: all cores)"},
             },
             target_size_options(),
             accumulation_options(),
             depth_camera_options(),
             {
                 {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal"},
                 {"help", 'h', nullptr, "show this help"},
             }})};

namespace {

/// One row of the per-view table: the paper's columns, then ground truth.
struct Row {
  int view = 0;
  double scan_s = 0, registration_s = 0, integration_s = 0, frontiers_voids_s = 0, search_s = 0;
  std::size_t void_cells = 0;      ///< the paper's column: U of the chosen next view
  std::size_t map_void_cells = 0;  ///< every void cell of the map in S
  double utility_dm3 = 0;          ///< U · R³ in dm³
  double known_fraction = 0;       ///< of the observable empty space of S
  std::size_t target_cells = 0;
  bool target_seen = false;
  std::optional<std::size_t> revealed;  ///< of this view's void cells, known after the next scan
  std::size_t u_in_solid = 0;      ///< ground truth: of void_cells, cells inside material
  std::size_t free_in_solid = 0;   ///< ground truth: free map cells in S inside material
  std::optional<double> registration_fitness_m;
};

std::vector<std::string> cells(const Row& r) {
  return {std::to_string(r.view + 1),
          fixed(r.integration_s + r.frontiers_voids_s, 3),  // the paper's: octree, frontiers and voids
          fixed(r.search_s, 3),
          std::to_string(r.void_cells),
          fixed(r.utility_dm3, 2),
          std::to_string(r.map_void_cells),
          fixed(100.0 * r.known_fraction, 1),
          r.target_seen ? "yes" : "no",
          r.revealed ? std::to_string(*r.revealed) : "-",
          std::to_string(r.u_in_solid)};
}

const std::vector<std::string> kHeader = {"view",           "integration_s", "search_s",    "void_cells", "utility_dm3",
                                          "map_void_cells", "known_pct",     "target_seen", "revealed",
                                          "u_in_solid"};

Json row_json(const Row& r) {
  Json j = {{"view", r.view + 1},
            {"timing_s", {{"render", r.scan_s}, {"registration", r.registration_s}, {"integration", r.integration_s},
                          {"frontiers_voids", r.frontiers_voids_s}, {"search", r.search_s}}},
            {"void_cells", r.void_cells},
            {"map_void_cells", r.map_void_cells},
            {"utility_dm3", r.utility_dm3},
            {"known_fraction", r.known_fraction},
            {"target_cells_seen", r.target_cells},
            {"target_seen", r.target_seen},
            {"revealed_void_cells", r.revealed ? Json(*r.revealed) : Json(nullptr)},
            {"void_cells_in_solid", r.u_in_solid},
            {"free_cells_in_solid", r.free_in_solid},
            {"registration_fitness_m", r.registration_fitness_m ? Json(*r.registration_fitness_m) : Json(nullptr)}};
  return j;
}

/// The loop's settings from the options (all but the scene's: bounds and start come later).
session::ExploreConfig parse_config(const Args& args, double& target_size_m) {
  session::ExploreConfig config;
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  nc.strategy = parse_strategy_option(args, "explore", nbv::Strategy::FrontierVoid);
  nc.sensor = parse_depth_camera(args, "explore");
  nc.seed = std::uint64_t(args.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
  nc.threads = unsigned(args.integer("threads", 0, 0, 1024));
  parse_accumulation(args, nc);
  nc.view_bounds_m = parse_bounds(args, "view-bounds");
  if (args.has("near-voids") && args.has("far-voids-only"))
    throw UsageError("--near-voids and --far-voids-only contradict each other: give one");
  // A loop takes the views it picks, and a view nearer to a void than the sensor's minimum
  // depth measures nothing of it (fvx nbv --far-voids-only).
  nc.count_near_void_cells = args.has("near-voids");
  pc.clusters.seed = nc.seed;
  pc.resolution_m = args.number("resolution", 0.025, 0.001, 1.0);
  target_size_m = parse_target_size(args, 0.0);
  pc.min_void_width_cells = voids::void_width_for_target(target_size_m, pc.resolution_m);
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
session::Manifest manifest_of(const Args& args, const session::ExploreConfig& config, const ArmInputs& arm_inputs,
                              double target_size_m) {
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
  manifest.planner = nbv::to_string(nc.strategy);
  manifest.seed = config.seed;
  manifest.pose_noise_m = config.pose_noise_m;
  manifest.pose_noise_deg = config.pose_noise_deg;
  manifest.registration = pc.register_scans;
  manifest.near_voids = nc.count_near_void_cells;
  manifest.target_size_m = target_size_m;
  manifest.accumulation = utility::to_string(nc.accumulation);
  manifest.max_utility_vectors = nc.max_utility_vectors;
  return manifest;
}

/// The table row of a view, judged against the ground truth (revealed comes with the next).
Row row_of(const session::ViewRecord& v, const map::OccupancyMap& map, const sim::GroundTruth& gt,
           const sim::ExplorationScore& score, const Eigen::AlignedBox3d& S) {
  const pipeline::StepResult& step = v.step;
  const double R = map.resolution_m();
  Row row;
  row.view = v.view;
  row.scan_s = v.scan_s;
  row.registration_s = step.timing.registration_s;
  row.integration_s = step.timing.integration_s;
  row.frontiers_voids_s = step.timing.frontiers_voids_s;
  row.search_s = step.timing.search_s;
  row.map_void_cells = step.analysis.void_cells.size();
  row.void_cells = v.chosen ? step.nbv.views[*v.chosen].void_cells_seen : 0;
  row.utility_dm3 = frontier_voids::to_dm3(double(row.void_cells) * R * R * R);
  row.known_fraction = score.known_fraction(map);
  row.target_cells = score.target_cells_seen(map);
  row.target_seen = row.target_cells >= sim::ExplorationScore::kTargetCellsSeen;
  if (v.chosen) row.u_in_solid = gt.solid_among(step.nbv.views[*v.chosen].seen_void_cells);
  row.free_in_solid = gt.free_in_solid(map, S);
  if (step.registration) row.registration_fitness_m = step.registration->fitness_rmse_m;
  return row;
}

/// A view's report: its analysis, next best views, poses and table row.
Json view_report(const std::string& scene, const session::ViewRecord& v, const session::ManifestView& files,
                 const Row& row, double R, const std::vector<std::string>& joint_names, nbv::Strategy strategy) {
  const pipeline::StepResult& step = v.step;
  Json report = new_report("explore");
  report["inputs"] = {{"scene", scene}, {"view", v.view}, {"scan", files.scan}, {"map", files.map}};
  Json results = nbv_results_json(step.nbv, step.analysis, R, joint_names, strategy, true);
  results["T_world_sensor_prior"] = pose_json(v.T_world_sensor_prior);
  results["T_world_sensor_integrated"] = pose_json(step.T_world_sensor);
  results["T_world_sensor_true"] = pose_json(v.T_world_sensor_true);
  results["row"] = row_json(row);
  report["results"] = results;
  report["warnings"] = step.analysis.warnings;
  return report;
}

/// The run's report (--format json): the effective settings, the inputs, every row and how
/// the loop ended.
Json run_report(const Args& args, const session::ExploreConfig& config, double target_size_m,
                const ArmInputs& arm_inputs, const std::string& dir, const session::ExploreResult& result,
                const sim::ExplorationScore& score, const std::vector<Row>& rows) {
  const pipeline::Config& pc = config.pipeline;
  const nbv::Config& nc = pc.nbv;
  Json report = new_report("explore");
  report["config"] = {{"planner", nbv::to_string(nc.strategy)}, {"max_views", config.max_views},
                      {"resolution_m", pc.resolution_m}, {"bounds_m", bounds_json(*pc.bounds_m)},
                      {"pose_noise", {{"sigma_m", config.pose_noise_m}, {"sigma_deg", config.pose_noise_deg}}},
                      {"registration", pc.register_scans}, {"seed", config.seed},
                      {"target_size_m", target_size_m}, {"min_void_width_cells", pc.min_void_width_cells},
                      {"sensor", depth_camera_json(nc.sensor)}};
  report["config"].update(accumulation_json(nc));
  report["inputs"] = {{"scene", args.positional[0]}, {"capmap", capmap_json(args, arm_inputs)},
                      {"arm", args.has("arm") ? Json(args.get("arm")) : Json(nullptr)}};
  Json jrows = Json::array();
  for (const Row& r : rows) jrows.push_back(row_json(r));
  report["results"] = {{"session", dir}, {"views", result.views}, {"end", result.end},
                       {"utility_exhausted", result.utility_exhausted},
                       {"observable_cells", score.observable_cells()},
                       {"observable_target_cells",
                        score.observable_target_cells() ? Json(*score.observable_target_cells()) : Json(nullptr)},
                       {"rows", jrows}};
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
  double target_size_m = 0.0;
  session::ExploreConfig config = parse_config(args, target_size_m);
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
  session::Recorder recorder(dir.string(), manifest_of(args, config, arm_inputs, target_size_m), nc.sensor);

  const std::vector<std::string> joint_names =
      arm_inputs.arm ? arm_inputs.arm->joint_names() : std::vector<std::string>{};
  const session::Sensor kinect = kinect_of(*caster, render_config);
  std::vector<Row> rows;
  const session::ExploreResult result = session::explore(
      kinect, arm_inputs.reach, config, [&](const session::ViewRecord& v, const pipeline::State& state) {
        const Row row = row_of(v, state.map, gt, score, S);
        if (!rows.empty()) rows.back().revealed = v.revealed_void_cells;
        rows.push_back(row);

        // The view's files, then the manifest that lists them.
        recorder.add(v, state.map,
                     report_text(view_report(args.positional[0], v, recorder.files_of(v), row, R, joint_names, nc.strategy)));
        progress.update("fvx explore: view " + std::to_string(v.view + 1) + ": " + std::to_string(row.map_void_cells) +
                        " void cells, next view sees " + std::to_string(row.void_cells) + ", " +
                        fixed(100.0 * row.known_fraction, 1) + " % known" + (row.target_seen ? ", target seen" : ""));
      });
  progress.finish();

  if (format == Format::json) {
    write_report(run_report(args, config, target_size_m, arm_inputs, dir.string(), result, score, rows), "");
  } else {
    std::vector<std::vector<std::string>> table;
    for (const Row& r : rows) table.push_back(cells(r));
    print_table(kHeader, table, format, std::cout);
    if (format == Format::markdown) std::cout << "\n" << result.end << " after " << result.views << " views.\n";
  }
  if (score.observable_target_cells() && *score.observable_target_cells() < sim::ExplorationScore::kTargetCellsSeen)
    std::cerr << "fvx explore: warning: from this base no pose of the arm sees the target (ground truth: "
              << *score.observable_target_cells() << " of its cells measurable); move --base\n";
  std::cerr << "fvx explore: " << result.end << "; session in " << dir.string() << "\n";
  return 0;
}

}  // namespace fvx::cli
