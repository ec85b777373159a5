#pragma once
/// \file
/// Stage `scan` (paper §IV step 1): one recorded scan — points in the sensor frame and the
/// prior `T_world_sensor` — and its preprocessing: NaN removal, depth limits, optional voxel
/// downsampling.
#include "fvx/core/json.hpp"
#include <Eigen/Geometry>
#include <limits>
#include <string>
#include <vector>

#include "fvx/io/depth_image.hpp"
#include "fvx/io/intrinsics.hpp"

namespace fvx::scan {

/// Where a scan's pose prior came from.
enum class PoseSource { Viewpoint, Trajectory, Flag, Identity, Tf };
const char* to_string(PoseSource source);

struct Scan {
  std::string source;                          ///< file the scan was read from
  std::vector<Eigen::Vector3d> points_sensor;  ///< metres, sensor (optical) frame
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();  ///< pose prior
  PoseSource pose_source = PoseSource::Identity;
};

/// Preprocessing, applied in the order of the fields.
struct FilterConfig {
  /// Points closer than this along the optical axis (z, metres) are dropped. Default 0.
  double depth_min_m = 0.0;
  /// Points at or beyond this depth (z, metres) are dropped. Default: no limit.
  /// (slambook's recipe drops d >= 7 m, hence "at or beyond".)
  double depth_max_m = std::numeric_limits<double>::infinity();
  /// Edge of the downsampling voxel, metres; each occupied voxel keeps the centroid of its
  /// points. 0 (default) keeps every point.
  double voxel_m = 0.0;

  std::vector<std::string> validate() const;
};

/// The effective filter as a report echoes it (no depth limit: null).
Json config_json(const FilterConfig& c);

/// What filter() removed.
struct FilterStats {
  std::size_t input = 0;        ///< points before filtering
  std::size_t non_finite = 0;   ///< NaN or infinite points removed
  std::size_t out_of_depth = 0; ///< outside [depth_min_m, depth_max_m)
  std::size_t merged = 0;       ///< removed by voxel downsampling
  std::size_t kept = 0;         ///< points after filtering
};

/// Filters `scan.points_sensor` in place. Order of the surviving points is kept (downsampling
/// emits voxels in order of their first point), so results are deterministic.
FilterStats filter(Scan& scan, const FilterConfig& config);

/// Centroid of the points in each voxel of edge `voxel_m`, in order of first appearance.
std::vector<Eigen::Vector3d> voxel_downsample(const std::vector<Eigen::Vector3d>& points,
                                              double voxel_m);

/// Back-projects a depth image, pixel (u, v) with raw value d to
/// z = d / depth_scale, x = (u − cx)·z / fx, y = (v − cy)·z / fy. The result is organised
/// (index = v·width + u); pixels with d = 0 become NaN. Computed in double, as the reference
/// tools do, so maps built from the same files agree bit for bit.
std::vector<Eigen::Vector3d> backproject(const io::DepthImage& depth, const io::Intrinsics& K);

/// `T_world_sensor * p` for every point, rounded to float (the map's precision).
std::vector<Eigen::Vector3f> to_world(const Scan& scan);

}  // namespace fvx::scan
