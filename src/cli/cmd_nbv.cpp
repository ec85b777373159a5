// fvx nbv — a map (+ an arm's capability map) → the ranked next best views (paper §IV-C,
// Algorithm 1 and Eq. 3).

#include "analysis_output.hpp"
#include "command_table.hpp"
#include "fvx/core/atomic_file.hpp"  // lowercase_extension
#include "common_options.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/report/nbv.hpp"
#include "fvx/report/picture3d.hpp"
#include "fvx/voids/width.hpp"

namespace fvx::cli {

namespace {
const nbv::Config kNbv;  ///< the defaults --help shows
}  // namespace

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
                 {"top", 'n', "N", "ranked views to report", "/config/top", dflt(kNbv.top), in(1, kMaxInt)},
                 {"poses", 'N', "N", "stop after N valid poses", "/config/valid_poses", dflt(kNbv.valid_poses) + ", as in the paper",
                  in(1, kMaxInt)},
                 {"rescore", 0, "K", "rescore the K best screened poses with the full fan of rays",
                  "/config/rescored_poses", "0: top + min(top, 10)", in(0, kMaxInt)},
                 {"orientations", 0, "K", "orientations sampled per candidate cell", "/config/orientations_per_cell",
                  dflt(kNbv.orientations_per_cell), in(1, 10000)},
                 {"separation", 0, "M", "pass over cells nearer than M to a viewpoint already used, metres",
                  "/config/min_separation_m", dflt(kNbv.min_separation_m) + "; 0: every cell in utility order", in(0, 10)},
                 {"refine", 0, "K", "step the K best poses back along their optical axis and score the steps",
                  "/config/refine_poses", dflt(kNbv.refine_poses) + "; 0: off, as the paper", in(0, kMaxInt)},
                 {"refine-step", 0, "M", "refinement step and its limit, metres: STEP or STEP,MAX, 0 < STEP <= MAX <= 10",
                  "/config/refine_step_m", dflt(kNbv.refine_step_m) + "," + dflt(kNbv.refine_max_m)},
                 {"polish", 0, "K", "score the K best poses at 5 more rolls about their optical axis, 30 degrees apart",
                  "/config/polish_poses", dflt(kNbv.polish_poses) + "; 0: off, as the paper", in(0, kMaxInt)},
                 {"climb", 0, "N", "then N rounds of a local climb from each of the K best poses: moved 5 cm along "
                                   "each axis and tilted 4 degrees, halving when nothing is better",
                  "/config/climb_rounds", dflt(kNbv.climb_rounds) + ": off, as the paper", in(0, 100)},
                 {"jitter", 0, "DEG", "tilt of sampled axes around their target, degrees", "/config/jitter_deg",
                  dflt(kNbv.jitter_deg), in(0, 90)},
                 {"clearance", 0, "M", "no occupied cell within M of a viewpoint, metres", "/config/clearance_m",
                  dflt(kNbv.clearance_m), in(0, 2)},
                 {"rays", 0, "COLSxROWS", "field-of-view rays: a decimated pixel grid, 1 to 4096 each", "/config/rays",
                  dflt(kNbv.ray_cols) + "x" + dflt(kNbv.ray_rows)},
                 {"rolls", 0, "N", "exhaustive: rolls per direction over 180 degrees", "/config/exhaustive_rolls",
                  dflt(kNbv.exhaustive_rolls), in(1, 360)},
                 {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space S, metres (default: the box of the known cells)",
                  "/config/bounds_m"},
                 {"view-bounds", 0, "x0,y0,z0,x1,y1,z1", "the sensor stays in this box, metres (default: the "
                                                         "box of the known cells)", "/config/view_bounds_m"},
                 min_fit_score_option("/config/min_fit_score", "void clusters keep a fit score (Eq. 2) at or above S"),
                 seed_option("/config/seed", "seed of cluster growing, orientation jitter and roll, IK restarts", kNbv.seed),
                 threads_option("/config/threads", "threads for accumulation and scoring", "; same result"),
             },
             search_model_options("/config", "/config"),
             {
                 {"utility-cloud", 0, "FILE", "the utility field as a coloured cloud, .ply or .pcd: red (low), "
                                              "yellow, green (high) by rank; pruned cells grey", "-"},
                 {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
                 {"timing", 0, nullptr, "add the search time split (grid, accumulation, pruning, sampling, "
                                        "scoring) and ray-casting speed to the report", "-"},
                 {"help", 'h', nullptr, "show this help", "-"},
             },
             report::picture_options(false, "a 3-D picture: the search space's cells, void ellipsoids, the utility "
                                            "field by rank and the best view's frustum",
                                     "a top view of the utility field, the voids and the best view")})};


