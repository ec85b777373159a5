#pragma once
/// \file
/// `fvx simulate` as a library call: the frames a Kinect would record at given poses,
/// written as a recording that `fvx integrate` and `fvx replay` read back.
#include <functional>
#include <string>
#include <vector>

#include <optional>

#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/scene.hpp"

namespace fvx::sim {

enum class FrameFormat { Pcd, DepthPng };

/// One written frame; the pixel counts as Frame has them.
struct RecordedFrame {
  std::string file;
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  std::size_t valid = 0, no_surface = 0, too_near = 0, grazing = 0;
};

/// Renders each pose with `sensor` (frame i seeded by i) and writes it: to `output` itself
/// (one pose, `to_folder` false), or into the folder `output` (created) as NNNNNN.pcd or
/// NNNNNN.png, with trajectory.txt (TUM, stamp i for frame i, so that integrate matches
/// files by stamp) and, for PNGs, intrinsics.json. A PCD carries its pose as VIEWPOINT.
/// Warns of a sensor inside a solid and of a frame without measurement. `progress(i)` before
/// frame i.
std::vector<RecordedFrame> record_frames(const RayCaster& caster, const std::vector<Eigen::Isometry3d>& poses,
                                         const SensorConfig& sensor, const std::string& output, bool to_folder,
                                         FrameFormat format, std::vector<std::string>& warnings,
                                         const std::function<void(std::size_t)>& progress);

/// A TUM trajectory (stamp tx ty tz qx qy qz qw) with stamp i for pose i, written atomically.
void write_tum_trajectory(const std::string& path, const std::vector<Eigen::Isometry3d>& poses);

/// The region a scene's ground truth covers: `bounds` if given, else the scene's search
/// space, else the mesh's bounds.
Eigen::AlignedBox3d ground_truth_region(const Scene& scene, const std::optional<Eigen::AlignedBox3d>& bounds);

}  // namespace fvx::sim
