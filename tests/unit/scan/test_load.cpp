// Pose priors: matching trajectories to scans, VIEWPOINT, --pose.
#include <gtest/gtest.h>

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
  Scan s = load_scan({dir / "s.pcd", std::nullopt, PoseSource::Identity}, config, warnings);
  EXPECT_EQ(s.pose_source, PoseSource::Viewpoint);
  EXPECT_TRUE(s.T_world_sensor.isApprox(T));
  config.use_viewpoint = false;
  s = load_scan({dir / "s.pcd", std::nullopt, PoseSource::Identity}, config, warnings);
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
  const Scan s = load_scan({path, std::nullopt, PoseSource::Identity}, LoadConfig{}, warnings);
  EXPECT_EQ(s.pose_source, PoseSource::Viewpoint);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("--ignore-viewpoint"), std::string::npos);
}

TEST(LoadScan, DepthImageWithoutIntrinsicsIsAUsageError) {
  std::vector<std::string> warnings;
  EXPECT_THROW(load_scan({"frame.png", std::nullopt, PoseSource::Identity}, LoadConfig{}, warnings), UsageError);
}

}  // namespace
}  // namespace fvx::scan
