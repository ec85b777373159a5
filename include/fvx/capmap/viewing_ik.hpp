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
  /// When set, the goal is a region instead of a point: the function says whether a pose
  /// (sensor position, viewing axis; base frame) lies in it and, when not, sets the errors
  /// that pull it in (position, metres; rotation vector, radians), which then replace the
  /// errors towards the point asked. Any pose the descent passes inside is reached.
  std::function<bool(const Eigen::Vector3d& p, const Eigen::Vector3d& d, Eigen::Vector3d& e_p, Eigen::Vector3d& e_r)>
      region;

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

/// The region of an fk-witness bit for IkConfig::region: inside when the sensor lies in
/// `voxel` and the axis in the cell of `direction`. Outside, the position error points to the
/// voxel shrunk by 1 % of its edge on each side (to enter it, not to touch it), and the
/// direction error turns the axis along the great circle to the direction's own point until
/// it is 1 % of the mean spacing inside the cell (a spherical Voronoi cell is convex, so that
/// path stays in). Larger margins (5 %) left the descent short of bits thinner than them.
std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&, Eigen::Vector3d&, Eigen::Vector3d&)>
bit_region(const CapabilityMap& map, std::int64_t voxel, int direction);

/// IK for some pose in an fk-witness bit: descents into bit_region() from `start` when given,
/// then from `config.restarts` random configurations. A pose at a corner of the voxel and the
/// edge of the direction cell counts as much as a central one (descents aimed at the centre
/// and the octants' centres missed 2 % of a youBot map's bits, mostly such corners).
IkResult solve_in_region(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int direction,
                         const IkConfig& config, std::mt19937_64& rng, const Eigen::VectorXd* start = nullptr);

/// IK for a viewing pose that `map` calls reachable. A centre bit (IK methods) promises the
/// pose within the IK tolerances; an fk-witness bit only some pose in its voxel and direction
/// cell, so when the pose asked is not reached, solve_in_region looks for one in the same bit,
/// starting from the configuration that came closest (IkResult::snapped). On a witness map a
/// miss thus costs a second IK solve.
IkResult solve_in_bit(const CapabilityMap& map, const Arm& arm, const Eigen::Vector3d& position_base,
                      const Eigen::Vector3d& direction_base, const IkConfig& config, std::mt19937_64& rng);

}  // namespace fvx::capmap
