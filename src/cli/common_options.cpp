#include "common_options.hpp"

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/sim/builtin_scenes.hpp"

namespace fvx::cli {

std::vector<OptionSpec> options(std::initializer_list<std::vector<OptionSpec>> tables) {
  std::vector<OptionSpec> all;
  for (const auto& table : tables) all.insert(all.end(), table.begin(), table.end());
  return all;
}

std::vector<OptionSpec> intrinsics_options(bool with_size, const std::string& echo) {
  std::vector<OptionSpec> table = {
      {"intrinsics", 'K', "FILE", "depth camera intrinsics JSON (fvx or Open3D layout)", echo},
      {"fx", 0, "PX", "focal length along u, pixels (overrides --intrinsics; default 525)", echo + "/fx"},
      {"fy", 0, "PX", "focal length along v, pixels; may be negative (default 525)", echo + "/fy"},
      {"cx", 0, "PX", "principal point u, pixels (default 319.5)", echo + "/cx"},
      {"cy", 0, "PX", "principal point v, pixels (default 239.5)", echo + "/cy"},
      {"depth-scale", 0, "N", "raw depth units per metre: 1000 (mm) or 5000 (TUM) (default 1000)",
       echo + "/depth_scale"},
  };
  if (with_size) {
    table.push_back({"width", 0, "PX", "image width, pixels (default 640)", echo + "/width"});
    table.push_back({"height", 0, "PX", "image height, pixels (default 480)", echo + "/height"});
  }
  return table;
}

namespace {

/// --fx … --height over `K`.
io::Intrinsics apply_intrinsics_flags(const Args& args, io::Intrinsics K) {
  const double big = 1e6;
  K.fx = args.number("fx", K.fx, -big, big);
  K.fy = args.number("fy", K.fy, -big, big);
  K.cx = args.number("cx", K.cx, -big, big);
  K.cy = args.number("cy", K.cy, -big, big);
  K.depth_scale = args.number("depth-scale", K.depth_scale, 0.0, big, true);
  K.width = int(args.integer("width", K.width, 1, 16384));
  K.height = int(args.integer("height", K.height, 1, 16384));
  return K;
}

}  // namespace

std::optional<io::Intrinsics> parse_intrinsics(const Args& args, const std::string& command) {
  const bool any_flag = args.has("fx") || args.has("fy") || args.has("cx") || args.has("cy") ||
                        args.has("depth-scale") || args.has("width") || args.has("height");
  if (!args.has("intrinsics") && !any_flag) return std::nullopt;
  const io::Intrinsics K = apply_intrinsics_flags(
      args, args.has("intrinsics") ? io::read_intrinsics(args.get("intrinsics")) : io::Intrinsics{});
  throw_if_problems("fvx " + command + ": intrinsics", K.validate());
  return K;
}

std::vector<OptionSpec> depth_camera_options(const std::string& echo) {
  return options({{{"sensor", 0, "FILE", "sensor JSON: intrinsics, width, height, depth_min_m, depth_max_m "
                                         "(default Kinect v1: 640x480, f 525, 0.5-4 m)", echo + "/sensor"},
                   {"depth-min", 0, "M", "nearest measured depth, metres (overrides --sensor; default 0.5)",
                    echo + "/sensor/depth_min_m"},
                   {"depth-max", 0, "M", "farthest measured depth = sensor range s_r, metres (default 4)",
                    echo + "/sensor/depth_max_m"}},
                  intrinsics_options(true, echo + "/sensor/intrinsics")});
}

io::DepthCamera parse_depth_camera(const Args& args, const std::string& command) {
  io::DepthCamera camera = args.has("sensor") ? io::read_depth_camera(args.get("sensor")) : io::DepthCamera{};
  if (args.has("intrinsics")) camera.intrinsics = io::read_intrinsics(args.get("intrinsics"));
  camera.intrinsics = apply_intrinsics_flags(args, camera.intrinsics);
  camera.depth_min_m = args.number("depth-min", camera.depth_min_m, 0.0, 1e3);
  camera.depth_max_m = args.number("depth-max", camera.depth_max_m, 0.0, 1e3, true);
  throw_if_problems("fvx " + command + ": sensor", camera.validate());
  return camera;
}

double parse_resolution(const Args& args, double fallback) {
  return args.number("resolution", fallback, 0.001, 1.0);
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

std::vector<OptionSpec> arm_options() {
  return {
      {"capmap", 0, "FILE.fcm", "the arm's capability map (fvx capmap build)", "/inputs/capmap/file"},
      {"base", 0, "x,y,z,roll,pitch,yaw", "T_world_base: where the capability map's base stands, "
                                          "metres and degrees (default 0,0,0,0,0,0)", "/inputs/capmap/T_world_base"},
      {"no-capmap", 0, nullptr, "a free-flying sensor: no reachability constraint", "/inputs/capmap"},
      {"arm", 0, "URDF", "the arm the capability map was built for: each view then needs IK, "
                         "which gives its joint configuration", "/inputs/capmap/arm"},
  };
}

void check_arm_options(const Args& args, const std::string& command) {
  if (args.has("capmap") == args.has("no-capmap"))
    throw UsageError(command + ": give --capmap FILE.fcm (with --base) for an arm, or --no-capmap for a free-flying sensor");
  if (args.has("no-capmap") && (args.has("base") || args.has("arm")))
    throw UsageError(command + ": --base and --arm need --capmap");
}

void load_arm_inputs(const Args& args, const std::string& command, ArmInputs& out) {
  check_arm_options(args, command);
  out.T_world_base = args.has("base") ? parse_xyz_rpy_deg(args.get("base"), "--base") : Eigen::Isometry3d::Identity();
  if (!args.has("capmap")) return;
  load_arm_files(args.get("capmap"), args.has("arm") ? args.get("arm") : "", out.T_world_base, command, out);
}

void load_arm_files(const std::string& capmap_path, const std::string& urdf_path,
                    const Eigen::Isometry3d& T_world_base, const std::string& command, ArmInputs& out) {
  out.T_world_base = T_world_base;
  out.capability_map = capmap::CapabilityMap::load(capmap_path);
  const capmap::CapabilityHeader& h = out.capability_map->header();
  if (h.shard_count != 1)
    throw UsageError(command + ": " + capmap_path + " is shard " + std::to_string(h.shard_index) + " of " +
                     std::to_string(h.shard_count) + "; merge the shards first (fvx capmap merge)");
  if (!urdf_path.empty()) {
    out.arm = capmap::Arm::from_urdf(urdf_path, capmap::arm_config_of(h));
    if (out.arm->urdf_hash() != h.urdf_hash)
      throw Error(command + ": " + capmap_path + " was built from another URDF than " + urdf_path +
                  " (hash " + h.urdf_hash + " vs " + out.arm->urdf_hash() + "); rebuild it with fvx capmap build");
  }
  out.reach = nbv::Reach{&*out.capability_map, out.T_world_base, out.arm ? &*out.arm : nullptr, {}};
  out.reach->ik.position_tolerance_m = h.position_tolerance_m;
  out.reach->ik.angle_tolerance_rad = h.angle_tolerance_rad;
}

Json capmap_json(const std::string& path, const std::string& urdf_path, const ArmInputs& in) {
  if (!in.capability_map) return nullptr;
  const capmap::CapabilityHeader& h = in.capability_map->header();
  return {{"file", path},
          {"base_link", h.base_link},
          {"tip_link", h.tip_link},
          {"urdf_hash", h.urdf_hash},
          {"voxel_m", h.voxel_m},
          {"directions", h.directions},
          {"T_world_base", pose_json(in.T_world_base)},
          {"arm", urdf_path.empty() ? Json(nullptr) : Json(urdf_path)}};
}

Json capmap_json(const Args& args, const ArmInputs& in) {
  return capmap_json(args.has("capmap") ? args.get("capmap") : "", args.has("arm") ? args.get("arm") : "", in);
}

std::vector<OptionSpec> search_model_options(const std::string& pipeline_echo, const std::string& nbv_echo) {
  return options({near_voids_options(nbv_echo), target_size_options(pipeline_echo), accumulation_options(nbv_echo),
                  depth_camera_options(nbv_echo)});
}

std::vector<OptionSpec> session_report_options() {
  return {{"timing", 0, nullptr, "add per-stage times (seconds) to the reports (without it they repeat "
                                 "byte for byte)", "-"},
          {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
          {"help", 'h', nullptr, "show this help", "-"}};
}

double parse_depth_noise(const Args& args) {
  const std::string model = args.has("noise") ? args.get("noise") : "none";
  if (model == "kinect") return 1.4e-3;
  if (model != "none") throw UsageError("--noise: '" + model + "' is not a noise model; use none or kinect");
  return 0.0;
}

std::vector<OptionSpec> target_size_options(const std::string& echo) {
  return {{"target-size", 0, "M", "the searched object's smallest extent, metres: only void cells in an all-unknown "
                                  "cube of floor(M/R)-1 cells count, as only those can hide it (default 0: every "
                                  "void cell, the paper's)", echo + "/target_size_m"}};
}

std::vector<OptionSpec> accumulation_options(const std::string& echo) {
  return {{"accumulation", 0, "MODE", "Algorithm 1's accumulation: sampled (default: above --utility-vectors, "
                                      "a stratified sample of each frontier-void's frontier cells, weighted so "
                                      "that the expected field is the exact one) or exact (every utility vector, "
                                      "the paper's; minutes on large maps)", echo + "/accumulation"},
          {"utility-vectors", 0, "N", "sampled: trace about N utility vectors at most (default 2097152); "
                                      "under it the field is exact", echo + "/max_utility_vectors"}};
}

void parse_accumulation(const Args& args, nbv::Config& config) {
  if (args.has("accumulation")) config.accumulation = utility::parse_accumulation(args.get("accumulation"));
  config.max_utility_vectors = std::size_t(
      args.integer("utility-vectors", (long long)config.max_utility_vectors, 7, std::numeric_limits<long long>::max()));
}

double parse_target_size(const Args& args, double fallback) {
  return args.has("target-size") ? args.number("target-size", 0.0, 0.0, 10.0) : fallback;
}

Eigen::Isometry3d parse_look_at(const std::string& text, const std::string& what) {
  const std::vector<double> v = parse_double_list(text, what + " (ex,ey,ez,tx,ty,tz)", 6);
  const Eigen::Vector3d eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]);
  const Eigen::Vector3d z = target - eye;
  if (z.norm() < 1e-9) throw UsageError(what + ": the eye and the target coincide");
  const Eigen::Vector3d forward = z.normalized();
  // Optical frame: x right, y down. Looking straight up or down, take world x as "up".
  const Eigen::Vector3d up = std::abs(forward.z()) > 0.999 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d x = forward.cross(up).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, forward.cross(x), forward;
  T.translation() = eye;
  return T;
}

sim::Scene scene_from(const std::string& source, const Args& args) {
  const std::string prefix = "builtin:";
  if (source.rfind(prefix, 0) == 0) {
    sim::Scene s = sim::builtin_scene(source.substr(prefix.size()));
    if (args.has("scene-info")) {
      s.info = sim::read_scene_info(args.get("scene-info"));
      s.info_path = args.get("scene-info");
    }
    return s;
  }
  return sim::load_scene(source, args.has("scene-info") ? args.get("scene-info") : "");
}

nbv::Strategy parse_strategy_option(const Args& args, const std::string& command, nbv::Strategy fallback) {
  if (args.has("strategy") && args.has("planner"))
    throw UsageError("fvx " + command + ": --planner is another name for --strategy: give one");
  if (args.has("strategy")) return nbv::parse_strategy(args.get("strategy"), "--strategy");
  if (args.has("planner")) return nbv::parse_strategy(args.get("planner"), "--planner");
  return fallback;
}

}  // namespace fvx::cli
