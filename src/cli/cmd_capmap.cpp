// fvx capmap — an arm's capability map: build, info, query, eval, export, merge.
#include <atomic>
#include <csignal>
#include <cmath>
#include <iostream>

#include "command_table.hpp"
#include "fvx/core/atomic_file.hpp"  // lowercase_extension
#include "common_options.hpp"
#include "fvx/capmap/build.hpp"
#include "fvx/capmap/evaluate.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/core/stopwatch.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/report/capmap.hpp"
#include "report.hpp"

namespace fvx::cli {

namespace {
const capmap::BuildConfig kBuild;  ///< the defaults --help shows
constexpr int kEvalSamples = 2000;  ///< eval: queries for precision and for recall each
}  // namespace

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
        {"voxel", 0, "M", "build: voxel edge, metres", "/results/header/voxel_m", dflt(kBuild.voxel_m), above(0, 10)},
        {"directions", 0, "N", "build: viewing directions per voxel", "/results/header/directions",
         dflt(kBuild.directions), in(1, 4096)},
        {"position-tolerance", 0, "M", "build: IK position tolerance, metres", "/results/header/position_tolerance_m",
         dflt(kBuild.position_tolerance_m), above(0, 1)},
        {"angle-tolerance", 0, "DEG", "build: IK angle tolerance, degrees (default: half the mean "
                                      "direction spacing)", "/results/header/angle_tolerance_deg", "", above(0, 90)},
        seed_option("/config/seed", "build, eval: random seed", kBuild.seed),
        {"method", 0, "NAME", "build: fk-witness (default: some pose in the voxel, axis in the direction's cell, "
         "from FK samples), or fk-seeded-ik or exhaustive-ik (IK at the voxel centre)", "/results/header/method"},
        {"target-recall", 0, "R", "build, fk-witness: sample until a round's estimate of the recall reaches R", "/config/target_recall", dflt(kBuild.target_recall), above(0, 1)},
        {"fk-samples", 0, "N", "build: at most N configurations (fk-witness, default 2^27), or the forward pre-pass (fk-seeded-ik, default 400000)", "/config/fk_samples", "", in(1, 1e9)},
        {"restarts", 0, "N", "build, IK methods: IK restarts per bit after the seed", "/config/ik_restarts",
         dflt(kBuild.ik_restarts), in(0, 1000)},
        {"fk-per-witness", 0, nullptr, "build, fk-witness: forward kinematics for every witness instead of one per "
         "group turned about the first joint's axis (the same bits, slower: a check)", "/config/use_first_joint_turn"},
        {"layout", 0, "NAME", "build, fk-witness: grid (default: bits per voxel) or turn (one witness per cell "
         "of the first joint's turn, expanded on load; needs a revolute first joint)", "/config/layout"},
        {"exhaustive", 0, nullptr, "build: the same as --method exhaustive-ik (a slow baseline)", "/results/header/method"},
        threads_option("/config/threads", "build: threads"),
        {"shard", 0, "I/N", "build: only z-slab I of N (1-based; turn layout: the height cells = I-1 mod N); merge the parts later",
         "/results/header/shard_index"},
        {"shard-split", 0, "NAME", "build: how shards divide the build: slab (default: z-slabs) or samples (fk-witness grid: "
         "shard I draws its share of --fk-samples; the merge applies --target-recall)", "/config/shard_split"},
        {"point", 0, "x,y,z", "query: a position in the base frame, metres", "/results/point_m"},
        {"direction", 0, "x,y,z", "query: a viewing direction (need not be unit)", "/results/direction"},
        {"samples", 0, "N", "eval: queries for precision and for recall each", "/config/samples", dflt(kEvalSamples),
         in(1, 1e8)},
        {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
        {"help", 'h', nullptr, "show this help", "-"},
    }};

