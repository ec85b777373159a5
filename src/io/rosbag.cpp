// ROS 1 bags through librosbag_storage and tf2's BufferCore (Debian's packages; no ROS
// installation). Part of fvx-heavy.so: its libraries load only for --bag.
#include "fvx/io/rosbag.hpp"

#include <console_bridge/console.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/isolated.hpp"

namespace fvx::io {

namespace {

constexpr const char* kCloudType = "sensor_msgs/PointCloud2";
constexpr const char* kImageType = "sensor_msgs/Image";

/// Opens the bag for reading; FileError for a file that is not one.
void open_bag(rosbag::Bag& bag, const std::string& path) {
  require_readable_file(path);
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);  // fvx reports, once
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw FileError(path, std::string("not a readable ROS 1 bag: ") + e.what());
  }
}

std::string topics_of(const rosbag::Bag& bag) {
  rosbag::View all(bag);
  std::set<std::string> topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) topics.insert(c->topic + " (" + c->datatype + ")");
  std::string text;
  for (const std::string& t : topics) text += (text.empty() ? "" : ", ") + t;
  return text.empty() ? "none" : text;
}

/// A frame id as tf2 takes it: old (tf) bags write "/odom", tf2 refuses a leading slash.
std::string tf2_frame(const std::string& frame) { return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame; }

/// Every /tf and /tf_static transform of the bag, for look-ups at any stamp in it.
void load_tf(const rosbag::Bag& bag, tf2::BufferCore& buffer) {
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"}));
  for (const rosbag::MessageInstance& m : view) {
    const auto tf = m.instantiate<tf2_msgs::TFMessage>();
    if (!tf) continue;
    for (geometry_msgs::TransformStamped t : tf->transforms) {
      t.header.frame_id = tf2_frame(t.header.frame_id);
      t.child_frame_id = tf2_frame(t.child_frame_id);
      buffer.setTransform(t, "bag", m.getTopic() == "/tf_static");
    }
  }
}

Eigen::Isometry3d isometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d T(Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized());
  T.pretranslate(Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z));
  return T;
}

/// The CameraInfo beside an Image topic: <namespace>/camera_info.
std::string camera_info_topic(const std::string& topic) {
  const auto slash = topic.find_last_of('/');
  return (slash == std::string::npos ? std::string() : topic.substr(0, slash)) + "/camera_info";
}

Intrinsics intrinsics_from(const sensor_msgs::CameraInfo& info, const std::string& path, const std::string& topic) {
  Intrinsics K;
  K.fx = info.K[0];
  K.fy = info.K[4];
  K.cx = info.K[2];
  K.cy = info.K[5];
  K.width = int(std::min<std::uint32_t>(info.width, std::uint32_t(kMaxImageSidePx) + 1));
  K.height = int(std::min<std::uint32_t>(info.height, std::uint32_t(kMaxImageSidePx) + 1));
  K.size_stated = true;
  const auto problems = K.validate();
  if (!problems.empty()) throw FileError(path, topic + ": " + join_problems(problems));
  return K;
}

Intrinsics image_intrinsics(const rosbag::Bag& bag, const BagQuery& query) {
  if (query.intrinsics) return *query.intrinsics;
  const std::string info_topic = camera_info_topic(query.topic);
  rosbag::View view(bag, rosbag::TopicQuery(info_topic));
  for (const rosbag::MessageInstance& m : view)
    if (const auto info = m.instantiate<sensor_msgs::CameraInfo>()) return intrinsics_from(*info, query.path, info_topic);
  throw FileError(query.path, "no sensor_msgs/CameraInfo on " + info_topic + " for the depth images on " +
                                  query.topic + "; give --intrinsics");
}

template <typename Message>
std::pair<double, std::string> header_of(const rosbag::MessageInstance& m, const std::string& path) {
  const auto msg = m.instantiate<Message>();
  if (!msg) throw FileError(path, "a message on " + m.getTopic() + " does not hold its connection's type");
  return {msg->header.stamp.toSec(), msg->header.frame_id};
}

