#pragma once
// The builtin crates scene explored free-flying with a coarse ray fan, for tests of the
// session layer. Needs fvx_session and fvx_sim.
#include "fvx/session/session.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::test {

/// The virtual Kinect on `caster`, a frame per view seeded by the view.
inline session::Sensor kinect_on(const sim::RayCaster& caster) {
  return [&caster](const Eigen::Isometry3d& T, int view) {
    const sim::Frame f = sim::render(caster, T, sim::SensorConfig{}, std::uint64_t(view));
    std::vector<Eigen::Vector3d> points;
    for (const auto& p : f.points_sensor) points.push_back(p.cast<double>());
    return points;
  };
}

/// `max_views` views of the crates scene, starting above its base, 40 × 30 rays.
inline session::ExploreConfig crates_explore(const sim::Scene& scene, int max_views) {
  session::ExploreConfig config;
  config.pipeline.bounds_m = scene.info.search_space;
  config.pipeline.nbv.ray_cols = 40;
  config.pipeline.nbv.ray_rows = 30;
  config.max_views = max_views;
  const Eigen::Vector3d eye(0.05, 0.0, 0.95), target = scene.info.search_space->center();
  config.T_world_sensor_start.translation() = eye;
  config.T_world_sensor_start.linear() = viewpoints::look_along(target - eye, 0.0);
  return config;
}

}  // namespace fvx::test
