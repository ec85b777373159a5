#pragma once
/// \file
/// Which directions of a rigid correction the scan's geometry constrains (Zhang, Kaess &
/// Singh, "On degeneracy of optimization-based state estimation problems", ICRA 2016).
/// A correction is a 6-vector δ = (t, L·ω) in the registration's local frame (world axes,
/// origin at the prior sensor position): translation t in metres and rotation vector ω in
/// radians scaled by a length L (metres), so that both halves are in metres. Each
/// point-to-plane constraint (point p, unit normal n) contributes J = (n, p×n / L); the
/// information matrix is H = Σ J Jᵀ. Directions whose eigenvalue per constraint, λ/N, is
/// small are barely constrained: a corridor seen end-on constrains nothing along its axis,
/// and a correction there is noise.
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace fvx::registration {

/// One point-to-plane constraint in the local frame.
struct PlaneConstraint {
  Eigen::Vector3d point_local;
  Eigen::Vector3d normal;  ///< unit length
};

using Vector6d = Eigen::Matrix<double, 6, 1>;

struct Observability {
  double length_scale_m = 1.0;  ///< L: rotation ↔ translation units
  /// Eigenvalues of H divided by the number of constraints, ascending; a translation
  /// direction constrained by every point (all normals along it) has 1.
  Vector6d strength = Vector6d::Zero();
  Eigen::Matrix<double, 6, 6> directions = Eigen::Matrix<double, 6, 6>::Identity();  ///< columns
  int weak_count = 0;  ///< directions with strength below the threshold (the first columns)
};

/// Eigen-decomposes H. `min_strength` separates weak from constrained directions.
Observability analyse_observability(const std::vector<PlaneConstraint>& constraints,
                                    double length_scale_m, double min_strength);

/// The correction T_refined · T_priorᵀ (both local, world axes) restricted to the
/// constrained directions: the weak components of δ are removed, so the pose stays at the
/// prior where the geometry cannot tell.
Eigen::Isometry3d constrain_correction(const Eigen::Isometry3d& T_local_prior,
                                       const Eigen::Isometry3d& T_local_refined,
                                       const Observability& observability);

/// "translation along (1.00, 0.00, 0.00)" or "rotation about (...)" for weak direction i
/// (by its dominant half), world axes.
std::string describe_direction(const Observability& observability, int i);

}  // namespace fvx::registration
