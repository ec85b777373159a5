#include "point_to_plane.hpp"

#include "nearest.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace fvx::registration {

struct TargetSurface::Tree {
  CloudPoints points;
  PointTree index;
  explicit Tree(const Cloud& cloud) : points{&cloud}, index(3, points, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

TargetSurface::TargetSurface(const Cloud::ConstPtr& cloud) : cloud_(cloud), tree_(std::make_unique<Tree>(*cloud)) {
  normals_.assign(cloud_->size(), Eigen::Vector3f::Zero());
  planar_.assign(cloud_->size(), 0);
  constexpr std::size_t k = 12;
  std::array<std::uint32_t, k> index;
  std::array<float, k> distance_sq;
  for (std::size_t i = 0; i < cloud_->size(); ++i) {
    const std::size_t found = tree_->index.knnSearch(cloud_->points[i].data, k, index.data(), distance_sq.data());
    if (found < 6) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t j = 0; j < found; ++j) mean += cloud_->points[index[j]].getVector3fMap().cast<double>();
    mean /= double(found);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (std::size_t j = 0; j < found; ++j) {
      const Eigen::Vector3d d = cloud_->points[index[j]].getVector3fMap().cast<double>() - mean;
      covariance += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(covariance);
    normals_[i] = pca.eigenvectors().col(0).cast<float>();
    planar_[i] = pca.eigenvalues()[0] <= 0.1 * pca.eigenvalues()[1];  // edges and corners are not
  }
}

TargetSurface::~TargetSurface() = default;

int TargetSurface::nearest(const Eigen::Vector3f& q, float limit_sq, float& distance_sq) const {
  NearestWithin result(limit_sq);
  tree_->index.findNeighbors(result, q.data(), nanoflann::SearchParams());
  if (result.index() < 0) return -1;
  distance_sq = result.distance_sq();
  return result.index();
}

int TargetSurface::nearest_near(const Eigen::Vector3f& q, float limit_sq, int hint, float& distance_sq) const {
  if (hint < 0) return nearest(q, limit_sq, distance_sq);
  // The hint's squared distance by the tree's own metric, so that the hint itself passes
  // the search's strict test against the bound.
  const float hint_sq = tree_->index.distance.evalMetric(q.data(), std::uint32_t(hint), 3);
  const int found = nearest(q, std::min(limit_sq, hint_sq), distance_sq);
  return found >= 0 ? found : nearest(q, limit_sq, distance_sq);
}

namespace {

/// The residual of a source point at q: to the plane of its partner, or to the partner.
/// Returns false without a partner. `partner` comes in as the hint (nearest_near), or -1.
bool residual(const TargetSurface& target, const Eigen::Vector3f& q, float limit_sq, int& partner, double& r) {
  float distance_sq = 0;
  partner = target.nearest_near(q, limit_sq, partner, distance_sq);
  if (partner < 0) return false;
  r = target.planar(partner) ? double(target.normal(partner).dot(q - target.cloud().points[std::size_t(partner)].getVector3fMap()))
                             : std::sqrt(double(distance_sq));
  return true;
}

}  // namespace

double robust_cost(const Cloud& source, const TargetSurface& target, const Eigen::Matrix4f& T, const FineConfig& c) {
  if (source.empty()) return 1.0;
  const double s2 = c.scale_m * c.scale_m;
  double sum = 0.0;
  for (const auto& p : source.points) {
    const Eigen::Vector3f q = (T * Eigen::Vector4f(p.x, p.y, p.z, 1.0f)).head<3>();
    int partner = -1;
    double r;
    sum += residual(target, q, c.limit_m * c.limit_m, partner, r) ? r * r / (s2 + r * r) : 1.0;
  }
  return sum / double(source.size());
}

std::pair<double, double> compare_on_common_points(const Cloud& source, const TargetSurface& target,
                                                   const Eigen::Matrix4f& T_a, const Eigen::Matrix4f& T_b,
                                                   const FineConfig& c) {
  const double s2 = c.scale_m * c.scale_m;
  double sum_a = 0.0, sum_b = 0.0;
  std::size_t common = 0;
  for (const auto& p : source.points) {
    const Eigen::Vector4f h(p.x, p.y, p.z, 1.0f);
    int partner = -1;
    double r_a, r_b;
    if (!residual(target, (T_a * h).head<3>(), c.limit_m * c.limit_m, partner, r_a) ||
        !residual(target, (T_b * h).head<3>(), c.limit_m * c.limit_m, partner, r_b))
      continue;
    sum_a += r_a * r_a / (s2 + r_a * r_a);
    sum_b += r_b * r_b / (s2 + r_b * r_b);
    ++common;
  }
  if (common < 30) return {1.0, 1.0};
  return {sum_a / double(common), sum_b / double(common)};
}

FineFit refine_point_to_plane(const Cloud& source, const TargetSurface& target, const Eigen::Matrix4f& T_start,
                              const FineConfig& c) {
  FineFit fit;
  Eigen::Matrix4d T = T_start.cast<double>();
  const double s2 = c.scale_m * c.scale_m;
  std::vector<int> partners(source.size(), -1);  // each point's partner in the iteration before
  for (fit.iterations = 1; fit.iterations <= c.max_iterations; ++fit.iterations) {
    // Rotations are scaled by the length L so that both halves of the step are in metres.
    const double L = c.length_scale_m;
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Vector6d g = Vector6d::Zero();
    double weight_sum = 0.0;
    std::size_t used = 0;
    for (std::size_t i = 0; i < source.size(); ++i) {
      const auto& p = source.points[i];
      const Eigen::Vector3d q = (T * Eigen::Vector4d(p.x, p.y, p.z, 1.0)).head<3>();
      int& partner = partners[i];
      double r;
      if (!residual(target, q.cast<float>(), c.limit_m * c.limit_m, partner, r) || !target.planar(partner)) continue;
      const Eigen::Vector3d n = target.normal(partner).cast<double>();
      Vector6d J;
      J << n, q.cross(n) / L;  // ∂r/∂(t, L·ω) for q' = exp(ω)·q + t
      const double w = s2 / ((s2 + r * r) * (s2 + r * r)) * s2;  // Geman–McClure IRLS weight, 1 at r = 0
      H.noalias() += w * J * J.transpose();
      g.noalias() += w * r * J;
      weight_sum += w;
      ++used;
    }
    if (used < 6) break;
    // Solve in the eigenbasis of H, dropping directions whose information per point is weak.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(H);
    Vector6d scaled = Vector6d::Zero();
    for (int k = 0; k < 6; ++k) {
      const double lambda = eigen.eigenvalues()[k];
      if (lambda / weight_sum < c.min_observability) continue;
      const Vector6d v = eigen.eigenvectors().col(k);
      scaled -= v * (v.dot(g) / lambda);
    }
    Vector6d delta = scaled;
    delta.tail<3>() /= L;
    if (!delta.allFinite()) break;
    Eigen::Matrix4d step = Eigen::Matrix4d::Identity();
    const Eigen::Vector3d omega = delta.tail<3>();
    if (omega.norm() > 0) step.topLeftCorner<3, 3>() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
    step.topRightCorner<3, 1>() = delta.head<3>();
    T = step * T;
    if (delta.head<3>().norm() < c.translation_epsilon_m && omega.norm() < c.rotation_epsilon_rad) {
      fit.converged = true;
      break;
    }
  }
  fit.iterations = std::min(fit.iterations, c.max_iterations);
  fit.T_local_sensor = T.cast<float>();
  fit.cost = robust_cost(source, target, fit.T_local_sensor, c);
  return fit;
}

std::vector<PlaneConstraint> plane_constraints(const Cloud& source, const TargetSurface& target,
                                               const Eigen::Matrix4f& T, float limit_m, double& length_scale_m) {
  std::vector<PlaneConstraint> constraints;
  std::vector<double> ranges;
  for (const auto& p : source.points) {
    const Eigen::Vector3f q = (T * Eigen::Vector4f(p.x, p.y, p.z, 1.0f)).head<3>();
    float distance_sq = 0;
    const int partner = target.nearest(q, limit_m * limit_m, distance_sq);
    if (partner < 0 || !target.planar(partner)) continue;
    constraints.push_back({q.cast<double>(), target.normal(partner).cast<double>()});
    ranges.push_back(q.cast<double>().norm());
  }
  length_scale_m = 1.0;
  if (!ranges.empty()) {
    std::nth_element(ranges.begin(), ranges.begin() + long(ranges.size() / 2), ranges.end());
    length_scale_m = std::max(0.5, ranges[ranges.size() / 2]);
  }
  return constraints;
}

}  // namespace fvx::registration
