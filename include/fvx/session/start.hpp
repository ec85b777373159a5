#pragma once
/// \file
/// Where an exploration starts, and every pose an arm's capability map offers: what `fvx
/// explore` needs of the arm before the loop runs (the first view; the poses from which the
/// ground truth's observable space is judged).
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <vector>

#include "fvx/nbv/nbv.hpp"

namespace fvx::session {

/// The first views a robot would try, best first, all looking at `target`. With an arm: the
/// capability map's reachable poses outside the search space `S`; those that aim within 10°
/// of `target` first, farthest from it first (the widest view of the scene, as a robot's
/// first look would be), then the others, best aimed first. Error when the map reaches no
/// pose outside S. Without an arm: one pose, from (−0.15, 0, 0.95) m in the base frame
/// T_world_base.
std::vector<Eigen::Isometry3d> start_candidates(const std::optional<nbv::Reach>& reach,
                                                const Eigen::Isometry3d& T_world_base, const Eigen::AlignedBox3d& S,
                                                const Eigen::Vector3d& target);

/// The default first view: the first of start_candidates that `usable` accepts (every one
/// when `usable` is empty); Error naming how many were tried when none is.
Eigen::Isometry3d default_start(const std::optional<nbv::Reach>& reach, const Eigen::Isometry3d& T_world_base,
                                const Eigen::AlignedBox3d& S, const Eigen::Vector3d& target,
                                const std::function<bool(const Eigen::Isometry3d&)>& usable = {});

/// Every pose of the arm's capability map, world frame: at each voxel centre that is not
/// `blocked`, the optical axis along each direction the voxel reaches (roll 0).
std::vector<Eigen::Isometry3d> capmap_view_poses(const nbv::Reach& reach,
                                                 const std::function<bool(const Eigen::Vector3d&)>& blocked);

}  // namespace fvx::session
