#include "common_options.hpp"

#include "fvx/core/error.hpp"

namespace fvx::cli {

std::vector<OptionSpec> options(std::initializer_list<std::vector<OptionSpec>> tables) {
  std::vector<OptionSpec> all;
  for (const auto& table : tables) all.insert(all.end(), table.begin(), table.end());
  return all;
}

std::vector<OptionSpec> intrinsics_options(bool with_size) {
  std::vector<OptionSpec> table = {
      {"intrinsics", 'K', "FILE", "depth camera intrinsics JSON (fvx or Open3D layout)"},
      {"fx", 0, "PX", "focal length along u, pixels (overrides --intrinsics; default 525)"},
      {"fy", 0, "PX", "focal length along v, pixels; may be negative (default 525)"},
      {"cx", 0, "PX", "principal point u, pixels (default 319.5)"},
      {"cy", 0, "PX", "principal point v, pixels (default 239.5)"},
      {"depth-scale", 0, "N", "raw depth units per metre: 1000 (mm) or 5000 (TUM) (default 1000)"},
  };
  if (with_size) {
    table.push_back({"width", 0, "PX", "image width, pixels (default 640)"});
    table.push_back({"height", 0, "PX", "image height, pixels (default 480)"});
  }
  return table;
}

namespace {

/// --fx … --height over `K`.
io::Intrinsics apply_intrinsics_flags(const Args& args, io::Intrinsics K) {
  const double big = 1e6;
  K.fx = args.number("fx", K.fx, -big, big);
  K.fy = args.number("fy", K.fy, -big, big);
  K.cx = args.number("cx", K.cx, -big, big);
  K.cy = args.number("cy", K.cy, -big, big);
  K.depth_scale = args.number("depth-scale", K.depth_scale, 0.0, big, true);
  K.width = int(args.integer("width", K.width, 1, 16384));
  K.height = int(args.integer("height", K.height, 1, 16384));
  return K;
}

}  // namespace

std::optional<io::Intrinsics> parse_intrinsics(const Args& args, const std::string& command) {
  const bool any_flag = args.has("fx") || args.has("fy") || args.has("cx") || args.has("cy") ||
                        args.has("depth-scale") || args.has("width") || args.has("height");
  if (!args.has("intrinsics") && !any_flag) return std::nullopt;
  const io::Intrinsics K = apply_intrinsics_flags(
      args, args.has("intrinsics") ? io::read_intrinsics(args.get("intrinsics")) : io::Intrinsics{});
  for (const auto& problem : K.validate()) throw UsageError("fvx " + command + ": intrinsics: " + problem);
  return K;
}

Json intrinsics_json(const io::Intrinsics& K) {
  return {{"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy},
          {"depth_scale", K.depth_scale}, {"width", K.width}, {"height", K.height}};
}

std::vector<OptionSpec> depth_camera_options() {
  return options({{{"sensor", 0, "FILE", "sensor JSON: intrinsics, width, height, depth_min_m, depth_max_m "
                                         "(default Kinect v1: 640x480, f 525, 0.5-4 m)"},
                   {"depth-min", 0, "M", "nearest measured depth, metres (overrides --sensor; default 0.5)"},
                   {"depth-max", 0, "M", "farthest measured depth = sensor range s_r, metres (default 4)"}},
                  intrinsics_options(true)});
}

io::DepthCamera parse_depth_camera(const Args& args, const std::string& command) {
  io::DepthCamera camera = args.has("sensor") ? io::read_depth_camera(args.get("sensor")) : io::DepthCamera{};
  if (args.has("intrinsics")) camera.intrinsics = io::read_intrinsics(args.get("intrinsics"));
  camera.intrinsics = apply_intrinsics_flags(args, camera.intrinsics);
  camera.depth_min_m = args.number("depth-min", camera.depth_min_m, 0.0, 1e3);
  camera.depth_max_m = args.number("depth-max", camera.depth_max_m, 0.0, 1e3, true);
  for (const auto& problem : camera.validate()) throw UsageError("fvx " + command + ": sensor: " + problem);
  return camera;
}

Json depth_camera_json(const io::DepthCamera& camera) {
  return {{"intrinsics", intrinsics_json(camera.intrinsics)},
          {"depth_min_m", camera.depth_min_m},
          {"depth_max_m", camera.depth_max_m}};
}

}  // namespace fvx::cli
