// Planner sweeps: the lists users write, the plan's checks before anything is written, and
// the merge's tables worked out by hand from made-up explore reports.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "fvx/batch/sweep.hpp"
#include "fvx/core/error.hpp"
#include "test_support.hpp"

namespace fvx::batch {
namespace {

using nlohmann::json;

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(BatchSweep, ListsExpandAsWritten) {
  EXPECT_EQ(parse_scene_list("1-3,closed-box scenes/shelf.ply builtin:room"),
            (std::vector<std::string>{"builtin:suite/1", "builtin:suite/2", "builtin:suite/3", "builtin:closed-box",
                                      "scenes/shelf.ply", "builtin:room"}));
  EXPECT_THROW(parse_scene_list("3-1"), UsageError);
  EXPECT_THROW(parse_scene_list(" , "), UsageError);
  EXPECT_EQ(parse_seed_list("1-3,7"), (std::vector<int>{1, 2, 3, 7}));
  EXPECT_THROW(parse_seed_list("1,x"), UsageError);
  const std::vector<Planner> p = parse_planner_list("frontier-void,random fv-b=frontier-void,--utility-vectors,262144");
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[1].label, "random");
  EXPECT_EQ(p[2].label, "fv-b");
  EXPECT_EQ(p[2].strategy, "frontier-void");
  EXPECT_EQ(p[2].flags, (std::vector<std::string>{"--utility-vectors", "262144"}));
  for (const char* bad : {"frontier-vide", "a_b=random", "random random", "x=", ""})
    EXPECT_THROW(parse_planner_list(bad), UsageError) << bad;
}

TEST(BatchSweep, APlanIsOneRunPerSceneAndPlannerAndSeedAfterItsInputsAreChecked) {
  const test::TempDir dir;
  std::ofstream(dir / "shelf.ply") << "ply\n";
  Sweep sweep{{"builtin:suite/2", dir / "shelf.ply"}, parse_planner_list("frontier-void random"), {1, 2}, 4, {"--resolution", "0.05"}};
  const Plan plan = sweep_plan("/usr/bin/fvx", sweep, dir / "plan");
  ASSERT_EQ(plan.tasks.size(), 8u);
  EXPECT_EQ(plan.tasks[0].output, dir / "plan/parts/suite-2_frontier-void_1.json");
  EXPECT_EQ(plan.tasks[7].output, dir / "plan/parts/shelf.ply_random_2.json");
  EXPECT_NE(plan.tasks[3].command.find("explore 'builtin:suite/2' '--resolution' '0.05' --strategy 'random' --seed 2 "
                                       "--max-views 4 --timing --format json"),
            std::string::npos)
      << plan.tasks[3].command;
  EXPECT_EQ(plan.result, dir / "plan/summary.md");

  Sweep bad = sweep;
  bad.scenes = {dir / "missing.ply"};
  EXPECT_THROW(sweep_plan("/usr/bin/fvx", bad, dir / "p2"), FileError);
  bad.scenes = {"builtin:nowhere"};
  EXPECT_THROW(sweep_plan("/usr/bin/fvx", bad, dir / "p2"), UsageError);
  std::filesystem::create_directory(dir / "other");
  std::ofstream(dir / "other/shelf.ply") << "ply\n";
  bad.scenes = {dir / "shelf.ply", dir / "other/shelf.ply"};
  EXPECT_THROW(sweep_plan("/usr/bin/fvx", bad, dir / "p2"), UsageError) << "two scenes of one name";
  bad = sweep;
  bad.options = {"--capmap", dir / "missing.fcm"};
  EXPECT_THROW(sweep_plan("/usr/bin/fvx", bad, dir / "p2"), FileError);
  EXPECT_FALSE(std::filesystem::exists(dir / "p2"));
}

/// An explore report with these coverages after each view.
json report(const std::vector<double>& void_known, bool exhausted, std::optional<int> target_cells, int seen_at) {
  json rows = json::array();
  for (std::size_t v = 0; v < void_known.size(); ++v)
    rows.push_back({{"view", v + 1}, {"void_known_fraction", void_known[v]}, {"known_fraction", 0.5},
                    {"target_seen", int(v + 1) >= seen_at}, {"timing_s", {{"search", 0.25 * double(v + 1)}}}});
  return {{"config", {{"max_views", 3}}},
          {"results",
           {{"views", void_known.size()}, {"end", "done, really"}, {"utility_exhausted", exhausted},
            {"observable_void_cells", 100}, {"observable_target_cells", target_cells ? json(*target_cells) : json()},
            {"rows", rows}}}};
}

TEST(BatchSweep, TheMergeWritesTheTablesWorkedOutByHand) {
  const test::TempDir dir;
  Sweep sweep{{"builtin:suite/1", "builtin:suite/2"}, parse_planner_list("frontier-void random"), {1}, 3, {}};
  const Plan plan = sweep_plan("/usr/bin/fvx", sweep, dir / "plan");
  write_plan(plan);
  const auto part = [&](std::size_t i, const json& j) { std::ofstream(plan.tasks[i].output) << j.dump(); };
  part(0, report({0.5, 0.96}, true, 20, 1));   // suite-1 frontier-void: 95 % at view 2, ends there
  part(1, report({0.2, 0.4, 0.6}, false, 20, 9));  // suite-1 random: never, target not seen
  part(2, report({0.25, 0.5, 0.75}, false, 3, 2));  // suite-2 frontier-void: target not observable (3 < 5)
  EXPECT_THROW(merge_sweep(plan), FileError) << "the fourth run is missing";
  EXPECT_FALSE(std::filesystem::exists(dir / "plan/runs.csv"));
  std::ofstream(plan.tasks[3].output) << "{\"results\": 1";
  EXPECT_THROW(merge_sweep(plan), FileError) << "a damaged report";
  part(3, report({0.1, 0.95, 0.99}, false, std::nullopt, 9));
  merge_sweep(plan);

  EXPECT_EQ(slurp(dir / "plan/runs.csv"),
            "scene,planner,seed,views,end,utility_exhausted,observable_void_cells,target_observable,target_seen_at,"
            "views_to_95,void_known_final,known_final,auc\n"
            "suite-1,frontier-void,1,2,done; really,true,100,yes,1,2,0.96,0.5,0.8067\n"
            "suite-1,random,1,3,done; really,false,100,yes,,,0.6,0.5,0.4000\n"
            "suite-2,frontier-void,1,3,done; really,false,100,no,2,,0.75,0.5,0.5000\n"
            "suite-2,random,1,3,done; really,false,100,,,2,0.99,0.5,0.6800\n");
  const std::string coverage = slurp(dir / "plan/coverage.csv");
  EXPECT_NE(coverage.find("suite-1,frontier-void,1,3,0.96\n"), std::string::npos) << "carried to max-views: " << coverage;
  // frontier-void: views to 95 % {2, 4 (never)} → lower median 2; random {4, 2} → 2.
  // AUC: frontier-void (0.8067 + 0.5) / 2, random (0.4 + 0.68) / 2; frontier-void higher on suite-1 only.
  EXPECT_EQ(slurp(dir / "plan/summary.csv"),
            "planner,runs,views_to_95_median,reached_95,ended_utility_0,target_observable,target_seen,auc_mean,"
            "first_auc_higher,runs_compared\n"
            "frontier-void,2,2,1,1,1,1,0.6533,0,0\n"
            "random,2,2,1,0,1,0,0.5400,1,2\n");
  EXPECT_NE(slurp(dir / "plan/summary.md").find("| random | 2 | 2 | 1/2 | 0/2 | 0/1 | 0.540 | 1/2 |"), std::string::npos);
  EXPECT_EQ(slurp(dir / "plan/timing.csv").rfind("scene,planner,seed,search_s_median,search_s_total\n"
                                                 "suite-1,frontier-void,1,0.2500,0.750\n", 0), 0u);
  const std::string png = slurp(dir / "plan/coverage.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(slurp(dir / "plan/coverage.dat").find("# random\n1 10.000 10.000 10.000\n"), std::string::npos);
}

}  // namespace
}  // namespace fvx::batch
