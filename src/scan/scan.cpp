#include "fvx/scan/scan.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "fvx/core/error.hpp"

namespace fvx::scan {

const char* to_string(PoseSource source) {
  switch (source) {
    case PoseSource::Viewpoint: return "viewpoint";
    case PoseSource::Trajectory: return "trajectory";
    case PoseSource::Flag: return "flag";
    case PoseSource::Identity: return "identity";
    case PoseSource::Tf: return "tf";
  }
  return "?";
}

std::vector<std::string> FilterConfig::validate() const {
  std::vector<std::string> problems;
  if (!(depth_min_m >= 0.0)) problems.push_back("depth_min_m must be >= 0 m");
  if (!(depth_max_m > depth_min_m)) problems.push_back("depth_max_m must be > depth_min_m");
  if (!(voxel_m >= 0.0) || !std::isfinite(voxel_m)) problems.push_back("voxel_m must be >= 0 m");
  return problems;
}

std::vector<Eigen::Vector3d> voxel_downsample(const std::vector<Eigen::Vector3d>& points,
                                              double voxel_m) {
  FVX_ASSERT(voxel_m > 0.0, "voxel edge " + std::to_string(voxel_m));
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::size_t count = 0;
  };
  auto hash = [](const Eigen::Vector3i& k) {
    return std::size_t(k.x()) * 73856093u ^ std::size_t(k.y()) * 19349663u ^ std::size_t(k.z()) * 83492791u;
  };
  auto equal = [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) { return a == b; };
  std::unordered_map<Eigen::Vector3i, std::size_t, decltype(hash), decltype(equal)> index(
      points.size() / 4 + 1, hash, equal);
  std::vector<Cell> cells;
  for (const auto& p : points) {
    const Eigen::Vector3i key = (p / voxel_m).array().floor().cast<int>();
    const auto [it, inserted] = index.try_emplace(key, cells.size());
    if (inserted) cells.emplace_back();
    cells[it->second].sum += p;
    cells[it->second].count += 1;
  }
  std::vector<Eigen::Vector3d> centroids;
  centroids.reserve(cells.size());
  for (const Cell& c : cells) centroids.push_back(c.sum / double(c.count));
  return centroids;
}

FilterStats filter(Scan& scan, const FilterConfig& config) {
  throw_if_problems("filter", config.validate());
  FilterStats stats;
  stats.input = scan.points_sensor.size();
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(scan.points_sensor.size());
  for (const auto& p : scan.points_sensor) {
    if (!p.allFinite()) {
      ++stats.non_finite;
    } else if (p.z() < config.depth_min_m || p.z() >= config.depth_max_m) {
      ++stats.out_of_depth;
    } else {
      kept.push_back(p);
    }
  }
  if (config.voxel_m > 0.0) {
    const std::size_t before = kept.size();
    kept = voxel_downsample(kept, config.voxel_m);
    stats.merged = before - kept.size();
  }
  stats.kept = kept.size();
  scan.points_sensor = std::move(kept);
  return stats;
}

std::vector<Eigen::Vector3d> backproject(const io::DepthImage& depth, const io::Intrinsics& K) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Eigen::Vector3d> points(depth.raw.size(), Eigen::Vector3d(nan, nan, nan));
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const std::uint16_t d = depth.at(v, u);
      // 0 is no measurement; so is the saturated 65535 (65.5 m at 1 mm units, beyond any depth
      // camera): an image of it cast 300 000 rays of 65 m for two minutes.
      if (d == 0 || d == io::kDepthSaturated) continue;
      const double z = double(d) / K.depth_scale;
      points[std::size_t(v) * depth.width + u] = {(u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z};
    }
  }
  return points;
}

std::vector<Eigen::Vector3f> to_world(const Scan& scan) {
  std::vector<Eigen::Vector3f> world;
  world.reserve(scan.points_sensor.size());
  for (const auto& p : scan.points_sensor) world.push_back((scan.T_world_sensor * p).cast<float>());
  return world;
}

}  // namespace fvx::scan

namespace fvx::scan {

Json config_json(const FilterConfig& c) {
  return {{"depth_min_m", c.depth_min_m}, {"depth_max_m", finite_or_null(c.depth_max_m)}, {"voxel_m", c.voxel_m}};
}

}  // namespace fvx::scan
