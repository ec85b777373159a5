#pragma once
/// \file
/// Planner sweeps as a batch plan (`fvx batch sweep`, `scripts/evaluate-planners.sh`): one
/// `fvx explore` per scene × planner × seed, and the merge that turns their reports into the
/// evaluation's tables and coverage plot (man fvx-explore: the share of the observable void
/// volume known after each view is the headline).
#include <string>
#include <vector>

#include "fvx/batch/plan.hpp"

namespace fvx::batch {

/// A planner of the sweep: `fvx explore --strategy STRATEGY FLAGS` under its own label.
struct Planner {
  std::string label;  ///< letters, digits, '.', '+', '-' (it names files: no '_')
  std::string strategy;
  std::vector<std::string> flags;
};

/// The planners a sweep compares unless told otherwise (parse_planner_list's syntax).
inline const char* const kSweepPlanners = "frontier-void frontier random exhaustive";

struct Sweep {
  std::vector<std::string> scenes;    ///< explore's scene arguments: builtin:NAME, builtin:suite/N, a mesh
  std::vector<Planner> planners;
  std::vector<int> seeds;
  int max_views = 15;
  std::vector<std::string> options;   ///< words passed to every run (the arm: --capmap, --arm; --threads ...)
};

/// "1-3,paper-setting-1 7": items separated by commas or spaces; "A-B" is every number from A
/// to B; a number N is builtin:suite/N, a built-in name is builtin:NAME, anything else is
/// taken as given (builtin:..., a mesh). UsageError for an empty list or a range backwards.
std::vector<std::string> parse_scene_list(const std::string& text);

/// "1-3,7": seeds, commas or spaces between items. UsageError naming the item otherwise.
std::vector<int> parse_seed_list(const std::string& text);

/// Space-separated items: a strategy name, several joined by commas ("frontier-void,random"),
/// or LABEL=STRATEGY,FLAG,... — a variant under its own label, its flags the words after the
/// strategy ("fv-b=frontier-void,--utility-vectors,262144"). UsageError for an unknown
/// strategy, a label with other characters, or a label twice.
std::vector<Planner> parse_planner_list(const std::string& text);

/// The plan: task i runs, in the folder where the plan was made, `FVX explore SCENE OPTIONS
/// --strategy S FLAGS --seed N --max-views M --timing --format json -o
/// FOLDER/parts/ID.session` into FOLDER/parts/ID.json (renamed into place when whole; a task
/// whose report exists does nothing, so a killed sweep resumes), its stderr in
/// FOLDER/parts/ID.log. ID = SCENE_PLANNER_SEED with the scene's name ("suite-3",
/// "closed-box", a mesh's file name). The merge is `FVX batch merge FOLDER`. Checked before
/// anything is written: built-in scene names, meshes and the files that OPTIONS name
/// (--capmap, --arm, --scene-info) are readable; FileError or UsageError naming the first
/// problem; UsageError when two scenes have the same name.
Plan sweep_plan(const std::string& fvx, const Sweep& sweep, const std::string& folder);

/// The merge of a sweep plan: reads every part's explore report in task order (FileError
/// naming a missing or damaged one; nothing is written then) and writes into the plan's
/// folder runs.csv (per run), coverage.csv (void_known_fraction per run and view, the last
/// carried to max-views), summary.md and summary.csv (per planner: views to 95 % of the
/// observable void volume, runs that reached it and that ended with utility 0, target seen
/// where observable, mean area under the coverage curve and on how many scene-seed pairs
/// the first planner's is higher), coverage.png (per planner the median coverage after each
/// view and the band between the quartiles across runs; drawn by gnuplot from coverage.dat
/// and coverage.gp) and timing.csv (each run's search seconds). All but timing.csv depend
/// only on the runs' results, so the same plan run anywhere merges into the same bytes.
void merge_sweep(const Plan& plan);

}  // namespace fvx::batch
