// ROS 1 bags (issue 20): a bag written here with librosbag_storage from the slambook frames
// (16UC1 depth + CameraInfo, and the same frames as PointCloud2), posed by /tf (odom→base_link,
// two stamps around each frame; uncompressed, bz2 and lz4 chunks) and /tf_static (base_link→optical frame), read back against
// the frames and the trajectory it came from; integrated through the binary; bad bags refused.
#include <gtest/gtest.h>

#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "fvx/core/error.hpp"
#include "fvx/io/depth_image.hpp"
#include "fvx/io/rosbag.hpp"
#include "fvx/io/trajectory.hpp"
#include "fvx/scan/scan.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

const io::Intrinsics kSlambookK{518.0, 519.0, 325.5, 253.5, 1000.0, 640, 480, true};
constexpr const char* kOptical = "camera_depth_optical_frame";

geometry_msgs::TransformStamped stamped(const Eigen::Isometry3d& T, double stamp_s, const std::string& parent,
                                        const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time(stamp_s);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  const Eigen::Quaterniond q(T.rotation());
  t.transform.rotation.x = q.x(), t.transform.rotation.y = q.y(), t.transform.rotation.z = q.z(), t.transform.rotation.w = q.w();
  t.transform.translation.x = T.translation().x(), t.transform.translation.y = T.translation().y();
  t.transform.translation.z = T.translation().z();
  return t;
}

void write_tf(rosbag::Bag& bag, const std::string& topic, const geometry_msgs::TransformStamped& t) {
  tf2_msgs::TFMessage message;
  message.transforms.push_back(t);
  bag.write(topic, t.header.stamp, message);
}

sensor_msgs::Image depth_message(const io::DepthImage& depth, double stamp_s) {
  sensor_msgs::Image image;
  image.header.stamp = ros::Time(stamp_s);
  image.header.frame_id = kOptical;
  image.encoding = "16UC1";
  image.width = std::uint32_t(depth.width), image.height = std::uint32_t(depth.height);
  image.step = image.width * 2;
  image.data.resize(depth.raw.size() * 2);
  std::memcpy(image.data.data(), depth.raw.data(), image.data.size());
  return image;
}

sensor_msgs::PointCloud2 cloud_message(const std::vector<Eigen::Vector3d>& points, int width, double stamp_s) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = ros::Time(stamp_s);
  cloud.header.frame_id = kOptical;
  cloud.width = std::uint32_t(width), cloud.height = std::uint32_t(points.size() / std::size_t(width));
  for (std::uint32_t k = 0; k < 3; ++k) {
    sensor_msgs::PointField f;
    f.name = std::string(1, char('x' + k)), f.offset = 4 * k, f.datatype = sensor_msgs::PointField::FLOAT32, f.count = 1;
    cloud.fields.push_back(f);
  }
  cloud.point_step = 16, cloud.row_step = 16 * cloud.width;
  cloud.data.assign(std::size_t(cloud.row_step) * cloud.height, 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const float v = float(points[i][k]);
      std::memcpy(cloud.data.data() + 16 * i + 4 * std::size_t(k), &v, 4);
    }
  return cloud;
}

