#pragma once
/// \file
/// Stage `capmap`, part 1: the arm that carries the sensor. A URDF (urdfdom) is converted to
/// an orocos-kdl chain between a base and a tip link — written here, not through kdl_parser,
/// which pulls in ROS. A fixed sensor mount may follow the tip; the sensor looks along its
/// viewing axis, and roll about that axis is free (ARCHITECTURE.md §3).
#include <Eigen/Geometry>
#include <memory>
#include <optional>
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

/// The line the arm's first movable joint turns about, when that joint is revolute. Every
/// pose is then this line's rotation of a pose with the joint at 0,
/// FK(q₀, q₁…) = R(q₀) · FK(0, q₁…): reachability depends on the other joints and the turn
/// only (RM4D, ICRA 2025, for a first joint about the base's vertical; the identity holds for
/// any axis). The turn's limits are the joint's.
struct FirstJointAxis {
  Eigen::Vector3d point_base = Eigen::Vector3d::Zero();      ///< a point of the axis
  Eigen::Vector3d direction_base = Eigen::Vector3d::UnitZ();  ///< unit; the joint turns about it

  /// The sensor pose with the first joint turned from 0 to `q0_rad`, from the pose at 0.
  Eigen::Isometry3d turn(const Eigen::Isometry3d& T_base_sensor_at_zero, double q0_rad) const;
  /// The angle between the axis and the base's z axis (either way), radians.
  double tilt_from_vertical_rad() const;
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
  /// FNV-1a 64 hash of the URDF text (standard offset basis), hex: ties capability maps to
  /// the model they came from.
  const std::string& urdf_hash() const;
  /// Is `hash` this URDF's hash — urdf_hash(), or the hash with the offset basis a digit short
  /// (14695981039346656037 without its 7) that maps built before fvx used the standard one hold?
  bool is_urdf_hash(const std::string& hash) const;

  /// The axis of joint 0, when it is revolute (not prismatic).
  const std::optional<FirstJointAxis>& first_joint_axis() const;

  /// Forward kinematics: T_base_sensor for joint values `q` (radians, metres).
  Eigen::Isometry3d fk(const Eigen::VectorXd& q) const;
  /// The viewing direction in the base frame at `q`.
  Eigen::Vector3d viewing_direction(const Eigen::VectorXd& q) const;
  /// Joint values drawn uniformly within the limits, one draw of `rng` per joint in order.
  Eigen::VectorXd random_configuration(std::mt19937_64& rng) const;
  /// Joint `joint` drawn uniformly within its limits, one draw of `rng`.
  double random_joint_rad(int joint, std::mt19937_64& rng) const;
  /// d(position of the sensor)/dq (3×n) and d(rotation vector)/dq (3×n), base frame.
  void jacobian(const Eigen::VectorXd& q, Eigen::Matrix3Xd& J_position, Eigen::Matrix3Xd& J_rotation) const;

  struct Impl;

 private:
  explicit Arm(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace fvx::capmap
