#pragma once
/// \file
/// A virtual depth camera (Kinect v1 by default): renders the depth image and the organised
/// cloud a real sensor would record from a pose, by casting one ray per pixel.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "fvx/io/depth_image.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/sim/ray_caster.hpp"

namespace fvx::sim {

struct SensorConfig {
  io::Intrinsics intrinsics;      ///< default Kinect v1: 640×480, f = 525, c = (319.5, 239.5)
  double depth_min_m = 0.5;       ///< nearer surfaces give no measurement (z, metres)
  double depth_max_m = 4.0;       ///< farther surfaces give no measurement (z, metres)
  /// Gaussian depth noise σ = noise_m_per_m2 · z² (Kinect v1: about 1.4 mm at 1 m,
  /// Khoshelham & Elberink 2012). 0 (default): exact depth.
  double noise_m_per_m2 = 0.0;
  /// Round depth to the Kinect v1's 1/8-pixel disparity steps: d = fx·b/z,
  /// z' = fx·b / (round(8d)/8). Off by default.
  bool quantize_disparity = false;
  double baseline_m = 0.075;      ///< projector–camera baseline for quantisation, metres
  /// Surfaces seen at more than this angle from their normal give no measurement, degrees.
  /// 90 (default): none dropped.
  double dropout_incidence_deg = 90.0;
  /// > depth_max_m: a ray that meets no surface within depth_max_m is reported as the point
  /// at this depth (not in the depth image), as a laser reports a max-range return, so that
  /// integration clears the ray up to its range. 0 (default): NaN, no measurement, as a
  /// Kinect gives.
  double no_return_depth_m = 0.0;
  std::uint64_t seed = 1;         ///< noise seed; each frame mixes in its index
  unsigned threads = 0;           ///< 0: all cores

  std::vector<std::string> validate() const;
  /// The virtual twin of `camera` (its intrinsics and depth range), seeded, noiseless.
  static SensorConfig of(const io::DepthCamera& camera, std::uint64_t seed, unsigned threads);
};

struct Frame {
  /// Raw depth, intrinsics.depth_scale units per metre, 0 = no measurement.
  io::DepthImage depth;
  /// Organised cloud, sensor optical frame, metres; NaN where there is no measurement.
  std::vector<Eigen::Vector3f> points_sensor;
  std::size_t valid = 0;          ///< pixels with a measurement
  std::size_t no_surface = 0;     ///< rays that hit nothing within depth_max_m
  std::size_t too_near = 0;       ///< hits nearer than depth_min_m
  std::size_t grazing = 0;        ///< dropped for their incidence angle
};

/// Renders the frame seen from `T_world_sensor`. The pixel ray is ((u−cx)/fx, (v−cy)/fy, 1)
/// in the optical frame, so the hit distance along it is the depth z. Noise is a function of
/// (seed, frame_index, pixel) only: the same inputs give the same frame on any number of
/// threads.
Frame render(const RayCaster& caster, const Eigen::Isometry3d& T_world_sensor,
             const SensorConfig& config, std::uint64_t frame_index = 0);

}  // namespace fvx::sim