/// The slambook frames as a bag: frame i at 100 + i s; odom→base_link at ±0.1 s around it
/// (translations ±1 cm about the true one, so the interpolation lands on it), base_link→optical
/// static; chunks compressed as asked. Returns the true poses T_odom_optical.
std::vector<Eigen::Isometry3d> write_slambook_bag(const std::string& frames, const std::string& path,
                                                  rosbag::compression::CompressionType compression) {
  const io::Trajectory trajectory = io::read_trajectory(frames + "/pose.txt");
  Eigen::Isometry3d T_base_optical(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
  T_base_optical.pretranslate(Eigen::Vector3d(0.1, 0.02, 0.3));
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  write_tf(bag, "/tf_static", stamped(T_base_optical, 99.0, "base_link", kOptical));
  sensor_msgs::CameraInfo info;
  info.width = 640, info.height = 480;
  info.K = {518.0, 0.0, 325.5, 0.0, 519.0, 253.5, 0.0, 0.0, 1.0};
  std::vector<Eigen::Isometry3d> truth;
  for (int i = 0; i < 5; ++i) {
    const double t = 100.0 + i;
    // The file's quaternions are unit to 1e-6: the bag holds rigid transforms.
    Eigen::Isometry3d T_odom_optical(Eigen::Quaterniond(trajectory.entries[std::size_t(i)].T_world_sensor.rotation()).normalized());
    T_odom_optical.pretranslate(trajectory.entries[std::size_t(i)].T_world_sensor.translation());
    truth.push_back(T_odom_optical);
    const Eigen::Isometry3d T_odom_base = T_odom_optical * T_base_optical.inverse();
    for (const double dt : {-0.1, 0.1}) {
      Eigen::Isometry3d moved = T_odom_base;
      moved.pretranslate(Eigen::Vector3d(dt / 10.0, 0, 0));
      write_tf(bag, "/tf", stamped(moved, t + dt, "odom", "base_link"));
    }
    const io::DepthImage depth = io::read_depth_image(frames + "/depth/" + std::to_string(i + 1) + ".pgm");
    info.header.stamp = ros::Time(t), info.header.frame_id = kOptical;
    bag.write("/camera/depth/camera_info", ros::Time(t), info);
    bag.write("/camera/depth/image_raw", ros::Time(t), depth_message(depth, t));
    bag.write("/camera/depth/points", ros::Time(t), cloud_message(scan::backproject(depth, kSlambookK), depth.width, t));
  }
  return truth;
}

TEST(BagRealData, SlambookFramesComeBackWithTheirPosesDepthAndPoints) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  const TempDir dir;
  const std::vector<Eigen::Isometry3d> truth = write_slambook_bag(frames, dir / "run.bag", rosbag::compression::Uncompressed);
  io::BagQuery query{dir / "run.bag", "/camera/depth/image_raw", "odom", "", std::nullopt};
  const std::vector<io::BagMessage> messages = io::index_bag(query);
  ASSERT_EQ(messages.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(messages[i].frame_id, kOptical);
    EXPECT_DOUBLE_EQ(messages[i].stamp_s, 100.0 + double(i));
    EXPECT_LT((messages[i].T_fixed_sensor.translation() - truth[i].translation()).norm(), 1e-9) << i;
    EXPECT_LT((messages[i].T_fixed_sensor.linear() - truth[i].linear()).cwiseAbs().maxCoeff(), 1e-9) << i;
  }
  const io::BagScan image = io::read_bag_scan(query, messages[3]);
  ASSERT_TRUE(image.depth.has_value());
  EXPECT_EQ(image.depth->raw, io::read_depth_image(frames + "/depth/4.pgm").raw);
  EXPECT_EQ(image.intrinsics.fx, 518.0);
  EXPECT_EQ(image.intrinsics.cy, 253.5);
  query.topic = "/camera/depth/points";
  const io::BagScan cloud = io::read_bag_scan(query, io::index_bag(query)[2]);
  const auto expected = scan::backproject(io::read_depth_image(frames + "/depth/3.pgm"), kSlambookK);
  ASSERT_EQ(cloud.points.size(), expected.size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (!expected[i].allFinite()) {
      EXPECT_FALSE(cloud.points[i].allFinite());
      continue;
    }
    ++finite;
    ASSERT_EQ(cloud.points[i], expected[i].cast<float>().cast<double>()) << i;
  }
  EXPECT_GT(finite, 100000u);
}

