#include "fvx/utility/utility.hpp"

#include <algorithm>
#include <cmath>

#include "fvx/core/error.hpp"

namespace fvx::utility {

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems;
  if (!(sensor_range_m > 0.0) || !std::isfinite(sensor_range_m)) problems.push_back("sensor_range_m must be > 0 m");
  return problems;
}

Field accumulate(const map::DenseGrid& grid, const frontier_voids::Analysis& a, const Config& config) {
  FVX_ASSERT(config.validate().empty(), "invalid utility::Config");
  Field field;
  field.util_m3.assign(grid.cell_count(), 0.0);
  for (const auto& fv : a.frontier_voids) {
    if (fv.enclosed()) continue;
    const auto corners = a.void_clusters[std::size_t(fv.void_id)].corners();
    const double u = fv.utility_m3;
    for (const int id : fv.frontier_ids) {
      for (const map::VoxelKey& f : a.frontier_clusters[std::size_t(id)].cells) {
        if (!grid.contains(f)) continue;
        const Eigen::Vector3d start = grid.center_of(f);
        for (const Eigen::Vector3d& c : corners) {
          const Eigen::Vector3d dir = start - c;
          if (dir.norm() < 1e-9) continue;  // a corner in the frontier cell: no direction
          ++field.vectors;
          grid.walk(start, dir, config.sensor_range_m, [&](std::size_t index, map::VoxelState s) {
            if (s != map::VoxelState::Free) return false;
            field.util_m3[index] += u;
            return true;
          });
        }
      }
    }
  }
  for (const double v : field.util_m3) {
    field.cells += v > 0.0;
    field.max_m3 = std::max(field.max_m3, v);
  }
  return field;
}

}  // namespace fvx::utility
