// fvx batch as users run it: a capability map planned as 4 shards and run by GNU parallel
// (-j2, local) merges into the bytes of one process; a batch killed midway and run again
// with --resume does too; status reads the job log; a missing shard stops the merge before
// it writes anything; bad plans are refused on one line. A planner sweep run by GNU parallel
// merges into the bytes of the same sweep run one task after another.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_support.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

const std::string kArmOptions = " --base base_link --tip kinect_optical --voxel 0.15 --directions 50 --seed 3";

std::string fvx_arm() { return "'" + std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm.urdf'"; }

/// Runs `command` with sh in `dir`; its exit status.
int sh(const TempDir& dir, const std::string& command) {
  const int status = std::system(("cd '" + dir.path().string() + "' && { " + command + "; }").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

json status_of(const TempDir& dir, const std::string& plan) {
  const RunResult r = run_fvx(dir, "batch status " + plan);
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? json::parse(r.out)["results"] : json();
}

std::size_t log_lines(const TempDir& dir, const std::string& log) { return line_count(slurp(dir / log)); }

TEST(CliBatch, CapmapShardsRunByGnuParallelMergeIntoTheSingleBuild) {
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0) << "GNU parallel is missing (scripts/install-deps.sh)";
  const TempDir dir;
  ASSERT_EQ(run_fvx(dir, "capmap build " + fvx_arm() + kArmOptions + " -o one.fcm").status, 0);
  RunResult r = run_fvx(dir, "batch capmap " + fvx_arm() + kArmOptions + " --shards 4 -o plan");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["results"]["tasks"], 4);
  EXPECT_EQ(json::parse(r.out)["config"]["build_options"]["voxel"], "0.15");
  EXPECT_EQ(log_lines(dir, "plan/tasks.txt"), 4u);
  EXPECT_EQ(sh(dir, "sh -n plan/slurm.sbatch && sh -n plan/merge.sh"), 0) << "the scripts do not parse";
  json s = status_of(dir, "plan");
  EXPECT_EQ(s["remaining"], 4);
  EXPECT_EQ(s["job_log_read"], false);

  ASSERT_EQ(sh(dir, "parallel -j2 --joblog plan/joblog --resume < plan/tasks.txt > /dev/null 2>&1"), 0);
  s = status_of(dir, "plan");
  EXPECT_EQ(s["done"], 4);
  EXPECT_EQ(s["merged"], false);
  ASSERT_EQ(sh(dir, "sh plan/merge.sh > /dev/null"), 0);
  EXPECT_TRUE(slurp(dir / "plan/map.fcm") == slurp(dir / "one.fcm")) << "the merged shards differ from one build";
  EXPECT_EQ(status_of(dir, "plan")["merged"], true);

  // A missing shard: the merge names it and writes nothing.
  std::filesystem::remove(dir / "plan/map.fcm");
  std::filesystem::remove(dir / "plan/parts/shard-2-of-4.fcm");
  r = run_fvx(dir, "batch status plan");
  EXPECT_EQ(json::parse(r.out)["results"]["remaining"], 1);
  EXPECT_NE(r.err.find("3 done, 0 failed, 1 remaining"), std::string::npos) << r.err;
  EXPECT_EQ(sh(dir, "sh plan/merge.sh 2> merge.err"), 1);
  EXPECT_NE(slurp(dir / "merge.err").find("shard-2-of-4.fcm"), std::string::npos) << slurp(dir / "merge.err");
  EXPECT_FALSE(std::filesystem::exists(dir / "plan/map.fcm"));
}

// Samples shards (each draws its share of a budget; the merge applies the stop rule): through
// GNU parallel they merge into the one-process build with the same budget, and each task
// leaves its report beside its shard.
TEST(CliBatch, SamplesShardsRunByGnuParallelMergeIntoTheOneProcessBuild) {
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0) << "GNU parallel is missing (scripts/install-deps.sh)";
  const TempDir dir;
  const std::string budget = " --fk-samples 800000";  // three rounds and a part of one
  ASSERT_EQ(run_fvx(dir, "capmap build " + fvx_arm() + kArmOptions + budget + " -o one.fcm").status, 0);
  const RunResult r = run_fvx(dir, "batch capmap " + fvx_arm() + kArmOptions + budget + " --shard-split samples --threads 1 "
                                   "--shards 4 -o plan");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["config"]["build_options"]["shard-split"], "samples");
  ASSERT_EQ(sh(dir, "parallel -j2 --joblog plan/joblog < plan/tasks.txt > out.txt 2>&1 && sh plan/merge.sh > /dev/null"), 0);
  EXPECT_EQ(slurp(dir / "out.txt"), "") << "the tasks' reports belong beside their shards";
  EXPECT_TRUE(slurp(dir / "plan/map.fcm") == slurp(dir / "one.fcm")) << "the merged samples shards differ from one build";
  const json shard = json::parse(slurp(dir / "plan/parts/shard-2-of-4.json"));
  EXPECT_EQ(shard["results"]["header"]["shard_index"], 1);
  EXPECT_LT(shard["results"]["fk_samples"].get<double>(), 800000.0 / 2) << "a shard draws its share only";
}