TEST(BagRealData, IntegrateReadsTheBagAsTheFramesWithTheirTrajectory) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  const TempDir dir;
  const std::vector<Eigen::Isometry3d> truth = write_slambook_bag(frames, dir / "run.bag", rosbag::compression::BZ2);
  const RunResult r = run_fvx(dir, "integrate --bag run.bag --topic /camera/depth/image_raw --fixed-frame odom "
                                   "-o bag.bt --resolution 0.05 --depth-max 7 --no-register");
  ASSERT_EQ(r.status, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["inputs"]["pose_match"], "tf");
  ASSERT_EQ(report["results"]["scans"].size(), 5u);
  EXPECT_EQ(report["results"]["scans"][0]["pose_source"], "tf");
  EXPECT_EQ(report["results"]["scans"][4]["file"], "run.bag:/camera/depth/image_raw#4");
  // The same frames at the same (rigid) poses, from files: the same map.
  std::ofstream poses(dir / "poses.txt");
  poses.precision(17);
  for (const auto& T : truth) {
    const Eigen::Quaterniond q(T.rotation());
    poses << T.translation().x() << ' ' << T.translation().y() << ' ' << T.translation().z() << ' ' << q.x() << ' '
          << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  poses.close();
  std::string depth;
  for (int i = 1; i <= 5; ++i) depth += " " + frames + "/depth/" + std::to_string(i) + ".pgm";
  const RunResult files = run_fvx(dir, "integrate -o files.bt --resolution 0.05 --depth-max 7 --no-register --fx 518 "
                                       "--fy 519 --cx 325.5 --cy 253.5 --trajectory poses.txt" + depth);
  ASSERT_EQ(files.status, 0) << files.err;
  EXPECT_EQ(json::parse(files.out)["results"]["map"], report["results"]["map"]);
}

TEST(BagRealData, BadBagsTopicsAndFramesAreRefusedOnOneLine) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  const TempDir dir;
  write_slambook_bag(frames, dir / "run.bag", rosbag::compression::LZ4);
  std::ofstream(dir / "text.bag") << "this is no bag\n";
  const std::vector<std::tuple<std::string, int, std::string>> cases = {
      {"--bag run.bag --topic /nope --fixed-frame odom", 1, "run.bag: no message on topic /nope; the bag holds: /camera"},
      {"--bag run.bag --topic /camera/depth/camera_info --fixed-frame odom", 1, "holds sensor_msgs/CameraInfo"},
      {"--bag run.bag --topic /camera/depth/points --fixed-frame map", 1,
       "no transform from 'camera_depth_optical_frame' to 'map'"},
      {"--bag run.bag --topic /camera/depth/points --fixed-frame odom --frame camera_link", 1,
       "no transform from 'camera_link' to 'odom'"},
      {"--bag text.bag --topic /camera/depth/points --fixed-frame odom", 1, "text.bag: not a readable ROS 1 bag"},
      {"--bag run.bag --fixed-frame odom", 2, "--bag needs --topic"},
      {"--topic /camera/depth/points a.pcd", 2, "--topic goes with --bag"},
      {"--bag run.bag --topic /camera/depth/points --fixed-frame odom --trajectory t.txt", 2, "posed by its TF"},
  };
  for (const auto& [arguments, status, message] : cases) {
    const RunResult r = run_fvx(dir, "integrate -o m.bt " + arguments);
    EXPECT_EQ(r.status, status) << arguments << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << arguments << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << arguments << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "m.bt")) << arguments;
  }
  // A fixed frame written as old tf bags write frames ("/odom") is the same frame.
  const RunResult slash = run_fvx(dir, "integrate -o m.bt --bag run.bag --topic /camera/depth/points --fixed-frame /odom "
                                       "-r 0.1 --no-register");
  EXPECT_EQ(slash.status, 0) << slash.err;
  // Replay reads the same bag: one row per message.
  const RunResult replay = run_fvx(dir, "replay --bag run.bag --topic /camera/depth/points --fixed-frame odom "
                                        "--no-capmap --no-register -r 0.1 --search-every 0 --format json -o out");
  ASSERT_EQ(replay.status, 0) << replay.err;
  EXPECT_EQ(json::parse(replay.out)["results"]["rows"].size(), 5u);
}

}  // namespace
}  // namespace fvx::test