int run_nbv(const Args& args) {
  if (args.positional.size() != 1)
    throw UsageError("fvx nbv: give one map (.bt or .ot), got " + std::to_string(args.positional.size()));
  nbv::Config config = pipeline::read_search_options(args);
  const auto bounds = parse_bounds(args);
  voids::ClusterConfig cluster_config;
  args.read("min-fit-score", cluster_config.min_fit_score);
  cluster_config.seed = config.seed;
  const double target_size_m = parse_target_size(args, 0.0);
  const bool hull_in_bounds = parse_void_hull(args, false);
  args.read("unknown-depth", config.unknown_depth_cells);
  check_arm_options(args, "fvx nbv");
  if (config.strategy == nbv::Strategy::Exhaustive && !args.has("capmap"))
    throw UsageError("fvx nbv: --strategy exhaustive enumerates a capability map: give --capmap");
  // Output names are checked before the search, which may take seconds.
  if (args.has("utility-cloud") && lowercase_extension(args.get("utility-cloud")) != ".ply" &&
      lowercase_extension(args.get("utility-cloud")) != ".pcd")
    throw UsageError("--utility-cloud " + args.get("utility-cloud") + ": expected a .ply or .pcd file");
  const report::PictureRequest pictures = report::read_picture_options(args);

  // Inputs first, so that a bad file fails before any work.
  const map::OccupancyMap map = map::OccupancyMap::load(args.positional[0]);
  ArmInputs arm_inputs;
  load_arm_inputs(args, "fvx nbv", arm_inputs);
  const std::optional<nbv::Reach>& reach = arm_inputs.reach;
  const Eigen::Isometry3d& T_world_base = arm_inputs.T_world_base;

  config.keep_utility_field = args.has("utility-cloud") || args.has("picture") || args.has("picture-top");
  Progress progress(args.has("progress"));
  config.progress = [&](const std::string& stage, std::size_t done, std::size_t total) {
    progress.update("fvx nbv: " + stage + (total ? " " + std::to_string(done) + "/" + std::to_string(total) : ""));
  };
  progress.update("fvx nbv: frontiers, voids and frontier-voids of " + args.positional[0]);
  cluster_config.progress = config.progress;
  const int void_width = voids::void_width_for_target(target_size_m, map.resolution_m());
  const frontier_voids::Analysis a = frontier_voids::analyse_map(map, bounds, cluster_config, void_width, true, hull_in_bounds);
  const nbv::Result r = nbv::select(map, a, reach, config);
  progress.finish();
  if (args.has("utility-cloud")) write_utility_cloud(args.get("utility-cloud"), r);
  const Json picture = report::write_search_pictures(pictures, map, a, r, config.sensor,
                                                     reach ? std::optional<Eigen::Vector3d>(T_world_base.translation()) : std::nullopt);

  const double R = map.resolution_m();
  Json report = new_report("nbv");
  report["config"] = search_config_json(config, target_size_m, void_width, hull_in_bounds, bounds, cluster_config,
                                 reach ? std::optional<Eigen::Isometry3d>(T_world_base) : std::nullopt);
  report["inputs"] = {{"map", args.positional[0]},
                      {"resolution_m", R},
                      {"capmap", capmap_json(args, arm_inputs)},
                      {"arm", args.has("arm") ? Json(args.get("arm")) : Json(nullptr)}};
  report["results"] = nbv_results_json(r, a, R, arm_inputs.joint_names(),
                                       config.strategy, args.has("timing"));
  report["results"]["picture"] = picture;
  Json warnings = a.warnings;
  if (!r.reason.empty()) warnings.push_back(r.reason);
  report["warnings"] = warnings;
  write_report(report, args.has("output") ? args.get("output") : "");
  return core::end_process(0);
}

}  // namespace fvx::cli
