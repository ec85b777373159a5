// fvx simulate as a user runs it: scans that fvx integrate reads back, ground truth, errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

std::string scene_path(const std::string& name) {
  return std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/scenes/" + name;
}

TEST(CliSimulate, OnePoseToAnOrganisedPcdThatIntegrateReads) {
  const TempDir dir;
  const RunResult r = run_fvx(dir, "simulate " + scene_path("crates.ply") + " --look-at 0.1,0,0.9,0.8,0,0.15 -o scan.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["command"], "simulate");
  EXPECT_EQ(report["inputs"]["scene_name"], "three crates");  // the sidecar was found
  EXPECT_GT(report["results"]["frames"][0]["pixels"]["valid"].get<int>(), 200000);
  const io::CloudFile cloud = io::read_cloud(dir / "scan.pcd");
  EXPECT_EQ(cloud.width, 640);
  EXPECT_EQ(cloud.height, 480);
  EXPECT_NEAR(cloud.viewpoint.translation().z(), 0.9, 1e-6);
  const RunResult integrate = run_fvx(dir, "integrate -o m.bt -r 0.05 scan.pcd");  // the cells below: 5 cm
  ASSERT_EQ(integrate.status, 0) << integrate.err;
  EXPECT_EQ(json::parse(integrate.out)["results"]["scans"][0]["pose_source"], "viewpoint");
  // The crate with the side opening was seen: its front wall is occupied, in front of it free.
  const map::OccupancyMap m = map::OccupancyMap::load(dir / "m.bt");
  EXPECT_EQ(m.state(*m.key_of({0.626, -0.2, 0.25})), map::VoxelState::Occupied);
  EXPECT_EQ(m.state(*m.key_of({0.5, -0.2, 0.25})), map::VoxelState::Free);
}

TEST(CliSimulate, PosesToDepthPngsWithTrajectoryAndIntrinsics) {
  const TempDir dir;
  std::ofstream(dir / "views.txt") << "# stamp tx ty tz qx qy qz qw\n"
                                      "0 0.1 0.0 0.9 -0.6830127 0.6830127 -0.1830127 0.1830127\n"
                                      "1 0.1 0.3 0.9 -0.6830127 0.6830127 -0.1830127 0.1830127\n";
  const RunResult r = run_fvx(dir, "simulate builtin:crates --poses views.txt --depth-png --noise kinect --seed 3 -o scans");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"scans/000000.png", "scans/000001.png", "scans/trajectory.txt", "scans/intrinsics.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  const RunResult integrate = run_fvx(dir, "integrate -o m.ot --no-register --trajectory scans/trajectory.txt "
                                           "--intrinsics scans/intrinsics.json scans/000000.png scans/000001.png");
  ASSERT_EQ(integrate.status, 0) << integrate.err;
  const json report = json::parse(integrate.out);
  EXPECT_EQ(report["inputs"]["pose_match"], "timestamp");
  EXPECT_NEAR(report["results"]["scans"][1]["T_world_sensor"]["position_m"][1].get<double>(), 0.3, 1e-6);
  // Same seed, same scans.
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --poses views.txt --depth-png --noise kinect --seed 3 -o again").status, 0);
  EXPECT_EQ(slurp(dir / "scans/000001.png"), slurp(dir / "again/000001.png"));
}

TEST(CliSimulate, GroundTruthReportsContainerVolumes) {
  const TempDir dir;
  const RunResult r = run_fvx(dir, "simulate " + scene_path("closed-box.ply") + " --ground-truth gt.bt -r 0.02");
  ASSERT_EQ(r.status, 0) << r.err;
  const json gt = json::parse(r.out)["results"]["ground_truth"];
  // The interior is 0.46 × 0.46 × 0.36 m = 76.2 dm³; cells cut by the walls are not free.
  EXPECT_NEAR(gt["containers"][0]["free_volume_dm3"].get<double>(), 76.2, 76.2 * 0.12);
  const map::OccupancyMap m = map::OccupancyMap::load(dir / "gt.bt");
  EXPECT_EQ(m.state(*m.key_of({0.77, -0.02, 0.2})), map::VoxelState::Free);
  EXPECT_EQ(m.state(*m.key_of({0.53, 0.0, 0.2})), map::VoxelState::Occupied);
}

