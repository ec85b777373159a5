#include "fvx/session/simulated_world.hpp"

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/session/start.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::session {

namespace {

/// Every place the sensor can be: the start and, with an arm, its capability map's voxels.
std::vector<Eigen::Vector3d> sensor_positions(const Eigen::Vector3d& start, const std::optional<nbv::Reach>& reach) {
  std::vector<Eigen::Vector3d> positions = {start};
  if (reach)
    for (const auto& entry : reach->capmap->voxels())
      positions.push_back(reach->T_world_base * reach->capmap->center_of(entry.first));
  return positions;
}

/// Observable = what the first view or some pose of the arm's capability map would reveal
/// (coarse rays: the union over thousands of poses fills their gaps; the target, whose cells
/// such a fan misses, by the rays through its image).
void restrict_to_arm(const nbv::Reach& reach, const Eigen::Isometry3d& T_start, const sim::GroundTruth& gt,
                     const sim::RayCaster& caster, const io::DepthCamera& camera, unsigned threads,
                     sim::ExplorationScore& score) {
  std::vector<Eigen::Isometry3d> poses = capmap_view_poses(reach, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3i cell = gt.cell_of(p);
    return gt.contains(cell) && gt.solid(cell);
  });
  poses.push_back(T_start);
  score.restrict_to_views(gt, poses, viewpoints::ray_fan(camera.intrinsics, 20, 15), camera.depth_min_m,
                          camera.depth_max_m, threads);
  score.restrict_target_to_views(caster, poses, camera.intrinsics, camera.depth_min_m, camera.depth_max_m,
                                 gt.resolution_m(), threads);
}

/// No surface within `clearance_m` of `eye` along any of the 26 grid directions (nor is the
/// eye inside a solid, from where the nearest faces are hit at once).
bool clear_around(const sim::RayCaster& caster, const Eigen::Vector3d& eye, double clearance_m) {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const Eigen::Vector3f d = Eigen::Vector3f(float(dx), float(dy), float(dz)).normalized();
        if (caster.cast(eye.cast<float>(), d, 0.0f, float(clearance_m)).hit()) return false;
      }
  return true;
}

}  // namespace

bool usable_start(const sim::RayCaster& caster, const Eigen::Isometry3d& T_world_sensor,
                  const std::optional<nbv::Reach>& reach, const io::DepthCamera& camera,
                  const Eigen::AlignedBox3d& S, double clearance_m, std::uint64_t seed) {
  Eigen::Isometry3d T_executed;  // where the arm really puts the sensor (FK of its IK solution)
  try {
    T_executed = start_configuration(reach, T_world_sensor, seed).first;
  } catch (const Error&) {
    return false;
  }
  for (const Eigen::Isometry3d& T : {T_world_sensor, T_executed}) {
    const Eigen::Vector3d eye = T.translation();
    if (sim::inside_solid(caster, eye.cast<float>()) || !clear_around(caster, eye, clearance_m)) return false;
    bool measures_S = false;
    for (const Eigen::Vector3d& ray : viewpoints::ray_fan(camera.intrinsics, 20, 15)) {  // depth 1 along z
      const Eigen::Vector3d d_world = T.linear() * ray;
      const sim::Hit hit = caster.cast(eye.cast<float>(), d_world.cast<float>(), 0.0f, float(camera.depth_max_m));
      measures_S = hit.hit() && hit.distance >= camera.depth_min_m && S.contains(eye + double(hit.distance) * d_world);
      if (measures_S) break;
    }
    if (!measures_S) return false;
  }
  return true;
}

SimulatedWorld::SimulatedWorld(const sim::Scene& scene, double resolution_m, const Eigen::AlignedBox3d& S,
                               const std::optional<Eigen::Isometry3d>& T_world_sensor_start,
                               const Eigen::Isometry3d& T_world_base, const Eigen::Vector3d& look_at,
                               const std::optional<nbv::Reach>& reach, const io::DepthCamera& camera,
                               double clearance_m, std::uint64_t seed, unsigned threads,
                               const std::function<void(const std::string&)>& progress)
    : S_(S), caster_(sim::make_ray_caster(scene.mesh)) {
  if (T_world_sensor_start) {
    start_ = *T_world_sensor_start;
  } else {
    progress("the first view");
    start_ = default_start(reach, T_world_base, S, look_at, [&](const Eigen::Isometry3d& T) {
      return usable_start(*caster_, T, reach, camera, S, clearance_m, seed);
    });
  }
  const Eigen::Vector3d eye = start_.translation();
  if (sim::inside_solid(*caster_, eye.cast<float>()))
    throw Error("fvx explore: the start pose " + point_text(eye) + " is inside an obstacle of the scene");
  const Eigen::Isometry3d T_start_reached = start_configuration(reach, start_, seed).first;  // Error when it cannot
  progress("ground truth of the search space");
  gt_ = std::make_unique<sim::GroundTruth>(scene.mesh, *caster_, resolution_m,
                                           sim::exploration_region(S, sensor_positions(eye, reach)));
  std::optional<Eigen::AlignedBox3d> target_box;
  if (scene.info.target) target_box = scene.info.target->box;
  score_ = std::make_unique<sim::ExplorationScore>(*gt_, S, target_box);
  if (reach) {
    progress("the space the arm can observe at all (ground truth)");
    restrict_to_arm(*reach, T_start_reached, *gt_, *caster_, camera, threads, *score_);
  }
}

Sensor SimulatedWorld::kinect(const sim::SensorConfig& render) const {
  return [caster = caster_.get(), render](const Eigen::Isometry3d& T_world_sensor, int view) {
    const sim::Frame frame = sim::render(*caster, T_world_sensor, render, std::uint64_t(view));
    std::vector<Eigen::Vector3d> points;
    points.reserve(frame.points_sensor.size());
    for (const auto& p : frame.points_sensor) points.push_back(p.cast<double>());
    return points;
  };
}

ViewRow SimulatedWorld::row_of(const ViewRecord& v, const map::OccupancyMap& map) const {
  ViewRow row = session::row_of(v, map, S_);
  TruthColumns truth;
  truth.known_fraction = score_->known_fraction(map);
  truth.void_known_fraction = score_->void_known_fraction(map);
  truth.target_cells = score_->target_cells_seen(map);
  truth.target_seen = truth.target_cells >= sim::ExplorationScore::kTargetCellsSeen;
  if (v.chosen) truth.u_in_solid = gt_->solid_among(v.step.nbv.views[*v.chosen].seen_void_cells);
  truth.free_in_solid = gt_->free_in_solid(map, S_);
  row.truth = truth;
  return row;
}

}  // namespace fvx::session
