// Trajectory files: the real TUM-like and Redwood samples, a TUM file with stamps, bad files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fvx/core/error.hpp"
#include "fvx/io/trajectory.hpp"
#include "test_support.hpp"

namespace fvx::io {
namespace {

TEST(TrajectoryRealData, SlambookPosesWithoutStampsOrTrailingNewline) {
  FVX_REAL_DATA_OR_SKIP(path, "slambook-joinmap-5kf/pose.txt");
  const Trajectory t = read_trajectory(path);
  EXPECT_EQ(t.format, TrajectoryFormat::TumNoStamp);
  ASSERT_EQ(t.entries.size(), 5u);
  EXPECT_FALSE(t.entries[0].stamp_s.has_value());
  for (const auto& e : t.entries) {
    // Written with 6-7 digits: unit within 1e-6, used as given (see pose.cpp).
    EXPECT_NEAR(Eigen::Quaterniond(e.T_world_sensor.rotation()).norm(), 1.0, 1e-6);
  }
}

TEST(TrajectoryRealData, IclNuimFirstPose) {
  FVX_REAL_DATA_OR_SKIP(path, "icl-nuim-slambook2-5f/pose.txt");
  const Trajectory t = read_trajectory(path);
  ASSERT_EQ(t.entries.size(), 5u);
  // Line 1: 0.000466347 0.00895357 -2.24935 -0.00101358 0.00052453 -0.000231475 0.999999
  EXPECT_NEAR((t.entries[0].T_world_sensor.translation() - Eigen::Vector3d(0.000466347, 0.00895357, -2.24935)).norm(), 0, 1e-9);
}

TEST(TrajectoryRealData, RedwoodLogsStartWhereTheyStart) {
  FVX_REAL_DATA_OR_SKIP(odometry, "open3d-redwood-testdata/RGBD/odometry.log");
  FVX_REAL_DATA_OR_SKIP(livingroom, "redwood-livingroom1-micro/trajectory_open3d_estimated.log");
  const Trajectory a = read_trajectory(odometry);
  EXPECT_EQ(a.format, TrajectoryFormat::RedwoodLog);
  ASSERT_EQ(a.entries.size(), 5u);
  EXPECT_EQ(a.entries[0].frame_id, 0);
  EXPECT_NEAR((a.entries[0].T_world_sensor.translation() - Eigen::Vector3d(2, 2, -0.3)).norm(), 0, 1e-9);
  const Trajectory b = read_trajectory(livingroom);
  ASSERT_EQ(b.entries.size(), 211u);
  EXPECT_EQ(b.entries[210].frame_id, 210);
  EXPECT_TRUE(b.entries[0].T_world_sensor.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
}

TEST(Trajectory, TumWithStampsAndComments) {
  const test::TempDir dir;
  std::ofstream(dir / "t.txt") << "# timestamp tx ty tz qx qy qz qw\n"
                                  "1305031102.1753 1 2 3 0 0 0 1\n\n"
                                  "1305031102.2112 1 2 3 0 0 0 -1  # sign flip\n";
  const Trajectory t = read_trajectory(dir / "t.txt");
  EXPECT_EQ(t.format, TrajectoryFormat::Tum);
  ASSERT_EQ(t.entries.size(), 2u);
  EXPECT_DOUBLE_EQ(*t.entries[1].stamp_s, 1305031102.2112);
  EXPECT_TRUE(t.entries[0].T_world_sensor.isApprox(t.entries[1].T_world_sensor, 1e-12));
}

TEST(Trajectory, BadFilesNameTheFileAndLine) {
  const test::TempDir dir;
  std::ofstream(dir / "fields.txt") << "1 2 3 0 0 0 1\n1 2 3 0 0 1\n";
  std::ofstream(dir / "text.txt") << "1 2 3 0 0 0 1\n1 2 x 0 0 0 1\n";
  std::ofstream(dir / "zero.txt") << "1 2 3 0 0 0 0\n";
  std::ofstream(dir / "empty.txt") << "# nothing\n";
  std::ofstream(dir / "shear.log") << "0 0 1\n1 0.5 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  std::ofstream(dir / "short.log") << "0 0 1\n1 0 0 0\n0 1 0 0\n";
  for (const char* name : {"fields.txt", "text.txt", "zero.txt", "empty.txt", "shear.log", "short.log", "missing.txt"}) {
    try {
      read_trajectory(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  try {
    read_trajectory(dir / "text.txt");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("text.txt:2"), std::string::npos) << e.what();
  }
}

/// A rigid transform with every rotation entry non-zero, and its 4x4 matrix as text rows.
Eigen::Isometry3d some_pose(double angle) {
  Eigen::Isometry3d T(Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()));
  T.pretranslate(Eigen::Vector3d(0.5, -1.25, 2.0 + angle));
  return T;
}

std::string matrix_text(const Eigen::Isometry3d& T, int rows) {
  std::ostringstream out;
  out.precision(17);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < 4; ++c) out << T.matrix()(r, c) << (c < 3 ? " " : "\n");
  }
  return out.str();
}

TEST(Trajectory, KittiRowsAreFramesInLineOrder) {
  const test::TempDir dir;
  std::string rows;
  for (int i = 0; i < 3; ++i) {
    std::string row = matrix_text(some_pose(0.3 * i), 3);
    std::replace(row.begin(), row.end(), '\n', ' ');
    rows += row + "\n";
  }
  std::ofstream(dir / "00.txt") << rows;
  for (const auto choice : {PoseFormatChoice::Auto, PoseFormatChoice::Kitti}) {
    const Trajectory t = read_trajectory(dir / "00.txt", choice);
    EXPECT_EQ(t.format, TrajectoryFormat::Kitti);
    ASSERT_EQ(t.entries.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(t.entries[std::size_t(i)].frame_id, i);
      EXPECT_TRUE(t.entries[std::size_t(i)].T_world_sensor.isApprox(some_pose(0.3 * i), 1e-12));
    }
  }
  // Forced as TUM, twelve fields are refused with the formats named.
  try {
    read_trajectory(dir / "00.txt", PoseFormatChoice::Tum);
    ADD_FAILURE() << "KITTI rows read as TUM";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("12 (KITTI)"), std::string::npos) << e.what();
  }
}

TEST(Trajectory, SevenScenesAndScanNetPoseFoldersMatchByFrameName) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir / "seq-01");
  std::filesystem::create_directories(dir / "pose");
  for (int i = 0; i < 3; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame-%06d.pose.txt", i);
    std::ofstream(dir / ("seq-01/" + std::string(name))) << matrix_text(some_pose(0.1 * i), 4);
    std::ofstream(dir / ("seq-01/" + std::string(name).substr(0, 12) + ".color.png")) << "not a pose";
    std::ofstream(dir / ("pose/" + std::to_string(i * 5) + ".txt")) << matrix_text(some_pose(0.2 * i), 4);
  }
  const Trajectory seven = read_trajectory(dir / "seq-01");
  EXPECT_EQ(seven.format, TrajectoryFormat::PoseFiles);
  ASSERT_EQ(seven.entries.size(), 3u);
  EXPECT_EQ(seven.entries[2].frame_name, "frame-000002");
  EXPECT_TRUE(seven.entries[2].T_world_sensor.isApprox(some_pose(0.2), 1e-12));
  const Trajectory scannet = read_trajectory(dir / "pose");
  ASSERT_EQ(scannet.entries.size(), 3u);
  EXPECT_EQ(scannet.entries[0].frame_name, "0");
  EXPECT_EQ(scannet.entries[1].frame_name, "5");  // by length, then name: 5 before 10
  EXPECT_EQ(scannet.entries[2].frame_name, "10");
  EXPECT_TRUE(scannet.entries[2].T_world_sensor.isApprox(some_pose(0.4), 1e-12));
  EXPECT_EQ(frame_name("/x/frame-000002.depth.png"), "frame-000002");
  EXPECT_EQ(frame_name("depth/12.png"), "12");
}

