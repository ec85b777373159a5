#pragma once
/// \file
/// Inverse kinematics for a viewing pose: the sensor at a position, looking along a
/// direction, roll about the viewing axis free. Damped least squares on the arm's forward
/// kinematics and Jacobian, the roll projected out of the task, joints clamped to their
/// limits, restarts from seeded random configurations.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"

namespace fvx::capmap {

struct IkConfig {
  double position_tolerance_m = 0.005;  ///< reached when the sensor is this close, metres
  /// Reached when the viewing axis is within this angle, radians. The capability map uses
  /// half the mean spacing of its direction set (200 directions: 0.125 rad, 7.2°).
  double angle_tolerance_rad = 0.125;
  int max_iterations = 60;              ///< per attempt
  int restarts = 20;                    ///< random starts after the first
  double damping = 0.05;                ///< λ of damped least squares
  /// Metres per radian of direction error: weighs direction against position. Default 0.3.
  double direction_weight_m = 0.3;
  /// When set, any pose the descent passes (sensor position, viewing axis; base frame) for
  /// which it returns true is reached as well: the IK then looks for a pose in a region (an
  /// fk-witness bit), aiming at the pose asked.
  std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)> accept;

  std::vector<std::string> validate() const;
};

struct IkResult {
  bool reached = false;
  /// solve_in_bit: the pose asked was not reached, but q's pose lies in the same bit of an
  /// fk-witness map (reached is then true): the view moves to q's pose.
  bool snapped = false;
  Eigen::VectorXd q;                 ///< the best configuration found
  double position_error_m = 0;
  double angle_error_rad = 0;
  int attempts = 0;                  ///< starts used
  int iterations = 0;                ///< all iterations of all attempts
};

/// Solves for the sensor at `position_base` looking along `direction_base` (unit), base
/// frame. Starts from `start` when given (a neighbouring solution), then from random
/// configurations drawn from `rng`.
IkResult solve_viewing_ik(const Arm& arm, const Eigen::Vector3d& position_base,
                          const Eigen::Vector3d& direction_base, const IkConfig& config, std::mt19937_64& rng,
                          const Eigen::VectorXd* start = nullptr);

/// Whether the sensor at `p_base` looking along `d_base` lies in `voxel` with the axis in the
/// cell of `direction` (nearer to it than to any other direction): an fk-witness bit.
bool in_bit(const CapabilityMap& map, std::int64_t voxel, int direction, const Eigen::Vector3d& p_base,
            const Eigen::Vector3d& d_base);

/// IK for some pose in an fk-witness bit: aimed at `aim_base` and the bit's direction, then at
/// each octant of the voxel; any pose the descents pass inside the bit is reached.
IkResult solve_in_region(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int direction,
                         const Eigen::Vector3d& aim_base, const IkConfig& config, std::mt19937_64& rng);

/// IK for a viewing pose that `map` calls reachable. A centre bit (IK methods) promises the
/// pose within the IK tolerances; an fk-witness bit only some pose in its voxel and direction
/// cell, so when the pose asked is not reached, solve_in_region looks for one in the same bit
/// (IkResult::snapped). On a witness map a miss thus costs up to nine more IK solves.
IkResult solve_in_bit(const CapabilityMap& map, const Arm& arm, const Eigen::Vector3d& position_base,
                      const Eigen::Vector3d& direction_base, const IkConfig& config, std::mt19937_64& rng);

}  // namespace fvx::capmap
