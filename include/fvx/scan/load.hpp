#pragma once
/// \file
/// Reading recorded scans with their pose priors. Poses come, in order of precedence, from a
/// trajectory file, from one `--pose` for every scan, or from the PCD `VIEWPOINT` header
/// (unless ignored). Depth images need intrinsics.
#include <optional>
#include <string>
#include <vector>

#include "fvx/io/intrinsics.hpp"
#include "fvx/io/trajectory.hpp"
#include "fvx/scan/scan.hpp"

namespace fvx::scan {

struct LoadConfig {
  /// Intrinsics and depth scale for depth images; required when any input is an image.
  std::optional<io::Intrinsics> intrinsics;
  /// Use a cloud's VIEWPOINT as its pose prior. Legacy OpenNI captures store a 180° rotation
  /// about x there while their points are already in the optical frame: switch this off
  /// (`--ignore-viewpoint`) for them.
  bool use_viewpoint = true;
  /// One pose for every scan (`--pose`).
  std::optional<Eigen::Isometry3d> pose;
  /// Trajectory file (`--trajectory`): TUM or Redwood .log.
  std::string trajectory_path;
  /// Largest |stamp(file name) − stamp(pose)| accepted when matching by timestamp, seconds.
  double max_time_diff_s = 0.02;
};

/// A scan to be read: its file and, when known before reading, its pose prior.
struct ScanSource {
  std::string path;
  std::optional<Eigen::Isometry3d> T_world_sensor;  ///< empty: VIEWPOINT or identity
  PoseSource pose_source = PoseSource::Identity;
};

/// How the trajectory's poses were matched to the scan files.
enum class PoseMatch { None, ByOrder, ByTimestamp, ByFrameId };
const char* to_string(PoseMatch match);

struct ScanPlan {
  std::vector<ScanSource> scans;
  PoseMatch match = PoseMatch::None;
  std::vector<std::string> warnings;
};

/// Assigns pose priors to `paths` without reading the scans. A trajectory is matched
///  - by frame id when it is a Redwood .log and every file stem is an integer;
///  - by timestamp when it has stamps and every file stem is a number (TUM names);
///  - otherwise by order, which needs at least as many poses as scans.
/// Throws Error when a scan gets no pose (too few poses, no stamp within max_time_diff_s).
ScanPlan plan_scans(const std::vector<std::string>& paths, const LoadConfig& config);

/// Reads one scan (PCD, PLY or depth image) into the sensor frame with its pose prior.
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

}  // namespace fvx::scan
