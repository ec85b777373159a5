#pragma once
/// \file
/// Stage `viewpoints`, part 2: sensor orientations sampled at a viewpoint (paper §IV-C:
/// "camera orientations are sampled at the viewpoints c sorted by util(c)"). Each sample
/// points the optical axis at one of the targets (the corners and centres of the voids whose
/// utility reached the cell), turned by a seeded jitter and a seeded roll.
#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace fvx::viewpoints {

/// `count` rotations R_world_sensor at `position_m`: sample k looks at
/// targets_m[k mod targets], its axis tilted by an angle uniform in [0, jitter_rad] in a
/// uniform direction (sample 0 of each target untilted when `exact_first`), its roll uniform
/// in [0, π) (a pinhole image turned by π covers the same rays). Targets at the position are
/// skipped; none left → no rotations.
std::vector<Eigen::Matrix3d> sample_orientations(const Eigen::Vector3d& position_m,
                                                 const std::vector<Eigen::Vector3d>& targets_m, int count,
                                                 double jitter_rad, std::mt19937_64& rng, bool exact_first = true);

}  // namespace fvx::viewpoints
