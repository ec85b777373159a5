#pragma once
/// \file
/// Stage `capmap`, part 1: the arm that carries the sensor. A URDF (urdfdom) is converted to
/// an orocos-kdl chain between a base and a tip link — written here, not through kdl_parser,
/// which pulls in ROS. A fixed sensor mount may follow the tip; the sensor looks along its
/// viewing axis, and roll about that axis is free (ARCHITECTURE.md §3).
#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace fvx::capmap {

struct ArmConfig {
  std::string base_link;  ///< chain root, e.g. "base_link"
  std::string tip_link;   ///< chain end, e.g. "arm_link_5"
  /// Fixed transform from the tip link to the sensor frame (`--mount`). Default identity.
  Eigen::Isometry3d T_tip_sensor = Eigen::Isometry3d::Identity();
  /// The sensor's viewing axis in the sensor frame, unit length. Default +z (optical axis).
  Eigen::Vector3d viewing_axis_sensor = Eigen::Vector3d::UnitZ();
};

class Arm {
 public:
  /// Reads the URDF and builds the chain. Throws FileError for a URDF that does not parse,
  /// UsageError for an unknown link, a tip that is not below the base, or a joint type the
  /// converter does not support (floating, planar).
  static Arm from_urdf(const std::string& urdf_path, const ArmConfig& config);
  /// The same from URDF text; `source` names it in messages.
  static Arm from_urdf_string(const std::string& urdf, const ArmConfig& config, const std::string& source);

  ~Arm();
  Arm(Arm&&) noexcept;
  Arm& operator=(Arm&&) noexcept;

  int dof() const;
  const std::vector<std::string>& joint_names() const;
  const Eigen::VectorXd& lower_rad() const;  ///< joint limits (continuous joints: −π)
  const Eigen::VectorXd& upper_rad() const;  ///< (continuous joints: +π)
  const ArmConfig& config() const;
  /// FNV-1a hash of the URDF text, hex: ties capability maps to the model they came from.
  const std::string& urdf_hash() const;

  /// Forward kinematics: T_base_sensor for joint values `q` (radians, metres).
  Eigen::Isometry3d fk(const Eigen::VectorXd& q) const;
  /// The viewing direction in the base frame at `q`.
  Eigen::Vector3d viewing_direction(const Eigen::VectorXd& q) const;
  /// Joint values drawn uniformly within the limits, one draw of `rng` per joint in order.
  Eigen::VectorXd random_configuration(std::mt19937_64& rng) const;
  /// d(position of the sensor)/dq (3×n) and d(rotation vector)/dq (3×n), base frame.
  void jacobian(const Eigen::VectorXd& q, Eigen::Matrix3Xd& J_position, Eigen::Matrix3Xd& J_rotation) const;

  struct Impl;

 private:
  explicit Arm(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace fvx::capmap
