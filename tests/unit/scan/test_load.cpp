// Pose priors: matching trajectories to scans, VIEWPOINT, --pose.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fvx/core/error.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/scan/load.hpp"
#include "test_support.hpp"

namespace fvx::scan {
namespace {

std::string pose_line(double x) { return std::to_string(x) + " 0 0 0 0 0 1\n"; }

TEST(PlanScans, ByOrderNeedsAPoseForEveryScan) {
  const test::TempDir dir;
  std::ofstream(dir / "poses.txt") << pose_line(1) << pose_line(2);
  LoadConfig config;
  config.trajectory_path = dir / "poses.txt";
  const ScanPlan plan = plan_scans({"a.pcd", "b.pcd"}, config);
  EXPECT_EQ(plan.match, PoseMatch::ByOrder);
  EXPECT_EQ(plan.scans[1].T_world_sensor->translation().x(), 2.0);
  try {
    plan_scans({"a.pcd", "b.pcd", "c.pcd"}, config);
    FAIL() << "three scans, two poses";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("poses.txt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("2 poses for 3 scans"), std::string::npos) << e.what();
  }
  EXPECT_EQ(plan_scans({"a.pcd"}, config).warnings.size(), 1u);  // extra poses are reported
}

TEST(PlanScans, ByTimestampInTheFileName) {
  const test::TempDir dir;
  std::ofstream(dir / "gt.txt") << "100.00 1 0 0 0 0 0 1\n100.50 2 0 0 0 0 0 1\n101.00 3 0 0 0 0 0 1\n";
  LoadConfig config;
  config.trajectory_path = dir / "gt.txt";
  const ScanPlan plan = plan_scans({"depth/101.005.png", "depth/100.49.png"}, config);
  EXPECT_EQ(plan.match, PoseMatch::ByTimestamp);
  EXPECT_EQ(plan.scans[0].T_world_sensor->translation().x(), 3.0);
  EXPECT_EQ(plan.scans[1].T_world_sensor->translation().x(), 2.0);
  EXPECT_THROW(plan_scans({"depth/100.25.png"}, config), Error);  // nearest is 0.25 s away
}

TEST(PlanScansRealData, RedwoodByFrameId) {
  FVX_REAL_DATA_OR_SKIP(log, "redwood-livingroom1-micro/trajectory_open3d_estimated.log");
  LoadConfig config;
  config.trajectory_path = log;
  const ScanPlan plan = plan_scans({"depth/00010.png", "depth/00003.png"}, config);
  EXPECT_EQ(plan.match, PoseMatch::ByFrameId);
  const io::Trajectory t = io::read_trajectory(log);
  EXPECT_TRUE(plan.scans[0].T_world_sensor->isApprox(t.entries[10].T_world_sensor));
  EXPECT_TRUE(plan.scans[1].T_world_sensor->isApprox(t.entries[3].T_world_sensor));
}

TEST(LoadScan, ViewpointIsThePriorUnlessIgnoredOrOverridden) {
  const test::TempDir dir;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << 1, 2, 3;
  io::write_pcd(dir / "s.pcd", {Eigen::Vector3f(0, 0, 1)}, T);
  std::vector<std::string> warnings;
  LoadConfig config;
  Scan s = load_scan({dir / "s.pcd", std::nullopt, PoseSource::Identity, std::nullopt}, config, warnings);
  EXPECT_EQ(s.pose_source, PoseSource::Viewpoint);
  EXPECT_TRUE(s.T_world_sensor.isApprox(T));
  config.use_viewpoint = false;
  s = load_scan({dir / "s.pcd", std::nullopt, PoseSource::Identity, std::nullopt}, config, warnings);
  EXPECT_EQ(s.pose_source, PoseSource::Identity);
  EXPECT_TRUE(s.T_world_sensor.isApprox(Eigen::Isometry3d::Identity()));
  config.pose = Eigen::Isometry3d::Identity();
  const ScanPlan plan = plan_scans({dir / "s.pcd"}, config);
  s = load_scan(plan.scans[0], config, warnings);
  EXPECT_EQ(s.pose_source, PoseSource::Flag);
  EXPECT_TRUE(warnings.empty());
}

TEST(LoadScanRealData, LegacyOpenNiViewpointIsUsedButWarnedAbout) {
  FVX_REAL_DATA_OR_SKIP(path, "pcl-kinect-sequences/pairwise_tutorial/capture0001.pcd");
  std::vector<std::string> warnings;
  const Scan s = load_scan({path, std::nullopt, PoseSource::Identity, std::nullopt}, LoadConfig{}, warnings);
  EXPECT_EQ(s.pose_source, PoseSource::Viewpoint);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("--ignore-viewpoint"), std::string::npos);
}

TEST(PlanScans, PoseFoldersMatchByFrameNameAndKittiByFrameId) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir / "seq");
  for (int i = 0; i < 3; ++i)
    std::ofstream(dir / ("seq/frame-00000" + std::to_string(i) + ".pose.txt"))
        << "1 0 0 " << i << "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  LoadConfig config;
  config.trajectory_path = dir / "seq";
  const ScanPlan plan = plan_scans({"x/frame-000002.depth.png", "x/frame-000000.depth.png"}, config);
  EXPECT_EQ(plan.match, PoseMatch::ByFrameName);
  EXPECT_EQ(plan.scans[0].T_world_sensor->translation().x(), 2.0);
  EXPECT_EQ(plan.scans[1].T_world_sensor->translation().x(), 0.0);
  try {
    plan_scans({"x/frame-000007.depth.png"}, config);
    FAIL() << "a frame without a pose file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no pose file for frame 'frame-000007'"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "kitti.txt") << "1 0 0 5 0 1 0 0 0 0 1 0\n1 0 0 6 0 1 0 0 0 0 1 0\n";
  config.trajectory_path = dir / "kitti.txt";
  const ScanPlan kitti = plan_scans({"image/000001.png"}, config);
  EXPECT_EQ(kitti.match, PoseMatch::ByFrameId);
  EXPECT_EQ(kitti.scans[0].T_world_sensor->translation().x(), 6.0);
}

