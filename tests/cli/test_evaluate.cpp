// scripts/evaluate-planners.sh as CI runs it: three scenes of the suite, the four planners,
// two views. Its tables parse, hold one line per run and per planner with values in range,
// the plot is a PNG, and a second call finds every run done and writes the same tables.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <sstream>

#include "cli_support.hpp"

namespace fvx::test {
namespace {

std::vector<std::vector<std::string>> read_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    rows.push_back(cells);
  }
  return rows;
}

RunResult run_script(const TempDir& dir, const std::string& arguments) {
  const std::filesystem::path build = std::filesystem::path(FVX_BINARY).parent_path().parent_path();
  const std::string command = "FVX_BUILD_DIR='" + build.string() + "' '" + source("scripts/evaluate-planners.sh") + "' " +
                              arguments + " > '" + (dir / ".out") + "' 2> '" + (dir / ".err") + "'";
  const int raw = std::system(command.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), slurp(dir / ".out"), slurp(dir / ".err")};
}

TEST(EvaluatePlanners, TheSmokeRunParsesAndResumes) {
  const TempDir dir;
  const std::string out = dir / "eval";
  const std::string args = "--scenes 1-3 --max-views 2 --jobs 2 -o '" + out + "'";
  const RunResult r = run_script(dir, args);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto runs = read_csv(slurp(out + "/runs.csv"));
  ASSERT_EQ(runs.size(), 1u + 3 * 4);
  ASSERT_EQ(runs[0][0], "scene");
  const std::size_t columns = runs[0].size();
  std::map<std::string, int> per_planner;
  for (std::size_t i = 1; i < runs.size(); ++i) {
    ASSERT_EQ(runs[i].size(), columns) << i;
    ++per_planner[runs[i][1]];
    const int views = std::stoi(runs[i][3]);
    EXPECT_GE(views, 1);
    EXPECT_LE(views, 2);
    EXPECT_GT(std::stoi(runs[i][6]), 0) << "observable void cells";
    for (const int c : {10, 11, 12}) {  // void_known_final, known_final, auc
      EXPECT_GE(std::stod(runs[i][std::size_t(c)]), 0.0);
      EXPECT_LE(std::stod(runs[i][std::size_t(c)]), 1.0);
    }
  }
  for (const char* p : {"frontier-void", "frontier", "random", "exhaustive"}) EXPECT_EQ(per_planner[p], 3) << p;
  const auto summary = read_csv(slurp(out + "/summary.csv"));
  ASSERT_EQ(summary.size(), 5u);
  EXPECT_EQ(summary[1][0], "frontier-void");  // in the order the planners were given
  const std::string png = slurp(out + "/coverage.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(r.out.find("| frontier-void | 3 |"), std::string::npos) << r.out;
  // Everything is done: the second call runs nothing and writes the same tables.
  const std::string first = slurp(out + "/runs.csv");
  const RunResult again = run_script(dir, args);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.err.find("0 runs to do"), std::string::npos) << again.err;
  EXPECT_EQ(slurp(out + "/runs.csv"), first);
  // Nonsense options are refused.
  EXPECT_EQ(run_script(dir, "--max-views 0 -o '" + out + "'").status, 2);
  EXPECT_EQ(run_script(dir, "--bogus").status, 2);
}

}  // namespace
}  // namespace fvx::test