TEST(CliSimulate, BadInputIsRefusedOnOneLine) {
  const TempDir dir;
  std::ofstream(dir / "bad.ply") << "ply\nformat ascii 1.0\nelement vertex x\n";
  std::ofstream(dir / "points.obj") << "v 0 0 0\n";
  const char* cases[][2] = {
      {"simulate bad.ply --pose 0,0,1,0,0,0,1 -o x.pcd", "bad.ply"},
      {"simulate points.obj --pose 0,0,1,0,0,0,1 -o x.pcd", "points.obj"},
      {"simulate builtin:crates --pose 0,0,1,0,0,0,0 -o x.pcd", "--pose"},
      {"simulate builtin:crates --look-at 1,1,1,1,1,1 -o x.pcd", "--look-at"},
      {"simulate builtin:crates --pose 0,0,1,0,0,0,1 --noise loud -o x.pcd", "--noise"},
      {"simulate builtin:crates --pose 0,0,1,0,0,0,1 -o x.ply", "x.ply"},
      {"simulate builtin:nope --pose 0,0,1,0,0,0,1 -o x.pcd", "nope"},
      {"simulate builtin:crates", "nothing to do"},
  };
  for (const auto& c : cases) {
    const RunResult r = run_fvx(dir, c[0]);
    EXPECT_TRUE(r.status == 1 || r.status == 2) << c[0];
    EXPECT_EQ(line_count(r.err), 1u) << c[0] << ": " << r.err;
    EXPECT_NE(r.err.find(c[1]), std::string::npos) << c[0] << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.pcd")) << c[0];
  }
}

// Two exact views of the crates scene overlap by ~80 %, and two crates' parallel walls 9 cm
// apart alias a 9 cm slide: registration used to move the second pose by 7–9 cm.
TEST(CliSimulate, RegistrationLeavesExactSimulatedPosesAlone) {
  const TempDir dir;
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0,0.9,0.8,0,0.15 -o a.pcd").status, 0);
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0.4,0.9,0.8,0,0.15 -o b.pcd").status, 0);
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0.4,0.9,0.8,0,0.15 --noise kinect --seed 7 -o c.pcd").status, 0);
  const RunResult r = run_fvx(dir, "integrate -o m.ot a.pcd b.pcd c.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json scans = json::parse(r.out)["results"]["scans"];
  for (int i = 1; i < 3; ++i) {
    EXPECT_EQ(scans[i]["registration"]["converged"], true) << i;
    EXPECT_LT(scans[i]["registration"]["correction"]["translation_m"].get<double>(), 0.005) << i;
    EXPECT_LT(scans[i]["registration"]["correction"]["rotation_deg"].get<double>(), 0.2) << i;
  }
}

// --discretize (OctoMap's discretised insertion; the oracle tests compare it with OctoMap node
// for node): the same occupied cells as the exact insertion, which also marks each distinct
// endpoint cell once, fewer free updates since one ray goes to each cell's centre, another map.
TEST(CliSimulate, DiscretizedIntegrationUpdatesTheSameEndpointCells) {
  const TempDir dir;
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0,0.9,0.8,0,0.15 -o a.pcd").status, 0);
  RunResult r = run_fvx(dir, "integrate --no-register -o exact.ot a.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json exact = json::parse(r.out);
  r = run_fvx(dir, "integrate --no-register --discretize -o discrete.ot a.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json discrete = json::parse(r.out);
  EXPECT_EQ(exact["config"]["discretize"], false);
  EXPECT_EQ(discrete["config"]["discretize"], true);
  const json& e = exact["results"]["scans"][0]["integration"];
  const json& d = discrete["results"]["scans"][0]["integration"];
  EXPECT_EQ(d["occupied_updates"], e["occupied_updates"]);
  EXPECT_GT(d["free_updates"].get<int>(), 0);
  EXPECT_NE(slurp(dir / "exact.ot"), slurp(dir / "discrete.ot"));
}

TEST(CliSimulate, APoseInsideASolidIsAWarning) {
  const TempDir dir;
  // Inside the 1.5 cm x− wall of the closed crate (0.55 … 0.565).
  const RunResult r = run_fvx(dir, "simulate builtin:crates --pose 0.557,0.4,0.2,0,0,0,1 -o in.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json warnings = json::parse(r.out)["warnings"];
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].get<std::string>().find("inside a solid"), std::string::npos);
}

}  // namespace
}  // namespace fvx::test
