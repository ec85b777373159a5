// fvx nbv — a map (+ an arm's capability map) → the ranked next best views (paper §IV-C,
// Algorithm 1 and Eq. 3).
#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis_output.hpp"
#include "nbv_output.hpp"
#include "command_table.hpp"
#include "common_options.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/io/visual.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/voids/width.hpp"

namespace fvx::cli {

const CommandSpec kNbvSpec = {
    "nbv",
    "MAP.bt|MAP.ot (--capmap ARM.fcm [--base POSE] | --no-capmap) [-o VIEWS.json] [options]",
    "the next best views: utility vectors, pruning by the arm's reach, U by ray tracing (Eq. 3)",
    options({{
                 {"output", 'o', "FILE", "write the JSON report to FILE instead of stdout", "-"},
             },
             arm_options(),
             {
                 {"strategy", 0, "NAME", "frontier-void (default, the paper's), exhaustive (every reachable "
                                         "voxel and direction of the capability map), frontier (view the "
                                         "largest frontier cluster) or random (a random reachable view that "
                                         "sees a void cell)", "/config/strategy"},
                 {"top", 'n', "N", "ranked views to report (default 10)", "/config/top"},
                 {"poses", 'N', "N", "stop after N valid poses (default 50, as in the paper)", "/config/valid_poses"},
                 {"orientations", 0, "K", "orientations sampled per candidate cell (default 2)",
                  "/config/orientations_per_cell"},
                 {"separation", 0, "M", "pass over cells nearer than M to a viewpoint already used, metres "
                                        "(default 0.15; 0: every cell in utility order)", "/config/min_separation_m"},
                 {"refine", 0, "K", "step the K best poses back along their optical axis and score the steps "
                                    "(default 10; 0: off, as the paper)", "/config/refine_poses"},
                 {"refine-step", 0, "M", "refinement step and its limit, metres: STEP or STEP,MAX (default 0.1,0.8)",
                  "/config/refine_step_m"},
                 {"polish", 0, "K", "score the K best poses at 5 more rolls about their optical axis, 30 degrees "
                                    "apart (default 3; 0: off, as the paper)", "/config/polish_poses"},
                 {"climb", 0, "N", "then N rounds of a local climb from each of the K best poses: moved 5 cm along "
                                   "each axis and tilted 4 degrees, halving when nothing is better (default 0: off, "
                                   "as the paper)", "/config/climb_rounds"},
                 {"jitter", 0, "DEG", "tilt of sampled axes around their target, degrees (default 5)",
                  "/config/jitter_deg"},
                 {"clearance", 0, "M", "no occupied cell within M of a viewpoint, metres (default 0.1)",
                  "/config/clearance_m"},
                 {"rays", 0, "COLSxROWS", "field-of-view rays: a decimated pixel grid (default 80x60)", "/config/rays"},
                 {"rolls", 0, "N", "exhaustive: rolls per direction over 180 degrees (default 2)",
                  "/config/exhaustive_rolls"},
                 {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space S, metres (default: the box of the known cells)",
                  "/config/bounds_m"},
                 {"view-bounds", 0, "x0,y0,z0,x1,y1,z1", "the sensor stays in this box, metres (default: the "
                                                         "box of the known cells)", "/config/view_bounds_m"},
                 {"min-fit-score", 0, "S", "void clusters keep a fit score (Eq. 2) at or above S (default 0.7)",
                  "/config/min_fit_score"},
                 {"seed", 0, "N", "seed of cluster growing, orientation jitter and roll, IK restarts (default 1)",
                  "/config/seed"},
                 {"threads", 0, "N", "threads for accumulation and scoring (default 0: all cores; same result)",
                  "/config/threads"},
             },
             search_model_options("/config", "/config"),
             {
                 {"utility-cloud", 0, "FILE", "the utility field as a coloured cloud, .ply or .pcd: red (low), "
                                              "yellow, green (high) by rank; pruned cells grey", "-"},
                 {"picture", 0, "FILE.png", "a top view of the utility field, the voids and the best view", "-"},
                 {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
                 {"timing", 0, nullptr, "add the search time split (grid, accumulation, pruning, sampling, "
                                        "scoring) and ray-casting speed to the report", "-"},
                 {"help", 'h', nullptr, "show this help", "-"},
             }})};

namespace {

io::Rgb ramp(double t) {  // red → yellow → green, as the paper's Figure 4
  t = std::clamp(t, 0.0, 1.0);
  return t < 0.5 ? io::Rgb{230, std::uint8_t(230 * 2 * t), 30} : io::Rgb{std::uint8_t(230 * 2 * (1 - t)), 200, 30};
}

/// Each kept cell's utility as its rank among the kept cells, in [0, 1]: utility spans orders
/// of magnitude (it piles up next to the frontier), so a linear scale would paint nearly all
/// of it "low".
std::vector<double> utility_ranks(const nbv::Result& r) {
  std::vector<double> kept;
  for (const auto& c : r.utility_field)
    if (c.kept) kept.push_back(c.utility_m3);
  std::sort(kept.begin(), kept.end());
  std::vector<double> ranks;
  for (const auto& c : r.utility_field) {
    const auto below = std::lower_bound(kept.begin(), kept.end(), c.utility_m3) - kept.begin();
    ranks.push_back(kept.size() > 1 ? double(below) / double(kept.size() - 1) : 1.0);
  }
  return ranks;
}

void write_utility_cloud(const std::string& path, const nbv::Result& r) {
  const std::vector<double> rank = utility_ranks(r);
  std::vector<Eigen::Vector3f> points;
  std::vector<io::Rgb> colors;
  for (std::size_t i = 0; i < r.utility_field.size(); ++i) {
    const auto& c = r.utility_field[i];
    points.push_back(c.center_m.cast<float>());
    colors.push_back(c.kept ? ramp(rank[i]) : io::Rgb{170, 170, 170});
  }
  io::write_colored_cloud(path, points, colors);
}

void write_utility_picture(const std::string& path, const map::OccupancyMap& map, const frontier_voids::Analysis& a,
                           const nbv::Result& r) {
  // The whole map's occupied cells: viewpoints may lie outside the search space.
  const map::Stats stats = map.stats();
  std::vector<io::PictureLayer> layers = {
      occupied_layer(map, Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m)), void_layer(map, a)};
  const std::vector<double> rank = utility_ranks(r);
  io::PictureLayer pruned{"utility, pruned", {200, 200, 200}, {}, true, false};
  io::PictureLayer low{"utility, lowest third", ramp(0.0), {}, false, false},
      mid{"utility, middle third", ramp(0.5), {}, false, false}, high{"utility, highest third", ramp(1.0), {}, false, false};
  for (std::size_t i = 0; i < r.utility_field.size(); ++i) {
    const auto& c = r.utility_field[i];
    if (!c.kept) {
      pruned.centers_m.push_back(c.center_m);
      continue;
    }
    (rank[i] < 1.0 / 3 ? low : rank[i] < 2.0 / 3 ? mid : high).centers_m.push_back(c.center_m);
  }
  for (auto* layer : {&pruned, &low, &mid, &high}) layers.push_back(std::move(*layer));
  io::PictureLayer best{"best view", {30, 90, 230}, {}, false, false};
  if (!r.views.empty()) {
    // The viewpoint and its optical axis for half a metre.
    const Eigen::Isometry3d& T = r.views.front().T_world_sensor;
    for (double s = 0.0; s <= 0.5; s += map.resolution_m()) best.centers_m.push_back(T * Eigen::Vector3d(0, 0, s));
  }
  layers.push_back(std::move(best));
  io::write_top_view_png(path, map.resolution_m(), layers);
}

Json view_json(const nbv::View& v, int rank, double R, const frontier_voids::Analysis& a,
               const std::vector<std::string>& joint_names, nbv::Strategy strategy) {
  const Eigen::Isometry3d& T = v.T_world_sensor;
  const Eigen::Vector3d rpy = rpy_of(T.linear()) * 180.0 / M_PI;
  Json j = {{"rank", rank}};
  const Json pose = pose_json(T);
  j["position_m"] = pose["position_m"];
  j["quaternion_xyzw"] = pose["quaternion_xyzw"];
  j["rpy_deg"] = vec_json(rpy);
  j["viewing_direction"] = vec_json(T.linear().col(2));
  if (v.joints_rad.size() > 0) {
    Json joints = Json::object();
    for (int i = 0; i < v.joints_rad.size(); ++i) joints[joint_names[std::size_t(i)]] = v.joints_rad[i];
    j["joints_rad"] = joints;
  } else {
    j["joints_rad"] = nullptr;
  }
  j["void_cells_seen"] = v.void_cells_seen;
  j["utility_dm3"] = frontier_voids::to_dm3(double(v.void_cells_seen) * R * R * R);  // as fvx voids
  if (strategy == nbv::Strategy::Frontier) {
    j["frontier_cells_seen"] = v.frontier_cells_seen;
    j["frontier_rays_through_cell"] = v.frontier_rays_through_cell;
  } else {
    j["accumulated_utility_dm3"] = frontier_voids::to_dm3(v.accumulated_utility_m3);
  }
  Json serves = Json::array();
  for (const auto& [void_id, cells] : v.voids_seen)
    serves.push_back({{"void_id", void_id}, {"cells_seen", cells},
                      {"void_cells", a.void_clusters[std::size_t(void_id)].cells.size()}});
  j["voids_seen"] = serves;
  Json from = Json::array();
  for (const int fv : v.utility_from)
    from.push_back({{"frontier_void", fv}, {"void_id", a.frontier_voids[std::size_t(fv)].void_id},
                    {"utility_dm3", frontier_voids::to_dm3(a.frontier_voids[std::size_t(fv)].utility_m3)}});
  j["utility_from"] = from;
  j["pose_index"] = v.pose_index;
  j["stepped_back_from"] = v.stepped_back_from ? Json(*v.stepped_back_from) : Json(nullptr);
  j["polished_from"] = v.polished_from ? Json(*v.polished_from) : Json(nullptr);
  return j;
}

Json pruning_json(const nbv::Pruning& p) {
  return {{"utility_cells", p.utility_cells},
          {"not_free", p.not_free},
          {"outside_view_bounds", p.outside_view_bounds},
          {"too_close_to_obstacle", p.too_close_to_obstacle},
          {"unreachable_position", p.unreachable_position},
          {"candidate_cells", p.candidate_cells},
          {"too_near_a_tried_cell", p.too_near_a_tried_cell},
          {"cells_tried", p.cells_tried},
          {"orientations_sampled", p.orientations_sampled},
          {"unreachable_orientation", p.unreachable_orientation},
          {"ik_failed", p.ik_failed},
          {"valid_poses", p.valid_poses},
          {"refinement_steps", p.refinement_steps},
          {"refinement_poses", p.refinement_poses},
          {"polish_poses", p.polish_poses},
          {"culled_no_void_in_frustum", p.culled},
          {"seeing_no_void", p.seeing_nothing}};
}

std::pair<int, int> parse_rays(const Args& args) {
  if (!args.has("rays")) return {80, 60};
  const std::string text = args.get("rays");
  const auto x = text.find('x');
  if (x == std::string::npos) throw UsageError("--rays '" + text + "': expected COLSxROWS, e.g. 80x60");
  return {int(parse_int_in(text.substr(0, x), "--rays columns", 1, 4096)),
          int(parse_int_in(text.substr(x + 1), "--rays rows", 1, 4096))};
}

/// The search's options: strategy, sensor, rays, sampling, refinement, polish, accumulation.
nbv::Config parse_search_options(const Args& args) {
  const auto max_int = std::numeric_limits<int>::max();
  nbv::Config config;
  config.strategy = args.has("strategy") ? nbv::parse_strategy(args.get("strategy")) : config.strategy;
  config.sensor = parse_depth_camera(args, "nbv");
  std::tie(config.ray_cols, config.ray_rows) = parse_rays(args);
  config.top = int(args.integer("top", config.top, 1, max_int));
  config.valid_poses = int(args.integer("poses", config.valid_poses, 1, max_int));
  config.orientations_per_cell = int(args.integer("orientations", config.orientations_per_cell, 1, 10000));
  config.jitter_deg = args.number("jitter", config.jitter_deg, 0.0, 90.0);
  config.min_separation_m = args.number("separation", config.min_separation_m, 0.0, 10.0);
  config.clearance_m = args.number("clearance", config.clearance_m, 0.0, 2.0);
  config.refine_poses = int(args.integer("refine", config.refine_poses, 0, max_int));
  if (args.has("refine-step")) {
    const std::string text = args.get("refine-step");
    const bool with_max = text.find(',') != std::string::npos;
    const std::vector<double> v = parse_double_list(text, "--refine-step", with_max ? 2 : 1);
    config.refine_step_m = v[0];
    if (with_max) config.refine_max_m = v[1];
    if (!(config.refine_step_m > 0.0 && config.refine_step_m <= config.refine_max_m && config.refine_max_m <= 10.0))
      throw UsageError("--refine-step '" + args.get("refine-step") + "': expected 0 < STEP <= MAX <= 10 metres");
  }
  config.polish_poses = int(args.integer("polish", config.polish_poses, 0, max_int));
  config.climb_rounds = int(args.integer("climb", config.climb_rounds, 0, 100));
  config.exhaustive_rolls = int(args.integer("rolls", config.exhaustive_rolls, 1, 360));
  config.count_near_void_cells = parse_near_voids(args, true);
  config.view_bounds_m = parse_bounds(args, "view-bounds");
  config.seed = std::uint64_t(args.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
  config.threads = unsigned(args.integer("threads", 0, 0, 1024));
  parse_accumulation(args, config);
  return config;
}

/// The effective settings: the search's, then the analysis's and where the arm stands.
Json config_json(const nbv::Config& config, double target_size_m, int void_width,
                 const std::optional<Eigen::AlignedBox3d>& bounds, const voids::ClusterConfig& cluster_config,
                 const std::optional<Eigen::Isometry3d>& T_world_base) {
  Json j = nbv::config_json(config);
  j["target_size_m"] = target_size_m;
  j["min_void_width_cells"] = void_width;
  j["bounds_m"] = bounds_json(bounds);
  j["min_fit_score"] = cluster_config.min_fit_score;
  j["T_world_base"] = T_world_base ? pose_json(*T_world_base) : Json(nullptr);
  return j;
}

}  // namespace

Json nbv_results_json(const nbv::Result& r, const frontier_voids::Analysis& a, double R,
                      const std::vector<std::string>& joint_names, nbv::Strategy strategy, bool timing) {
  Json views = Json::array();
  for (std::size_t i = 0; i < r.views.size(); ++i)
    views.push_back(view_json(r.views[i], int(i + 1), R, a, joint_names, strategy));
  const std::size_t open = std::size_t(std::count_if(a.frontier_voids.begin(), a.frontier_voids.end(),
                                                     [](const auto& fv) { return !fv.enclosed(); }));
  Json results = {{"bounds_m", bounds_json(a.bounds_m)},
                  {"void_cells", a.void_cells.size()},
                  {"thin_void_cells", a.thin_void_cells},
                  {"void_clusters", a.void_clusters.size()},
                  {"frontier_cells", a.frontier_cells.size()},
                  {"frontier_voids_open", open},
                  {"utility_vectors", r.utility_vectors},
                  {"exact_utility_vectors", r.exact_utility_vectors},
                  {"poses_scored", r.poses_scored},
                  {"best_void_cells_seen", r.views.empty() ? 0 : r.views.front().void_cells_seen},
                  {"best_utility_dm3", r.views.empty() ? 0.0 : views.front()["utility_dm3"].get<double>()},
                  {"reason", r.reason.empty() ? Json(nullptr) : Json(r.reason)},
                  {"pruning", pruning_json(r.pruning)},
                  {"views", views}};
  if (timing) {
    const auto& t = r.timing;
    results["timing_s"] = {{"grid", t.grid_s},         {"accumulation", t.accumulation_s}, {"pruning", t.pruning_s},
                           {"sampling", t.sampling_s}, {"scoring", t.scoring_s},           {"total", t.total_s},
                           {"rays", t.rays},           {"cells_visited", t.cells_visited},
                           {"cells_per_s", t.scoring_s > 0 ? double(t.cells_visited) / t.scoring_s : 0.0}};
  }
  return results;
}

int run_nbv(const Args& args) {
  if (args.positional.size() != 1)
    throw UsageError("fvx nbv: give one map (.bt or .ot), got " + std::to_string(args.positional.size()));
  nbv::Config config = parse_search_options(args);
  const auto bounds = parse_bounds(args);
  voids::ClusterConfig cluster_config;
  cluster_config.min_fit_score = args.number("min-fit-score", cluster_config.min_fit_score, 0.0, 1.0, true);
  cluster_config.seed = config.seed;
  const double target_size_m = parse_target_size(args, 0.0);
  check_arm_options(args, "fvx nbv");
  if (config.strategy == nbv::Strategy::Exhaustive && !args.has("capmap"))
    throw UsageError("fvx nbv: --strategy exhaustive enumerates a capability map: give --capmap");
  // Output names are checked before the search, which may take seconds.
  if (args.has("utility-cloud") && lowercase_extension(args.get("utility-cloud")) != ".ply" &&
      lowercase_extension(args.get("utility-cloud")) != ".pcd")
    throw UsageError("--utility-cloud " + args.get("utility-cloud") + ": expected a .ply or .pcd file");
  if (args.has("picture") && lowercase_extension(args.get("picture")) != ".png")
    throw UsageError("--picture " + args.get("picture") + ": expected a .png file");

  // Inputs first, so that a bad file fails before any work.
  const map::OccupancyMap map = map::OccupancyMap::load(args.positional[0]);
  ArmInputs arm_inputs;
  load_arm_inputs(args, "fvx nbv", arm_inputs);
  const std::optional<nbv::Reach>& reach = arm_inputs.reach;
  const Eigen::Isometry3d& T_world_base = arm_inputs.T_world_base;
  const std::optional<capmap::Arm>& arm = arm_inputs.arm;

  config.keep_utility_field = args.has("utility-cloud") || args.has("picture");
  Progress progress(args.has("progress"));
  config.progress = [&](const std::string& stage, std::size_t done, std::size_t total) {
    progress.update("fvx nbv: " + stage + (total ? " " + std::to_string(done) + "/" + std::to_string(total) : ""));
  };
  progress.update("fvx nbv: frontiers, voids and frontier-voids of " + args.positional[0]);
  const int void_width = voids::void_width_for_target(target_size_m, map.resolution_m());
  const frontier_voids::Analysis a = frontier_voids::analyse_map(map, bounds, cluster_config, void_width);
  const nbv::Result r = nbv::select(map, a, reach, config);
  progress.finish();
  if (args.has("utility-cloud")) write_utility_cloud(args.get("utility-cloud"), r);
  if (args.has("picture")) write_utility_picture(args.get("picture"), map, a, r);

  const double R = map.resolution_m();
  Json report = new_report("nbv");
  report["config"] = config_json(config, target_size_m, void_width, bounds, cluster_config,
                                 reach ? std::optional<Eigen::Isometry3d>(T_world_base) : std::nullopt);
  report["inputs"] = {{"map", args.positional[0]},
                      {"resolution_m", R},
                      {"capmap", capmap_json(args, arm_inputs)},
                      {"arm", args.has("arm") ? Json(args.get("arm")) : Json(nullptr)}};
  report["results"] = nbv_results_json(r, a, R, arm ? arm->joint_names() : std::vector<std::string>{},
                                       config.strategy, args.has("timing"));
  Json warnings = a.warnings;
  if (!r.reason.empty()) warnings.push_back(r.reason);
  report["warnings"] = warnings;
  write_report(report, args.has("output") ? args.get("output") : "");
  return 0;
}

}  // namespace fvx::cli
