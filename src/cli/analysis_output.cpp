#include "analysis_output.hpp"

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"

namespace fvx::cli {
std::optional<Eigen::AlignedBox3d> parse_bounds(const Args& args, const std::string& name) {
  if (!args.has(name)) return std::nullopt;
  const auto b = parse_double_list(args.get(name), "--" + name + " (x0,y0,z0,x1,y1,z1)", 6);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(b[0], b[1], b[2]), Eigen::Vector3d(b[3], b[4], b[5]));
  if (!(box.min().array() < box.max().array()).all())
    throw UsageError("--" + name + ": the minimum must be below the maximum on every axis");
  return box;
}

}  // namespace fvx::cli
