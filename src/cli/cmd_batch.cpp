// fvx batch — a job as independent tasks for GNU parallel or Slurm (capmap, replay, sweep), and its status.
#include <filesystem>
#include <iostream>

#include "command_table.hpp"
#include "fvx/batch/plan.hpp"
#include "fvx/batch/sweep.hpp"
#include "fvx/capmap/build.hpp"
#include "fvx/core/atomic_file.hpp"  // require_readable_file
#include "fvx/core/error.hpp"
#include "fvx/report/batch.hpp"
#include "report.hpp"

namespace fvx::cli {

namespace {

/// capmap build's options that every shard's command line passes on.
bool passed_on(const OptionSpec& o) {
  const std::string name = o.name;
  return std::string(o.help).rfind("build", 0) == 0 && name != "shard" && name != "output";
}

}  // namespace

const CommandSpec& batch_spec() {
  static const CommandSpec spec = [] {
    CommandSpec s{"batch", "capmap ARM.urdf --base LINK --tip LINK --shards N -o PLAN [capmap build options] | replay --list "
                  "FILE -o PLAN [-- replay options] | sweep --scenes LIST -o PLAN [-- explore options] | status PLAN | merge PLAN",
                  "a job as independent tasks for GNU parallel or Slurm (capability maps, replays, planner sweeps), and "
                  "its progress", {}};
    s.options = {{"output", 'o', "DIR", "the plan's folder", "-"},
                 {"shards", 0, "N", "capmap: tasks, one z-slab of the map each", "/config/shards", "", in(1, 100000)},
                 {"map", 0, "FILE", "capmap, replay: the merged result (default PLAN/map.fcm, PLAN/tables.csv)", "/results/result"},
                 {"list", 0, "FILE", "replay: the sequences, one replay's inputs per line", "/inputs/list"},
                 {"joblog", 0, "FILE", "status: GNU parallel's --joblog (default PLAN/joblog)", "/inputs/joblog"},
                 {"scenes", 0, "LIST", "sweep: N, A-B (builtin:suite/N), built-in names, meshes", "/config/scenes"},
                 {"planners", 0, "LIST", "sweep: strategies, LABEL=STRATEGY,FLAG,...", "/config/planners", batch::kSweepPlanners},
                 {"seeds", 0, "LIST", "sweep: seeds and ranges A-B", "/config/seeds", "1"},
                 {"max-views", 0, "N", "sweep: views per run", "/config/max_views", dflt(batch::Sweep{}.max_views), in(1, 10000)}};
    for (OptionSpec o : kCapmapSpec.options)
      if (passed_on(o)) {
        o.echo = "/config/build_options/" + std::string(o.name);  // passed on as given
        o.default_text.clear();
        s.options.push_back(o);
      }
    s.options.push_back({"help", 'h', nullptr, "show this help", "-"});
    return s;
  }();
  return spec;
}

namespace {

batch::Plan plan_capmap(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx batch capmap: give one URDF");
  if (!args.has("output") || !args.has("shards")) throw UsageError("fvx batch capmap: --shards and -o are required");
  require_readable_file(args.positional[1]);  // else every task would fail on it
  std::vector<std::pair<std::string, std::string>> options;  // checked here, so that no task fails on them
  for (const OptionSpec& o : batch_spec().options)
    if (passed_on(o) && args.has(o.name)) {
      if (o.range) args.number(o.name, 0);
      options.emplace_back(o.name, args.get(o.name));
    }
  capmap::BuildConfig c;  // the names and combinations every task would refuse
  if (args.has("method")) c.method = capmap::parse_build_method(args.get("method"), "--method");
  if (args.has("layout")) c.layout = capmap::parse_map_layout(args.get("layout"), "--layout");
  if (args.has("shard-split")) c.shard_split = capmap::parse_shard_split(args.get("shard-split"), "--shard-split");
  args.read("fk-samples", c.fk_samples);
  throw_if_problems("fvx batch capmap", c.validate());
  Json given = Json::object();  // every option a task may take: as given, or null
  for (const OptionSpec& o : batch_spec().options)
    if (passed_on(o)) given[o.name] = args.has(o.name) ? Json(args.get(o.name)) : Json(nullptr);
  report["config"] = {{"shards", args.integer("shards", 1)}, {"build_options", given}};
  report["inputs"] = {{"urdf", args.positional[1]}};
  return batch::capmap_plan(batch::fvx_binary(), args.positional[1], options, int(args.integer("shards", 1)),
                            args.get("output"), args.has("map") ? args.get("map") : "");
}

batch::Plan plan_replay(const Args& args, Json& report) {
  if (!args.has("output") || !args.has("list")) throw UsageError("fvx batch replay: --list and -o are required");
  const std::vector<std::string> options(args.positional.begin() + 1, args.positional.end());  // after --
  report["config"] = {{"replay_options", options}};
  report["inputs"] = {{"list", args.get("list")}};
  return batch::replay_plan(batch::fvx_binary(), args.get("list"), options, args.get("output"),
                            args.has("map") ? args.get("map") : "");
}

batch::Plan plan_sweep(const Args& args, Json& report) {
  if (!args.has("output") || !args.has("scenes")) throw UsageError("fvx batch sweep: --scenes and -o are required");
  const batch::Sweep sweep{batch::parse_scene_list(args.get("scenes")),
                           batch::parse_planner_list(args.has("planners") ? args.get("planners") : batch::kSweepPlanners),
                           batch::parse_seed_list(args.has("seeds") ? args.get("seeds") : "1"),
                           int(args.integer("max-views", batch::Sweep{}.max_views)),
                           {args.positional.begin() + 1, args.positional.end()}};  // after --
  report["config"] = report::sweep_json(sweep);
  return batch::sweep_plan(batch::fvx_binary(), sweep, args.get("output"));
}

void merge(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx batch merge: give the plan's folder");
  const batch::Plan plan = batch::read_plan(args.positional[1]);
  batch::merge_plan(plan);
  report["inputs"] = {{"plan", args.positional[1]}};
  report["results"] = {{"job", plan.job}, {"parts", plan.tasks.size()}, {"result", plan.result}};
}

void status(const Args& args, Json& report) {
  if (args.positional.size() != 2) throw UsageError("fvx batch status: give the plan's folder");
  const std::string folder = args.positional[1];
  const std::string log = args.has("joblog") ? args.get("joblog") : (std::filesystem::path(folder) / "joblog").string();
  const batch::Status s = batch::plan_status(folder, log);
  report["inputs"] = {{"plan", folder}, {"joblog", log}};
  report["results"] = report::batch_status_json(s);
  std::cerr << "fvx batch status: " << report::batch_status_line(s) << "\n";
}

}  // namespace

int run_batch(const Args& args) {
  const std::string action = args.positional.empty() ? "" : args.positional[0];
  Json report = new_report("batch " + action);
  const auto plan = [&](const batch::Plan& p) {  // made after its inputs were checked
    batch::write_plan(p);
    report["results"] = report::batch_plan_json(p);
  };
  if (action == "capmap") plan(plan_capmap(args, report));
  else if (action == "replay") plan(plan_replay(args, report));
  else if (action == "sweep") plan(plan_sweep(args, report));
  else if (action == "status") status(args, report);
  else if (action == "merge") merge(args, report);
  else throw UsageError("fvx batch: give an action: capmap, replay, sweep, status or merge");
  write_report(report, "");
  return 0;
}

}  // namespace fvx::cli
