#include "fvx/pipeline/options.hpp"

#include <tuple>

#include <nlohmann/json.hpp>

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/io/camera_options.hpp"
#include "fvx/scan/load.hpp"

namespace fvx::pipeline {

OptionSpec resolution_option(const std::string& echo, const char* help, const std::string& note) {
  return {"resolution", 'r', "M", help, echo, dflt(kDefaultResolution_m) + note, in(0.001, 1)};
}

OptionSpec discretize_option(const std::string& echo) {
  return {"discretize", 0, nullptr, "OctoMap's discretised insertion: one ray per distinct endpoint cell, to its "
                                    "centre (insertPointCloud's discretize; faster, a slightly different map)", echo};
}

OptionSpec max_time_diff_option() {
  return {"max-time-diff", 0, "S", "largest stamp difference when matching by timestamp, seconds",
          "/config/max_time_diff_s", dflt(scan::LoadConfig{}.max_time_diff_s), in(0, 1e6)};
}

std::vector<OptionSpec> trajectory_options(bool replay) {
  const char* help = replay ? "pose priors for --scans (default: each scan's own, e.g. a PCD's VIEWPOINT) or --tum: "
                              "a TUM (stamp tx ty tz qx qy qz qw, or without stamp), Redwood .log or KITTI file, "
                              "or a folder of per-frame 4x4 pose files (frame-XXXXXX.pose.txt, ScanNet's N.txt)"
                            : "pose priors: a TUM (stamp tx ty tz qx qy qz qw, or without stamp), Redwood .log or "
                              "KITTI file, or a folder of per-frame 4x4 pose files (frame-XXXXXX.pose.txt, "
                              "ScanNet's N.txt)";
  return {{"trajectory", 't', "FILE|DIR", help, "/inputs/trajectory"},
          {"pose-format", 0, "NAME", "the --trajectory file's format: auto (by the file: a folder of "
                                     "per-frame 4x4 files, .log Redwood, 7 or 8 fields TUM, 12 KITTI), tum, "
                                     "redwood or kitti (3x4 rows)", "/config/pose_format", "auto"},
          max_time_diff_option()};
}

std::vector<OptionSpec> bag_options() {
  return {{"bag", 0, "FILE", "scans from a ROS 1 bag: --topic's PointCloud2 or depth Image (+ its CameraInfo), "
                             "posed by the bag's /tf and /tf_static", "/inputs/bag"},
          {"topic", 0, "NAME", "with --bag: the scans' topic", "/inputs/topic"},
          {"fixed-frame", 0, "NAME", "with --bag: the world frame of the poses (e.g. odom or map)", "/inputs/fixed_frame"},
          {"frame", 0, "NAME", "with --bag: the scans' frame, instead of each message's header.frame_id",
           "/inputs/frame"}};
}

std::optional<io::BagQuery> read_bag_options(const Args& args, const std::optional<io::Intrinsics>& intrinsics) {
  if (!args.has("bag")) {
    for (const char* name : {"topic", "fixed-frame", "frame"})
      if (args.has(name)) throw UsageError(std::string("--") + name + " goes with --bag");
    return std::nullopt;
  }
  if (!args.positional.empty()) throw UsageError("give scan files (or a session) or --bag, not both");
  if (!args.has("topic") || !args.has("fixed-frame"))
    throw UsageError("--bag needs --topic (the scans) and --fixed-frame (the world frame of their poses)");
  for (const char* name : {"trajectory", "pose", "pose-format"})
    if (args.has(name)) throw UsageError(std::string("--") + name + ": a bag's scans are posed by its TF, not by --" + name);
  io::BagQuery query{args.get("bag"), args.get("topic"), args.get("fixed-frame"), "", intrinsics};
  if (args.has("frame")) query.sensor_frame = args.get("frame");
  return query;
}

Json bag_inputs_json(const std::optional<io::BagQuery>& query) {
  if (!query) return {{"bag", nullptr}, {"topic", nullptr}, {"fixed_frame", nullptr}, {"frame", nullptr}};
  return {{"bag", query->path}, {"topic", query->topic}, {"fixed_frame", query->fixed_frame},
          {"frame", query->sensor_frame.empty() ? Json(nullptr) : Json(query->sensor_frame)}};
}

void read_trajectory_options(const Args& args, scan::LoadConfig& load) {
  if (args.has("pose-format") && !args.has("trajectory")) throw UsageError("--pose-format goes with --trajectory");
  if (args.has("trajectory")) load.trajectory_path = args.get("trajectory");
  if (args.has("pose-format")) load.pose_format = io::parse_pose_format(args.get("pose-format"), "--pose-format");
  args.read("max-time-diff", load.max_time_diff_s);
}

OptionSpec min_fit_score_option(const std::string& echo, const char* help) {
  return {"min-fit-score", 0, "S", help, echo, dflt(voids::ClusterConfig{}.min_fit_score), above(0, 1)};
}

std::optional<Eigen::AlignedBox3d> parse_bounds(const Args& args, const std::string& name) {
  if (!args.has(name)) return std::nullopt;
  const auto b = parse_double_list(args.get(name), "--" + name + " (x0,y0,z0,x1,y1,z1)", 6);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(b[0], b[1], b[2]), Eigen::Vector3d(b[3], b[4], b[5]));
  if (!(box.min().array() < box.max().array()).all())
    throw UsageError("--" + name + ": the minimum must be below the maximum on every axis");
  return box;
}

