#include "fvx/core/pose.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"

namespace fvx {

Eigen::Isometry3d pose_from_translation_quaternion(const Eigen::Vector3d& t, double qx, double qy,
                                                   double qz, double qw, const std::string& what) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  const double norm = q.norm();
  if (!std::isfinite(norm) || norm < 1e-9 || !t.allFinite())
    throw UsageError(what + ": the pose is not finite or its quaternion is zero");
  // A quaternion written with 6-7 digits is unit to within ~1e-7; normalising it would move
  // points by ~1e-6 m and shift a few of them across voxel borders, so that maps built by
  // other tools from the same files (the slambook oracle) would differ. Rescale only what is
  // visibly off the unit sphere.
  if (std::abs(norm - 1.0) > 1e-6) q.coeffs() /= norm;
  Eigen::Isometry3d T(q);
  T.pretranslate(t);
  return T;
}

Eigen::Isometry3d parse_pose(const std::string& text, const std::string& what) {
  const std::vector<double> v = parse_double_list(text, what + " (x,y,z,qx,qy,qz,qw)", 7);
  return pose_from_translation_quaternion({v[0], v[1], v[2]}, v[3], v[4], v[5], v[6], what);
}

Eigen::Isometry3d pose_from_xyz_rpy(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Isometry3d T(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
  T.translation() << x, y, z;
  return T;
}

Eigen::Isometry3d parse_xyz_rpy_deg(const std::string& text, const std::string& what) {
  const std::vector<double> v = parse_double_list(text, what + " (x,y,z,roll,pitch,yaw)", 6);
  const double d = M_PI / 180.0;
  return pose_from_xyz_rpy(v[0], v[1], v[2], v[3] * d, v[4] * d, v[5] * d);
}

Eigen::Vector3d parse_vector3(const std::string& text, const std::string& what) {
  const std::vector<double> v = parse_double_list(text, what, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector3d parse_direction(const std::string& text, const std::string& what) {
  const Eigen::Vector3d d = parse_vector3(text, what);
  if (d.norm() < 1e-9) throw UsageError(what + ": the direction must not be zero");
  return d.normalized();
}

Eigen::Vector3d rpy_of(const Eigen::Matrix3d& R) {
  // R = Rz(yaw)·Ry(pitch)·Rx(roll): R(2,0) = −sin(pitch).
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  if (std::abs(R(2, 0)) > 1.0 - 1e-12) {  // gimbal lock: only roll ∓ yaw is defined; take yaw = 0
    return {std::atan2(-R(1, 2), R(1, 1)), pitch, 0.0};
  }
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

double rotation_angle_deg(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.rotation());
  return std::abs(aa.angle()) * 180.0 / M_PI;
}

const char* version() { return FVX_VERSION_STRING; }

Eigen::Isometry3d parse_look_at(const std::string& text, const std::string& what) {
  const std::vector<double> v = parse_double_list(text, what + " (ex,ey,ez,tx,ty,tz)", 6);
  const Eigen::Vector3d eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]);
  const Eigen::Vector3d z = target - eye;
  if (z.norm() < 1e-9) throw UsageError(what + ": the eye and the target coincide");
  const Eigen::Vector3d forward = z.normalized();
  // Optical frame: x right, y down. Looking straight up or down, take world x as "up".
  const Eigen::Vector3d up = std::abs(forward.z()) > 0.999 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d x = forward.cross(up).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, forward.cross(x), forward;
  T.translation() = eye;
  return T;
}

std::string point_text(const Eigen::Vector3d& p_m) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f)", p_m.x(), p_m.y(), p_m.z());
  return buf;
}

}  // namespace fvx
