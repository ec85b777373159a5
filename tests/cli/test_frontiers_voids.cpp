// fvx frontiers and fvx voids as users run them: reports, files people open, bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

TEST(CliFrontiersVoids, ReportsAndFilesPeopleOpen) {
  const TempDir dir;
  make_crates_map(dir);
  const std::string bounds = "--bounds 0.4,-0.8,0.0,1.2,0.75,0.55";
  RunResult r = run_fvx(dir, "frontiers map.ot " + bounds + " -o f.json --cloud f.ply --picture f.png");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  const json f = json::parse(slurp(dir / "f.json"));
  EXPECT_EQ(f["command"], "frontiers");
  EXPECT_GT(f["results"]["frontier_cells"].get<int>(), 100);
  EXPECT_EQ(io::read_cloud(dir / "f.ply").points.size(), f["results"]["frontier_cells"].get<std::size_t>());
  EXPECT_GT(std::filesystem::file_size(dir / "f.png"), 1000u);

  r = run_fvx(dir, "voids map.ot " + bounds + " --cloud v.pcd --by-cluster --ellipsoids e.ply --picture v.png");
  ASSERT_EQ(r.status, 0) << r.err;
  const json v = json::parse(r.out);
  const json& res = v["results"];
  const double R = 0.025;
  EXPECT_GT(res["void_cells"].get<int>(), 1000);
  std::size_t clustered = 0;
  for (const auto& c : res["void_clusters"]) clustered += c["cells"].get<std::size_t>();
  EXPECT_EQ(clustered, res["void_cells"].get<std::size_t>());
  ASSERT_EQ(res["frontier_voids"].size(), res["void_clusters"].size());
  for (const auto& fv : res["frontier_voids"]) {
    // Utility in dm³ = void cells × R³ × 1000, exactly.
    EXPECT_EQ(fv["utility_dm3"].get<double>(), double(fv["void_cells"].get<std::size_t>()) * R * R * R * 1000.0);
    EXPECT_EQ(fv["enclosed"].get<bool>(), fv["frontier_ids"].empty());
  }
  EXPECT_EQ(io::read_cloud(dir / "v.pcd").points.size(),
            res["void_cells"].get<std::size_t>() + res["frontier_cells"].get<std::size_t>());
  EXPECT_GT(std::filesystem::file_size(dir / "e.ply"), 1000u);
  // Deterministic: the same map gives the same report.
  EXPECT_EQ(run_fvx(dir, "voids map.ot " + bounds).out, run_fvx(dir, "voids map.ot " + bounds).out);
  EXPECT_FALSE(res.contains("timing_s"));
  // The hull of the occupied cells in the search space only: the floor beyond it no longer
  // spans the hull, so fewer void cells, all of them void cells of the whole map's hull too.
  r = run_fvx(dir, "voids map.ot " + bounds + " --void-hull search-space --cloud s.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(r.out);
  EXPECT_EQ(s["config"]["hull_in_bounds"], true);
  EXPECT_EQ(v["config"]["hull_in_bounds"], false);
  EXPECT_GT(s["results"]["void_cells"].get<int>(), 0);
  EXPECT_LT(s["results"]["void_cells"].get<int>(), res["void_cells"].get<int>());
  // --timing adds the load and analysis times, on both commands.
  for (const char* command : {"voids", "frontiers"}) {
    const RunResult timed = run_fvx(dir, std::string(command) + " map.ot --timing " + bounds);
    ASSERT_EQ(timed.status, 0) << timed.err;
    EXPECT_GT(json::parse(timed.out)["results"]["timing_s"]["analysis"].get<double>(), 0.0) << command;
  }
}

TEST(CliFrontiersVoidsRealData, BothCommandsRunOnRealMaps) {
  for (const char* name : {"octomap-maps/slambook_ch13/octomap.bt", "octomap-maps/octomap-share-data/geb079.bt"}) {
    FVX_REAL_DATA_OR_SKIP(path, name);
    const TempDir dir;
    for (const char* command : {"frontiers ", "voids "}) {
      const RunResult r = run_fvx(dir, command + path);
      ASSERT_EQ(r.status, 0) << command << name << ": " << r.err;
      const json j = json::parse(r.out);
      EXPECT_GT(j["results"]["frontier_cells"].get<int>(), 1000) << command << name;
      EXPECT_TRUE(j["warnings"].empty()) << command << name;
    }
  }
}

TEST(CliFrontiersVoidsRealData, OccupiedOnlyMapIsAValidEmptyResult) {
  FVX_REAL_DATA_OR_SKIP(path, "octomap-maps/octomap_tutor/sample.bt");
  const TempDir dir;
  const RunResult r = run_fvx(dir, "frontiers " + path);
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["results"]["frontier_cells"], 0);
  ASSERT_EQ(j["warnings"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("no free cells"), std::string::npos);
}

TEST(CliFrontiersVoids, BadInputIsRefusedOnOneLine) {
  const TempDir dir;
  std::ofstream(dir / "text.ot") << "not a map\n";
  const char* cases[][3] = {
      {"voids missing.bt", "1", "missing.bt"},
      {"voids text.ot", "1", "text.ot"},
      {"frontiers", "2", "one map"},
      {"voids text.ot --bounds 1,1,1,0,0,0", "2", "--bounds"},
      {"voids text.ot --min-fit-score 0", "2", "--min-fit-score"},
      {"voids text.ot --void-hull walls", "2", "--void-hull"},
  };
  for (const auto& c : cases) {
    const RunResult r = run_fvx(dir, c[0]);
    EXPECT_EQ(r.status, std::stoi(c[1])) << c[0] << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << c[0] << ": " << r.err;
    EXPECT_NE(r.err.find(c[2]), std::string::npos) << c[0] << ": " << r.err;
  }
}

TEST(CliFrontiersVoids, BoundsThatExcludeEverythingGiveAnEmptyResultAndAWarning) {
  const TempDir dir;
  make_crates_map(dir);
  const RunResult r = run_fvx(dir, "voids map.ot --bounds 10,10,10,11,11,11");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["results"]["void_cells"], 0);
  EXPECT_EQ(j["results"]["frontier_cells"], 0);
  EXPECT_FALSE(j["warnings"].empty());
}

