#pragma once
/// \file
/// Rigid transforms. Names carry frames: `T_world_sensor` maps sensor-frame points into the
/// world, `p_world = T_world_sensor * p_sensor`, and chains cancel
/// (`T_world_base * T_base_sensor`). Camera optical frame: z forward, x right, y down.
#include <Eigen/Geometry>
#include <string>

namespace fvx {

/// Builds `T_a_b` from a translation and a quaternion given scalar-last (x, y, z, w), the
/// order of TUM, slambook and ROS files. The quaternion is normalised; q and -q give the same
/// rotation. Throws UsageError naming `what` if the quaternion is zero or not finite.
Eigen::Isometry3d pose_from_translation_quaternion(const Eigen::Vector3d& t, double qx, double qy,
                                                   double qz, double qw, const std::string& what);

/// Parses "x,y,z,qx,qy,qz,qw" (metres, scalar-last quaternion) as given to `--pose`.
Eigen::Isometry3d parse_pose(const std::string& text, const std::string& what);

/// `T_a_b` from x, y, z (metres) and roll, pitch, yaw (radians): R = Rz(yaw)·Ry(pitch)·Rx(roll),
/// the URDF convention.
Eigen::Isometry3d pose_from_xyz_rpy(double x, double y, double z, double roll, double pitch, double yaw);

/// Parses "x,y,z,roll,pitch,yaw" (metres, degrees) as given to `--base` and `--mount`.
Eigen::Isometry3d parse_xyz_rpy_deg(const std::string& text, const std::string& what);

/// Parses "x,y,z".
Eigen::Vector3d parse_vector3(const std::string& text, const std::string& what);
/// Parses "x,y,z" and normalises it; UsageError naming `what` for a zero vector.
Eigen::Vector3d parse_direction(const std::string& text, const std::string& what);

/// Parses "ex,ey,ez,tx,ty,tz": a sensor at eye E looking at target T, world z up (optical
/// frame: x right, y down). UsageError naming `what`.
Eigen::Isometry3d parse_look_at(const std::string& text, const std::string& what);

/// "(x, y, z)" to the millimetre, for messages about a position in metres.
std::string point_text(const Eigen::Vector3d& p_m);

/// Roll, pitch, yaw (radians) of a rotation: the inverse of pose_from_xyz_rpy's rotation.
Eigen::Vector3d rpy_of(const Eigen::Matrix3d& R);

/// Angle of the rotation part in degrees, in [0, 180].
double rotation_angle_deg(const Eigen::Isometry3d& T);

/// The fvx release, e.g. "0.1.0".
const char* version();

}  // namespace fvx
