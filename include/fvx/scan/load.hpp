#pragma once
/// \file
/// Reading recorded scans with their pose priors. One rule for `integrate` and `replay`: the
/// pose comes from a trajectory file (or one `--pose` for every scan), else from the scan
/// itself (a PCD's `VIEWPOINT`, a PLY's camera element), else the scan is refused. Depth
/// images need intrinsics.
#include <optional>
#include <string>
#include <vector>

#include "fvx/io/intrinsics.hpp"
#include "fvx/io/rosbag.hpp"
#include "fvx/io/trajectory.hpp"
#include "fvx/scan/scan.hpp"

namespace fvx::scan {

struct LoadConfig {
  /// Intrinsics and depth scale for depth images; required when any input is an image.
  std::optional<io::Intrinsics> intrinsics;
  /// Use a cloud's VIEWPOINT as its pose prior. Legacy OpenNI captures store a 180° rotation
  /// about x there while their points are already in the optical frame: switch this off
  /// (`--ignore-viewpoint`) for them; a cloud without a trajectory is then at the identity.
  bool use_viewpoint = true;
  /// One pose for every scan (`--pose`).
  std::optional<Eigen::Isometry3d> pose;
  /// Trajectory (`--trajectory`): a TUM, Redwood .log or KITTI file, or a folder of per-frame
  /// 4x4 pose files; read as `pose_format` says (`--pose-format`).
  std::string trajectory_path;
  io::PoseFormatChoice pose_format = io::PoseFormatChoice::Auto;
  /// Largest |stamp(file name) − stamp(pose)| accepted when matching by timestamp, seconds.
  double max_time_diff_s = 0.02;
};

/// A scan to be read: its file and, when known before reading, its pose prior.
struct ScanSource {
  std::string path;                                 ///< a file, or a bag message's name
  std::optional<Eigen::Isometry3d> T_world_sensor;  ///< empty: VIEWPOINT or identity
  PoseSource pose_source = PoseSource::Identity;
  /// A message of a ROS bag (path is then io::bag_message_name), posed by its TF.
  std::optional<std::pair<io::BagQuery, io::BagMessage>> bag;
};

/// How the trajectory's poses were matched to the scan files.
enum class PoseMatch { None, ByOrder, ByTimestamp, ByFrameId, ByFrameName, ByTf };
const char* to_string(PoseMatch match);

struct ScanPlan {
  std::vector<ScanSource> scans;
  PoseMatch match = PoseMatch::None;
  std::vector<std::string> warnings;
};

/// Assigns pose priors to `paths` without reading the scans. A trajectory is matched
///  - by frame name (io::frame_name) when it is a folder of pose files;
///  - by frame id when it is a Redwood .log or KITTI file and every file stem is an integer;
///  - by timestamp when it has stamps and every file stem is a number (TUM names);
///  - otherwise by order, which needs at least as many poses as scans.
/// Throws Error when a scan gets no pose (too few poses, no stamp within max_time_diff_s, or a
/// depth image without trajectory or --pose).
ScanPlan plan_scans(const std::vector<std::string>& paths, const LoadConfig& config);

/// The messages of a bag's topic, each posed by the bag's TF in query.fixed_frame
/// (io::index_bag); FileError naming the bag otherwise.
ScanPlan plan_bag(const io::BagQuery& query);

/// Reads one scan (PCD, PLY, depth image or bag message) into the sensor frame with its pose prior: the
/// source's, else the file's own (unless config.use_viewpoint is off: the identity), else
/// FileError "no pose".
/// NaN points are kept here; filter() removes them. Appends notes to `warnings`.
Scan load_scan(const ScanSource& source, const LoadConfig& config,
               std::vector<std::string>& warnings);

/// The files matching a shell pattern (`*`, `?`, `[…]`), in name order; UsageError naming
/// `what` (the option it came from) when none matches.
std::vector<std::string> expand_glob(const std::string& pattern, const std::string& what);

/// The depth images of a TUM RGB-D folder `dir`: from the associations file when given (per
/// line the last column naming a file under depth/, else the second column; `#` comments),
/// else every file in dir/depth by name. FileError naming the file and line otherwise.
std::vector<std::string> tum_depth_images(const std::string& dir, const std::string& associations);

/// A TUM RGB-D folder's depth images (tum_depth_images) and, unless load names a trajectory,
/// its groundtruth.txt as load's trajectory; FileError when that file does not exist.
std::vector<std::string> tum_recording(const std::string& dir, const std::string& associations, LoadConfig& load);

}  // namespace fvx::scan
