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

std::optional<io::Intrinsics> parse_intrinsics(const Args& args, const std::string& command) {
  const bool any_flag = args.has("fx") || args.has("fy") || args.has("cx") || args.has("cy") ||
                        args.has("depth-scale") || args.has("width") || args.has("height");
  if (!args.has("intrinsics") && !any_flag) return std::nullopt;
  const double big = 1e6;
  io::Intrinsics K = args.has("intrinsics") ? io::read_intrinsics(args.get("intrinsics")) : io::Intrinsics{};
  K.fx = args.number("fx", K.fx, -big, big);
  K.fy = args.number("fy", K.fy, -big, big);
  K.cx = args.number("cx", K.cx, -big, big);
  K.cy = args.number("cy", K.cy, -big, big);
  K.depth_scale = args.number("depth-scale", K.depth_scale, 0.0, big, true);
  K.width = int(args.integer("width", K.width, 1, 16384));
  K.height = int(args.integer("height", K.height, 1, 16384));
  for (const auto& problem : K.validate()) throw UsageError("fvx " + command + ": intrinsics: " + problem);
  return K;
}

Json intrinsics_json(const io::Intrinsics& K) {
  return {{"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy},
          {"depth_scale", K.depth_scale}, {"width", K.width}, {"height", K.height}};
}

}  // namespace fvx::cli
