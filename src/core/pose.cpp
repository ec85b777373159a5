#include "fvx/core/pose.hpp"

#include <cmath>

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

double rotation_angle_deg(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.rotation());
  return std::abs(aa.angle()) * 180.0 / M_PI;
}

const char* version() { return FVX_VERSION_STRING; }

}  // namespace fvx
