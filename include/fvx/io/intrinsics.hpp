#pragma once
/// \file
/// Pinhole intrinsics of a depth camera and the scale of its raw depth values.
#include <string>
#include <vector>

namespace fvx::io {

/// Pinhole model in pixels: u = fx·x/z + cx, v = fy·y/z + cy (optical frame: z forward,
/// x right, y down). A negative focal length (ICL-NUIM's fy = −480) flips that axis and is
/// used as given.
struct Intrinsics {
  double fx = 525.0;             ///< focal length along u, pixels; Kinect v1 default
  double fy = 525.0;             ///< focal length along v, pixels
  double cx = 319.5;             ///< principal point, pixels
  double cy = 239.5;             ///< principal point, pixels
  double depth_scale = 1000.0;   ///< raw depth units per metre: 1000 (mm), 5000 (TUM)
  int width = 640;               ///< image width, pixels
  int height = 480;              ///< image height, pixels

  /// Every violation, one line each; empty when valid.
  std::vector<std::string> validate() const;
};

/// Reads intrinsics from JSON. Two layouts are accepted:
///  - fvx: {"fx":…, "fy":…, "cx":…, "cy":…, "depth_scale":…, "width":…, "height":…}
///    (depth_scale, width, height optional);
///  - Open3D PinholeCameraIntrinsic: {"width":…, "height":…, "intrinsic_matrix":[9 numbers,
///    column-major]}.
/// Unknown keys are refused (a typo must not silently fall back to a default).
/// Throws FileError naming the file and the problem.
Intrinsics read_intrinsics(const std::string& path);

}  // namespace fvx::io
