// The binary's contract: exit codes, JSON on stdout, logs on stderr, bad input refused with a
// one-line message and no damage to existing outputs.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "fvx/core/json.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/trajectory.hpp"
#include "fvx/map/occupancy_map.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

/// A wall 2 m in front of the sensor, seen from `x_m` to the side (PCD with VIEWPOINT). A
/// non-zero `prior_error_deg` tilts the VIEWPOINT by that much about x: a wrong prior.
void write_wall_scan(const std::string& path, double x_m, double prior_error_deg = 0.0) {
  std::vector<Eigen::Vector3f> points;
  for (int i = -20; i <= 20; ++i)
    for (int j = -15; j <= 15; ++j) points.emplace_back(0.05f * i, 0.05f * j, 2.0f);
  Eigen::Isometry3d T(Eigen::AngleAxisd(prior_error_deg * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  T.translation() << x_m, 0, 0;
  io::write_pcd(path, points, T);
}

TEST(Cli, VersionHelpAndUnknownCommands) {
  const TempDir dir;
  RunResult r = run_fvx(dir, "--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("fvx ", 0), 0u);
  r = run_fvx(dir, "--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("integrate"), std::string::npos);
  r = run_fvx(dir, "help integrate");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--trajectory"), std::string::npos);
  EXPECT_EQ(run_fvx(dir, "integrate --help").out, r.out);

  r = run_fvx(dir, "integrat -o x.bt a.pcd");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean 'integrate'"), std::string::npos) << r.err;
  EXPECT_EQ(line_count(r.err), 1u);
  EXPECT_EQ(run_fvx(dir, "").status, 2);
  EXPECT_EQ(run_fvx(dir, "--bogus").status, 2);
  r = run_fvx(dir, "integrate --resolutoin 0.1 -o x.bt a.pcd");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean --resolution?"), std::string::npos) << r.err;
}

// PCL and OpenCV live in fvx-heavy.so, loaded on first use: commands on maps run without it,
// commands on clouds say in one line that it is missing, or that it is not fvx's module.
TEST(Cli, PclAndOpenCvAreLoadedOnlyByCommandsThatNeedThem) {
  const TempDir dir;
  write_wall_scan(dir / "scan.pcd", 0.0);
  ASSERT_EQ(run_fvx(dir, "integrate -r 0.1 --no-register -o map.ot scan.pcd").status, 0);
  const std::string missing = "FVX_HEAVY=" + (dir / "nowhere") + "/fvx-heavy.so";
  for (const std::string command : {"frontiers map.ot", "voids map.ot", "nbv map.ot --no-capmap"}) {
    const RunResult r = run_fvx(dir, command, missing);
    EXPECT_EQ(r.status, 0) << command << ": " << r.err;
  }
  RunResult r = run_fvx(dir, "integrate -r 0.1 --no-register -o map2.ot scan.pcd", missing);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot find fvx-heavy.so"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("FVX_HEAVY"), std::string::npos) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "map2.ot"));
  std::ofstream(dir / "fake.so") << "not a shared object\n";
  r = run_fvx(dir, "integrate -r 0.1 --no-register -o map2.ot scan.pcd", "FVX_HEAVY=" + (dir / "fake.so"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot load"), std::string::npos) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
}

TEST(Cli, IntegrateWritesAMapAndAJsonReport) {
  const TempDir dir;
  write_wall_scan(dir / "a.pcd", 0.0);
  write_wall_scan(dir / "b.pcd", 0.3);
  const RunResult r = run_fvx(dir, "integrate -o map.bt --resolution 0.05 a.pcd b.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no progress when stderr is not a terminal
  const json report = json::parse(r.out);
  EXPECT_EQ(report["schema_version"], 1);
  EXPECT_EQ(report["command"], "integrate");
  EXPECT_TRUE(report["fvx_version"].is_string());
  EXPECT_EQ(report["config"]["resolution_m"], 0.05);
  EXPECT_EQ(report["inputs"]["scans"].size(), 2u);
  const json& scans = report["results"]["scans"];
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0]["pose_source"], "viewpoint");
  EXPECT_EQ(scans[0]["registration"]["attempted"], false);
  EXPECT_EQ(scans[1]["registration"]["attempted"], true);
  EXPECT_EQ(scans[1]["registration"]["converged"], true);
  EXPECT_TRUE(scans[1]["registration"]["fitness_rmse_m"].is_number());
  EXPECT_GT(scans[0]["integration"]["changed_cells"].get<int>(), 1000);
  EXPECT_FALSE(scans[0].contains("timing_s"));
  EXPECT_GT(report["results"]["map"]["occupied_leaves"].get<int>(), 0);
  EXPECT_TRUE(report["warnings"].empty());

  const map::OccupancyMap m = map::OccupancyMap::load(dir / "map.bt");
  EXPECT_EQ(m.state(*m.key_of({0.0, 0.0, 2.01})), map::VoxelState::Occupied);
  EXPECT_EQ(m.state(*m.key_of({0.0, 0.0, 1.0})), map::VoxelState::Free);
  EXPECT_EQ(m.state(*m.key_of({0.0, 0.0, 2.5})), map::VoxelState::Unknown);
}

TEST(Cli, ReportsAreDeterministicAndTimingOnlyOnRequest) {
  const TempDir dir;
  write_wall_scan(dir / "a.pcd", 0.0);
  const RunResult one = run_fvx(dir, "integrate -o m1.ot a.pcd");
  const RunResult two = run_fvx(dir, "integrate -o m1.ot a.pcd");
  ASSERT_EQ(one.status, 0);
  EXPECT_EQ(one.out, two.out);
  const RunResult timed = run_fvx(dir, "integrate -o m2.ot --timing a.pcd");
  EXPECT_TRUE(json::parse(timed.out)["results"]["scans"][0]["timing_s"]["integration"].is_number());
  const RunResult to_file = run_fvx(dir, "integrate -o m3.ot --report report.json a.pcd");
  EXPECT_EQ(to_file.out, "");
  EXPECT_EQ(json::parse(slurp(dir / "report.json"))["command"], "integrate");
  const RunResult progress = run_fvx(dir, "integrate -o m4.ot --progress a.pcd");
  EXPECT_NE(progress.err.find("scan 1/1"), std::string::npos);
}

TEST(Cli, UpdatingAMapRegistersTheNewScan) {
  const TempDir dir;
  write_wall_scan(dir / "a.pcd", 0.0);
  write_wall_scan(dir / "b.pcd", 0.2);
  ASSERT_EQ(run_fvx(dir, "integrate -o map.ot a.pcd").status, 0);
  const RunResult r = run_fvx(dir, "integrate --map map.ot -o map2.ot --register b.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["inputs"]["map"], "map.ot");
  EXPECT_EQ(report["results"]["scans"][0]["registration"]["converged"], true);
  EXPECT_EQ(run_fvx(dir, "integrate --map map.ot --resolution 0.1 -o map3.ot b.pcd").status, 2);
}

// The bundled sample has exact poses: registration, on by default, must leave them alone.
TEST(Cli, RegistrationKeepsTheExactPosesOfTheSample) {
  const char* source = std::getenv("FVX_SOURCE_DIR");
  ASSERT_NE(source, nullptr);
  const TempDir dir;
  std::string scans;
  for (int v = 0; v < 4; ++v) scans += std::string(" ") + source + "/data/sample/box-room/view" + std::to_string(v) + ".pcd";
  const RunResult r = run_fvx(dir, "integrate -o m.ot" + scans);
  ASSERT_EQ(r.status, 0) << r.err;
  const json report = json::parse(r.out);
  for (int v = 1; v < 4; ++v) {
    const json& reg = report["results"]["scans"][v]["registration"];
    EXPECT_EQ(reg["converged"], true) << v;
    EXPECT_LT(reg["correction"]["translation_m"].get<double>(), 0.005) << v;
    EXPECT_LT(reg["correction"]["rotation_deg"].get<double>(), 0.2) << v;
  }
}

TEST(Cli, ARegistrationThatDoesNotConvergeKeepsThePriorAndWarns) {
  const TempDir dir;
  write_wall_scan(dir / "a.pcd", 0.0);
  write_wall_scan(dir / "b.pcd", 0.3, 5.0);
  const RunResult r = run_fvx(dir, "integrate -o m.ot --reg-max-iter 1 a.pcd b.pcd");
  ASSERT_EQ(r.status, 0) << r.err;
  const json report = json::parse(r.out);
  const json& scan = report["results"]["scans"][1];
  EXPECT_EQ(scan["registration"]["converged"], false);
  EXPECT_TRUE(scan["registration"].contains("problem"));
  EXPECT_EQ(scan["T_world_sensor"], scan["prior"]);
  ASSERT_EQ(report["warnings"].size(), 1u);
  EXPECT_NE(report["warnings"][0].get<std::string>().find("b.pcd"), std::string::npos);
}

struct BadInput {
  const char* name;
  const char* arguments;
  int status;
  const char* must_mention;
};

class CliBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliBadInput, OneLineErrorAndTheExistingMapIsUntouched) {
  const BadInput c = GetParam();
  const TempDir dir;
  write_wall_scan(dir / "good.pcd", 0.0);
  ASSERT_EQ(run_fvx(dir, "integrate -o out.bt good.pcd").status, 0);
  const std::string before = slurp(dir / "out.bt");
  std::ofstream(dir / "empty.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                      "WIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n";
  std::ofstream(dir / "nan.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                    "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\nnan nan nan\nnan nan nan\n";
  std::ofstream(dir / "corrupt.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH two\n";
  std::ofstream(dir / "text.ot") << "this is a text file\n";
  std::ofstream(dir / "one-pose.txt") << "0 0 0 0 0 0 1\n";
  const std::string map_bytes = slurp(dir / "out.bt");
  std::ofstream(dir / "truncated.bt", std::ios::binary) << map_bytes.substr(0, map_bytes.size() / 2);

  const RunResult r = run_fvx(dir, c.arguments);
  EXPECT_EQ(r.status, c.status) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_EQ(r.err.rfind("fvx", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find("fvx: fvx"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(c.must_mention), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(slurp(dir / "out.bt"), before);
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadInput,
    ::testing::Values(
        BadInput{"missing", "integrate -o out.bt good.pcd missing.pcd", 1, "missing.pcd"},
        BadInput{"empty", "integrate -o out.bt good.pcd empty.pcd", 1, "empty.pcd"},
        BadInput{"all_nan", "integrate -o out.bt good.pcd nan.pcd", 1, "nan.pcd"},
        BadInput{"corrupt_header", "integrate -o out.bt corrupt.pcd", 1, "corrupt.pcd"},
        BadInput{"truncated_map", "integrate --map truncated.bt -o out.bt good.pcd", 1, "truncated.bt"},
        BadInput{"text_as_ot", "integrate --map text.ot -o out.bt good.pcd", 1, "text.ot"},
        BadInput{"non_numeric_resolution", "integrate --resolution fine -o out.bt good.pcd", 2, "--resolution"},
        BadInput{"zero_resolution", "integrate --resolution 0 -o out.bt good.pcd", 2, "--resolution"},
        BadInput{"few_poses", "integrate --trajectory one-pose.txt -o out.bt good.pcd good.pcd", 1, "one-pose.txt"},
        BadInput{"no_output", "integrate good.pcd", 2, "--output"},
        BadInput{"bad_output_ext", "integrate -o out.txt good.pcd", 2, "out.txt"},
        BadInput{"image_without_intrinsics", "integrate -o out.bt frame.png", 2, "intrinsics"},
        BadInput{"bad_pose", "integrate --pose 1,2,3 -o out.bt good.pcd", 2, "--pose"},
        BadInput{"bad_method", "integrate --reg-method ndt -o out.bt good.pcd", 2, "--reg-method"}),
    [](const auto& test_info) { return std::string(test_info.param.name); });

TEST(CliRealData, SlambookWithTheRecipeReproducesTheReference) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  FVX_REAL_DATA_OR_SKIP(reference, "octomap-maps/slambook_ch13/octomap.bt");
  const TempDir dir;
  std::string depth;
  for (int i = 1; i <= 5; ++i) depth += " " + frames + "/depth/" + std::to_string(i) + ".pgm";
  const RunResult r = run_fvx(dir, "integrate -o s.bt --resolution 0.05 --depth-max 7 --fx 518 --fy 519 "
                                   "--cx 325.5 --cy 253.5 --depth-scale 1000 --no-register --trajectory " +
                                       frames + "/pose.txt" + depth);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["inputs"]["pose_match"], "order");
  EXPECT_EQ(slurp(dir / "s.bt"), slurp(reference));
}

// Issue 20: the slambook frames laid out as 7-Scenes / 3DMatch do it (frame-XXXXXX.depth
// images, one 4x4 frame-XXXXXX.pose.txt per frame, a 3x3 K in camera-intrinsics.txt)
// integrate with the poses of the TUM trajectory the matrices were written from, matched by
// frame name, and give the reference map.
TEST(CliRealData, SlambookInTheSevenScenesLayoutIntegratesAsItsTrajectory) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  FVX_REAL_DATA_OR_SKIP(reference, "octomap-maps/slambook_ch13/octomap.bt");
  const TempDir dir;
  std::filesystem::create_directories(dir / "seq-01");
  const io::Trajectory trajectory = io::read_trajectory(frames + "/pose.txt");
  ASSERT_EQ(trajectory.entries.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "seq-01/frame-%06d", i);
    std::filesystem::copy_file(frames + "/depth/" + std::to_string(i + 1) + ".pgm", dir / (std::string(name) + ".depth.pgm"));
    std::ofstream pose(dir / (std::string(name) + ".pose.txt"));
    pose << std::setprecision(17) << trajectory.entries[std::size_t(i)].T_world_sensor.matrix() << "\n";
  }
  std::ofstream(dir / "seq-01/camera-intrinsics.txt") << "518 0 325.5\n0 519 253.5\n0 0 1\n";
  const RunResult r = run_fvx(dir, "integrate --trajectory seq-01/ --intrinsics seq-01/camera-intrinsics.txt -o s.bt "
                                   "--resolution 0.05 --depth-max 7 --no-register seq-01/*.depth.pgm");
  ASSERT_EQ(r.status, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["inputs"]["pose_match"], "frame-name");
  const json& scans = report["results"]["scans"];
  ASSERT_EQ(scans.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const json expected = pose_json(trajectory.entries[i].T_world_sensor);
    EXPECT_EQ(scans[i]["pose_source"], "trajectory");
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(scans[i]["prior"]["position_m"][k].get<double>(), expected["position_m"][k].get<double>(), 1e-12);
    // The file's quaternions are unit to 1e-6 and used as given; the matrix reader makes its
    // rotations orthonormal, which moves them by up to 2e-8 here: the map is the same.
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(scans[i]["prior"]["quaternion_xyzw"][k].get<double>(), expected["quaternion_xyzw"][k].get<double>(), 1e-7);
  }
  EXPECT_EQ(slurp(dir / "s.bt"), slurp(reference));
  // A pose file of three rows is refused, naming the file, before any map is written.
  std::ofstream(dir / "seq-01/frame-000002.pose.txt") << "1 0 0 0\n0 1 0 0\n0 0 1 0\n";
  const RunResult bad = run_fvx(dir, "integrate --trajectory seq-01 --intrinsics seq-01/camera-intrinsics.txt -o t.bt "
                                     "seq-01/*.depth.pgm");
  EXPECT_EQ(bad.status, 1);
  EXPECT_EQ(line_count(bad.err), 1u) << bad.err;
  EXPECT_NE(bad.err.find("frame-000002.pose.txt: expected a 4x4 matrix"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.bt"));
}

}  // namespace
}  // namespace fvx::test