/// Eight occupied cells at the corners of a 6 km cube (0.1 m cells) and a few free cells at its
/// centre: a hull of 2·10^14 cells, more than any machine holds, around a small known place.
void make_huge_map(const TempDir& dir) {
  map::OccupancyMap map(0.1);
  for (const int x : {-30000, 30000})
    for (const int y : {-30000, 30000})
      for (const int z : {-30000, 30000})
        map.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)},
                      map::VoxelState::Occupied);
  for (int x = -3; x <= 3; ++x) map.set_state({std::uint16_t(32768 + x), 32768, 32768}, map::VoxelState::Free);
  map.save(dir / "huge.bt");
}

TEST(CliFrontiersVoids, AMapTooLargeForTheMachineIsRefusedBeforeItAllocatesAndBoundsMakeItFit) {
  const TempDir dir;
  make_huge_map(dir);
  for (const char* command : {"voids huge.bt", "nbv huge.bt --no-capmap"}) {
    const RunResult r = run_fvx(dir, command);
    EXPECT_EQ(r.status, 1) << command << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << command << ": " << r.err;
    EXPECT_NE(r.err.find("memory is available"), std::string::npos) << command << ": " << r.err;
    EXPECT_NE(r.err.find("--bounds"), std::string::npos) << command << ": " << r.err;
    EXPECT_EQ(r.out, "") << command;
  }
  // Frontiers alone hold only the known cells: the map's few.
  const RunResult f = run_fvx(dir, "frontiers huge.bt");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_EQ(json::parse(f.out)["results"]["frontier_cells"], 7);
  // A search space around the known cells reads a grid around it alone; the hull, from every
  // occupied cell, holds all of it, so each of its unknown cells is a void.
  const RunResult v = run_fvx(dir, "voids huge.bt --bounds -0.5,-0.5,-0.5,0.5,0.5,0.5 --progress");
  ASSERT_EQ(v.status, 0) << v.err;
  EXPECT_EQ(json::parse(v.out)["results"]["void_cells"], 10 * 10 * 10 - 7);
  EXPECT_NE(v.err.find("fvx voids: frontiers, voids and frontier-voids of huge.bt"), std::string::npos) << v.err;
  const RunResult n = run_fvx(dir, "nbv huge.bt --no-capmap --bounds -0.5,-0.5,-0.5,0.5,0.5,0.5 --depth-max 2");
  ASSERT_EQ(n.status, 0) << n.err;
  EXPECT_GT(json::parse(n.out)["results"]["best_void_cells_seen"].get<int>(), 0);
  // The sensor allowed anywhere in the 6 km: the search's grid is refused before it is allocated.
  const RunResult g = run_fvx(dir, "nbv huge.bt --no-capmap --bounds -0.5,-0.5,-0.5,0.5,0.5,0.5 "
                                   "--view-bounds -3000,-3000,-3000,3000,3000,3000");
  EXPECT_EQ(g.status, 1) << g.err;
  EXPECT_EQ(line_count(g.err), 1u) << g.err;
  EXPECT_NE(g.err.find("the search's grid holds"), std::string::npos) << g.err;
  EXPECT_NE(g.err.find("--view-bounds"), std::string::npos) << g.err;
  EXPECT_EQ(g.out, "");
}

}  // namespace
}  // namespace fvx::test
