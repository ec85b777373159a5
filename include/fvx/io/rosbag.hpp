#pragma once
/// \file
/// Scans from a ROS 1 bag (librosbag_storage, no ROS installation): sensor_msgs/PointCloud2,
/// or sensor_msgs/Image depth with the sensor_msgs/CameraInfo beside it, each posed by the
/// bag's /tf and /tf_static (tf2's BufferCore: the chain from the scan's frame to a fixed
/// frame, interpolated to the scan's header stamp). Read in two passes: an index of the
/// topic's messages with their poses, then one message's points when its turn comes.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fvx/io/depth_image.hpp"
#include "fvx/io/intrinsics.hpp"

namespace fvx::io {

struct BagQuery {
  std::string path;          ///< the .bag file
  std::string topic;         ///< PointCloud2 or depth Image messages
  std::string fixed_frame;   ///< the world frame of the poses (`--fixed-frame`, e.g. odom, map)
  std::string sensor_frame;  ///< overrides each message's header.frame_id (`--frame`); "" keeps it
  /// Overrides the CameraInfo of an Image topic (`--intrinsics`); its depth_scale reads 16UC1.
  std::optional<Intrinsics> intrinsics;
};

/// One message of the topic and the pose of its frame at its stamp.
struct BagMessage {
  std::size_t index = 0;            ///< 0-based, in the bag's time order
  std::uint32_t record_sec = 0, record_nsec = 0;  ///< the bag's record time (finds it again)
  std::uint32_t record_rank = 0;    ///< messages recorded earlier at the same record time
  double stamp_s = 0.0;             ///< header.stamp, seconds
  std::string frame_id;             ///< the frame the points are in (optical: z forward)
  Eigen::Isometry3d T_fixed_sensor = Eigen::Isometry3d::Identity();
};

/// What one message holds: points (PointCloud2, in its frame; NaN kept) or a depth image
/// (16UC1/mono16 as is, 32FC1 metres rounded to depth_scale units) with its intrinsics.
struct BagScan {
  std::vector<Eigen::Vector3d> points;
  std::optional<DepthImage> depth;
  Intrinsics intrinsics;
};

/// The topic's messages with their poses. FileError naming the bag: not a bag, no message on
/// the topic (the topics it has are listed), a type other than PointCloud2 or Image, an Image
/// topic without CameraInfo (unless query.intrinsics), a frame with no transform to the fixed
/// frame at the message's stamp (tf2's reason: not connected, or extrapolation).
std::vector<BagMessage> index_bag(const BagQuery& query);

/// The points or the depth image of one indexed message. FileError for a message that does
/// not hold what its header declares (field layout, step, encoding, big-endian data).
BagScan read_bag_scan(const BagQuery& query, const BagMessage& message);

/// A name for a message in reports and errors: "run.bag:/camera/depth/points#12".
inline std::string bag_message_name(const BagQuery& query, const BagMessage& message) {
  return query.path + ":" + query.topic + "#" + std::to_string(message.index);
}

}  // namespace fvx::io
