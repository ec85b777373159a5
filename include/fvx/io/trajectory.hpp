#pragma once
/// \file
/// Sensor trajectories: `T_world_sensor` per frame, from TUM-style text files or Redwood /
/// Open3D `.log` files.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace fvx::io {

enum class TrajectoryFormat {
  Tum,          ///< `stamp tx ty tz qx qy qz qw` per line (TUM RGB-D)
  TumNoStamp,   ///< `tx ty tz qx qy qz qw` per line, frame i on line i (slambook)
  RedwoodLog,   ///< `id id n` then a 4x4 camera-to-world matrix, per frame (Redwood, Open3D)
};

const char* to_string(TrajectoryFormat format);

struct TrajectoryEntry {
  std::optional<double> stamp_s;  ///< TUM timestamp, seconds
  std::optional<long> frame_id;   ///< Redwood frame id
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
};

struct Trajectory {
  TrajectoryFormat format = TrajectoryFormat::Tum;
  std::vector<TrajectoryEntry> entries;
};

/// Reads a trajectory; `.log` files are Redwood, other files TUM with or without stamps
/// (decided by the field count of the first pose line). `#` starts a comment. Quaternions are
/// scalar-last and normalised; Redwood rotations must be orthonormal within 1e-3 and are
/// re-orthonormalised. Throws FileError naming file:line.
Trajectory read_trajectory(const std::string& path);

}  // namespace fvx::io
