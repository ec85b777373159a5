#pragma once
/// \file
/// Inverse kinematics for a viewing pose: the sensor at a position, looking along a
/// direction, roll about the viewing axis free. Damped least squares on the arm's forward
/// kinematics and Jacobian, the roll projected out of the task, joints clamped to their
/// limits, restarts from seeded random configurations.
#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "fvx/capmap/arm.hpp"

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

  std::vector<std::string> validate() const;
};

struct IkResult {
  bool reached = false;
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

}  // namespace fvx::capmap
