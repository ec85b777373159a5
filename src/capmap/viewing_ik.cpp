#include "fvx/capmap/viewing_ik.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "fvx/core/error.hpp"

namespace fvx::capmap {

std::vector<std::string> IkConfig::validate() const {
  std::vector<std::string> problems;
  if (!(position_tolerance_m > 0.0)) problems.push_back("position_tolerance_m must be > 0 m");
  if (!(angle_tolerance_rad > 0.0 && angle_tolerance_rad < M_PI)) problems.push_back("angle_tolerance_rad must be in (0, pi)");
  if (max_iterations < 1) problems.push_back("max_iterations must be >= 1");
  if (restarts < 0) problems.push_back("restarts must be >= 0");
  if (!(damping > 0.0)) problems.push_back("damping must be > 0");
  if (!(direction_weight_m > 0.0)) problems.push_back("direction_weight_m must be > 0 m");
  return problems;
}

namespace {

struct Attempt {
  Eigen::VectorXd q;
  double position_error_m = INFINITY, angle_error_rad = INFINITY;
  int iterations = 0;
  bool reached = false;
};

/// The rotation vector that turns unit vector `d` onto unit vector `target`.
Eigen::Vector3d rotation_between(const Eigen::Vector3d& d, const Eigen::Vector3d& target) {
  const Eigen::Vector3d axis = d.cross(target);
  const double s = axis.norm(), c = d.dot(target);
  if (s < 1e-12) return c > 0 ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(M_PI * d.unitOrthogonal());
  return std::atan2(s, c) * axis / s;
}

/// The damped least-squares step J^T (J J^T + λ² I)^-1 e.
Eigen::VectorXd damped_step(const Eigen::MatrixXd& J, const Eigen::Matrix<double, 6, 1>& e, double damping) {
  const Eigen::Matrix<double, 6, 6> JJt = J * J.transpose() + damping * damping * Eigen::Matrix<double, 6, 6>::Identity();
  return J.transpose() * JJt.ldlt().solve(e);
}

/// The step again without the joints that sit at a limit and that `dq` pushes past it: the
/// clamp would drop their part of the step, and what the other joints do was chosen
/// assuming it. Region bits that an arm reaches only at a joint limit (the youBot's
/// witnesses often are) were missed without this.
Eigen::VectorXd step_within_limits(const Arm& arm, const Eigen::VectorXd& q, Eigen::MatrixXd J,
                                   const Eigen::Matrix<double, 6, 1>& e, double damping, Eigen::VectorXd dq) {
  for (int round = 0; round < arm.dof(); ++round) {
    bool blocked = false;
    for (int j = 0; j < arm.dof(); ++j) {
      const bool at_lower = q[j] <= arm.lower_rad()[j] && dq[j] < 0, at_upper = q[j] >= arm.upper_rad()[j] && dq[j] > 0;
      if ((at_lower || at_upper) && J.col(j).squaredNorm() > 0) J.col(j).setZero(), blocked = true;
    }
    if (!blocked) return dq;
    dq = damped_step(J, e, damping);
  }
  return dq;
}

Attempt descend(const Arm& arm, const Eigen::Vector3d& p_goal, const Eigen::Vector3d& d_goal, const IkConfig& c,
                Eigen::VectorXd q) {
  Attempt a;
  const int n = arm.dof();
  Eigen::Matrix3Xd J_p(3, n), J_r(3, n);
  for (a.iterations = 0; a.iterations <= c.max_iterations; ++a.iterations) {
    const Eigen::Isometry3d T = arm.fk(q);
    const Eigen::Vector3d d = T.linear() * arm.config().viewing_axis_sensor;
    Eigen::Vector3d e_p = p_goal - T.translation(), e_r = rotation_between(d, d_goal);
    const bool inside = c.region && c.region(T.translation(), d, e_p, e_r);
    a.q = q;
    a.position_error_m = e_p.norm();
    a.angle_error_rad = e_r.norm();
    if (inside || (!c.region && a.position_error_m <= c.position_tolerance_m &&
                   a.angle_error_rad <= c.angle_tolerance_rad)) {
      a.reached = true;
      return a;
    }
    if (a.iterations == c.max_iterations) break;
    arm.jacobian(q, J_p, J_r);
    // Roll about the viewing axis does not change the view: keep only rotation rates
    // perpendicular to d.
    const Eigen::Matrix3d perpendicular = Eigen::Matrix3d::Identity() - d * d.transpose();
    Eigen::MatrixXd J(6, n);
    J.topRows<3>() = J_p;
    J.bottomRows<3>() = c.direction_weight_m * perpendicular * J_r;
    // Direction error inside half the angle tolerance does not pull: where the task has more
    // constraints than the arm has joints, least squares would otherwise trade position for
    // direction and settle outside the position tolerance (a planar arm lost a third of its
    // reachable bits to that). A region's errors already stop at its edge.
    const double dead_band = c.region ? 0.0 : 0.5 * c.angle_tolerance_rad, angle = e_r.norm();
    const Eigen::Vector3d e_r_pull = angle > dead_band ? Eigen::Vector3d(e_r * ((angle - dead_band) / angle))
                                                       : Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 6, 1> e;
    e << e_p, c.direction_weight_m * e_r_pull;
    Eigen::VectorXd dq = damped_step(J, e, c.damping);
    if (c.region) dq = step_within_limits(arm, q, J, e, c.damping, dq);
    const double largest = dq.cwiseAbs().maxCoeff();
    if (largest > 0.5) dq *= 0.5 / largest;  // at most 0.5 rad (or m) per joint per step
    q = (q + dq).cwiseMax(arm.lower_rad()).cwiseMin(arm.upper_rad());
  }
  return a;
}

}  // namespace

IkResult solve_viewing_ik(const Arm& arm, const Eigen::Vector3d& position_base, const Eigen::Vector3d& direction_base,
                          const IkConfig& config, std::mt19937_64& rng, const Eigen::VectorXd* start) {
  throw_if_problems("viewing IK", config.validate());
  FVX_ASSERT(std::abs(direction_base.norm() - 1.0) < 1e-6, "the viewing direction must be a unit vector");
  IkResult result;
  Attempt best;
  for (int attempt = 0; attempt <= config.restarts; ++attempt) {
    const Eigen::VectorXd q0 = attempt == 0 && start ? *start : arm.random_configuration(rng);
    const Attempt a = descend(arm, position_base, direction_base, config, q0);
    result.iterations += a.iterations;
    result.attempts = attempt + 1;
    const bool better = a.reached || a.position_error_m + config.direction_weight_m * a.angle_error_rad <
                                          best.position_error_m + config.direction_weight_m * best.angle_error_rad;
    if (better) best = a;
    if (a.reached) break;
  }
  result.reached = best.reached;
  result.q = best.q;
  result.position_error_m = best.position_error_m;
  result.angle_error_rad = best.angle_error_rad;
  return result;
}

bool in_bit(const CapabilityMap& map, std::int64_t voxel, int direction, const Eigen::Vector3d& p_base,
            const Eigen::Vector3d& d_base) {
  return voxel >= 0 && map.voxel_of(p_base) == voxel && map.directions().nearest(d_base.normalized()) == direction;
}

namespace {

/// The rotation vector that turns unit `d` along the great circle towards direction i of
/// `directions` until it lies `margin_rad` inside i's cell ({x : x·d_i ≥ x·d_j for all j}).
/// On the path x(t) = d cos t + w sin t (w: the unit tangent towards d_i) the boundary with
/// d_j, n·x = 0 with n = d_i − d_j, is crossed where tan t = −(n·d)/(n·w); the path enters the
/// cell at the last crossing of a boundary that d violates.
Eigen::Vector3d into_cell(const DirectionSet& directions, int i, const Eigen::Vector3d& d, double margin_rad) {
  const Eigen::Vector3d& d_i = directions[i];
  const Eigen::Vector3d axis = d.cross(d_i);
  const double s = axis.norm(), theta = std::atan2(s, d.dot(d_i));
  if (s < 1e-12) return theta < 1.0 ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(M_PI * d.unitOrthogonal());
  const Eigen::Vector3d w = (d_i - d.dot(d_i) * d) / s;
  double enter_rad = 0.0;
  for (int j = 0; j < directions.size(); ++j) {
    const Eigen::Vector3d n = d_i - directions[j];
    const double at_d = n.dot(d);
    if (j != i && at_d < 0.0) enter_rad = std::max(enter_rad, std::atan2(-at_d, n.dot(w)));
  }
  return std::min(theta, enter_rad + margin_rad) * axis / s;
}

}  // namespace

std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&, Eigen::Vector3d&, Eigen::Vector3d&)>
bit_region(const CapabilityMap& map, std::int64_t voxel, int direction) {
  const Eigen::Vector3d centre = map.center_of(voxel);
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.49 * map.header().voxel_m);
  const double margin_rad = 0.01 * map.directions().mean_spacing_rad();
  return [&map, voxel, direction, centre, half, margin_rad](const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                                                             Eigen::Vector3d& e_p, Eigen::Vector3d& e_r) {
    if (in_bit(map, voxel, direction, p, d)) return true;
    e_p = centre + (p - centre).cwiseMax(-half).cwiseMin(half) - p;
    e_r = into_cell(map.directions(), direction, d, margin_rad);
    return false;
  };
}

IkResult solve_in_region(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int direction,
                         const IkConfig& config, std::mt19937_64& rng, const Eigen::VectorXd* start) {
  IkConfig in_region = config;
  in_region.region = bit_region(map, voxel, direction);
  return solve_viewing_ik(arm, map.center_of(voxel), map.directions()[direction], in_region, rng, start);
}

IkResult solve_in_bit(const CapabilityMap& map, const Arm& arm, const Eigen::Vector3d& position_base,
                      const Eigen::Vector3d& direction_base, const IkConfig& config, std::mt19937_64& rng) {
  IkResult r = solve_viewing_ik(arm, position_base, direction_base, config, rng);
  if (r.reached || map.header().method != "fk-witness") return r;
  const std::int64_t voxel = map.voxel_of(position_base);
  const int direction = map.directions().nearest(direction_base);
  const int iterations = r.iterations, attempts = r.attempts;
  const Eigen::VectorXd nearest_q = r.q;  // the pose asked lies in the bit: start where IK came closest
  r = solve_in_region(map, arm, voxel, direction, config, rng, &nearest_q);
  r.snapped = r.reached;
  r.iterations += iterations;
  r.attempts += attempts;
  return r;
}

}  // namespace fvx::capmap
