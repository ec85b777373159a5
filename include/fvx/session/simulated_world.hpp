#pragma once
/// \file
/// The world of `fvx explore`: a scene mesh, a virtual Kinect in it, and the ground truth
/// each view is judged against (how much of the observable empty space is known, whether
/// the target was seen, void cells that are really solid).
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "fvx/session/rows.hpp"
#include "fvx/session/session.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/exploration_score.hpp"
#include "fvx/sim/ray_caster.hpp"

namespace fvx::session {

/// A first view that works in this scene: the arm takes it (start_configuration with `seed`:
/// the capability map's bit and, with the URDF, IK), and both the pose and the one the arm
/// really reaches (FK of the IK solution) have their eye outside every solid, no surface
/// within `clearance_m` of it (the search's own clearance), and at least one ray of a
/// 20 × 15 fan that measures a surface inside the search space `S` (the Kinect's rule: the
/// first hit, at a depth within `camera`'s limits).
bool usable_start(const sim::RayCaster& caster, const Eigen::Isometry3d& T_world_sensor,
                  const std::optional<nbv::Reach>& reach, const io::DepthCamera& camera,
                  const Eigen::AlignedBox3d& S, double clearance_m, std::uint64_t seed);

class SimulatedWorld {
 public:
  /// Ground truth at `resolution_m` around the search space `S` and over every place the
  /// sensor can be (the start and, with `reach`, the capability map's voxels): rays of the
  /// observability check start there. With `reach`, "observable" is what some pose of the
  /// capability map would reveal, by the Kinect's rule with `camera`'s depths. The start is
  /// `T_world_sensor_start`, or without it the first of start_candidates (looking at
  /// `target`, the base at `T_world_base`) that is a usable_start (with `clearance_m`). `scene` must outlive the
  /// world. Error when the start pose is inside an obstacle or the arm cannot take it
  /// (start_configuration with `seed`), or no candidate is usable. `progress` names each
  /// long stage.
  SimulatedWorld(const sim::Scene& scene, double resolution_m, const Eigen::AlignedBox3d& S,
                 const std::optional<Eigen::Isometry3d>& T_world_sensor_start, const Eigen::Isometry3d& T_world_base,
                 const Eigen::Vector3d& target, const std::optional<nbv::Reach>& reach, const io::DepthCamera& camera,
                 double clearance_m, std::uint64_t seed, unsigned threads,
                 const std::function<void(const std::string&)>& progress);

  /// The first view's pose, as asked or as chosen.
  const Eigen::Isometry3d& start() const { return start_; }

  /// The virtual Kinect: a frame rendered at the true pose with `render` (seeded by the view).
  Sensor kinect(const sim::SensorConfig& render) const;
  /// A view's table row with its ground-truth columns (revealed comes with the next view).
  ViewRow row_of(const ViewRecord& v, const map::OccupancyMap& map) const;
  const sim::ExplorationScore& score() const { return *score_; }
  const sim::GroundTruth& ground_truth() const { return *gt_; }

 private:
  Eigen::AlignedBox3d S_;
  std::unique_ptr<sim::RayCaster> caster_;
  Eigen::Isometry3d start_;
  std::unique_ptr<sim::GroundTruth> gt_;
  std::unique_ptr<sim::ExplorationScore> score_;
};

}  // namespace fvx::session