TEST(CliBatch, ABatchKilledMidwayResumesToTheSameBytes) {
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0) << "GNU parallel is missing (scripts/install-deps.sh)";
  const TempDir dir;
  ASSERT_EQ(run_fvx(dir, "capmap build " + fvx_arm() + kArmOptions + " -o one.fcm").status, 0);
  ASSERT_EQ(run_fvx(dir, "batch capmap " + fvx_arm() + kArmOptions + " --shards 4 -o plan").status, 0);
  // One task at a time in a session of its own; killed (the whole group, -9) once the log
  // holds the first finished task.
  ASSERT_EQ(sh(dir, "setsid parallel -j1 --joblog plan/joblog < plan/tasks.txt > /dev/null 2>&1 & echo $! > pid"), 0);
  const auto start = std::chrono::steady_clock::now();
  while (!(std::filesystem::exists(dir / "plan/joblog") && log_lines(dir, "plan/joblog") >= 2) &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const pid_t group = std::stoi(slurp(dir / "pid"));
  ASSERT_EQ(::kill(-group, SIGKILL), 0) << "the batch was not killed";
  for (int i = 0; i < 100 && ::kill(-group, 0) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_NE(::kill(-group, 0), 0) << "the batch still runs";
  json s = status_of(dir, "plan");
  std::printf("killed with %d done, %d remaining\n", s["done"].get<int>(), s["remaining"].get<int>());
  ASSERT_GE(s["done"].get<int>(), 1);
  ASSERT_GE(s["remaining"].get<int>(), 1) << "the batch finished before it was killed";
  EXPECT_EQ(s["failed"], 0);
  ASSERT_EQ(sh(dir, "parallel -j2 --joblog plan/joblog --resume < plan/tasks.txt > /dev/null 2>&1"), 0);
  EXPECT_EQ(status_of(dir, "plan")["done"], 4);
  ASSERT_EQ(sh(dir, "sh plan/merge.sh > /dev/null"), 0);
  EXPECT_TRUE(slurp(dir / "plan/map.fcm") == slurp(dir / "one.fcm")) << "the resumed batch differs from one build";
}

// The Slurm path on a real single-node Slurm (scripts/slurm-local.sh starts munged, slurmctld
// and slurmd on this machine as root and stops them after): `sbatch plan/slurm.sbatch`
// submits the 4-task array and the merge that waits for it; the merged map is the single
// build's bytes.
TEST(CliBatch, TheSlurmArrayAndItsDependentMergeGiveTheSingleBuild) {
  ASSERT_EQ(::getuid(), 0u) << "the Slurm test starts slurmd, which needs root (CI runs as root)";
  const TempDir dir;
  const std::string local = "'" + std::string(std::getenv("FVX_SOURCE_DIR")) + "/scripts/slurm-local.sh' ";
  struct Stop {
    std::string command;
    ~Stop() { std::system(command.c_str()); }
  } stop{local + "stop '" + dir / "cluster" + "'"};
  ASSERT_EQ(sh(dir, local + "start '" + dir / "cluster" + "' > /dev/null"), 0) << "a local Slurm did not start";
  const std::string slurm = "SLURM_CONF='" + dir / "cluster/slurm.conf" + "' ";
  ASSERT_EQ(run_fvx(dir, "capmap build " + fvx_arm() + kArmOptions + " -o one.fcm").status, 0);
  ASSERT_EQ(run_fvx(dir, "batch capmap " + fvx_arm() + kArmOptions + " --shards 4 -o plan").status, 0);
  ASSERT_EQ(sh(dir, slurm + "sbatch plan/slurm.sbatch > /dev/null"), 0);
  const auto start = std::chrono::steady_clock::now();
  while (!std::filesystem::exists(dir / "plan/map.fcm") && std::chrono::steady_clock::now() - start < std::chrono::seconds(180))
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_TRUE(std::filesystem::exists(dir / "plan/map.fcm")) << "no merged map after 180 s; Slurm logs in " << dir / "cluster/log";
  EXPECT_TRUE(slurp(dir / "plan/map.fcm") == slurp(dir / "one.fcm")) << "the Slurm batch differs from one build";
  const json s = status_of(dir, "plan");
  EXPECT_EQ(s["done"], 4);
  EXPECT_EQ(s["merged"], true);
  for (int i = 1; i <= 4; ++i)  // one log per array task, and the merge's
    EXPECT_EQ(sh(dir, "ls plan/slurm/fvx-capmap-*_" + std::to_string(i) + ".out > /dev/null 2>&1"), 0) << i;
  EXPECT_EQ(sh(dir, "ls plan/slurm/merge-*.out > /dev/null 2>&1"), 0);
}

// Replays of a list of sequences, run by GNU parallel (-j2) and one after another: the merged
// tables are the same bytes, every sequence's rows in list order without the columns of
// seconds; a missing part stops the merge, which then writes nothing.
// Hosts reached by ssh: an sshd on 127.0.0.1 (scripts/sshd-local.sh), one slot there and one
// here (`parallel --sshlogin 1/127.0.0.1,1/:`): each side runs tasks of a capmap plan, which
// merge into the one-process build, and of a sweep, which merges as the same sweep run here.
TEST(CliBatch, HostsReachedBySshRunTheirShareAndMergeAlike) {
  ASSERT_EQ(::getuid(), 0u) << "the ssh test starts an sshd, which needs root (CI runs as root)";
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0) << "GNU parallel is missing (scripts/install-deps.sh)";
  const TempDir dir;
  const std::string local = "'" + std::string(std::getenv("FVX_SOURCE_DIR")) + "/scripts/sshd-local.sh' ";
  struct Stop {
    std::string command;
    ~Stop() { std::system(command.c_str()); }
  } stop{local + "stop '" + dir / "sshd" + "'"};
  ASSERT_EQ(sh(dir, local + "start '" + dir / "sshd" + "' > ssh.txt"), 0) << "a local sshd did not start";
  const std::string parallel = "PARALLEL_SSH=\"$(cat ssh.txt)\" parallel --sshlogin 1/127.0.0.1,1/: ";
  ASSERT_EQ(run_fvx(dir, "capmap build " + fvx_arm() + kArmOptions + " -o one.fcm").status, 0);
  ASSERT_EQ(run_fvx(dir, "batch capmap " + fvx_arm() + kArmOptions + " --shards 4 -o plan").status, 0);
  ASSERT_EQ(sh(dir, parallel + "--joblog plan/joblog < plan/tasks.txt > /dev/null 2> err.txt"), 0) << slurp(dir / "err.txt");
  const std::string log = slurp(dir / "plan/joblog");
  EXPECT_NE(log.find("\t127.0.0.1\t"), std::string::npos) << "no task ran on the ssh host: " << log;
  EXPECT_NE(log.find("\t:\t"), std::string::npos) << "no task ran here: " << log;
  ASSERT_EQ(sh(dir, "sh plan/merge.sh > /dev/null"), 0);
  EXPECT_TRUE(slurp(dir / "plan/map.fcm") == slurp(dir / "one.fcm")) << "the batch over ssh differs from one build";

  const std::string arm = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm";
  for (const std::string plan : {"a", "b"})
    ASSERT_EQ(run_fvx(dir, "batch sweep --scenes closed-box --planners random --seeds 1-2 --max-views 1 -o " + plan +
                               " -- --capmap '" + arm + ".fcm' --arm '" + arm + ".urdf' --resolution 0.05 --threads 1")
                  .status,
              0);
  ASSERT_EQ(sh(dir, parallel + "--joblog a/joblog < a/tasks.txt > /dev/null 2> err.txt"), 0) << slurp(dir / "err.txt");
  EXPECT_NE(slurp(dir / "a/joblog").find("\t127.0.0.1\t"), std::string::npos) << slurp(dir / "a/joblog");
  ASSERT_EQ(sh(dir, "while IFS= read -r task; do sh -c \"$task\" || exit 1; done < b/tasks.txt"), 0);
  ASSERT_EQ(sh(dir, "sh a/merge.sh > /dev/null && sh b/merge.sh > /dev/null"), 0);
  for (const char* file : {"summary.md", "runs.csv", "coverage.png"})
    EXPECT_TRUE(slurp(dir / ("a/" + std::string(file))) == slurp(dir / ("b/" + std::string(file)))) << file;
}

