// fvx capmap — an arm's capability map: build, info, query, eval, export, merge.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <random>

#include "command_table.hpp"
#include "fvx/capmap/build.hpp"
#include "fvx/capmap/evaluate.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/io/visual.hpp"
#include "report.hpp"

namespace fvx::cli {

const CommandSpec kCapmapSpec = {
    "capmap",
    "build ARM.urdf --base LINK --tip LINK -o MAP.fcm | info MAP.fcm | query MAP.fcm --point P "
    "| eval MAP.fcm ARM.urdf | export MAP.fcm -o FILE.ply | merge PART.fcm... -o MAP.fcm",
    "capability maps of the arm that carries the sensor (where it can look from, and which way)",
    {
        {"output", 'o', "FILE", "build, merge: the map (.fcm); export: the cloud (.ply/.pcd)", "-"},
        {"base", 0, "LINK", "build: the arm's base link", "/results/header/base_link"},
        {"tip", 0, "LINK", "build: the link the sensor is mounted on", "/results/header/tip_link"},
        {"mount", 0, "x,y,z,roll,pitch,yaw", "build: sensor mount after the tip, metres and degrees "
                                             "(default 0)", "/results/header/mount_xyz_rpy"},
        {"axis", 0, "x,y,z", "build: viewing axis in the sensor frame (default 0,0,1)", "/results/header/viewing_axis"},
        {"voxel", 0, "M", "build: voxel edge, metres (default 0.05)", "/results/header/voxel_m"},
        {"directions", 0, "N", "build: viewing directions per voxel (default 200)", "/results/header/directions"},
        {"position-tolerance", 0, "M", "build: IK position tolerance, metres (default 0.005)",
         "/results/header/position_tolerance_m"},
        {"angle-tolerance", 0, "DEG", "build: IK angle tolerance, degrees (default: half the mean "
                                      "direction spacing)", "/results/header/angle_tolerance_deg"},
        {"seed", 0, "N", "build, eval: random seed (default 1)", "/config/seed"},
        {"fk-samples", 0, "N", "build: configurations of the forward pre-pass (default 400000)", "/config/fk_samples"},
        {"restarts", 0, "N", "build: IK restarts per bit after the seed (default 8)", "/config/ik_restarts"},
        {"exhaustive", 0, nullptr, "build: IK for every voxel and direction (a slow baseline)", "/config/exhaustive"},
        {"threads", 0, "N", "build: threads (default 0: all cores)", "/config/threads"},
        {"shard", 0, "I/N", "build: only z-slab I of N (1-based); merge the parts later",
         "/results/header/shard_index"},
        {"point", 0, "x,y,z", "query: a position in the base frame, metres", "/results/point_m"},
        {"direction", 0, "x,y,z", "query: a viewing direction (need not be unit)", "/results/direction"},
        {"samples", 0, "N", "eval: queries for precision and for recall each (default 2000)", "/config/samples"},
        {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
        {"help", 'h', nullptr, "show this help", "-"},
    }};

namespace {

std::atomic<bool> g_interrupted{false};
void on_interrupt(int) { g_interrupted = true; }

Eigen::Vector3d vec3(const Args& args, const std::string& name) {
  const auto v = parse_double_list(args.get(name), "--" + name, 3);
  return {v[0], v[1], v[2]};
}

std::string need(const Args& args, const std::string& name, const std::string& action) {
  if (!args.has(name)) throw UsageError("fvx capmap " + action + ": --" + name + " is required");
  return args.get(name);
}

Json header_json(const capmap::CapabilityHeader& h) {
  return {{"base_link", h.base_link},   {"tip_link", h.tip_link},   {"mount_xyz_rpy", h.mount_xyz_rpy},
          {"viewing_axis", vec_json(h.viewing_axis)},  {"urdf_hash", h.urdf_hash},
          {"voxel_m", h.voxel_m},       {"origin_m", vec_json(h.origin_m)},      {"dims", h.dims},
          {"directions", h.directions}, {"position_tolerance_m", h.position_tolerance_m},
          {"angle_tolerance_deg", h.angle_tolerance_rad * 180.0 / M_PI},      {"method", h.method},
          {"seed", h.seed},             {"shard_index", h.shard_index},     {"shard_count", h.shard_count},
          {"fvx_version", h.fvx_version}};
}

capmap::Arm load_arm(const std::string& urdf, const std::string& base, const std::string& tip, const Args& args) {
  capmap::ArmConfig config{base, tip};
  if (args.has("mount")) {
    config.T_tip_sensor = parse_xyz_rpy_deg(args.get("mount"), "--mount");
  }
  if (args.has("axis")) {
    const Eigen::Vector3d axis = vec3(args, "axis");
    if (axis.norm() < 1e-9) throw UsageError("--axis: the viewing axis must not be zero");
    config.viewing_axis_sensor = axis.normalized();
  }
  return capmap::Arm::from_urdf(urdf, config);
}

int build(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap build: give one URDF");
  const std::string output = need(args, "output", "build");
  if (lowercase_extension(output) != ".fcm") throw UsageError("fvx capmap build: --output " + output + ": expected a .fcm file");
  const capmap::Arm arm = load_arm(args.positional[1], need(args, "base", "build"), need(args, "tip", "build"), args);
  capmap::BuildConfig c;
  c.voxel_m = args.number("voxel", c.voxel_m, 0.0, 10.0, true);
  c.directions = int(args.integer("directions", c.directions, 1, 4096));
  c.position_tolerance_m = args.number("position-tolerance", c.position_tolerance_m, 0.0, 1.0, true);
  c.angle_tolerance_rad = args.number("angle-tolerance", 0.0, 0.0, 90.0, true) * M_PI / 180.0;
  c.seed = std::uint64_t(args.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
  c.fk_samples = std::size_t(args.integer("fk-samples", 400000, 1, 1000000000));
  c.ik_restarts = int(args.integer("restarts", c.ik_restarts, 0, 1000));
  c.threads = unsigned(args.integer("threads", 0, 0, 256));
  c.exhaustive = args.has("exhaustive");
  if (args.has("shard")) {
    const std::string s = args.get("shard");
    const auto slash = s.find('/');
    if (slash == std::string::npos) throw UsageError("--shard: expected I/N, e.g. 3/8");
    c.shard_count = std::uint32_t(parse_int_in(s.substr(slash + 1), "--shard N", 1, 100000));
    c.shard_index = std::uint32_t(parse_int_in(s.substr(0, slash), "--shard I", 1, c.shard_count)) - 1;
  }
  Progress progress(args.has("progress"));
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  capmap::BuildStats stats;
  const auto start = std::chrono::steady_clock::now();
  const capmap::CapabilityMap map = capmap::build_capability_map(
      arm, c, &stats,
      [&, last_percent = -1](std::size_t done, std::size_t total) mutable {
        const int percent = total ? int(100 * done / total) : 100;
        if (percent < last_percent + 5 && done < total) return;  // a line per 5 %
        last_percent = percent;
        progress.update("fvx capmap build: " + std::to_string(percent) + " % (" + std::to_string(done) + "/" +
                        std::to_string(total) + " bits checked)");
      },
      &g_interrupted);
  progress.finish();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (g_interrupted) throw Error("fvx capmap build: interrupted; " + output + " was not written");
  map.save(output);
  report["config"] = {{"seed", c.seed}, {"fk_samples", c.fk_samples}, {"ik_restarts", c.ik_restarts},
                      {"threads", c.threads}, {"exhaustive", c.exhaustive}};
  report["inputs"] = {{"urdf", args.positional[1]}, {"joints", arm.joint_names()}};
  report["results"] = {{"output", output},
                       {"header", header_json(map.header())},
                       {"voxels", map.voxel_count()},
                       {"bits", stats.reached},
                       {"candidates_checked", stats.candidates},
                       {"ik_iterations", stats.ik_iterations},
                       {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
  return 0;
}

int info(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap info: give one map");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  std::vector<std::size_t> histogram(10, 0);  // reachability index in 10 % bins
  std::size_t bits = 0;
  for (const auto& [voxel, words] : map.voxels()) {
    std::size_t n = 0;
    for (std::uint64_t w : words) n += std::size_t(__builtin_popcountll(w));
    bits += n;
    histogram[std::min<std::size_t>(9, n * 10 / std::size_t(map.header().directions))] += 1;
  }
  report["inputs"] = {{"map", args.positional[1]}};
  report["results"] = {{"header", header_json(map.header())}, {"voxels", map.voxel_count()}, {"bits", bits},
                       {"reachability_index_histogram", {{"bin_width_percent", 10}, {"voxels", histogram}}}};
  return 0;
}

int query(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap query: give one map");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  const Eigen::Vector3d p = vec3(args, "point");
  Json r = {{"point_m", vec_json(p)}, {"inside_grid", map.voxel_of(p) >= 0},
            {"reachability_index", map.reachability_index(p)}};
  if (args.has("direction")) {
    const Eigen::Vector3d d = vec3(args, "direction");
    if (d.norm() < 1e-9) throw UsageError("--direction must not be zero");
    r["direction"] = vec_json(d.normalized());
    r["reachable"] = map.reachable(p, d.normalized());
  }
  Json dirs = Json::array();
  for (int i : map.reachable_directions(p)) dirs.push_back(vec_json(map.directions()[i]));
  r["reachable_directions"] = dirs;
  report["inputs"] = {{"map", args.positional[1]}};
  report["results"] = r;
  return 0;
}

int eval(const Args& args, Json& report) {
  if (args.positional.size() != 3) throw UsageError("fvx capmap eval: give a map and the arm's URDF");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  const auto& h = map.header();
  const capmap::Arm arm = capmap::Arm::from_urdf(args.positional[2], capmap::arm_config_of(h));
  std::vector<std::string> warnings;
  if (arm.urdf_hash() != h.urdf_hash) warnings.push_back("the URDF differs from the one the map was built from");
  const int samples = int(args.integer("samples", 2000, 1, 100000000));
  const auto seed = std::uint64_t(args.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
  const capmap::Evaluation e = capmap::evaluate(map, arm, samples, seed);
  report["config"] = {{"seed", seed}, {"samples", samples}};
  report["inputs"] = {{"map", args.positional[1]}, {"urdf", args.positional[2]}};
  report["results"] = {{"precision", e.precision()},
                       {"precision_queries", e.precision_queries},
                       {"recall", e.recall()},
                       {"recall_queries", e.recall_queries}};
  report["warnings"] = warnings;
  return 0;
}

int export_cloud(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap export: give one map");
  const std::string output = need(args, "output", "export");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  std::vector<Eigen::Vector3f> points;
  std::vector<io::Rgb> colors;
  for (const auto& [voxel, words] : map.voxels()) {
    std::size_t n = 0;
    for (std::uint64_t w : words) n += std::size_t(__builtin_popcountll(w));
    const double ri = double(n) / map.header().directions;  // 0 … 1: blue (low) to red (high)
    points.push_back(map.center_of(voxel).cast<float>());
    colors.push_back({std::uint8_t(255 * std::min(1.0, 2 * ri)), 60, std::uint8_t(255 * std::max(0.0, 1 - 2 * ri))});
  }
  io::write_colored_cloud(output, points, colors);
  report["inputs"] = {{"map", args.positional[1]}};
  report["results"] = {{"output", output}, {"voxels", points.size()}};
  return 0;
}

int merge(const Args& args, Json& report) {
  if (args.positional.size() < 2) throw UsageError("fvx capmap merge: give the shard files");
  const std::string output = need(args, "output", "merge");
  std::vector<capmap::CapabilityMap> shards;
  for (std::size_t i = 1; i < args.positional.size(); ++i) shards.push_back(capmap::CapabilityMap::load(args.positional[i]));
  const auto map = capmap::CapabilityMap::merge(shards);
  map.save(output);
  report["inputs"] = {{"shards", std::vector<std::string>(args.positional.begin() + 1, args.positional.end())}};
  report["results"] = {{"output", output}, {"voxels", map.voxel_count()}};
  return 0;
}

}  // namespace

int run_capmap(const Args& args) {
  if (args.positional.empty())
    throw UsageError("fvx capmap: give an action: build, info, query, eval, export or merge");
  const std::string action = args.positional[0];
  Json report = new_report("capmap " + action);
  int status;
  if (action == "build") status = build(args, report);
  else if (action == "info") status = info(args, report);
  else if (action == "query") status = query(args, report);
  else if (action == "eval") status = eval(args, report);
  else if (action == "export") status = export_cloud(args, report);
  else if (action == "merge") status = merge(args, report);
  else throw UsageError("fvx capmap: '" + action + "' is not an action; use build, info, query, eval, export or merge");
  write_report(report, "");
  return status;
}

}  // namespace fvx::cli
