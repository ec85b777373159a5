#pragma once
// Scans a simulated scene into a map: the virtual Kinect renders each pose (no noise), the
// points go into the map with the exact pose. For tests that need a map with known truth.
#include <vector>

#include "fvx/map/occupancy_map.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/scene.hpp"

namespace fvx::test {

inline void integrate_views(map::OccupancyMap& map, const sim::Scene& scene,
                            const std::vector<Eigen::Isometry3d>& T_world_sensor) {
  const auto caster = sim::make_ray_caster(scene.mesh);
  for (const Eigen::Isometry3d& T : T_world_sensor) {
    const sim::Frame frame = sim::render(*caster, T, sim::SensorConfig{});
    std::vector<Eigen::Vector3f> points;
    for (const auto& p : frame.points_sensor)
      if (p.allFinite()) points.push_back((T * p.cast<double>()).cast<float>());
    map.integrate(points, T.translation().cast<float>());
  }
}

}  // namespace fvx::test
