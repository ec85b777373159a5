#include "fvx/capmap/viewing_ik.hpp"

#include <Eigen/Cholesky>
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

Attempt descend(const Arm& arm, const Eigen::Vector3d& p_goal, const Eigen::Vector3d& d_goal, const IkConfig& c,
                Eigen::VectorXd q) {
  Attempt a;
  const int n = arm.dof();
  Eigen::Matrix3Xd J_p(3, n), J_r(3, n);
  for (a.iterations = 0; a.iterations <= c.max_iterations; ++a.iterations) {
    const Eigen::Isometry3d T = arm.fk(q);
    const Eigen::Vector3d d = T.linear() * arm.config().viewing_axis_sensor;
    const Eigen::Vector3d e_p = p_goal - T.translation();
    const Eigen::Vector3d e_r = rotation_between(d, d_goal);
    a.q = q;
    a.position_error_m = e_p.norm();
    a.angle_error_rad = e_r.norm();
    if ((a.position_error_m <= c.position_tolerance_m && a.angle_error_rad <= c.angle_tolerance_rad) ||
        (c.accept && c.accept(T.translation(), d))) {
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
    // reachable bits to that).
    const double dead_band = 0.5 * c.angle_tolerance_rad, angle = e_r.norm();
    const Eigen::Vector3d e_r_pull = angle > dead_band ? Eigen::Vector3d(e_r * ((angle - dead_band) / angle))
                                                       : Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 6, 1> e;
    e << e_p, c.direction_weight_m * e_r_pull;
    const Eigen::Matrix<double, 6, 6> JJt = J * J.transpose() + c.damping * c.damping * Eigen::Matrix<double, 6, 6>::Identity();
    Eigen::VectorXd dq = J.transpose() * JJt.ldlt().solve(e);
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
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int attempt = 0; attempt <= config.restarts; ++attempt) {
    Eigen::VectorXd q0(arm.dof());
    if (attempt == 0 && start) {
      q0 = *start;
    } else {
      for (int j = 0; j < arm.dof(); ++j)
        q0[j] = arm.lower_rad()[j] + unit(rng) * (arm.upper_rad()[j] - arm.lower_rad()[j]);
    }
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

IkResult solve_in_region(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int direction,
                         const Eigen::Vector3d& aim_base, const IkConfig& config, std::mt19937_64& rng) {
  IkConfig in_region = config;  // any pose the descent passes inside the bit is reached
  in_region.accept = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& d) { return in_bit(map, voxel, direction, p, d); };
  const Eigen::Vector3d& d = map.directions()[direction];
  IkResult r = solve_viewing_ik(arm, aim_base, d, in_region, rng);
  // A bit may hold poses only in a corner of its voxel: aim at each octant's centre as well.
  const double quarter = 0.25 * map.header().voxel_m;
  for (int octant = 0; octant < 8 && !r.reached; ++octant) {
    const Eigen::Vector3d offset((octant & 1 ? 1 : -1) * quarter, (octant & 2 ? 1 : -1) * quarter,
                                 (octant & 4 ? 1 : -1) * quarter);
    const int iterations = r.iterations;
    r = solve_viewing_ik(arm, map.center_of(voxel) + offset, d, in_region, rng);
    r.iterations += iterations;
  }
  return r;
}

IkResult solve_in_bit(const CapabilityMap& map, const Arm& arm, const Eigen::Vector3d& position_base,
                      const Eigen::Vector3d& direction_base, const IkConfig& config, std::mt19937_64& rng) {
  IkResult r = solve_viewing_ik(arm, position_base, direction_base, config, rng);
  if (r.reached || map.header().method != "fk-witness") return r;
  const std::int64_t voxel = map.voxel_of(position_base);
  const int direction = map.directions().nearest(direction_base);
  r = solve_in_region(map, arm, voxel, direction, position_base, config, rng);
  r.snapped = r.reached;
  return r;
}

}  // namespace fvx::capmap