namespace {

std::pair<int, int> parse_rays(const Args& args) {
  if (!args.has("rays")) return {nbv::Config{}.ray_cols, nbv::Config{}.ray_rows};
  return parse_cols_rows(args.get("rays"), "--rays");
}

}  // namespace

nbv::Config read_search_options(const Args& args) {
  nbv::Config config;
  config.strategy = args.has("strategy") ? nbv::parse_strategy(args.get("strategy")) : config.strategy;
  config.sensor = io::parse_depth_camera(args, "nbv");
  std::tie(config.ray_cols, config.ray_rows) = parse_rays(args);
  args.read("top", config.top);
  args.read("poses", config.valid_poses);
  args.read("rescore", config.rescored_poses);
  args.read("orientations", config.orientations_per_cell);
  args.read("jitter", config.jitter_deg);
  args.read("separation", config.min_separation_m);
  args.read("clearance", config.clearance_m);
  args.read("refine", config.refine_poses);
  if (args.has("refine-step")) {
    const std::string text = args.get("refine-step");
    const bool with_max = text.find(',') != std::string::npos;
    const std::vector<double> v = parse_double_list(text, "--refine-step", with_max ? 2 : 1);
    config.refine_step_m = v[0];
    if (with_max) config.refine_max_m = v[1];
    if (!(config.refine_step_m > 0.0 && config.refine_step_m <= config.refine_max_m && config.refine_max_m <= 10.0))
      throw UsageError("--refine-step '" + args.get("refine-step") + "': expected 0 < STEP <= MAX <= 10 metres");
  }
  args.read("polish", config.polish_poses);
  args.read("climb", config.climb_rounds);
  args.read("rolls", config.exhaustive_rolls);
  config.count_near_void_cells = parse_near_voids(args, true);
  config.near_unknown = parse_near_unknown(args, config.near_unknown);
  config.exterior = parse_exterior(args, config.exterior);
  config.view_bounds_m = parse_bounds(args, "view-bounds");
  args.read("seed", config.seed);
  args.read("threads", config.threads);
  parse_accumulation(args, config);
  return config;
}


double parse_resolution(const Args& args, double fallback) {
  return args.number("resolution", fallback);
}

std::vector<OptionSpec> near_voids_options(const std::string& echo) {
  return {{"far-voids-only", 0, nullptr, "only what the sensor can measure: U counts void cells from its minimum "
                                         "depth on, Algorithm 1 adds utility from that distance beyond the "
                                         "frontier (default: every void cell a ray crosses, utility from the "
                                         "frontier on)", echo + "/count_near_void_cells"},
          {"near-voids", 0, nullptr, "every void cell a ray crosses counts (the default; kept for scripts)",
           echo + "/count_near_void_cells"}};
}

bool parse_near_voids(const Args& args, bool fallback) {
  if (args.has("near-voids") && args.has("far-voids-only"))
    throw UsageError("--near-voids and --far-voids-only contradict each other: give one");
  if (args.has("near-voids")) return true;
  if (args.has("far-voids-only")) return false;
  return fallback;
}

OptionSpec void_hull_option(const std::string& echo) {
  return {"void-hull", 0, "MODE", "the voids' hull: map (default: of every occupied cell, the paper's accumulated "
                                  "cloud) or search-space (of the occupied cells in the search space only)", echo};
}

