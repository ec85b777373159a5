#pragma once
/// \file
/// Batch work beyond one machine (`fvx batch`): a job becomes a plan — independent command
/// lines, one per task, each writing its own output file atomically, and a merge that joins
/// them — that GNU parallel (one machine, or hosts by ssh) or Slurm (a job array with the
/// merge as a dependent job) runs. fvx brings no scheduler of its own.
///
/// A plan's folder holds:
/// - `tasks.txt`: one sh command line per task (absolute paths; GNU parallel reads it on
///   stdin, a Slurm array task runs line $SLURM_ARRAY_TASK_ID);
/// - `merge.sh`: the merge, run once every task has succeeded; it names every output, so a
///   missing or corrupt one stops it with that output named, before anything is written;
/// - `slurm.sbatch`: submitted plainly, it submits itself as an array of the tasks and
///   `merge.sh` after them (`--dependency=afterok`); as an array task it runs its line;
/// - `plan.json`: the job, the tasks and their outputs, the merge and its result
///   (what `fvx batch status` reads);
/// - `parts/` for the task outputs and `slurm/` for Slurm's logs.
#include <string>
#include <utility>
#include <vector>

namespace fvx::batch {

/// One task: a command line (sh) and the file it writes.
struct Task {
  std::string command;
  std::string output;
};

struct Plan {
  std::string job;            ///< "capmap", "replay" or "sweep"
  std::string folder;         ///< absolute
  std::vector<Task> tasks;
  std::string merge_command;  ///< sh; joins the task outputs into `result`
  std::string result;         ///< absolute
};

/// The running fvx binary's absolute path (/proc/self/exe): what the tasks run.
std::string fvx_binary();

/// `path` absolute and normal, without a trailing slash ("plan/" is the folder plan), so that
/// the paths a plan writes read "PLAN/parts/…", not "PLAN//parts/…".
std::string absolute_path(const std::string& path);

/// `word` single-quoted for sh ('it'\''s').
std::string shell_quote(const std::string& word);

/// The capability map of `urdf` in `shards` z-slabs: task i runs
/// `FVX capmap build URDF OPTIONS --shard i/N -o FOLDER/parts/shard-i-of-N.fcm` (its JSON
/// report into shard-i-of-N.json beside it), the merge
/// `FVX capmap merge` of all of them into `result` (FOLDER/map.fcm when empty). `options` are
/// capmap build's (name without dashes, value; empty for a flag), passed on as given. Paths are
/// made absolute. UsageError for shards outside 1 to 100 000.
Plan capmap_plan(const std::string& fvx, const std::string& urdf,
                 const std::vector<std::pair<std::string, std::string>>& options, int shards,
                 const std::string& folder, const std::string& result = "");

/// One fvx replay per sequence of `list`: a text file whose every line (but empty ones and
/// those starting with #) holds the input arguments of one replay in sh syntax (a session
/// folder, `--tum DIR`, `--scans 'GLOB' --trajectory FILE`, ...), paths relative to the
/// list's folder. Task i runs, in that folder, `FVX replay LINE OPTIONS --format csv` into
/// FOLDER/parts/replay-i.tmp and its table into table.csv there, then renames the folder to
/// FOLDER/parts/replay-i (so a part that exists is whole). The merge (`FVX batch merge
/// FOLDER`) writes `result` (FOLDER/tables.csv when empty). `options` are words passed to
/// every replay (e.g. --no-capmap). FileError for a list without a sequence.
Plan replay_plan(const std::string& fvx, const std::string& list, const std::vector<std::string>& options,
                 const std::string& folder, const std::string& result = "");

/// The merge of a plan: for capmap, the shards in task order (CapabilityMap::merge) into
/// the result; for replay, the parts' tables in task order as one CSV whose first column,
/// `sequence`, is the task's number (1-based) and without the columns of seconds
/// (`*_s`: they differ from machine to machine and run to run), so that the same plan run
/// anywhere merges into the same bytes. FileError naming a missing or damaged part, or parts
/// whose tables have other columns; nothing is written then. For sweep, merge_sweep (sweep.hpp).
void merge_plan(const Plan& plan);

/// Creates the folder (and parts/, slurm/) and writes tasks.txt, merge.sh, slurm.sbatch and
/// plan.json, each atomically. FileError when the folder cannot be made or written, or when
/// it already holds a plan of other tasks (a rerun of the same plan is fine).
void write_plan(const Plan& plan);

/// Reads plan.json back. FileError for a folder without a plan or a damaged one.
Plan read_plan(const std::string& folder);

/// What became of each task: done (its output exists: outputs are written atomically),
/// failed (GNU parallel's job log records a non-zero exit or a signal for it and its output
/// is missing), remaining (neither).
struct Status {
  std::vector<std::size_t> done, failed, remaining;  ///< task indices, 0-based
  std::vector<int> exit_status;                      ///< per failed task: the job log's Exitval (or 128+Signal)
  bool merged = false;                               ///< the merge's result exists
  bool job_log = false;                              ///< a job log was read
};

/// The plan in `folder` against `job_log` (GNU parallel's --joblog file; none when empty or
/// absent). FileError for a job log that is not one.
Status plan_status(const std::string& folder, const std::string& job_log);

}  // namespace fvx::batch