TEST(CliBatch, ReplaysOfAListMergeIntoTheSameTableInParallelOrOneByOne) {
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0) << "GNU parallel is missing (scripts/install-deps.sh)";
  const TempDir dir;
  const std::string scans = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/sample/box-room/*.pcd";
  std::ofstream(dir / "sequences.txt") << "# the sample, whole and its first two views\n--scans '" << scans << "'\n\n"
                                       << "--scans '" << scans << "' --to 2\n";
  for (const char* plan : {"a", "b"}) {
    const RunResult r = run_fvx(dir, std::string("batch replay --list sequences.txt -o ") + plan +
                                         " -- --no-capmap --no-register --search-every 0 -r 0.05");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(r.out)["results"]["tasks"], 2);
  }
  ASSERT_EQ(sh(dir, "parallel -j2 --joblog a/joblog < a/tasks.txt > /dev/null 2>&1"), 0);
  ASSERT_EQ(sh(dir, "while IFS= read -r task; do sh -c \"$task\" > /dev/null 2>&1 || exit 1; done < b/tasks.txt"), 0);
  EXPECT_EQ(status_of(dir, "a")["done"], 2);
  ASSERT_EQ(sh(dir, "sh a/merge.sh > /dev/null && sh b/merge.sh > /dev/null"), 0);
  const std::string table = slurp(dir / "a/tables.csv");
  EXPECT_EQ(table, slurp(dir / "b/tables.csv")) << "parallel and one by one merge differently";
  EXPECT_EQ(table.rfind("sequence,view,", 0), 0u) << table;
  EXPECT_EQ(table.find("_s,"), std::string::npos) << "seconds are in the merged table: " << table;
  EXPECT_EQ(line_count(table), 1u + 4u + 2u) << table;  // the header, 4 views, 2 views
  EXPECT_NE(table.find("\n1,4,"), std::string::npos) << table;
  EXPECT_NE(table.find("\n2,2,"), std::string::npos) << table;
  EXPECT_EQ(status_of(dir, "a")["merged"], true);

  std::filesystem::remove(dir / "a/tables.csv");
  std::filesystem::remove_all(dir / "a/parts/replay-2");
  EXPECT_EQ(sh(dir, "sh a/merge.sh > /dev/null 2> merge.err"), 1);
  EXPECT_NE(slurp(dir / "merge.err").find("replay-2"), std::string::npos) << slurp(dir / "merge.err");
  EXPECT_FALSE(std::filesystem::exists(dir / "a/tables.csv"));
}

// The sweep: 3 scenes x 2 planners through GNU parallel (-j2, one thread per run)
// and the same sweep one run after another (two threads per run, so the thread count is
// varied too): the merged tables and plot are the same bytes.
TEST(CliBatch, APlannerSweepRunByGnuParallelMergesAsOneRunAfterAnother) {
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0) << "GNU parallel is missing (scripts/install-deps.sh)";
  const TempDir dir;
  const std::string arm = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm";
  for (const std::string plan : {"a", "b"}) {
    const RunResult r = run_fvx(dir, "batch sweep --scenes closed-box,crates,1 --planners frontier-void,random --seeds 1 "
                                     "--max-views 2 -o " + plan + " -- --capmap '" + arm + ".fcm' --arm '" + arm +
                                     ".urdf' --resolution 0.05 --threads " + (plan == "a" ? "1" : "2"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(r.out)["results"]["tasks"], 6);
  }
  ASSERT_EQ(sh(dir, "parallel -j2 --joblog a/joblog < a/tasks.txt > /dev/null 2>&1"), 0);
  ASSERT_EQ(sh(dir, "while IFS= read -r task; do sh -c \"$task\" || exit 1; done < b/tasks.txt"), 0);
  EXPECT_EQ(status_of(dir, "a")["done"], 6);
  ASSERT_EQ(sh(dir, "sh a/merge.sh > /dev/null && sh b/merge.sh > /dev/null"), 0);
  for (const char* file : {"summary.md", "summary.csv", "runs.csv", "coverage.csv", "coverage.png"})
    EXPECT_TRUE(slurp(dir / ("a/" + std::string(file))) == slurp(dir / ("b/" + std::string(file)))) << file << " differs between parallel and one by one";
  const std::string runs = slurp(dir / "a/runs.csv");
  EXPECT_EQ(line_count(runs), 7u) << runs;
  EXPECT_NE(runs.find("\nsuite-1,random,1,"), std::string::npos) << runs;
  EXPECT_EQ(line_count(slurp(dir / "a/summary.csv")), 3u);
  EXPECT_EQ(status_of(dir, "a")["merged"], true);

  std::filesystem::remove(dir / "a/summary.md");  // a run missing: named, nothing written
  std::filesystem::remove(dir / "a/parts/crates_random_1.json");
  EXPECT_EQ(sh(dir, "sh a/merge.sh > /dev/null 2> merge.err"), 1);
  EXPECT_NE(slurp(dir / "merge.err").find("crates_random_1"), std::string::npos) << slurp(dir / "merge.err");
  EXPECT_FALSE(std::filesystem::exists(dir / "a/summary.md"));
}

TEST(CliBatch, StatusNamesFailedTasksAndBadPlansAreRefused) {
  const TempDir dir;
  ASSERT_EQ(run_fvx(dir, "batch capmap " + fvx_arm() + kArmOptions + " --shards 3 -o plan").status, 0);
  // A job log in GNU parallel's format: task 2 exited 1, task 3 was killed by signal 9.
  const json plan = json::parse(slurp(dir / "plan/plan.json"));
  std::ofstream(dir / "log") << "Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand\n"
                             << "2\t:\t1.0\t0.5\t0\t0\t1\t0\t" << plan["tasks"][1]["command"].get<std::string>() << "\n"
                             << "3\t:\t1.0\t0.5\t0\t0\t0\t9\t" << plan["tasks"][2]["command"].get<std::string>() << "\n";
  RunResult r = run_fvx(dir, "batch status plan --joblog log");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(r.out)["results"];
  EXPECT_EQ(s["failed_tasks"], json({1, 2}));
  EXPECT_EQ(s["failed_exit_status"], json({1, 137}));
  EXPECT_EQ(s["remaining"], 1);

  std::ofstream(dir / "notalog") << "hello\n";
  const std::vector<std::tuple<std::string, int, std::string>> cases = {
      {"batch capmap " + fvx_arm() + kArmOptions + " -o p2", 2, "--shards"},
      {"batch capmap " + fvx_arm() + kArmOptions + " --shards 0 -o p2", 2, "--shards"},
      {"batch capmap " + fvx_arm() + kArmOptions + " --voxel -1 --shards 2 -o p2", 2, "--voxel"},
      {"batch capmap " + fvx_arm() + kArmOptions + " --shards 2 -o plan", 1, "holds a plan of other tasks"},
      {"batch capmap missing.urdf --base a --tip b --shards 2 -o p2", 1, "missing.urdf"},
      {"batch capmap " + fvx_arm() + kArmOptions + " --shard-split samples --shards 2 -o p2", 2, "--fk-samples"},
      {"batch capmap " + fvx_arm() + kArmOptions + " --shard-split rows --shards 2 -o p2", 2, "--shard-split"},
      {"batch status nowhere", 1, "no batch plan here"},
      {"batch status plan --joblog notalog", 1, "not a GNU parallel job log"},
      {"batch frobnicate", 2, "capmap, replay, sweep, status or merge"},
      {"batch sweep -o p2", 2, "--scenes"},
      {"batch sweep --scenes nowhere.ply -o p2", 1, "nowhere.ply"},
      {"batch sweep --scenes builtin:nowhere -o p2", 2, "nowhere"},
      {"batch sweep --scenes 1 --planners frontier-void,bogus -o p2", 2, "bogus"},
      {"batch sweep --scenes 1 --seeds 3-1 -o p2", 2, "--seeds"},
      {"batch sweep --scenes 1 --max-views 0 -o p2", 2, "--max-views"},
      {"batch sweep --scenes 1 -o p2 -- --arm missing.urdf", 1, "missing.urdf"},
      {"batch replay --list nolist.txt -o p2", 1, "nolist.txt"},
      {"batch replay -o p2 -- --no-capmap", 2, "--list"},
  };
  for (const auto& [command, status, mention] : cases) {
    r = run_fvx(dir, command);
    EXPECT_EQ(r.status, status) << command << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << command << ": " << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << command << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "p2"));
}

}  // namespace
}  // namespace fvx::test