std::vector<OptionSpec> void_model_options(const std::string& pipeline_echo, const std::string& nbv_echo) {
  return {void_hull_option(pipeline_echo + "/hull_in_bounds"),
          {"unknown-depth", 0, "N", "U counts only the first N unknown cells of each ray, those a view reveals for "
                                    "sure (default 0: every void cell a ray crosses, the paper's)",
           nbv_echo + "/unknown_depth_cells", dflt(0), in(0, 1000)},
          {"near-unknown", 0, "MODE", "what an unknown cell nearer than the sensor's minimum depth does to a ray of "
                                      "U: ignore (nothing), void (a void cell there leaves the ray "
                                      "counting nothing, as a surface hidden in it leaves the pixel without depth), "
                                      "any (any unknown cell there) or hidden (the default: a void cell there in a void where a view "
                                      "taken left cells it was expected to reveal unknown, in explore and replay; a "
                                      "single search has none)", nbv_echo + "/near_unknown"},
          {"exterior", 0, "MODE", "unknown cells outside the voids' hull: view (the default: taken for air, as "
                                  "MoveIt's collision checking takes unknown space: viewpoints may stand in them, "
                                  "anywhere in the arm's reach within --depth-max of the search space), unknown "
                                  "(the paper's: the sensor stands in a known free cell) or free (view, and "
                                  "Algorithm 1's rays pass them)",
           nbv_echo + "/exterior"}};
}

nbv::Exterior parse_exterior(const Args& args, nbv::Exterior fallback) {
  return args.has("exterior") ? nbv::parse_exterior(args.get("exterior"), "--exterior") : fallback;
}

viewpoints::NearUnknown parse_near_unknown(const Args& args, viewpoints::NearUnknown fallback) {
  return args.has("near-unknown") ? viewpoints::parse_near_unknown(args.get("near-unknown"), "--near-unknown")
                                  : fallback;
}

bool parse_void_hull(const Args& args, bool fallback) {
  if (!args.has("void-hull")) return fallback;
  const std::string mode = args.get("void-hull");
  if (mode != "map" && mode != "search-space")
    throw UsageError("--void-hull '" + mode + "': expected map or search-space");
  return mode == "search-space";
}

std::vector<OptionSpec> search_model_options(const std::string& pipeline_echo, const std::string& nbv_echo) {
  return options({near_voids_options(nbv_echo), target_size_options(pipeline_echo), accumulation_options(nbv_echo),
                  void_model_options(pipeline_echo, nbv_echo), io::depth_camera_options(nbv_echo)});
}

std::vector<OptionSpec> target_size_options(const std::string& echo) {
  return {{"target-size", 0, "M", "the searched object's smallest extent, metres: only void cells in an all-unknown "
                                  "cube of floor(M/R)-1 cells count, as only those can hide it", echo + "/target_size_m",
           dflt(pipeline::Config{}.target_size_m) + ": every void cell, the paper's", in(0, 10)}};
}

std::vector<OptionSpec> accumulation_options(const std::string& echo) {
  return {{"accumulation", 0, "MODE", "Algorithm 1's accumulation: sampled (default: above --utility-vectors, "
                                      "a stratified sample of each frontier-void's frontier cells, weighted so "
                                      "that the expected field is the exact one) or exact (every utility vector, "
                                      "the paper's; minutes on large maps)", echo + "/accumulation"},
          {"utility-vectors", 0, "N", "sampled: trace about N utility vectors at most; under it the field is exact",
           echo + "/max_utility_vectors", dflt(nbv::Config{}.max_utility_vectors),
           in(7, double(std::numeric_limits<long long>::max()))},
          {"coarse-rays", 0, "COLSxROWS", "frontier-void and exhaustive: screen the poses with this coarser "
                                          "fan of field-of-view rays (exhaustive, above 1024 poses: the best "
                                          "quarter by a fan half as fine each way), then rank the best with "
                                          "the full fan (--rays); off: every pose with the full fan",
           echo + "/coarse_rays",
           dflt(nbv::Config{}.coarse_ray_cols) + "x" + dflt(nbv::Config{}.coarse_ray_rows)}};
}

std::pair<int, int> parse_cols_rows(const std::string& text, const std::string& option) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw UsageError(option + " '" + text + "': expected COLSxROWS, e.g. 80x60");
  return {int(parse_int_in(text.substr(0, x), option + " columns", 1, 4096)),
          int(parse_int_in(text.substr(x + 1), option + " rows", 1, 4096))};
}

void parse_accumulation(const Args& args, nbv::Config& config) {
  if (args.has("accumulation")) config.accumulation = utility::parse_accumulation(args.get("accumulation"));
  args.read("utility-vectors", config.max_utility_vectors);
  if (!args.has("coarse-rays")) return;
  if (args.get("coarse-rays") == "off")
    config.coarse_ray_cols = config.coarse_ray_rows = 0;
  else
    std::tie(config.coarse_ray_cols, config.coarse_ray_rows) = parse_cols_rows(args.get("coarse-rays"), "--coarse-rays");
}

double parse_target_size(const Args& args, double fallback) {
  return args.number("target-size", fallback);
}

}  // namespace fvx::pipeline