std::vector<BagMessage> index_bag_here(const BagQuery& query) {
  rosbag::Bag bag;
  open_bag(bag, query.path);
  rosbag::View view(bag, rosbag::TopicQuery(query.topic));
  if (view.size() == 0)
    throw FileError(query.path, "no message on topic " + query.topic + "; the bag holds: " + topics_of(bag));
  const std::string type = view.getConnections().front()->datatype;
  if (type != kCloudType && type != kImageType)
    throw FileError(query.path, "topic " + query.topic + " holds " + type + "; expected " + kCloudType + " or " + kImageType);
  if (type == kImageType) image_intrinsics(bag, query);  // refused now, not at the first scan
  const double span_s = (view.getEndTime() - view.getBeginTime()).toSec();
  tf2::BufferCore buffer(ros::Duration(std::max(10.0, span_s + 10.0)));
  load_tf(bag, buffer);
  std::vector<BagMessage> messages;
  for (const rosbag::MessageInstance& m : view) {
    BagMessage out;
    out.index = messages.size();
    out.record_sec = m.getTime().sec;
    out.record_nsec = m.getTime().nsec;
    const bool same_time = !messages.empty() && messages.back().record_sec == out.record_sec &&
                           messages.back().record_nsec == out.record_nsec;
    out.record_rank = same_time ? messages.back().record_rank + 1 : 0;
    std::tie(out.stamp_s, out.frame_id) =
        type == kCloudType ? header_of<sensor_msgs::PointCloud2>(m, query.path) : header_of<sensor_msgs::Image>(m, query.path);
    if (!query.sensor_frame.empty()) out.frame_id = query.sensor_frame;
    try {
      out.T_fixed_sensor = isometry(
          buffer.lookupTransform(tf2_frame(query.fixed_frame), tf2_frame(out.frame_id), ros::Time(out.stamp_s)).transform);
    } catch (const tf2::TransformException& e) {
      throw FileError(query.path, "message " + std::to_string(out.index) + " on " + query.topic + ": no transform from '" +
                                      out.frame_id + "' to '" + query.fixed_frame + "' at " + std::to_string(out.stamp_s) +
                                      " s: " + e.what());
    }
    messages.push_back(out);
  }
  return messages;
}

/// x, y, z of a PointCloud2 (FLOAT32 or FLOAT64 fields, little-endian), NaN kept.
std::vector<Eigen::Vector3d> cloud_points(const sensor_msgs::PointCloud2& cloud, const std::string& where) {
  const sensor_msgs::PointField* fields[3] = {nullptr, nullptr, nullptr};
  for (const auto& f : cloud.fields)
    for (int k = 0; k < 3; ++k)
      if (f.name == std::string(1, char('x' + k))) fields[k] = &f;
  if (!fields[0] || !fields[1] || !fields[2]) throw FileError(where, "the cloud has no x, y, z fields");
  const std::uint64_t n = std::uint64_t(cloud.width) * cloud.height;
  if (cloud.is_bigendian) throw FileError(where, "big-endian point data is not read");
  if (std::uint64_t(cloud.row_step) * cloud.height > cloud.data.size() || std::uint64_t(cloud.point_step) * cloud.width > cloud.row_step)
    throw FileError(where, "the cloud's data is shorter than its width, height and steps declare");
  for (const auto* f : fields) {
    const std::uint32_t bytes = f->datatype == sensor_msgs::PointField::FLOAT32 ? 4 : f->datatype == sensor_msgs::PointField::FLOAT64 ? 8 : 0;
    if (bytes == 0 || f->count != 1 || std::uint64_t(f->offset) + bytes > cloud.point_step)
      throw FileError(where, "field " + f->name + " is not one float32 or float64 inside the point");
  }
  std::vector<Eigen::Vector3d> points(n);
  for (std::uint64_t row = 0, i = 0; row < cloud.height; ++row)
    for (std::uint64_t col = 0; col < cloud.width; ++col, ++i) {
      const std::uint8_t* p = cloud.data.data() + row * cloud.row_step + col * cloud.point_step;
      for (int k = 0; k < 3; ++k) {
        if (fields[k]->datatype == sensor_msgs::PointField::FLOAT32) {
          float v;
          std::memcpy(&v, p + fields[k]->offset, 4);
          points[i][k] = v;
        } else {
          std::memcpy(&points[i][k], p + fields[k]->offset, 8);
        }
      }
    }
  return points;
}

/// A 16UC1 / mono16 image as is, a 32FC1 image in metres as depth_scale units.
DepthImage depth_image(const sensor_msgs::Image& image, double depth_scale, const std::string& where) {
  const bool u16 = image.encoding == "16UC1" || image.encoding == "mono16";
  if (!u16 && image.encoding != "32FC1")
    throw FileError(where, "depth encoding '" + image.encoding + "': expected 16UC1, mono16 or 32FC1");
  if (image.is_bigendian) throw FileError(where, "big-endian depth is not read");
  const std::uint32_t bytes = u16 ? 2 : 4;
  if (image.width == 0 || image.height == 0 || image.width > std::uint32_t(kMaxImageSidePx) ||
      image.height > std::uint32_t(kMaxImageSidePx) || std::uint64_t(image.step) < std::uint64_t(image.width) * bytes ||
      std::uint64_t(image.step) * image.height > image.data.size())
    throw FileError(where, "the image's data does not hold its width, height and step");
  DepthImage depth;
  depth.width = int(image.width);
  depth.height = int(image.height);
  depth.raw.resize(std::size_t(image.width) * image.height);
  for (std::uint32_t v = 0; v < image.height; ++v)
    for (std::uint32_t u = 0; u < image.width; ++u) {
      const std::uint8_t* p = image.data.data() + std::size_t(v) * image.step + std::size_t(u) * bytes;
      std::uint16_t& out = depth.raw[std::size_t(v) * image.width + u];
      if (u16) {
        std::memcpy(&out, p, 2);
        continue;
      }
      float z_m;
      std::memcpy(&z_m, p, 4);
      const double raw = std::round(double(z_m) * depth_scale);
      out = std::isfinite(raw) && raw > 0 && raw < kDepthSaturated ? std::uint16_t(raw) : 0;
    }
  return depth;
}

