// Batch plans: sh quoting that survives any path, shard outputs named in task order, plans
// that refuse to mix with another in one folder.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "fvx/batch/plan.hpp"
#include "fvx/core/error.hpp"
#include "test_support.hpp"

namespace fvx::batch {
namespace {

std::string sh_output(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  for (int c; pipe && (c = std::fgetc(pipe)) != EOF;) out += char(c);
  if (pipe) ::pclose(pipe);
  return out;
}

TEST(BatchPlan, QuotedWordsReachTheCommandUnchanged) {
  for (const std::string word : {"plain", "two words", "it's", "'", "$HOME `id` \"x\" \\n *", "-o", ""})
    EXPECT_EQ(sh_output("printf %s " + shell_quote(word)), word) << word;
}

TEST(BatchPlan, ShardsAreNamedInTaskOrderAndMergedInIt) {
  const Plan plan = capmap_plan("/usr/bin/fvx", "/arms/a b.urdf", {{"voxel", "0.05"}, {"exhaustive", ""}}, 12, "/tmp/p");
  ASSERT_EQ(plan.tasks.size(), 12u);
  EXPECT_EQ(plan.tasks[0].output, "/tmp/p/parts/shard-01-of-12.fcm");
  EXPECT_EQ(plan.tasks[11].output, "/tmp/p/parts/shard-12-of-12.fcm");
  EXPECT_EQ(plan.tasks[2].command, "'/usr/bin/fvx' capmap build '/arms/a b.urdf' --voxel '0.05' --exhaustive --shard 3/12 "
                                   "-o '/tmp/p/parts/shard-03-of-12.fcm' > '/tmp/p/parts/shard-03-of-12.json'");
  EXPECT_EQ(plan.result, "/tmp/p/map.fcm");
  std::size_t at = 0;  // the merge names the shards in task order
  for (const Task& t : plan.tasks) {
    at = plan.merge_command.find(shell_quote(t.output), at);
    ASSERT_NE(at, std::string::npos) << t.output;
  }
  EXPECT_THROW(capmap_plan("fvx", "a.urdf", {}, 0, "/tmp/p"), UsageError);
  // "-o plan/" as users type it: the same paths, not ".../p//parts/...".
  const Plan slash = capmap_plan("/usr/bin/fvx", "/arms/a b.urdf", {{"voxel", "0.05"}, {"exhaustive", ""}}, 12, "/tmp/p/");
  EXPECT_EQ(slash.folder, "/tmp/p");
  EXPECT_EQ(slash.tasks[2].command, plan.tasks[2].command);
  EXPECT_EQ(slash.merge_command, plan.merge_command);
  EXPECT_EQ(absolute_path("/"), "/");
  EXPECT_EQ(absolute_path("/tmp/./p//"), "/tmp/p");
}

TEST(BatchPlan, AFolderHoldsOnePlan) {
  const test::TempDir dir;
  const Plan plan = capmap_plan("/usr/bin/fvx", "/a.urdf", {}, 3, dir / "plan");
  write_plan(plan);
  EXPECT_NO_THROW(write_plan(plan));  // the same plan again
  const Plan back = read_plan(dir / "plan");
  EXPECT_EQ(back.tasks.size(), 3u);
  EXPECT_EQ(back.merge_command, plan.merge_command);
  EXPECT_THROW(write_plan(capmap_plan("/usr/bin/fvx", "/a.urdf", {{"voxel", "0.1"}}, 3, dir / "plan")), FileError);
  const Status s = plan_status(dir / "plan", "");
  EXPECT_EQ(s.remaining.size(), 3u);
  std::ofstream(plan.tasks[1].output) << "x";
  EXPECT_EQ(plan_status(dir / "plan", "").done, std::vector<std::size_t>{1});
}

// The merged table: every part's rows in task order behind its number, the header once,
// the columns of seconds left out; parts with other columns or a part missing: an error
// naming it, and no table.
TEST(BatchPlan, ReplayTablesMergeInTaskOrderWithoutSeconds) {
  const test::TempDir dir;
  std::ofstream(dir / "list.txt") << "# two\nsession-a/\n\n--scans 'b/*.pcd' --to 2\n";
  const Plan plan = replay_plan("/usr/bin/fvx", dir / "list.txt", {"--no-capmap"}, dir / "plan");
  ASSERT_EQ(plan.tasks.size(), 2u);
  EXPECT_NE(plan.tasks[1].command.find("replay --scans 'b/*.pcd' --to 2 '--no-capmap' --format csv -o "), std::string::npos)
      << plan.tasks[1].command;
  write_plan(plan);
  const auto part = [&](std::size_t i, const std::string& table) {
    std::filesystem::create_directories(plan.tasks[i].output);
    std::ofstream(plan.tasks[i].output + "/table.csv") << table;
  };
  part(0, "view,integration_s,void_cells,search_s\n1,0.84,100,-\n2,1.02,90,0.5\n");
  EXPECT_THROW(merge_plan(plan), FileError);  // the second part is missing
  EXPECT_FALSE(std::filesystem::exists(plan.result));
  part(1, "view,integration_s,void_cells,search_s\n1,0.91,7,-\n");
  merge_plan(plan);
  std::ifstream in(plan.result);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), {}), "sequence,view,void_cells\n1,1,100\n1,2,90\n2,1,7\n");
  std::filesystem::remove(plan.result);
  part(1, "view,void_cells\n1,7\n");
  EXPECT_THROW(merge_plan(plan), FileError);
  EXPECT_FALSE(std::filesystem::exists(plan.result));
  std::ofstream(dir / "comments.txt") << "# nothing\n\n";
  EXPECT_THROW(replay_plan("/usr/bin/fvx", dir / "comments.txt", {}, dir / "p2"), FileError) << "a list without a sequence";
}

}  // namespace
}  // namespace fvx::batch
