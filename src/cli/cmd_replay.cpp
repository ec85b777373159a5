// fvx replay — a recorded session through the closed loop's step, offline: per scan register,
// integrate, frontiers and voids, next best view; the paper's per-view table (Tables I and II),
// per-view maps and reports, and a plot of the known and void volume.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "analysis_output.hpp"
#include "command_table.hpp"
#include "common_options.hpp"
#include "fvx/core/error.hpp"
#include "fvx/scan/load.hpp"
#include "fvx/session/recorder.hpp"
#include "fvx/session/replay_inputs.hpp"
#include "fvx/report/nbv.hpp"
#include "fvx/report/picture3d.hpp"
#include "fvx/report/session.hpp"
#include "table.hpp"

namespace fvx::cli {

namespace {
constexpr int kFirstView = 1;  ///< --from: views are reported from the first, 1-based
}  // namespace

const CommandSpec kReplaySpec = {
    "replay",
    "SESSION/ | --tum DIR | --scans 'GLOB' [--trajectory FILE|DIR] | --bag FILE --topic T --fixed-frame F; -o OUT/ [options]",
    "a recorded session offline: per scan integrate, voids, next best view; the paper's per-view table",
    options({{
                 {"output", 'o', "DIR", "per-view maps, reports and the volume plot (must not exist or be empty)", "-"},
                 {"tum", 0, "DIR", "a TUM RGB-D style folder: depth/ and groundtruth.txt (or --associations)",
                  "/inputs/tum"},
                 {"associations", 0, "FILE", "with --tum: lines 'stamp rgb/… stamp depth/…' (or 'stamp depth/…') "
                                             "naming the depth images, relative to DIR", "/inputs/associations"},
                 {"scans", 0, "GLOB", "the scans (PCD, PLY, depth images) in file-name order; quote the pattern",
                  "/inputs/scans"},
             },
             trajectory_options(true),
             bag_options(),
             {
                 {"from", 0, "N", "first view reported, 1-based", "/config/first_view",
                  dflt(kFirstView) + "; earlier views are still replayed", in(1, 1e6)},
                 {"to", 0, "N", "last view replayed, 1-based (default: all)", "/config/last_view", "", in(1, 1e6)},
                 {"format", 0, "NAME", "the table on stdout: markdown (default), csv or json", "-"},
                 {"search-every", 0, "N", "search the next best view after every N-th view only",
                  "/config/search_every",
                  dflt(session::ReplayConfig{}.search_every) + "; 0: never, the table then holds integration alone",
                  in(0, 1e6)},
             },
             arm_options(),
             {
                 {"strategy", 0, "NAME", "frontier-void (default, or the session's), frontier, random or exhaustive",
                  "/config/pipeline/nbv/strategy"},
                 {"planner", 0, "NAME", "the same as --strategy (its earlier name here)",
                  "/config/pipeline/nbv/strategy"},
                 {"register", 0, nullptr, "register every scan to the map (default for --tum and --scans; "
                                          "a session: as recorded)", "/config/pipeline/register_scans"},
                 {"no-register", 0, nullptr, "integrate scans at their logged poses",
                  "/config/pipeline/register_scans"},
                 resolution_option("/config/pipeline/resolution_m", "map cell edge, metres", ", or the session's"),
                 pipeline::discretize_option("/config/pipeline/discretize"),
                 {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space S, metres (default: the session's, else the "
                                                    "known cells' box)", "/config/pipeline/bounds_m"},
                 {"view-bounds", 0, "x0,y0,z0,x1,y1,z1", "the sensor stays in this box, metres (default: the "
                                                         "session's, else the known cells' box)",
                  "/config/pipeline/nbv/view_bounds_m"},
                 {"seed", 0, "N", "seed of the planner", "/config/pipeline/nbv/seed",
                  dflt(nbv::Config{}.seed) + ", or the session's", in(0, 9.2e18)},
                 threads_option("/config/pipeline/nbv/threads", "threads for the search"),
             },
             search_model_options("/config/pipeline", "/config/pipeline/nbv"),
             report::picture_options(true, nullptr, nullptr),
             session_report_options()})};

namespace {

const std::vector<std::string> kReplayColumns = {"view",      "integration_s", "search_s", "void_cells",
                                                 "utility_dm3", "fitness_m",  "next_m",   "next_deg",
                                                 "revealed",  "map_void_cells", "known_dm3"};

/// What a replay reads: the scans (loaded when their turn comes) and what the JSON names.
struct Inputs {
  std::vector<session::RecordedScan> scans;
  std::string source;
  /// What the report's inputs echo of the files named (null: not a recording's).
  Json files = {{"tum", nullptr}, {"associations", nullptr}, {"scans", nullptr}, {"trajectory", nullptr},
                {"bag", nullptr}, {"topic", nullptr}, {"fixed_frame", nullptr}, {"frame", nullptr}};
  std::string capmap_path, arm_path;  ///< the arm's files, when there is one
  scan::LoadConfig load;              ///< how scan files are read and posed
};

/// A session: the loop's settings as recorded (flags go on top later), the arm from its
/// manifest unless --capmap/--no-capmap, each scan at its recorded prior.
Inputs session_inputs(const Args& args, bool arm_flags, session::ReplayConfig& config, ArmInputs& arm_inputs) {
  Inputs in;
  in.source = args.positional[0];
  session::SessionRecording recording = session::read_session(in.source, config);
  in.scans = std::move(recording.scans);
  if (args.has("sensor") || args.has("intrinsics") || args.has("depth-min") || args.has("depth-max"))
    config.pipeline.nbv.sensor = parse_depth_camera(args, "replay");
  if (arm_flags) {
    load_arm_inputs(args, "fvx replay", arm_inputs);
    if (args.has("capmap")) in.capmap_path = args.get("capmap");
    if (args.has("arm")) in.arm_path = args.get("arm");
  } else if (!recording.capmap_path.empty()) {
    in.capmap_path = recording.capmap_path;
    in.arm_path = recording.arm_path;
    nbv::load_arm(in.capmap_path, in.arm_path, recording.T_world_base, "fvx replay", arm_inputs);
  }
  return in;
}

/// Recorded scans with a trajectory (a TUM folder or a list of files): registration on, the
/// measurable U of fvx explore, the arm only when --capmap is given (else free-flying).
Inputs recorded_inputs(const Args& args, bool arm_flags, session::ReplayConfig& config, ArmInputs& arm_inputs) {
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  Inputs in;
  nc.sensor = parse_depth_camera(args, "replay");
  std::vector<std::string> paths;
  scan::LoadConfig& load = in.load;
  read_trajectory_options(args, load);
  if (args.has("tum")) {
    paths = scan::tum_recording(args.get("tum"), args.has("associations") ? args.get("associations") : "", load);
    if (!args.has("depth-scale")) nc.sensor.intrinsics.depth_scale = 5000;  // TUM's depth units per metre
    in.source = args.get("tum");
  } else if (args.has("scans")) {
    paths = scan::expand_glob(args.get("scans"), "fvx replay: --scans");
    // Without --trajectory, each scan's own pose (scan::load_scan's rule).
    in.source = args.get("scans");
  }
  load.intrinsics = nc.sensor.intrinsics;
  std::vector<std::string> warnings;
  const std::optional<io::BagQuery> bag = read_bag_options(args, std::nullopt);  // intrinsics from CameraInfo
  if (bag) in.source = bag->path;
  in.scans = bag ? session::recorded_scans(scan::plan_bag(*bag), load) : session::recorded_scans(paths, load, warnings);
  for (const auto& warning : warnings) std::cerr << "fvx replay: warning: " << warning << "\n";
  pc.register_scans = !args.has("no-register");
  nc.strategy = nbv::Strategy::FrontierVoid;
  if (arm_flags) load_arm_inputs(args, "fvx replay", arm_inputs);  // else a free-flying sensor
  if (args.has("capmap")) in.capmap_path = args.get("capmap");
  if (args.has("arm")) in.arm_path = args.get("arm");
  for (const char* key : {"tum", "associations", "scans"}) in.files[key] = args.has(key) ? Json(args.get(key)) : Json(nullptr);
  in.files["trajectory"] = load.trajectory_path.empty() ? Json(nullptr) : Json(load.trajectory_path);
  in.files.update(bag_inputs_json(bag));
  return in;
}

/// The options that pick and qualify the input: one source, what goes with which, an output
/// folder that is new or empty. Returns whether --capmap or --no-capmap was given.
bool check_input_options(const Args& args) {
  const int sources = int(args.positional.size() == 1) + int(args.has("tum")) + int(args.has("scans")) + int(args.has("bag"));
  if (sources != 1 || args.positional.size() > 1)
    throw UsageError("fvx replay: give one input: a session directory, --tum DIR, --scans GLOB or --bag FILE");
  if (!args.has("output")) throw UsageError("fvx replay: -o/--output DIR is required");
  if (args.has("register") && args.has("no-register"))
    throw UsageError("fvx replay: --register and --no-register contradict each other");
  if (args.has("associations") && !args.has("tum")) throw UsageError("fvx replay: --associations goes with --tum");
  if (args.positional.size() == 1 && args.has("trajectory"))
    throw UsageError("fvx replay: a session has its poses in its manifest; --trajectory goes with --scans or --tum");
  // The arm: --capmap or --no-capmap; without either, a session's own, else free-flying.
  const bool arm_flags = args.has("capmap") || args.has("no-capmap");
  if (arm_flags) check_arm_options(args, "fvx replay");
  if (!args.has("capmap") && (args.has("base") || args.has("arm")))
    throw UsageError("fvx replay: --base and --arm go with --capmap");
  const std::filesystem::path dir = args.get("output");
  if (std::filesystem::exists(dir) && (!std::filesystem::is_directory(dir) || !std::filesystem::is_empty(dir)))
    throw UsageError("fvx replay: -o " + dir.string() + " exists and is not an empty folder; nothing is overwritten");
  return arm_flags;
}

/// The flags over what the recording says, then the whole config checked.
void apply_flags(const Args& args, const Inputs& inputs, const ArmInputs& arm_inputs, int from, int to,
                 session::ReplayConfig& config) {
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  nc.strategy = parse_strategy_option(args, "replay", nc.strategy);
  if (args.has("register")) pc.register_scans = true;
  if (args.has("no-register")) pc.register_scans = false;
  nc.count_near_void_cells = parse_near_voids(args, nc.count_near_void_cells);
  pc.resolution_m = parse_resolution(args, pc.resolution_m);
  pc.target_size_m = parse_target_size(args, pc.target_size_m);
  pc.hull_in_bounds = parse_void_hull(args, pc.hull_in_bounds);
  if (args.has("discretize")) pc.discretize = true;  // a session's recorded choice otherwise
  args.read("unknown-depth", nc.unknown_depth_cells);
  nc.near_unknown = pipeline::parse_near_unknown(args, nc.near_unknown);
  nc.exterior = pipeline::parse_exterior(args, nc.exterior);
  if (args.has("bounds")) pc.bounds_m = parse_bounds(args);
  if (args.has("view-bounds")) nc.view_bounds_m = parse_bounds(args, "view-bounds");
  args.read("seed", nc.seed);
  args.read("threads", nc.threads);
  parse_accumulation(args, nc);  // over the recording's
  pc.tie_to_search();
  if (nc.strategy == nbv::Strategy::Exhaustive && !arm_inputs.reach)
    throw UsageError("fvx replay: --strategy exhaustive enumerates a capability map: give --capmap");
  if (args.has("to")) config.last_view = to - 1;
  args.read("search-every", config.search_every);
  if (from > int(inputs.scans.size()))
    throw UsageError("fvx replay: --from " + std::to_string(from) + ": the recording has " +
                     std::to_string(inputs.scans.size()) + " views");
  throw_if_problems("fvx replay", config.validate());
}

}  // namespace

int run_replay(const Args& args) {
  const bool arm_flags = check_input_options(args);
  const Format format = parse_format(args);
  const int from = int(args.integer("from", kFirstView));
  const int to = int(args.integer("to", 0));
  if (args.has("to") && to < from) throw UsageError("fvx replay: --to " + std::to_string(to) + " is before --from");
  const std::filesystem::path dir = args.get("output");

  session::ReplayConfig config;
  pipeline::Config& pc = config.pipeline;
  nbv::Config& nc = pc.nbv;
  ArmInputs arm_inputs;
  const Inputs inputs = args.positional.size() == 1 ? session_inputs(args, arm_flags, config, arm_inputs)
                                                    : recorded_inputs(args, arm_flags, config, arm_inputs);
  const std::vector<session::RecordedScan>& scans = inputs.scans;
  apply_flags(args, inputs, arm_inputs, from, to, config);
  const session::Recorder recorder(dir.string());  // maps/ and reports/
  report::SessionPictures pictures(dir.string(), report::read_picture_options(args), nc.sensor,
                                   arm_inputs.reach ? std::optional(arm_inputs.T_world_base) : std::nullopt);
  std::vector<Eigen::Vector3f> occupied_m;  // of the view whose search runs
  const double R = pc.resolution_m;
  const std::vector<std::string> joint_names = arm_inputs.joint_names();
  const std::size_t total = config.last_view < 0 ? scans.size() : std::min<std::size_t>(scans.size(), to);
  Progress progress(args.has("progress"));
  std::vector<session::ViewRow> rows;  // every replayed view; the reported ones are view + 1 >= from
  std::string failure;
  try {
    // Each view's map is written while its search runs (the next scan changes the map).
    const auto save_map = [&](int view, const pipeline::State& state) {
      if (view + 1 >= from) recorder.save_map(view, state.map), occupied_m = state.map.occupied_centers();
    };
    session::replay(scans, arm_inputs.reach, config, save_map, [&](const session::ReplayView& v) {
      session::append_row(rows, session::row_of(v, R), v.revealed_void_cells, v.from_choice_m, v.from_choice_deg);
      const session::ViewRow& row = rows.back();
      if (v.view + 1 >= from) pictures.add(v.view, occupied_m, R, v.step, v.chosen);
      if (v.view + 1 >= from)
        recorder.save_report(v.view, report_text(view_report("replay", {{"source", inputs.source}, {"view", v.view + 1},
                                                                        {"scan", v.name}},
                                                             v.step, v.chosen, row, R, joint_names, nc.strategy,
                                                             args.has("timing"))));
      progress.update("fvx replay: view " + std::to_string(v.view + 1) + "/" + std::to_string(total) + ": " +
                      std::to_string(row.map_void_cells) + " void cells, best view sees " +
                      std::to_string(row.void_cells));
    });
  } catch (const Error& e) {
    failure = e.what();
  }
  progress.finish();

  // What was replayed is reported even when a scan failed: its views' files are complete.
  std::vector<session::ViewRow> shown;
  for (const session::ViewRow& r : rows)
    if (r.view + 1 >= from) shown.push_back(r);
  pictures.finish("fvx replay " + inputs.source);
  if (!shown.empty())
    write_volume_plot((dir / "volumes.png").string(),
                      "fvx replay: known and void volume in the search space after each view", shown);
  if (format == Format::json) {
    Json report = new_report("replay");
    report["config"] = session::config_json(config);
    report["config"]["first_view"] = from;
    report["config"]["max_time_diff_s"] = inputs.load.max_time_diff_s;
    report["config"]["pose_format"] = io::to_string(inputs.load.pose_format);
    report["inputs"] = {{"source", inputs.source}, {"views", scans.size()}};
    report["inputs"].update(inputs.files);
    report["inputs"]["capmap"] = arm_json(inputs.capmap_path, inputs.arm_path, arm_inputs);
    report["results"] = {{"output", dir.string()},
                         {"views", rows.size()},
                         {"rows", rows_json(shown, args.has("timing"))},
                         {"error", failure.empty() ? Json(nullptr) : Json(failure)}};
    report["warnings"] = Json::array();
    write_report(report, "");
  } else {
    print_rows(shown, kReplayColumns, format, std::cout);
  }
  if (!failure.empty()) throw Error("fvx replay: " + failure + (shown.empty() ? "; nothing was written" : "; the " +
                                    std::to_string(shown.size()) + " views before it are in " + dir.string()));
  std::cerr << "fvx replay: " << rows.size() << " views; maps, reports, volumes.png and views.png in " << dir.string() << "\n";
  return core::end_process(0);
}

}  // namespace fvx::cli
