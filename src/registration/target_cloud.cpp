#include "fvx/registration/target_cloud.hpp"

#include <cmath>
#include <limits>

#include "fvx/core/error.hpp"

namespace fvx::registration {

TargetCloud::TargetCloud(double cell_m) : cell_m_(cell_m) {
  FVX_ASSERT(cell_m >= 0.0 && std::isfinite(cell_m), "TargetCloud cell " + std::to_string(cell_m));
}

void TargetCloud::add_point(const Eigen::Vector3d& p_world) {
  if (!p_world.allFinite()) return;
  if (cell_m_ <= 0.0) {
    means_.push_back(p_world.cast<float>());
    return;
  }
  const Eigen::Vector3d scaled = (p_world / cell_m_).array().floor();
  // Beyond ±2^31 cells (±50 000 km at 2.5 cm) a point is no surface a sensor saw.
  if ((scaled.array().abs() >= double(std::numeric_limits<int>::max())).any()) return;
  const auto [it, inserted] = cells_.try_emplace(scaled.cast<int>(), std::uint32_t(means_.size()));
  if (inserted) {
    sums_.push_back(p_world);
    counts_.push_back(1);
    means_.push_back(p_world.cast<float>());
    return;
  }
  const std::uint32_t i = it->second;
  sums_[i] += p_world;
  ++counts_[i];
  means_[i] = (sums_[i] / double(counts_[i])).cast<float>();
}

void TargetCloud::add(const Eigen::Isometry3d& T_world_sensor, const std::vector<Eigen::Vector3d>& points_sensor) {
  for (const Eigen::Vector3d& p : points_sensor) add_point(T_world_sensor * p);
}

void TargetCloud::add(const std::vector<Eigen::Vector3f>& points_world) {
  for (const Eigen::Vector3f& p : points_world) add_point(p.cast<double>());
}

}  // namespace fvx::registration
