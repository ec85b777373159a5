#pragma once
/// \file
/// Sensor trajectories: `T_world_sensor` per frame, from TUM-style text files, Redwood /
/// Open3D `.log` files, KITTI pose rows, or a folder of per-frame 4x4 matrix files
/// (7-Scenes / 3DMatch / SUN3D `frame-XXXXXX.pose.txt`, ScanNet `pose/N.txt`).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace fvx::io {

enum class TrajectoryFormat {
  Tum,          ///< `stamp tx ty tz qx qy qz qw` per line (TUM RGB-D)
  TumNoStamp,   ///< `tx ty tz qx qy qz qw` per line, frame i on line i (slambook)
  RedwoodLog,   ///< `id id n` then a 4x4 camera-to-world matrix, per frame (Redwood, Open3D)
  Kitti,        ///< 12 numbers per line: a 3x4 camera-to-world matrix, row-major; line i is frame i
  PoseFiles,    ///< a folder of one 4x4 camera-to-world matrix file per frame, named by frame
};

const char* to_string(TrajectoryFormat format);

/// What `--pose-format` asks for: Auto decides by the file (a folder: PoseFiles; `.log`:
/// Redwood; else by the first line's field count: 7 or 8 TUM, 12 KITTI).
enum class PoseFormatChoice { Auto, Tum, Redwood, Kitti };
const char* to_string(PoseFormatChoice choice);
/// Parses auto, tum, redwood or kitti; UsageError naming `what` otherwise.
PoseFormatChoice parse_pose_format(const std::string& text, const std::string& what);

struct TrajectoryEntry {
  std::optional<double> stamp_s;  ///< TUM timestamp, seconds
  std::optional<long> frame_id;   ///< Redwood frame id; KITTI line index from 0
  std::string frame_name;         ///< PoseFiles: the file name up to its first '.'

  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
};

struct Trajectory {
  TrajectoryFormat format = TrajectoryFormat::Tum;
  std::vector<TrajectoryEntry> entries;
};

/// Reads a trajectory as `choice` says (see PoseFormatChoice). `#` starts a comment.
/// Quaternions are scalar-last and normalised; matrices must be finite rigid transforms
/// (rotation orthonormal within 1e-3, last row 0 0 0 1) and are re-orthonormalised. A folder
/// holds `*.pose.txt` files (7-Scenes) or, without any, `*.txt` files (ScanNet's pose/),
/// each one 4x4 matrix, and at most kMaxPoseFiles of them. Throws FileError naming file:line.
Trajectory read_trajectory(const std::string& path, PoseFormatChoice choice = PoseFormatChoice::Auto);

/// The most per-frame pose files a folder may hold (ScanNet scenes have up to ~10^4 frames).
inline constexpr std::size_t kMaxPoseFiles = 1000000;

/// The frame name that matches a scan to its pose file: the file name up to its first '.'
/// (frame-000000.depth.png and frame-000000.pose.txt → frame-000000; 12.png, 12.txt → 12).
std::string frame_name(const std::string& path);

}  // namespace fvx::io
