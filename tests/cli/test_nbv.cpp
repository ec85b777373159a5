// fvx nbv as users run it: the ranked views and the files people open, determinism, the
// empty answer, bad input, and the real slambook map checked by an independent ray cast.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <map>
#include <set>

#include "cli_support.hpp"
#include "fvx/frontiers/frontiers.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/voids/voids.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;


/// The closed box scanned from six sides (as tests/unit/nbv), with the binary itself.
void make_closed_box_map(const TempDir& dir) {
  const char* eyes[] = {"2.070,-0.020,0.900", "1.420,1.106,0.900",  "0.120,1.106,0.900",
                        "-0.530,-0.020,0.900", "0.120,-1.146,0.900", "1.420,-1.146,0.900"};
  std::string scans;
  for (int i = 0; i < 6; ++i) {
    const std::string scan = "s" + std::to_string(i) + ".pcd";
    ASSERT_EQ(run_fvx(dir, std::string("simulate builtin:closed-box --look-at ") + eyes[i] + ",0.77,-0.02,0.2 -o " + scan)
                  .status,
              0);
    scans += " " + scan;
  }
  ASSERT_EQ(run_fvx(dir, "integrate -o box.ot -r 0.02 --no-register" + scans).status, 0);
}

std::string arm_options(const std::string& base = "0.2,0,0,0,0,0") {
  return " --capmap '" + source("data/arms/fvx-arm.fcm") + "' --base " + base + " --arm '" +
         source("data/arms/fvx-arm.urdf") + "'";
}

