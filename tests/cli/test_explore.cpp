// fvx explore as users run it: the per-view table, the session directory read back (manifest,
// scans with VIEWPOINT, maps OctoMap loads), the command line ending with utility 0 on
// both paper replicas, and bad input refused before anything is written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/session/session.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

std::string arm(const std::string& base = "0.2,0,0,0,0,0") {
  return " --capmap '" + source("data/arms/fvx-arm.fcm") + "' --base " + base + " --arm '" +
         source("data/arms/fvx-arm.urdf") + "'";
}

const std::string kScene = " '" + source("data/scenes/paper-setting-2.ply") + "'";

TEST(CliExplore, WritesTheTableAndASessionThatReadsBack) {
  const TempDir dir;
  const RunResult r = run_fvx(dir, "explore" + kScene + arm() + " --max-views 3 -o session");
  ASSERT_EQ(r.status, 0) << r.err;
  // The markdown table: a header, a rule, one row per view.
  EXPECT_NE(r.out.find("| view | integration_s | search_s | void_cells | utility_dm3 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n| 3 |"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("\n| 4 |"), std::string::npos) << r.out;

  const session::Manifest m = session::read_manifest(dir / "session");
  EXPECT_EQ(m.strategy, "frontier-void");
  ASSERT_TRUE(m.T_world_base.has_value());
  EXPECT_NEAR(m.T_world_base->translation().x(), 0.2, 1e-12);
  ASSERT_EQ(m.views.size(), 3u);
  for (const session::ManifestView& v : m.views) {
    const io::CloudFile scan = io::read_cloud(dir / ("session/" + v.scan));
    EXPECT_TRUE(scan.viewpoint.isApprox(v.T_world_sensor_prior, 1e-5)) << v.scan;
    EXPECT_EQ(scan.points.size(), 640u * 480u);
    const map::OccupancyMap map = map::OccupancyMap::load(dir / ("session/" + v.map));
    EXPECT_GT(map.stats().occupied_leaves, 100u) << v.map;
    const json report = json::parse(slurp(dir / ("session/" + v.report)));
    EXPECT_EQ(report["command"], "explore");
    EXPECT_EQ(report["results"]["row"]["view"], v.view + 1);
    ASSERT_EQ(v.joints_rad.size(), 5);
  }
  // Each view after the first stands where the previous report's chosen view put it (FK of
  // its joints, within the capability map's tolerance).
  for (std::size_t i = 1; i < m.views.size(); ++i) {
    const json prev = json::parse(slurp(dir / ("session/" + m.views[i - 1].report)));
    bool found = false;
    for (const auto& view : prev["results"]["views"]) {
      const Eigen::Vector3d p(view["position_m"][0], view["position_m"][1], view["position_m"][2]);
      found |= (p - m.views[i].T_world_sensor_true->translation()).norm() < 0.006;
    }
    EXPECT_TRUE(found) << "view " << i << " is not one the search ranked";
  }

  // The same run as csv and json: the same numbers apart from the timings.
  const RunResult csv = run_fvx(dir, "explore" + kScene + arm() + " --max-views 3 --format csv -o session2");
  ASSERT_EQ(csv.status, 0) << csv.err;
  EXPECT_EQ(csv.out.substr(0, csv.out.find('\n')),
            "view,integration_s,search_s,void_cells,utility_dm3,map_void_cells,void_known_pct,known_pct,target_seen,"
            "revealed,u_in_solid");
  EXPECT_EQ(line_count(csv.out), 4u);
  const RunResult js = run_fvx(dir, "explore" + kScene + arm() + " --max-views 3 --format json -o session3");
  ASSERT_EQ(js.status, 0) << js.err;
  const json j = json::parse(js.out);
  ASSERT_EQ(j["results"]["rows"].size(), 3u);
  EXPECT_GT(j["results"]["observable_cells"].get<int>(), 1000);
  EXPECT_GT(j["results"]["observable_void_cells"].get<int>(), 100);
  EXPECT_LT(j["results"]["observable_void_cells"].get<int>(), j["results"]["observable_cells"].get<int>());
  const session::Manifest m3 = session::read_manifest(dir / "session3");
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_TRUE(m3.views[i].T_world_sensor_prior.isApprox(m.views[i].T_world_sensor_prior, 1e-12)) << "view " << i;
  for (const auto& row : j["results"]["rows"]) {
    EXPECT_NEAR(row["utility_dm3"].get<double>(), row["void_cells"].get<double>() * 0.015625, 1e-9);
    EXPECT_GE(row["known_fraction"].get<double>(), 0.0);
    EXPECT_LE(row["known_fraction"].get<double>(), 1.0);
    EXPECT_GE(row["void_known_fraction"].get<double>(), 0.0);
    EXPECT_LE(row["void_known_fraction"].get<double>(), 1.0);
    EXPECT_LE(row["void_cells_in_solid"].get<int>(), row["void_cells"].get<int>());
    EXPECT_GE(row["free_cells_in_solid"].get<int>(), 0);
    EXPECT_FALSE(row.contains("timing_s"));
  }
  // Without --timing, the same run gives the same report and the same view reports, byte for byte.
  std::filesystem::rename(dir / "session3", dir / "first");
  const RunResult again = run_fvx(dir, "explore" + kScene + arm() + " --max-views 3 --format json -o session3");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(again.out, js.out);
  for (const session::ManifestView& v : m3.views)
    EXPECT_EQ(slurp(dir / ("session3/" + v.report)), slurp(dir / ("first/" + v.report))) << v.report;
  EXPECT_EQ(slurp(dir / "session3/manifest.json"), slurp(dir / "first/manifest.json"));
}

// The command line on both replicas (the arm at the origin, each victim's size), with
// U counting only what the sensor can measure: the loop finds the victim and ends by itself
// (as the paper's did, with utility 0, or with nothing new left to take) within 20 views
// (the paper: 5 and 7). With the fk-seeded-ik
// capability map shipped before, 10 and 14 views sufficed, partly because it reached so
// little that no sampled orientation was reachable any more; the fk-witness map reaches
// more, and paper-setting-1 takes 17. (With the default U void cells nearer than the
// minimum depth, which no scan measures, keep U above 0: the loop runs to its limit.) Under
// the default --near-unknown hidden the two runs end with utility 0 after 13 and 11 views
// (with ignore: 17 views on a repeated view, and 16).
TEST(CliExplore, ThePaperReplicasEndWithUtilityZero) {
  const TempDir dir;
  struct Run {
    std::string scene, target_size, seed;
  };
  for (const Run& run : {Run{"paper-setting-1", "0.08", "2"}, Run{"paper-setting-2", "0.06", "3"}}) {
    const RunResult r = run_fvx(dir, "explore '" + source("data/scenes/" + run.scene + ".ply") + "'" +
                                         arm("0,0,0,0,0,0") + " --target-size " + run.target_size + " --seed " +
                                         run.seed + " --far-voids-only --max-views 20 --format json -o " + run.scene);
    ASSERT_EQ(r.status, 0) << r.err;
    const json results = json::parse(r.out)["results"];
    // It ends by itself: utility 0, or (as paper-setting-1 seed 2 on an AMD EPYC, whose
    // simulated scans differ from an Intel machine's in their last bits) the view it would
    // take next repeats one taken, with the last view's void cells at 0 and 98.8 % known.
    const std::string end = results["end"].get<std::string>();
    EXPECT_TRUE(results["utility_exhausted"].get<bool>() || end == "every ranked view repeats one already taken")
        << run.scene << ": " << end;
    EXPECT_LE(results["views"].get<int>(), 20) << run.scene;
    EXPECT_EQ(results["rows"].back()["void_cells"], 0) << run.scene;
    EXPECT_TRUE(results["rows"].back()["target_seen"].get<bool>()) << run.scene;
    EXPECT_GE(results["rows"].back()["known_fraction"].get<double>(), 0.95) << run.scene;
  }
}

// A suite scene: the arm stands where the sidecar puts it (no --base), and a scene without a
// target gives no target warning and no observable target count.
TEST(CliExplore, ASuiteSceneTakesItsBaseFromTheSidecar) {
  const TempDir dir;
  const std::string arm_only = " --capmap '" + source("data/arms/fvx-arm.fcm") + "' --arm '" +
                               source("data/arms/fvx-arm.urdf") + "'";
  const RunResult r = run_fvx(dir, "explore builtin:suite/6" + arm_only + " --max-views 1 --format json -o s");
  ASSERT_EQ(r.status, 0) << r.err;
  const json results = json::parse(r.out)["results"];
  EXPECT_TRUE(results["observable_target_cells"].is_null());
  EXPECT_GT(results["observable_void_cells"].get<int>(), 100);
  EXPECT_EQ(r.err.find("sees the target"), std::string::npos) << r.err;
  const session::Manifest m = session::read_manifest(dir / "s");
  ASSERT_TRUE(m.T_world_base.has_value());
  EXPECT_TRUE(m.T_world_base->translation().isApprox(Eigen::Vector3d(0.2, 0.0, 0.0)));
}

TEST(CliExplore, PoseNoiseTurnsRegistrationOn) {
  const TempDir dir;
  const RunResult r =
      run_fvx(dir, "explore" + kScene + arm() + " --max-views 2 --pose-noise 0.02,2 --timing --format json -o s");
  ASSERT_EQ(r.status, 0) << r.err;
  const session::Manifest m = session::read_manifest(dir / "s");
  EXPECT_TRUE(m.registration);
  ASSERT_EQ(m.views.size(), 2u);
  EXPECT_TRUE(m.views[0].T_world_sensor_prior.isApprox(*m.views[0].T_world_sensor_true));
  EXPECT_GT((m.views[1].T_world_sensor_prior.translation() - m.views[1].T_world_sensor_true->translation()).norm(), 1e-4);
  const json j = json::parse(r.out);
  EXPECT_TRUE(j["results"]["rows"][1]["registration_fitness_m"].is_number());
  // --timing: each stage's time, the virtual Kinect's among them.
  EXPECT_GT(j["results"]["rows"][1]["timing_s"]["registration"].get<double>(), 0.0);
  EXPECT_GT(j["results"]["rows"][1]["timing_s"]["render"].get<double>(), 0.0);
}

TEST(CliExplore, BadInputIsRefusedBeforeASessionIsWritten) {
  const TempDir dir;
  std::ofstream(dir / "other.urdf") << slurp(source("data/arms/fvx-arm.urdf")) << "<!-- another arm -->\n";
  std::filesystem::create_directories(dir / "full");
  std::ofstream(dir / "full/keep.txt") << "mine\n";
  struct Case {
    std::string arguments;
    int status;
    std::string message;
  };
  const std::vector<Case> cases = {
      // Inside the victim, a solid block (0.55…0.64, −0.05…0.03, 0.01…0.07).
      {"explore" + kScene + arm() + " --start 0.595,-0.01,0.04,0.9,0,0", 1, "inside an obstacle"},
      {"explore" + kScene + arm() + " --start 0.2,2.5,0.9,0.8,0,0", 1, "out of the arm's reach"},
      {"explore" + kScene + " --capmap '" + source("data/arms/fvx-arm.fcm") + "' --arm other.urdf", 1, "another URDF"},
      {"explore" + kScene + arm() + " --planner best", 2, "--planner"},
      {"explore" + kScene + arm() + " --strategy best", 2, "--strategy"},
      {"explore" + kScene + arm() + " --strategy frontier --planner frontier", 2, "another name for --strategy"},
      {"explore" + kScene + arm() + " --pose-noise 0.02", 2, "--pose-noise"},
      {"explore" + kScene + arm() + " --max-views 0", 2, "--max-views"},
      {"explore" + kScene + arm() + " --format xml", 2, "--format"},
      {"explore" + kScene, 2, "--no-capmap"},
      {"explore missing.ply --no-capmap", 1, "missing.ply"},
      {"explore" + kScene + " --no-capmap --planner exhaustive", 2, "exhaustive"},
  };
  for (const Case& c : cases) {
    const RunResult r = run_fvx(dir, c.arguments + " -o session");
    EXPECT_EQ(r.status, c.status) << c.arguments << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << c.arguments << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.arguments << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "session")) << c.arguments;
    std::filesystem::remove_all(dir / "session");
  }
  const RunResult full = run_fvx(dir, "explore" + kScene + arm() + " -o full");
  EXPECT_EQ(full.status, 2) << full.err;
  EXPECT_NE(full.err.find("not an empty folder"), std::string::npos) << full.err;
  const RunResult blocked = run_fvx(dir, "explore" + kScene + arm() + " --max-views 1 -o full/keep.txt/session");
  EXPECT_EQ(blocked.status, 1) << blocked.err;
  EXPECT_EQ(line_count(blocked.err), 1u) << blocked.err;
  EXPECT_NE(blocked.err.find("keep.txt/session: cannot write: 'full/keep.txt' is not a folder"), std::string::npos) << blocked.err;
  EXPECT_EQ(slurp(dir / "full/keep.txt"), "mine\n");
}

}  // namespace
}  // namespace fvx::test
