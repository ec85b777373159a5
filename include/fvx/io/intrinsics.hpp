#pragma once
/// \file
/// Pinhole intrinsics of a depth camera and the scale of its raw depth values.
#include "fvx/core/json.hpp"
#include <string>
#include <vector>

namespace fvx::io {

/// The limits of a camera model, the same on the command line (camera_options) and in files
/// (validate): image sides, |fx|, |fy|, |cx|, |cy| and depth_scale, and the farthest depth.
inline constexpr int kMaxImageSidePx = 16384;
inline constexpr double kMaxPixels = 1e6;
inline constexpr double kMaxDepthM = 1000.0;

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
  /// Whether a file or --width/--height stated the size (else it is the default): a depth
  /// image of another size is then refused, since cx, cy and the image disagree.
  bool size_stated = false;

  /// Every violation, one line each; empty when valid.
  std::vector<std::string> validate() const;
};

/// Reads intrinsics from JSON or a text matrix. The layouts accepted:
///  - fvx: {"fx":…, "fy":…, "cx":…, "cy":…, "depth_scale":…, "width":…, "height":…}
///    (depth_scale, width, height optional);
///  - Open3D PinholeCameraIntrinsic: {"width":…, "height":…, "intrinsic_matrix":[9 numbers,
///    column-major]};
///  - a text file of a 3x3 K (3DMatch / 7-Scenes camera-intrinsics.txt) or a 4x4 with K top
///    left (ScanNet intrinsic_depth.txt), row-major, no skew; the size is then not stated.
/// Unknown keys are refused (a typo must not silently fall back to a default).
/// Throws FileError naming the file and the problem.
Intrinsics read_intrinsics(const std::string& path);

/// A depth camera for planning and simulation: its pinhole model and the depths it measures.
struct DepthCamera {
  Intrinsics intrinsics;       ///< default Kinect v1
  double depth_min_m = 0.5;    ///< nearer surfaces give no measurement (z, metres)
  double depth_max_m = 4.0;    ///< farther surfaces give no measurement (z, metres); s_r

  std::vector<std::string> validate() const;
};

/// Reads a sensor file: the fvx intrinsics layout plus optional "depth_min_m" and
/// "depth_max_m", e.g. {"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "width": 640,
/// "height": 480, "depth_min_m": 0.5, "depth_max_m": 4.0}. Unknown keys are refused.
/// Throws FileError naming the file and the problem.
DepthCamera read_depth_camera(const std::string& path);

/// The report form: {"fx", "fy", "cx", "cy", "depth_scale", "width", "height"}.
Json intrinsics_json(const Intrinsics& K);
/// {"intrinsics": intrinsics_json, "depth_min_m", "depth_max_m"}.
Json camera_json(const DepthCamera& camera);

}  // namespace fvx::io