TEST(Trajectory, BadPoseFilesAreRefusedNamingTheFile) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir / "three");
  std::ofstream(dir / "three/frame-000000.pose.txt") << matrix_text(some_pose(0.1), 3);
  std::filesystem::create_directories(dir / "inf");
  std::ofstream(dir / "inf/0.txt") << "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n";
  std::filesystem::create_directories(dir / "empty");
  std::ofstream(dir / "row.txt") << "1 0 0 0 0 1 0 0 0 0 1\n";
  std::ofstream(dir / "shear.txt") << "1 0.5 0 0 0 1 0 0 0 0 1 0\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"three", "frame-000000.pose.txt: expected a 4x4 matrix (4 rows of 4 numbers), got 3 rows"},
      {"inf", "0.txt: line 1: the matrix is not finite"},
      {"empty", "the folder holds no pose file"},
      {"row.txt", "row.txt: line 1: expected 12 numbers"},
      {"shear.txt", "shear.txt: line 1: the matrix is not a rigid transform"}};
  for (const auto& [name, message] : cases) {
    try {
      read_trajectory(dir / name, name == "row.txt" ? PoseFormatChoice::Kitti : PoseFormatChoice::Auto);
      ADD_FAILURE() << name << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(read_trajectory(dir / "three", PoseFormatChoice::Kitti), FileError);
  EXPECT_THROW(parse_pose_format("kiti", "--pose-format"), UsageError);
}

}  // namespace
}  // namespace fvx::io
