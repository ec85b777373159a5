// fvx capmap as users run it: build, info, query, eval, export, shards and merge; bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

std::string fvx_arm() { return std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm.urdf"; }

TEST(CliCapmap, BuildInfoQueryExportAndShards) {
  const TempDir dir;
  const std::string build = "capmap build " + fvx_arm() + " --base base_link --tip kinect_optical --voxel 0.15 "
                            "--directions 50 --fk-samples 20000";
  RunResult r = run_fvx(dir, build + " -o arm.fcm");
  ASSERT_EQ(r.status, 0) << r.err;
  const json built = json::parse(r.out);
  EXPECT_EQ(built["command"], "capmap build");
  EXPECT_GT(built["results"]["bits"].get<int>(), 100);

  r = run_fvx(dir, "capmap info arm.fcm");
  ASSERT_EQ(r.status, 0) << r.err;
  const json info = json::parse(r.out)["results"];
  EXPECT_EQ(info["bits"], built["results"]["bits"]);
  EXPECT_EQ(info["header"]["directions"], 50);

  // A voxel in reach lists its directions; asking for one of them gives "reachable".
  bool checked = false;
  for (const char* point : {"0.45,0,0.75", "0.6,0,0.6", "0.3,0,0.9", "0.45,0.15,0.6", "0.75,0,0.45"}) {
    r = run_fvx(dir, std::string("capmap query arm.fcm --point ") + point);
    ASSERT_EQ(r.status, 0) << r.err;
    const json q = json::parse(r.out)["results"];
    if (q["reachable_directions"].empty()) continue;
    EXPECT_GT(q["reachability_index"].get<double>(), 0.0);
    const auto d = q["reachable_directions"][0];
    r = run_fvx(dir, std::string("capmap query arm.fcm --point ") + point + " --direction " +
                         std::to_string(d[0].get<double>()) + "," + std::to_string(d[1].get<double>()) + "," +
                         std::to_string(d[2].get<double>()));
    EXPECT_EQ(json::parse(r.out)["results"]["reachable"], true) << point;
    checked = true;
    break;
  }
  EXPECT_TRUE(checked) << "no voxel in reach among the points tried";
  r = run_fvx(dir, "capmap query arm.fcm --point 5,5,5");
  EXPECT_EQ(json::parse(r.out)["results"]["inside_grid"], false);

  ASSERT_EQ(run_fvx(dir, "capmap export arm.fcm -o arm.ply").status, 0);
  EXPECT_GT(std::filesystem::file_size(dir / "arm.ply"), 1000u);

  for (int i = 1; i <= 3; ++i)
    ASSERT_EQ(run_fvx(dir, build + " --shard " + std::to_string(i) + "/3 -o part" + std::to_string(i) + ".fcm").status, 0);
  ASSERT_EQ(run_fvx(dir, "capmap merge part1.fcm part2.fcm part3.fcm -o merged.fcm").status, 0);
  EXPECT_TRUE(slurp(dir / "merged.fcm") == slurp(dir / "arm.fcm")) << "merged shards differ from the single run";
  ASSERT_EQ(run_fvx(dir, build + " -o again.fcm").status, 0);
  EXPECT_TRUE(slurp(dir / "again.fcm") == slurp(dir / "arm.fcm")) << "same seed, different file";
  EXPECT_EQ(run_fvx(dir, "capmap merge part1.fcm part3.fcm -o bad.fcm").status, 1);  // a shard missing

  // The fvx arm's yaw turns about the base's z axis: one FK per 8 witnesses, the same bits as
  // one FK each; an option the method does not use is said, on stderr and in the report.
  const json axis = built["inputs"]["first_joint_axis"];
  EXPECT_EQ(axis["joint"], "yaw");
  EXPECT_NEAR(axis["tilt_from_vertical_deg"].get<double>(), 0.0, 1e-9);
  EXPECT_EQ(built["results"]["fk_evaluations"].get<long>() * 8, built["results"]["fk_samples"].get<long>());
  r = run_fvx(dir, build + " --fk-per-witness --restarts 3 -o each.fcm");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(slurp(dir / "each.fcm") == slurp(dir / "arm.fcm")) << "--fk-per-witness changed the bits";
  EXPECT_EQ(json::parse(r.out)["results"]["fk_evaluations"], built["results"]["fk_samples"]);
  EXPECT_NE(r.err.find("warning: --restarts is used by the IK methods only"), std::string::npos) << r.err;
  EXPECT_EQ(json::parse(r.out)["warnings"].size(), 1u);
}

// --layout turn: the file holds witnesses in the first joint's coordinates (format version 3);
// info, query and eval read it as any map; shards merge into the single run's bytes.
TEST(CliCapmap, TheTurnLayoutIsBuiltQueriedAndMergedAsAnyMap) {
  const TempDir dir;
  const std::string build = "capmap build " + fvx_arm() + " --base base_link --tip kinect_optical --voxel 0.15 "
                            "--directions 50 --layout turn";
  RunResult r = run_fvx(dir, build + " --fk-per-witness -o turn.fcm");
  ASSERT_EQ(r.status, 0) << r.err;
  const json built = json::parse(r.out);
  EXPECT_EQ(built["config"]["layout"], "turn");
  EXPECT_GT(built["results"]["turn_witnesses"].get<int>(), 100);
  EXPECT_EQ(built["results"]["fk_evaluations"], built["results"]["fk_samples"]);
  EXPECT_NE(r.err.find("warning: --fk-per-witness is used by the grid layout only"), std::string::npos) << r.err;
  r = run_fvx(dir, "capmap info turn.fcm");
  ASSERT_EQ(r.status, 0) << r.err;
  const json info = json::parse(r.out)["results"];
  EXPECT_EQ(info["header"]["layout"], "turn");
  EXPECT_EQ(info["turn_witnesses"], built["results"]["turn_witnesses"]);
  EXPECT_EQ(info["bits"], built["results"]["bits"]);
  EXPECT_NEAR(info["header"]["turn"]["limits_deg"][1].get<double>(), 2.967 * 180 / M_PI, 1e-9);  // the yaw joint's
  EXPECT_NEAR(info["header"]["turn"]["limits_deg"][0].get<double>(), -2.967 * 180 / M_PI, 1e-9);
  r = run_fvx(dir, "capmap query turn.fcm --point 0.45,0,0.75");
  ASSERT_EQ(r.status, 0) << r.err;
  r = run_fvx(dir, "capmap eval turn.fcm " + fvx_arm() + " --samples 300");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_GE(json::parse(r.out)["results"]["precision"].get<double>(), 0.95);
  for (int i = 1; i <= 3; ++i)
    ASSERT_EQ(run_fvx(dir, build + " --shard " + std::to_string(i) + "/3 -o part" + std::to_string(i) + ".fcm").status, 0);
  ASSERT_EQ(run_fvx(dir, "capmap merge part3.fcm part1.fcm part2.fcm -o merged.fcm").status, 0);
  EXPECT_TRUE(slurp(dir / "merged.fcm") == slurp(dir / "turn.fcm")) << "merged shards differ from the single run";
}

TEST(CliCapmapRealData, YoubotMapAtFiveCentimetresIsPrecise) {
  FVX_REAL_DATA_OR_SKIP(urdf, "arms/youbot_arm.urdf");
  const TempDir dir;
  RunResult r = run_fvx(dir, "capmap build " + urdf + " --base base_link --tip arm_link_5 --voxel 0.05 -o yb.fcm");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LT(std::filesystem::file_size(dir / "yb.fcm"), 400u * 1024);
  r = run_fvx(dir, "capmap eval yb.fcm " + urdf + " --samples 1000");
  ASSERT_EQ(r.status, 0) << r.err;
  const json e = json::parse(r.out)["results"];
  std::printf("youBot at 5 cm: precision %.3f, recall %.3f\n", e["precision"].get<double>(), e["recall"].get<double>());
  EXPECT_GE(e["precision"].get<double>(), 0.95);
  EXPECT_GT(e["recall"].get<double>(), 0.3);
}

TEST(CliCapmap, BadInputIsRefusedOnOneLine) {
  const TempDir dir;
  std::ofstream(dir / "broken.urdf") << "<robot name='x'><link name='a'";
  std::ofstream(dir / "slide.urdf") << R"(<robot name="slide"><link name="base"/><link name="sensor"/>
    <joint name="slide" type="prismatic"><parent link="base"/><child link="sensor"/>
      <axis xyz="1 0 0"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint></robot>)";
  ASSERT_EQ(run_fvx(dir, "capmap build " + fvx_arm() + " --base base_link --tip kinect_optical --voxel 0.2 "
                         "--directions 20 --fk-samples 2000 -o good.fcm").status, 0);
  const std::string good = slurp(dir / "good.fcm");
  std::string flipped = good;
  flipped[good.size() / 2] = char(flipped[good.size() / 2] ^ 1);
  std::ofstream(dir / "flipped.fcm", std::ios::binary) << flipped;
  std::ofstream(dir / "truncated.fcm", std::ios::binary) << good.substr(0, good.size() / 2);
  const std::string arm = fvx_arm();
  const std::vector<std::tuple<std::string, int, std::string>> cases = {
      {"capmap build broken.urdf --base a --tip a -o x.fcm", 1, "broken.urdf"},
      {"capmap build " + arm + " --base base_link --tip nope -o x.fcm", 2, "nope"},
      {"capmap build " + arm + " --base forearm --tip turret -o x.fcm", 2, "not below"},
      {"capmap build " + arm + " --base base_link --tip kinect_optical --voxel 0 -o x.fcm", 2, "--voxel"},
      {"capmap build " + arm + " --base base_link --tip kinect_optical -o x.bin", 2, "x.bin"},
      // Options are checked before the URDF is read: a bad value is named even when the URDF is too.
      {"capmap build broken.urdf --base a --tip a --voxel -1 -o x.fcm", 2, "--voxel"},
      {"capmap build missing.urdf --base a --tip a --shard 4/3 -o x.fcm", 2, "--shard"},
      {"capmap build missing.urdf --base a --tip a --angle-tolerance 400 -o x.fcm", 2, "--angle-tolerance"},
      {"capmap build missing.urdf --base a --tip a --layout rings -o x.fcm", 2, "--layout"},
      {"capmap build " + arm + " --base base_link --tip kinect_optical --layout turn --method fk-seeded-ik -o x.fcm", 2,
       "fk-witness"},
      {"capmap build slide.urdf --base base --tip sensor --voxel 0.2 --layout turn -o x.fcm", 1, "not revolute"},
      {"capmap info truncated.fcm", 1, "truncated.fcm"},
      {"capmap info flipped.fcm", 1, "flipped.fcm"},
      {"capmap query good.fcm --point 1,2", 2, "--point"},
      {"capmap frobnicate good.fcm", 2, "frobnicate"},
  };
  for (const auto& [command, status, mention] : cases) {
    const RunResult r = run_fvx(dir, command);
    EXPECT_EQ(r.status, status) << command << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << command << ": " << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << command << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.fcm")) << command;
  }
}

}  // namespace
}  // namespace fvx::test