TEST(CliNbv, RanksReachableViewsAndWritesTheUtilityField) {
  const TempDir dir;
  make_closed_box_map(dir);
  const std::string command = "nbv box.ot" + arm_options() + " --rays 40x30 --top 5";
  RunResult r = run_fvx(dir, command + " -o v.json --utility-cloud u.ply --picture u.png");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  const std::string first = slurp(dir / "v.json");
  const json v = json::parse(first);
  EXPECT_EQ(v["command"], "nbv");
  const json& res = v["results"];
  ASSERT_GE(res["views"].size(), 1u);
  ASSERT_LE(res["views"].size(), 5u);
  EXPECT_TRUE(res["reason"].is_null());
  const double R = 0.02;
  int rank = 1;
  for (const auto& view : res["views"]) {
    EXPECT_EQ(view["rank"], rank++);
    EXPECT_EQ(view["joints_rad"].size(), 5u);
    EXPECT_EQ(view["utility_dm3"].get<double>(), double(view["void_cells_seen"].get<std::size_t>()) * R * R * R * 1000.0);
    EXPECT_GT(view["accumulated_utility_dm3"].get<double>(), 0.0);
    EXPECT_FALSE(view["voids_seen"].empty());
    EXPECT_FALSE(view["utility_from"].empty());
  }
  EXPECT_EQ(res["best_void_cells_seen"], res["views"][0]["void_cells_seen"]);
  EXPECT_EQ(res["pruning"]["valid_poses"], 50);
  EXPECT_EQ(io::read_cloud(dir / "u.ply").points.size(), res["pruning"]["utility_cells"].get<std::size_t>());
  EXPECT_GT(std::filesystem::file_size(dir / "u.png"), 1000u);

  // Determinism: the same inputs give the same bytes, on one thread as on all.
  r = run_fvx(dir, command + " -o v2.json --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  const json v2 = json::parse(slurp(dir / "v2.json"));
  json pictured = v["results"];
  pictured["picture"] = nullptr;  // the run without --picture names none
  EXPECT_EQ(v2["results"], pictured);
  const std::string picture = slurp(dir / "u.png");
  r = run_fvx(dir, command + " -o v3.json --utility-cloud u.ply --picture u.png");
  EXPECT_EQ(slurp(dir / "v3.json"), first);
  EXPECT_EQ(slurp(dir / "u.png"), picture);  // the picture too, byte for byte
  // glibc's heap as it comes (core::use_huge_page_heap left out) changes no byte either.
  r = run_fvx(dir, command + " -o v4.json --utility-cloud u.ply --picture u.png", "FVX_DEFAULT_HEAP=1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(dir / "v4.json"), first);
  EXPECT_EQ(slurp(dir / "u.png"), picture);
  // Timing only when asked for.
  EXPECT_FALSE(res.contains("timing_s"));
  r = run_fvx(dir, command + " --timing");
  ASSERT_EQ(r.status, 0) << r.err;
  const json timed = json::parse(r.out);
  EXPECT_GT(timed["results"]["timing_s"]["cells_per_s"].get<double>(), 0.0);
}

TEST(CliNbv, AnswersEmptyWithAReasonWhenNothingReachableSeesAVoid) {
  const TempDir dir;
  make_closed_box_map(dir);
  RunResult r = run_fvx(dir, "nbv box.ot" + arm_options("30,0,0,0,0,0"));
  ASSERT_EQ(r.status, 0) << r.err;
  json v = json::parse(r.out);
  EXPECT_TRUE(v["results"]["views"].empty());
  EXPECT_EQ(v["results"]["best_utility_dm3"], 0.0);
  EXPECT_NE(v["results"]["reason"].get<std::string>().find("out of the arm's reach"), std::string::npos);
  EXPECT_FALSE(v["warnings"].empty());
  // Bounds that hold no voids: empty too, with the reason.
  r = run_fvx(dir, "nbv box.ot --no-capmap --bounds 0.0,0.9,0.0,0.2,1.0,0.1");
  ASSERT_EQ(r.status, 0) << r.err;
  v = json::parse(r.out);
  EXPECT_TRUE(v["results"]["views"].empty());
  EXPECT_NE(v["results"]["reason"].get<std::string>().find("no void cell"), std::string::npos);
}

TEST(CliNbv, SensorFileAndReferenceStrategies) {
  const TempDir dir;
  make_closed_box_map(dir);
  std::ofstream(dir / "kinect.json") << R"({"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "width": 640,
                                           "height": 480, "depth_min_m": 0.4, "depth_max_m": 2.5})";
  RunResult r = run_fvx(dir, "nbv box.ot --no-capmap --sensor kinect.json --strategy frontier --top 2");
  ASSERT_EQ(r.status, 0) << r.err;
  json v = json::parse(r.out);
  EXPECT_EQ(v["config"]["sensor"]["depth_max_m"], 2.5);
  EXPECT_EQ(v["config"]["sensor"]["depth_min_m"], 0.4);
  EXPECT_EQ(v["config"]["strategy"], "frontier");
  ASSERT_FALSE(v["results"]["views"].empty());
  EXPECT_GT(v["results"]["views"][0]["frontier_cells_seen"].get<int>(), 0);
  // Flags override the file.
  r = run_fvx(dir, "nbv box.ot --no-capmap --sensor kinect.json --depth-max 3 --top 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["config"]["sensor"]["depth_max_m"], 3.0);
  // Exhaustive on the committed map: every view is a capability-map pose.
  r = run_fvx(dir, "nbv box.ot --capmap '" + source("data/arms/fvx-arm.fcm") +
                       "' --base 0.2,0,0,0,0,0 --strategy exhaustive --rays 20x15 --rolls 1 --top 3");
  ASSERT_EQ(r.status, 0) << r.err;
  v = json::parse(r.out);
  ASSERT_FALSE(v["results"]["views"].empty());
  EXPECT_GT(v["results"]["pruning"]["culled_no_void_in_frustum"].get<int>(), 0);
  EXPECT_TRUE(v["results"]["views"][0]["joints_rad"].is_null());
}

TEST(CliNbv, BadInputGetsOneClearLineAndNoOutput) {
  const TempDir dir;
  make_closed_box_map(dir);
  struct Case {
    std::string arguments;
    int status;
    std::string message;
  };
  {
    std::ofstream(dir / "zero.json") << R"({"fx": 0, "fy": 525, "cx": 319.5, "cy": 239.5})";
    std::string urdf = slurp(source("data/arms/fvx-arm.urdf"));
    std::ofstream(dir / "other.urdf") << urdf << "<!-- another arm -->\n";
  }
  const std::vector<Case> cases = {
      {"nbv box.ot --capmap missing.fcm", 1, "missing.fcm"},
      {"nbv box.ot --capmap '" + source("data/arms/fvx-arm.fcm") + "' --arm other.urdf", 1, "another URDF"},
      {"nbv box.ot --no-capmap --sensor zero.json", 1, "fx"},
      {"nbv box.ot --no-capmap --fx 0", 2, "fx"},
      {"nbv box.ot --no-capmap --top 0", 2, "--top"},
      {"nbv box.ot", 2, "--no-capmap"},
      {"nbv box.ot --no-capmap --strategy exhaustive", 2, "exhaustive"},
      {"nbv box.ot --no-capmap --strategy best", 2, "--strategy"},
      {"nbv box.ot --no-capmap --rays 0x30", 2, "--rays"},
      {"nbv box.ot --no-capmap --refine -1", 2, "--refine"},
      {"nbv box.ot --no-capmap --refine-step 0.5,0.1", 2, "--refine-step"},
      {"nbv box.ot --no-capmap --base 1,2,3", 2, "--base"},
      {"nbv box.ot --capmap '" + source("data/arms/fvx-arm.fcm") + "' --base 1,2,3", 2, "--base"},
      {"nbv box.ot --no-capmap --accumulation fast", 2, "--accumulation"},
      {"nbv box.ot --no-capmap --utility-vectors 3", 2, "--utility-vectors"},
      {"nbv box.ot --no-capmap --utility-vectors many", 2, "--utility-vectors"},
      {"nbv box.ot --no-capmap --coarse-rays 0x30", 2, "--coarse-rays"},
      {"nbv box.ot --no-capmap --near-unknown none", 2, "--near-unknown"},
      {"nbv box.ot --no-capmap --coarse-rays coarse", 2, "--coarse-rays"},
      {"nbv missing.ot --no-capmap", 1, "missing.ot"},
      {"nbv s0.pcd --no-capmap", 1, "s0.pcd"},
  };
  for (const Case& c : cases) {
    const RunResult r = run_fvx(dir, c.arguments + " -o out.json");
    EXPECT_EQ(r.status, c.status) << c.arguments << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << c.arguments << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.arguments << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.json")) << c.arguments;
  }
}

// Under the budget the sampled accumulation is the exact one: the same report but for the
// echoed mode; forced to sample, the report says how many vectors it traced of how many.
// A user who gives a box "large enough for everything" gets the views of the map, not an
// abort: the search's grid reaches the sensor's range beyond the known cells and no farther
// (an eye beyond it sees nothing), where it once spanned the 2 km box (7·10¹⁰ cells).
TEST(CliNbv, BoundsFarBeyondTheMapGiveItsViews) {
  const TempDir dir;
  make_crates_map(dir);
  // A 2 m range keeps the grid of view bounds across all the air small (a 4 m one is 1.5 GB).
  const RunResult plain = run_fvx(dir, "nbv map.ot --no-capmap --depth-max 2");
  ASSERT_EQ(plain.status, 0) << plain.err;
  const int best = json::parse(plain.out)["results"]["best_void_cells_seen"].get<int>();
  ASSERT_GT(best, 0);
  for (const char* boxes : {"--bounds -1000,-1000,-1000,1000,1000,1000", "--view-bounds -1000,-1000,-1000,1000,1000,1000",
                            "--bounds -1000,-1000,-1000,1000,1000,1000 --exterior unknown"}) {
    const RunResult r = run_fvx(dir, std::string("nbv map.ot --no-capmap --depth-max 2 ") + boxes);
    ASSERT_EQ(r.status, 0) << boxes << ": " << r.err;
    const json j = json::parse(r.out);
    EXPECT_FALSE(j["results"]["views"].empty()) << boxes;
    EXPECT_GT(j["results"]["best_void_cells_seen"].get<int>(), best / 2) << boxes;
    // S beyond the known cells adds no void: the search space's known part is the default's.
    if (std::string(boxes).rfind("--bounds", 0) == 0 && std::string(boxes).find("exterior") == std::string::npos) {
      EXPECT_EQ(j["results"]["views"], json::parse(plain.out)["results"]["views"]);
    }
  }
  // View bounds far from the map: nowhere to stand that sees anything, an empty answer with
  // its reason (this aborted as well).
  const RunResult far = run_fvx(dir, "nbv map.ot --no-capmap --view-bounds 100,100,100,101,101,101");
  ASSERT_EQ(far.status, 0) << far.err;
  const json j = json::parse(far.out);
  EXPECT_TRUE(j["results"]["views"].empty());
  EXPECT_FALSE(j["results"]["reason"].get<std::string>().empty());
}

TEST(CliNbv, AccumulationModesAgreeUnderTheBudget) {
  const TempDir dir;
  make_closed_box_map(dir);
  const RunResult exact = run_fvx(dir, "nbv box.ot --no-capmap --accumulation exact -o exact.json");
  const RunResult sampled = run_fvx(dir, "nbv box.ot --no-capmap -o sampled.json");
  ASSERT_EQ(exact.status, 0) << exact.err;
  ASSERT_EQ(sampled.status, 0) << sampled.err;
  const json e = json::parse(slurp(dir / "exact.json")), s = json::parse(slurp(dir / "sampled.json"));
  EXPECT_EQ(e["config"]["accumulation"], "exact");
  EXPECT_EQ(s["config"]["accumulation"], "sampled");
  const std::size_t vectors = e["results"]["utility_vectors"].get<std::size_t>();
  ASSERT_GT(vectors, 1000u);
  EXPECT_EQ(e["results"], s["results"]);
  const std::string budget = std::to_string(vectors / 10);
  ASSERT_EQ(run_fvx(dir, "nbv box.ot --no-capmap --utility-vectors " + budget + " -o few.json").status, 0);
  const json few = json::parse(slurp(dir / "few.json"));
  EXPECT_EQ(few["config"]["max_utility_vectors"].get<std::size_t>(), vectors / 10);
  EXPECT_LT(few["results"]["utility_vectors"].get<std::size_t>(), vectors / 5);
  EXPECT_EQ(few["results"]["exact_utility_vectors"], e["results"]["exact_utility_vectors"]);
  EXPECT_FALSE(few["results"]["views"].empty());
}

// Screening is echoed; off, every pose is scored with the full fan (more rays traced), and
// either way the reported U is the full fan's, so the best view's U is comparable.
TEST(CliNbv, CoarseRaysAreEchoedAndOffScoresEveryPoseWithTheFullFan) {
  const TempDir dir;
  make_closed_box_map(dir);
  std::map<std::string, json> runs;
  for (const std::string flags : {"", "--coarse-rays off", "--coarse-rays 20x15"}) {
    const RunResult r = run_fvx(dir, "nbv box.ot --no-capmap --timing " + flags + " -o v.json");
    ASSERT_EQ(r.status, 0) << flags << ": " << r.err;
    runs[flags] = json::parse(slurp(dir / "v.json"));
  }
  EXPECT_EQ(runs[""]["config"]["coarse_rays"], json({40, 30}));
  EXPECT_EQ(runs["--coarse-rays off"]["config"]["coarse_rays"], json({0, 0}));
  EXPECT_EQ(runs["--coarse-rays 20x15"]["config"]["coarse_rays"], json({20, 15}));
  EXPECT_LT(runs[""]["results"]["timing_s"]["rays"].get<double>(),
            runs["--coarse-rays off"]["results"]["timing_s"]["rays"].get<double>());
  for (const auto& [flags, report] : runs)
    EXPECT_GE(report["results"]["best_void_cells_seen"].get<double>(),
              0.8 * runs["--coarse-rays off"]["results"]["best_void_cells_seen"].get<double>()) << flags;
}

// The real slambook map, free-flying: the top pose is a free cell, and an independent cast
// (fine steps along the pose's rays through the octree itself) sees the void cells it claims.
TEST(CliNbv, SlambookTopPoseStandsInFreeSpaceOrAirAndSeesVoids) {
  FVX_REAL_DATA_OR_SKIP(map_path, "octomap-maps/slambook_ch13/octomap.bt");
  const TempDir dir;
  const RunResult r = run_fvx(dir, "nbv '" + map_path + "' --no-capmap --top 3 -o v.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json v = json::parse(slurp(dir / "v.json"));
  ASSERT_FALSE(v["results"]["views"].empty()) << v["results"]["reason"];
  const json& top = v["results"]["views"][0];
  const auto map = map::OccupancyMap::load(map_path);
  const auto p = top["position_m"].get<std::vector<double>>();
  const auto q = top["quaternion_xyzw"].get<std::vector<double>>();
  const Eigen::Vector3d origin(p[0], p[1], p[2]);
  const Eigen::Matrix3d R = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).toRotationMatrix();
  voids::VoidSet void_set;
  void_set.rebuild(map);
  // The eye stands in a free cell or (--exterior view, the default) in the unknown air
  // outside the voids' hull.
  const map::VoxelState eye = map.state(*map.key_of(origin));
  ASSERT_TRUE(eye == map::VoxelState::Free ||
              (eye == map::VoxelState::Unknown && !void_set.hull().contains(map.center_of(*map.key_of(origin)))));
  const json& b = v["results"]["bounds_m"];
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(b["min"][0], b["min"][1], b["min"][2]),
                                   Eigen::Vector3d(b["max"][0], b["max"][1], b["max"][2]));
  const auto cells = void_set.cells(map, bounds);
  const std::set<map::VoxelKey> voids(cells.begin(), cells.end());
  // The default sensor: Kinect v1 intrinsics, 80×60 rays, depth 4 m along z.
  std::set<map::VoxelKey> seen;
  const double step = map.resolution_m() / 20.0;
  for (int row = 0; row < 60; ++row)
    for (int col = 0; col < 80; ++col) {
      const Eigen::Vector3d ray(((col + 0.5) * 8 - 0.5 - 319.5) / 525.0, ((row + 0.5) * 8 - 0.5 - 239.5) / 525.0, 1.0);
      const Eigen::Vector3d d = R * ray.normalized();
      for (double t = 0.0; t <= 4.0 * ray.norm(); t += step) {
        const auto k = map.key_of(origin + t * d);
        if (!k || map.state(*k) == map::VoxelState::Occupied) break;
        if (voids.count(*k)) seen.insert(*k);
      }
    }
  const auto claimed = top["void_cells_seen"].get<std::size_t>();
  EXPECT_GT(claimed, 1000u);
  // Fine steps may clip a corner the exact walk enters, or miss one it does not: within 3 %.
  EXPECT_NEAR(double(seen.size()), double(claimed), 0.03 * double(claimed));
}

}  // namespace
}  // namespace fvx::test
