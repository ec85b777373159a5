#include "fvx/io/camera_options.hpp"

#include <utility>

#include "fvx/core/error.hpp"

namespace fvx::io {

namespace {
const Intrinsics kK;  ///< the defaults --help shows
}  // namespace

std::vector<OptionSpec> intrinsics_options(bool with_size, const std::string& echo) {
  std::vector<OptionSpec> table = {
      {"intrinsics", 'K', "FILE", "depth camera intrinsics JSON (fvx or Open3D layout)", echo},
      {"fx", 0, "PX", "focal length along u, pixels; overrides --intrinsics", echo + "/fx", dflt(kK.fx), in(-kMaxPixels, kMaxPixels)},
      {"fy", 0, "PX", "focal length along v, pixels; may be negative", echo + "/fy", dflt(kK.fy), in(-kMaxPixels, kMaxPixels)},
      {"cx", 0, "PX", "principal point u, pixels", echo + "/cx", dflt(kK.cx), in(-kMaxPixels, kMaxPixels)},
      {"cy", 0, "PX", "principal point v, pixels", echo + "/cy", dflt(kK.cy), in(-kMaxPixels, kMaxPixels)},
      {"depth-scale", 0, "N", "raw depth units per metre: 1000 (mm) or 5000 (TUM)", echo + "/depth_scale",
       dflt(kK.depth_scale), above(0, kMaxPixels)},
  };
  if (with_size) {
    table.push_back({"width", 0, "PX", "image width, pixels", echo + "/width", dflt(kK.width), in(1, kMaxImageSidePx)});
    table.push_back({"height", 0, "PX", "image height, pixels", echo + "/height", dflt(kK.height), in(1, kMaxImageSidePx)});
  }
  return table;
}

namespace {

/// --fx … --height over `K`.
Intrinsics apply_intrinsics_flags(const Args& args, Intrinsics K) {
  for (const auto& [name, field] : {std::pair{"fx", &K.fx}, {"fy", &K.fy}, {"cx", &K.cx}, {"cy", &K.cy},
                                    {"depth-scale", &K.depth_scale}})
    args.read(name, *field);
  if (args.has("width")) args.read("width", K.width);  // only commands that render have them
  if (args.has("height")) args.read("height", K.height);
  K.size_stated = K.size_stated || (args.has("width") && args.has("height"));
  return K;
}

}  // namespace

std::optional<Intrinsics> parse_intrinsics(const Args& args, const std::string& command) {
  const bool any_flag = args.has("fx") || args.has("fy") || args.has("cx") || args.has("cy") ||
                        args.has("depth-scale") || args.has("width") || args.has("height");
  if (!args.has("intrinsics") && !any_flag) return std::nullopt;
  const Intrinsics K = apply_intrinsics_flags(
      args, args.has("intrinsics") ? read_intrinsics(args.get("intrinsics")) : Intrinsics{});
  throw_if_problems("fvx " + command + ": intrinsics", K.validate());
  return K;
}

std::vector<OptionSpec> depth_camera_options(const std::string& echo) {
  return options({{{"sensor", 0, "FILE", "sensor JSON: intrinsics, width, height, depth_min_m, depth_max_m "
                                         "(default Kinect v1: 640x480, f 525, 0.5-4 m)", echo + "/sensor"},
                   {"depth-min", 0, "M", "nearest measured depth, metres; overrides --sensor",
                    echo + "/sensor/depth_min_m", dflt(DepthCamera{}.depth_min_m), in(0, kMaxDepthM)},
                   {"depth-max", 0, "M", "farthest measured depth = sensor range s_r, metres",
                    echo + "/sensor/depth_max_m", dflt(DepthCamera{}.depth_max_m), above(0, kMaxDepthM)}},
                  intrinsics_options(true, echo + "/sensor/intrinsics")});
}

DepthCamera parse_depth_camera(const Args& args, const std::string& command) {
  DepthCamera camera = args.has("sensor") ? read_depth_camera(args.get("sensor")) : DepthCamera{};
  if (args.has("intrinsics")) camera.intrinsics = read_intrinsics(args.get("intrinsics"));
  camera.intrinsics = apply_intrinsics_flags(args, camera.intrinsics);
  args.read("depth-min", camera.depth_min_m);
  args.read("depth-max", camera.depth_max_m);
  throw_if_problems("fvx " + command + ": sensor", camera.validate());
  return camera;
}

}  // namespace fvx::io