BagScan read_bag_scan_here(const BagQuery& query, const BagMessage& message) {
  rosbag::Bag bag;
  open_bag(bag, query.path);
  const ros::Time t(message.record_sec, message.record_nsec);
  rosbag::View view(bag, rosbag::TopicQuery(query.topic), t, t);
  const std::string where = bag_message_name(query, message);
  std::size_t k = 0;
  for (const rosbag::MessageInstance& m : view) {
    if (k++ != message.record_rank) continue;
    BagScan scan;
    if (const auto cloud = m.instantiate<sensor_msgs::PointCloud2>()) {
      scan.points = cloud_points(*cloud, where);
    } else if (const auto image = m.instantiate<sensor_msgs::Image>()) {
      scan.intrinsics = image_intrinsics(bag, query);
      scan.depth = depth_image(*image, scan.intrinsics.depth_scale, where);
    } else {
      throw FileError(where, "the message holds neither a PointCloud2 nor an Image");
    }
    return scan;
  }
  throw FileError(query.path, "message " + std::to_string(message.index) + " on " + query.topic + " is gone");
}

/// Plain bytes across the child's pipe (core/isolated.hpp): values as they lie in memory.
struct Bytes {
  std::string data;
  std::size_t at = 0;
  template <typename T>
  void put(const T& v) { data.append(reinterpret_cast<const char*>(&v), sizeof v); }
  void put(const std::string& v) { put(v.size()), data.append(v); }
  template <typename T>
  void put(const std::vector<T>& v) {
    put(v.size());
    if (!v.empty()) data.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  template <typename T>
  void get(T& v) { std::memcpy(static_cast<void*>(&v), take(sizeof v), sizeof v); }
  void get(std::string& v) { std::size_t n; get(n), v.assign(take(n), n); }
  template <typename T>
  void get(std::vector<T>& v) {
    std::size_t n;
    get(n), v.resize(n);
    if (n) std::memcpy(static_cast<void*>(v.data()), take(n * sizeof(T)), n * sizeof(T));
  }
  const char* take(std::size_t n) {
    FVX_ASSERT(n <= data.size() - at, "the bag reader's answer is shorter than it says");
    at += n;
    return data.data() + at - n;
  }
};

}  // namespace

// librosbag reads past its buffers on some corrupt bags: both passes run in a child process.
std::vector<BagMessage> index_bag(const BagQuery& query) {
  Bytes bytes{run_isolated(query.path, "ROS bag", [&] {
    Bytes out;
    const std::vector<BagMessage> messages = index_bag_here(query);
    out.put(messages.size());
    for (const BagMessage& m : messages)
      out.put(m.index), out.put(m.record_sec), out.put(m.record_nsec), out.put(m.record_rank), out.put(m.stamp_s),
          out.put(m.frame_id), out.put(m.T_fixed_sensor.matrix());
    return out.data;
  })};
  std::size_t n;
  bytes.get(n);
  std::vector<BagMessage> messages(n);
  for (BagMessage& m : messages) {
    Eigen::Matrix4d T;
    bytes.get(m.index), bytes.get(m.record_sec), bytes.get(m.record_nsec), bytes.get(m.record_rank), bytes.get(m.stamp_s),
        bytes.get(m.frame_id), bytes.get(T);
    m.T_fixed_sensor.matrix() = T;
  }
  return messages;
}

BagScan read_bag_scan(const BagQuery& query, const BagMessage& message) {
  Bytes bytes{run_isolated(query.path, "ROS bag", [&] {
    const BagScan scan = read_bag_scan_here(query, message);
    Bytes out;
    out.put(scan.points), out.put(scan.depth.has_value());
    if (scan.depth) out.put(scan.depth->width), out.put(scan.depth->height), out.put(scan.depth->raw);
    const Intrinsics& K = scan.intrinsics;
    out.put(K.fx), out.put(K.fy), out.put(K.cx), out.put(K.cy), out.put(K.depth_scale), out.put(K.width), out.put(K.height),
        out.put(K.size_stated);
    return out.data;
  })};
  BagScan scan;
  bool depth = false;
  bytes.get(scan.points), bytes.get(depth);
  if (depth) {
    scan.depth.emplace();
    bytes.get(scan.depth->width), bytes.get(scan.depth->height), bytes.get(scan.depth->raw);
  }
  Intrinsics& K = scan.intrinsics;
  bytes.get(K.fx), bytes.get(K.fy), bytes.get(K.cx), bytes.get(K.cy), bytes.get(K.depth_scale), bytes.get(K.width),
      bytes.get(K.height), bytes.get(K.size_stated);
  return scan;
}

}  // namespace fvx::io
