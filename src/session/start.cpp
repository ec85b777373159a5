#include "fvx/session/start.hpp"

#include <algorithm>
#include <cmath>
#include <string>

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

std::vector<Eigen::Isometry3d> start_candidates(const std::optional<nbv::Reach>& reach,
                                                const Eigen::Isometry3d& T_world_base, const Eigen::AlignedBox3d& S,
                                                const Eigen::Vector3d& target) {
  if (!reach) {
    const Eigen::Vector3d eye = T_world_base * Eigen::Vector3d(-0.15, 0.0, 0.95);
    return {looking(eye, target - eye)};
  }
  struct Candidate {
    bool aimed;
    double rank;  // aimed: distance to the target; else: cosine of the aim
    Eigen::Isometry3d T;
  };
  const capmap::CapabilityMap& cm = *reach->capmap;
  const double aimed = std::cos(10.0 * M_PI / 180.0);
  std::vector<Candidate> candidates;
  for (const auto& [voxel, bits] : cm.voxels()) {
    const Eigen::Vector3d p = reach->T_world_base * cm.center_of(voxel);
    if (S.contains(p)) continue;
    const double distance = (target - p).norm();
    const Eigen::Vector3d want = (target - p) / distance;
    for (const int d : cm.reachable_directions(cm.center_of(voxel))) {
      const Eigen::Vector3d d_world = reach->T_world_base.linear() * cm.directions()[d];
      const double c = d_world.dot(want);
      candidates.push_back({c >= aimed, c >= aimed ? distance : c, looking(p, d_world)});
    }
  }
  if (candidates.empty()) throw Error("the capability map reaches no pose outside the search space; give --start");
  // Stable: among equals the map's own order decides, so the choice is the same on every run.
  std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.aimed != b.aimed) return a.aimed;
    return a.rank > b.rank;
  });
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(candidates.size());
  for (const Candidate& c : candidates) poses.push_back(c.T);
  return poses;
}

Eigen::Isometry3d default_start(const std::optional<nbv::Reach>& reach, const Eigen::Isometry3d& T_world_base,
                                const Eigen::AlignedBox3d& S, const Eigen::Vector3d& target,
                                const std::function<bool(const Eigen::Isometry3d&)>& usable) {
  const std::vector<Eigen::Isometry3d> candidates = start_candidates(reach, T_world_base, S, target);
  for (const Eigen::Isometry3d& T : candidates)
    if (!usable || usable(T)) return T;
  throw Error("none of the " + std::to_string(candidates.size()) +
              " first views tried (the arm takes it, it is in free space and it sees into the search space) "
              "works from this base; give --start or move --base");
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