namespace {

std::atomic<bool> g_interrupted{false};
void on_interrupt(int) { g_interrupted = true; }

std::string need(const Args& args, const std::string& name, const std::string& action) {
  if (!args.has(name)) throw UsageError("fvx capmap " + action + ": --" + name + " is required");
  return args.get(name);
}

capmap::Arm load_arm(const std::string& urdf, const std::string& base, const std::string& tip, const Args& args) {
  capmap::ArmConfig config{base, tip};
  if (args.has("mount")) config.T_tip_sensor = parse_xyz_rpy_deg(args.get("mount"), "--mount");
  if (args.has("axis")) config.viewing_axis_sensor = parse_direction(args.get("axis"), "--axis");
  return capmap::Arm::from_urdf(urdf, config);
}

/// Options given that the chosen method does not use: said, not silently dropped.
std::vector<std::string> ignored_build_options(const Args& args, bool witness) {
  std::vector<std::string> ignored;
  if (args.has("fk-per-witness") && args.has("layout") && args.get("layout") == "turn")
    ignored.push_back("--fk-per-witness is used by the grid layout only");
  if (witness && args.has("restarts")) ignored.push_back("--restarts is used by the IK methods only");
  for (const char* name : {"target-recall", "fk-per-witness"})
    if (!witness && args.has(name)) ignored.push_back(std::string("--") + name + " is used by fk-witness only");
  return ignored;
}

int build(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap build: give one URDF");
  const std::string output = need(args, "output", "build");
  if (lowercase_extension(output) != ".fcm") throw UsageError("fvx capmap build: --output " + output + ": expected a .fcm file");
  const std::string base = need(args, "base", "build"), tip = need(args, "tip", "build");
  capmap::BuildConfig c;  // every option is checked before the URDF is read
  args.read("voxel", c.voxel_m);
  args.read("directions", c.directions);
  args.read("position-tolerance", c.position_tolerance_m);
  c.angle_tolerance_rad = args.number("angle-tolerance", 0.0) * M_PI / 180.0;
  args.read("seed", c.seed);
  args.read("fk-samples", c.fk_samples);
  args.read("target-recall", c.target_recall);
  args.read("restarts", c.ik_restarts);
  args.read("threads", c.threads);
  if (args.has("method")) c.method = capmap::parse_build_method(args.get("method"), "--method");
  if (args.has("exhaustive") && args.has("method")) throw UsageError("fvx capmap build: give --exhaustive or --method");
  if (args.has("exhaustive")) c.method = capmap::BuildMethod::ExhaustiveIk;
  if (args.has("shard")) capmap::parse_shard(args.get("shard"), "--shard", c);
  if (args.has("shard-split")) c.shard_split = capmap::parse_shard_split(args.get("shard-split"), "--shard-split");
  c.use_first_joint_turn = !args.has("fk-per-witness");
  if (args.has("layout")) c.layout = capmap::parse_map_layout(args.get("layout"), "--layout");
  throw_if_problems("fvx capmap build", c.validate());
  const std::vector<std::string> warnings = ignored_build_options(args, c.method == capmap::BuildMethod::FkWitness);
  for (const auto& warning : warnings) std::cerr << "fvx capmap build: warning: " << warning << "\n";
  const capmap::Arm arm = load_arm(args.positional[1], base, tip, args);
  Progress progress(args.has("progress"));
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  capmap::BuildStats stats;
  const Stopwatch clock;
  const capmap::CapabilityMap map = capmap::build_capability_map(
      arm, c, &stats,
      [&, last_percent = -1](std::size_t done, std::size_t total) mutable {
        const bool rounds = c.method == capmap::BuildMethod::FkWitness;  // until the target recall: no fixed total
        const int percent = total ? int(100 * done / total) : 100;
        if (!rounds && percent < last_percent + 5 && done < total) return;  // a line per 5 %
        last_percent = percent;
        progress.update("fvx capmap build: " + (rounds ? std::to_string(done) + " configurations drawn"
                                                        : std::to_string(percent) + " % (" + std::to_string(done) +
                                                              "/" + std::to_string(total) + " bits checked)"));
      },
      &g_interrupted);
  progress.finish();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (g_interrupted) throw Error("fvx capmap build: interrupted; " + output + " was not written");
  map.save(output);
  report["config"] = capmap_build_config_json(c);
  report["inputs"] = {{"urdf", args.positional[1]}, {"joints", arm.joint_names()},
                      {"first_joint_axis", capmap_first_joint_axis_json(arm)}};
  report["results"] = capmap_build_json(map, stats, clock.seconds());
  report["results"]["output"] = output;
  report["warnings"] = warnings;
  return 0;
}

int info(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap info: give one map");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  report["inputs"] = {{"map", args.positional[1]}};
  report["results"] = capmap_info_json(map);
  return 0;
}

int query(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap query: give one map");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  const Eigen::Vector3d p = parse_vector3(args.get("point"), "--point");
  std::optional<Eigen::Vector3d> direction;
  if (args.has("direction")) direction = parse_direction(args.get("direction"), "--direction");
  report["inputs"] = {{"map", args.positional[1]}};
  report["results"] = capmap_query_json(map, p, direction);
  return 0;
}

int eval(const Args& args, Json& report) {
  if (args.positional.size() != 3) throw UsageError("fvx capmap eval: give a map and the arm's URDF");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  const auto& h = map.header();
  const capmap::Arm arm = capmap::Arm::from_urdf(args.positional[2], capmap::arm_config_of(h));
  std::vector<std::string> warnings;
  if (!arm.is_urdf_hash(h.urdf_hash)) warnings.push_back("the URDF differs from the one the map was built from");
  const int samples = int(args.integer("samples", kEvalSamples));
  const auto seed = std::uint64_t(args.integer("seed", (long long)kBuild.seed));
  const capmap::Evaluation e = capmap::evaluate(map, arm, samples, seed);
  report["config"] = {{"seed", seed}, {"samples", samples}};
  report["inputs"] = {{"map", args.positional[1]}, {"urdf", args.positional[2]}};
  report["results"] = capmap_evaluation_json(e, h.method);
  report["warnings"] = warnings;
  return 0;
}

int export_cloud(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx capmap export: give one map");
  const std::string output = need(args, "output", "export");
  const auto map = capmap::CapabilityMap::load(args.positional[1]);
  const std::size_t voxels = write_capmap_cloud(output, map);
  report["inputs"] = {{"map", args.positional[1]}};
  report["results"] = {{"output", output}, {"voxels", voxels}};
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
