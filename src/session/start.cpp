#include "fvx/session/start.hpp"

#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::session {

namespace {

Eigen::Isometry3d looking(const Eigen::Vector3d& eye, const Eigen::Vector3d& direction) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = eye;
  T.linear() = viewpoints::look_along(direction, 0.0);
  return T;
}

}  // namespace

Eigen::Isometry3d default_start(const std::optional<nbv::Reach>& reach, const Eigen::Isometry3d& T_world_base,
                                const Eigen::AlignedBox3d& S, const Eigen::Vector3d& target) {
  if (!reach) {
    const Eigen::Vector3d eye = T_world_base * Eigen::Vector3d(-0.15, 0.0, 0.95);
    return looking(eye, target - eye);
  }
  const capmap::CapabilityMap& cm = *reach->capmap;
  const double aimed = std::cos(10.0 * M_PI / 180.0);
  double best_cos = -2.0, best_far = -1.0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero(), dir = Eigen::Vector3d::UnitZ();
  for (const auto& [voxel, bits] : cm.voxels()) {
    const Eigen::Vector3d p = reach->T_world_base * cm.center_of(voxel);
    if (S.contains(p)) continue;
    const double distance = (target - p).norm();
    const Eigen::Vector3d want = (target - p) / distance;
    for (const int d : cm.reachable_directions(cm.center_of(voxel))) {
      const Eigen::Vector3d d_world = reach->T_world_base.linear() * cm.directions()[d];
      const double c = d_world.dot(want);
      // Aimed poses win by distance; until one is found, the best aim wins.
      const bool better = c >= aimed ? (best_cos < aimed || distance > best_far + 1e-9) : (best_cos < aimed && c > best_cos);
      if (better) {
        best_cos = c;
        best_far = distance;
        eye = p;
        dir = d_world;
      }
    }
  }
  if (best_cos < -1.0) throw Error("the capability map reaches no pose outside the search space; give --start");
  return looking(eye, dir);
}

std::vector<Eigen::Isometry3d> capmap_view_poses(const nbv::Reach& reach,
                                                 const std::function<bool(const Eigen::Vector3d&)>& blocked) {
  const capmap::CapabilityMap& cm = *reach.capmap;
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& [voxel, bits] : cm.voxels()) {
    const Eigen::Vector3d p = reach.T_world_base * cm.center_of(voxel);
    if (blocked(p)) continue;
    for (const int d : cm.reachable_directions(cm.center_of(voxel)))
      poses.push_back(looking(p, reach.T_world_base.linear() * cm.directions()[d]));
  }
  return poses;
}

}  // namespace fvx::session
