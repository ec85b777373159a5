#pragma once
/// \file
/// What `fvx capmap` shows of a capability map: its header, its reachability (the share of
/// directions reached per voxel), a point query, and the map as a coloured cloud.
#include <optional>
#include <string>

#include "fvx/capmap/build.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/capmap/evaluate.hpp"
#include "fvx/core/json.hpp"

namespace fvx::report {

Json capmap_header_json(const capmap::CapabilityHeader& h);
/// Header, voxels, bits set, and a histogram of the reachability index in 10 % bins.
Json capmap_info_json(const capmap::CapabilityMap& map);
/// fvx capmap eval's results: the bit definition, precision and recall with their 95 %
/// intervals, and recall per height band (the bands FK poses fell in).
Json capmap_evaluation_json(const capmap::Evaluation& e, const std::string& method);
/// At `point_m`: inside the grid, the reachability index, the directions reached, and with
/// `direction` (unit) whether it is reached.
Json capmap_query_json(const capmap::CapabilityMap& map, const Eigen::Vector3d& point_m,
                       const std::optional<Eigen::Vector3d>& direction);
/// fvx capmap build's settings, and its results: header, voxels, bits, the work done
/// (candidates and IK iterations, or configurations and forward kinematics), seconds.
Json capmap_build_config_json(const capmap::BuildConfig& c);
Json capmap_build_json(const capmap::CapabilityMap& map, const capmap::BuildStats& stats, double seconds);
/// The line the arm's first joint turns about (base frame): joint, point, direction, tilt from
/// the vertical and limits in degrees; null when that joint is not revolute.
Json capmap_first_joint_axis_json(const capmap::Arm& arm);
/// Each voxel's centre coloured by its reachability index, blue (low) to red (high), .ply or
/// .pcd; returns the number of points.
std::size_t write_capmap_cloud(const std::string& path, const capmap::CapabilityMap& map);

}  // namespace fvx::report
