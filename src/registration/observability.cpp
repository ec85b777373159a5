#include "fvx/registration/observability.hpp"

#include <Eigen/Eigenvalues>
#include <cstdio>

#include "fvx/core/error.hpp"

namespace fvx::registration {

Observability analyse_observability(const std::vector<PlaneConstraint>& constraints,
                                    double length_scale_m, double min_strength) {
  FVX_ASSERT(length_scale_m > 0.0, "length scale " + std::to_string(length_scale_m));
  Observability o;
  o.length_scale_m = length_scale_m;
  if (constraints.empty()) {
    o.weak_count = 6;
    return o;
  }
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  for (const PlaneConstraint& c : constraints) {
    Vector6d J;
    J << c.normal, c.point_local.cross(c.normal) / length_scale_m;
    H.noalias() += J * J.transpose();
  }
  H /= double(constraints.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(H);
  o.strength = solver.eigenvalues();  // ascending
  o.directions = solver.eigenvectors();
  while (o.weak_count < 6 && o.strength[o.weak_count] < min_strength) ++o.weak_count;
  return o;
}

Eigen::Isometry3d constrain_correction(const Eigen::Isometry3d& T_local_prior,
                                       const Eigen::Isometry3d& T_local_refined,
                                       const Observability& o) {
  const Eigen::Isometry3d correction = T_local_refined * T_local_prior.inverse();
  const Eigen::AngleAxisd aa(correction.linear());
  Vector6d delta;
  delta << correction.translation(), aa.angle() * aa.axis() * o.length_scale_m;
  for (int i = 0; i < o.weak_count; ++i) {
    const Vector6d v = o.directions.col(i);
    delta -= v * v.dot(delta);
  }
  const Eigen::Vector3d omega = delta.tail<3>() / o.length_scale_m;
  Eigen::Isometry3d constrained = Eigen::Isometry3d::Identity();
  if (omega.norm() > 0) constrained.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  constrained.translation() = delta.head<3>();
  return constrained * T_local_prior;
}

std::string describe_direction(const Observability& o, int i) {
  const Vector6d v = o.directions.col(i);
  const bool translation = v.head<3>().norm() >= v.tail<3>().norm();
  const Eigen::Vector3d axis = (translation ? v.head<3>() : v.tail<3>()).normalized();
  char text[96];
  std::snprintf(text, sizeof text, "%s (%.2f, %.2f, %.2f)",
                translation ? "translation along" : "rotation about", axis.x(), axis.y(), axis.z());
  return text;
}

}  // namespace fvx::registration