TEST(LoadScan, AScanWithoutAPoseIsRefused) {
  const test::TempDir dir;
  // A depth image states no pose: refused when planned, before any scan is read.
  LoadConfig with_intrinsics;
  with_intrinsics.intrinsics = io::Intrinsics{};
  try {
    plan_scans({dir / "0.png"}, with_intrinsics);
    FAIL() << "a depth image without a pose";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("0.png: no pose: a depth image states none"), std::string::npos) << e.what();
  }
  // A PCD without a VIEWPOINT line: refused when read.
  std::ofstream(dir / "bare.pcd") << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
                                     "POINTS 1\nDATA ascii\n0 0 1\n";
  std::vector<std::string> warnings;
  const ScanPlan plan = plan_scans({dir / "bare.pcd"}, LoadConfig{});
  try {
    load_scan(plan.scans[0], LoadConfig{}, warnings);
    FAIL() << "a PCD without VIEWPOINT";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("bare.pcd: no pose: the file states none"), std::string::npos) << e.what();
  }
  LoadConfig ignore;
  ignore.use_viewpoint = false;  // --ignore-viewpoint: the points are in the world frame
  EXPECT_EQ(load_scan(plan.scans[0], ignore, warnings).pose_source, PoseSource::Identity);
}

TEST(LoadScan, DepthImageWithoutIntrinsicsIsAUsageError) {
  std::vector<std::string> warnings;
  EXPECT_THROW(load_scan({"frame.png", std::nullopt, PoseSource::Identity, std::nullopt}, LoadConfig{}, warnings), UsageError);
}

TEST(TumFolder, AssociationsNameTheDepthImagesAndABadLineIsNamed) {
  const test::TempDir dir;
  std::ofstream(dir / "assoc.txt") << "# rgb then depth\n"
                                   << "1.0 rgb/1.0.png 1.01 depth/1.01.png\n"
                                   << "\n"
                                   << "2.0 depth/2.0.png\n"
                                   << "3.0 3.0.png\n";
  EXPECT_EQ(tum_depth_images(dir.path().string(), dir / "assoc.txt"),
            (std::vector<std::string>{dir / "depth/1.01.png", dir / "depth/2.0.png", dir / "3.0.png"}));
  std::ofstream(dir / "bad.txt") << "1.0 depth/1.0.png\nonly-a-stamp\n";
  try {
    tum_depth_images(dir.path().string(), dir / "bad.txt");
    FAIL() << "a line without a file was read";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tum_depth_images(dir.path().string(), dir / "missing.txt"), FileError);
}

TEST(TumFolder, WithoutAssociationsEveryDepthImageByName) {
  const test::TempDir dir;
  EXPECT_THROW(tum_depth_images(dir.path().string(), ""), FileError);  // no depth/
  std::filesystem::create_directories(dir / "depth");
  EXPECT_THROW(tum_depth_images(dir.path().string(), ""), FileError);  // empty
  for (const char* name : {"2.png", "10.png", "1.png"}) std::ofstream(dir / (std::string("depth/") + name)) << "x";
  EXPECT_EQ(tum_depth_images(dir.path().string(), ""),
            (std::vector<std::string>{dir / "depth/1.png", dir / "depth/10.png", dir / "depth/2.png"}));
  EXPECT_EQ(expand_glob(dir / "depth/1*.png", "--scans"),
            (std::vector<std::string>{dir / "depth/1.png", dir / "depth/10.png"}));
  try {
    expand_glob(dir / "depth/*.pcd", "--scans");
    FAIL() << "a pattern matching nothing was accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--scans"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fvx::scan
