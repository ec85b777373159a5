#include "fvx/registration/registration.hpp"

#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/registration/observability.hpp"

namespace fvx::registration {

const char* to_string(Method method) { return method == Method::Gicp ? "gicp" : "icp"; }

Method parse_method(const std::string& text, const std::string& what) {
  if (text == "gicp") return Method::Gicp;
  if (text == "icp") return Method::Icp;
  throw UsageError(what + ": '" + text + "' is not a registration method; use gicp or icp");
}

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems;
  if (!(voxel_m >= 0.0) || !std::isfinite(voxel_m)) problems.push_back("voxel_m must be >= 0 m");
  if (!(fine_voxel_m >= 0.0) || !std::isfinite(fine_voxel_m)) problems.push_back("fine_voxel_m must be >= 0 m");
  if (!(max_correspondence_m > 0.0) || !std::isfinite(max_correspondence_m))
    problems.push_back("max_correspondence_m must be > 0 m");
  if (!(fine_correspondence_m > 0.0) || !std::isfinite(fine_correspondence_m))
    problems.push_back("fine_correspondence_m must be > 0 m");
  if (max_iterations < 1) problems.push_back("max_iterations must be >= 1");
  if (!(translation_epsilon_m > 0.0)) problems.push_back("translation_epsilon_m must be > 0 m");
  if (!(rotation_epsilon_rad > 0.0)) problems.push_back("rotation_epsilon_rad must be > 0 rad");
  if (min_points < 3) problems.push_back("min_points must be >= 3");
  return problems;
}

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// PCL keeps the iteration count protected; every registration class has it.
template <typename Base>
struct CountingRegistration : Base {
  int iterations() const { return this->nr_iterations_; }
};

Cloud::Ptr downsample(const Cloud::Ptr& cloud, double voxel_m) {
  if (voxel_m <= 0.0) return cloud;
  Cloud::Ptr out(new Cloud);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setLeafSize(float(voxel_m), float(voxel_m), float(voxel_m));
  grid.setInputCloud(cloud);
  grid.filter(*out);
  return out;
}

/// One pass of `Registration` with correspondences up to `max_correspondence_m`, from
/// `guess`. Returns whether it stopped by the epsilons before the iteration cap.
template <typename Registration>
bool run_pass(Registration& reg, const Config& config, double max_correspondence_m,
              const Cloud::Ptr& source, const Cloud::Ptr& target, Eigen::Matrix4f& T_inout,
              int& iterations) {
  reg.setMaxCorrespondenceDistance(max_correspondence_m);
  reg.setMaximumIterations(config.max_iterations);
  reg.setInputSource(source);
  reg.setInputTarget(target);
  Cloud aligned;
  reg.align(aligned, T_inout);
  T_inout = reg.getFinalTransformation();
  iterations += reg.iterations();
  return reg.hasConverged() && reg.iterations() < config.max_iterations;
}

struct Pass {
  double correspondence_m;
  double voxel_m;
};

/// The coarse pass, then the fine pass from its result (Config documents why).
std::vector<Pass> schedule(const Config& config) {
  std::vector<Pass> passes = {{config.max_correspondence_m, config.voxel_m}};
  if (config.fine_correspondence_m < config.max_correspondence_m)
    passes.push_back({config.fine_correspondence_m, config.fine_voxel_m});
  return passes;
}

bool run_pass(const Config& config, const Pass& pass, const Cloud::Ptr& source,
              const Cloud::Ptr& target, Eigen::Matrix4f& T_inout, int& iterations) {
  if (config.method == Method::Gicp) {
    CountingRegistration<pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> gicp;
    // GICP compares each matrix entry's change with the epsilons: metres and radians.
    gicp.setTransformationEpsilon(config.translation_epsilon_m);
    gicp.setRotationEpsilon(config.rotation_epsilon_rad);
    return run_pass(gicp, config, pass.correspondence_m, source, target, T_inout, iterations);
  }
  CountingRegistration<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> icp;
  // ICP's criteria compare the *squared* translation step and the cosine of the rotation
  // step; with the metre value it stopped after two iterations, 0.8° off.
  icp.setTransformationEpsilon(config.translation_epsilon_m * config.translation_epsilon_m);
  icp.getConvergeCriteria()->setRotationThreshold(std::cos(config.rotation_epsilon_rad));
  return run_pass(icp, config, pass.correspondence_m, source, target, T_inout, iterations);
}

struct Constraints {
  std::vector<PlaneConstraint> constraints;
  double length_scale_m = 1.0;
};

/// Point-to-plane constraints of the aligned source: for every source point with a target
/// point within `limit_m`, the target's local plane (PCA of its 12 nearest target points).
/// Points whose neighbourhood is not planar (edges, corners, clutter) give no constraint.
Constraints plane_constraints(const Cloud& source, const Cloud& target, const pcl::KdTreeFLANN<pcl::PointXYZ>& tree,
                              const Eigen::Matrix4f& T_local_sensor, double limit_m) {
  Constraints out;
  std::vector<int> index;
  std::vector<float> distance_sq;
  std::vector<double> ranges;
  for (const auto& p : source.points) {
    const Eigen::Vector4f q = T_local_sensor * Eigen::Vector4f(p.x, p.y, p.z, 1.0f);
    const pcl::PointXYZ query(q.x(), q.y(), q.z());
    if (tree.nearestKSearch(query, 1, index, distance_sq) != 1 || distance_sq[0] > limit_m * limit_m) continue;
    if (tree.nearestKSearch(target.points[std::size_t(index[0])], 12, index, distance_sq) < 6) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int i : index) mean += target.points[std::size_t(i)].getVector3fMap().cast<double>();
    mean /= double(index.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int i : index) {
      const Eigen::Vector3d d = target.points[std::size_t(i)].getVector3fMap().cast<double>() - mean;
      covariance += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(covariance);
    if (pca.eigenvalues()[0] > 0.1 * pca.eigenvalues()[1]) continue;  // not a plane
    out.constraints.push_back({q.head<3>().cast<double>(), pca.eigenvectors().col(0)});
    ranges.push_back(q.head<3>().cast<double>().norm());
  }
  if (!ranges.empty()) {
    std::nth_element(ranges.begin(), ranges.begin() + long(ranges.size() / 2), ranges.end());
    out.length_scale_m = std::max(0.5, ranges[ranges.size() / 2]);
  }
  return out;
}

}  // namespace

Result align(const std::vector<Eigen::Vector3d>& points_sensor,
             const Eigen::Isometry3d& T_world_sensor_prior,
             const std::vector<Eigen::Vector3f>& target_world, const Config& config) {
  FVX_ASSERT(config.validate().empty(), "invalid registration::Config");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  Result result;
  result.T_world_sensor = T_world_sensor_prior;

  // The "local" frame: world axes, origin at the prior sensor position.
  const Eigen::Vector3d origin_world = T_world_sensor_prior.translation();
  Eigen::Isometry3d T_local_sensor_prior = T_world_sensor_prior;
  T_local_sensor_prior.translation().setZero();

  Cloud::Ptr source(new Cloud);
  Eigen::AlignedBox3f box_local;
  for (const auto& p : points_sensor) {
    if (!p.allFinite()) continue;
    source->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
    box_local.extend((T_local_sensor_prior * p).cast<float>());
  }

  Cloud::Ptr target(new Cloud);
  const float margin = float(config.max_correspondence_m);
  box_local.min().array() -= margin;
  box_local.max().array() += margin;
  for (const auto& q : target_world) {
    const Eigen::Vector3f local = (q.cast<double>() - origin_world).cast<float>();
    if (box_local.contains(local)) target->push_back(pcl::PointXYZ(local.x(), local.y(), local.z()));
  }

  Eigen::Matrix4f T_local_sensor = T_local_sensor_prior.matrix().cast<float>();
  bool stopped = true;
  Cloud::Ptr source_pass, target_pass;
  for (const Pass& pass : schedule(config)) {
    source_pass = downsample(source, pass.voxel_m);
    target_pass = downsample(target, pass.voxel_m);
    result.source_points = source_pass->size();
    result.target_points = target_pass->size();
    if (source_pass->size() < std::size_t(config.min_points) ||
        target_pass->size() < std::size_t(config.min_points)) {
      result.problem = "too few points to register (source " + std::to_string(source_pass->size()) +
                       ", target near the prior " + std::to_string(target_pass->size()) + ")";
      return result;
    }
    stopped &= run_pass(config, pass, source_pass, target_pass, T_local_sensor, result.iterations);
  }
  source = source_pass;
  target = target_pass;

  // Fitness against the target, computed here so that both methods report the same measure.
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(target);
  std::vector<int> index(1);
  std::vector<float> distance_sq(1);
  double sum_sq = 0.0;
  std::size_t inliers = 0;
  const double limit_m = std::min(config.max_correspondence_m, config.fine_correspondence_m);
  const double max_sq = limit_m * limit_m;
  for (const auto& p : source->points) {
    const Eigen::Vector4f q = T_local_sensor * Eigen::Vector4f(p.x, p.y, p.z, 1.0f);
    if (tree.nearestKSearch(pcl::PointXYZ(q.x(), q.y(), q.z()), 1, index, distance_sq) == 1 &&
        distance_sq[0] <= max_sq) {
      sum_sq += distance_sq[0];
      ++inliers;
    }
  }
  result.inlier_fraction = double(inliers) / double(source->size());
  result.fitness_rmse_m = inliers ? std::sqrt(sum_sq / double(inliers)) : 0.0;

  Eigen::Isometry3d T_world_sensor(T_local_sensor.cast<double>());
  T_world_sensor.pretranslate(origin_world);
  if (!T_local_sensor.allFinite()) {
    result.problem = "the solver returned a non-finite transform";
    return result;
  }
  // PCL's float matrix is near-orthonormal; make it exact.
  T_world_sensor.linear() = Eigen::Quaterniond(T_world_sensor.rotation()).normalized().toRotationMatrix();
  if (!stopped) {
    result.problem = "no convergence within " + std::to_string(config.max_iterations) + " iterations per pass";
    return result;
  }
  if (inliers == 0) {
    result.problem = "no source point lies within the correspondence limit of the target";
    return result;
  }
  // Keep the prior along directions the geometry does not constrain (observability.hpp).
  const Constraints planes = plane_constraints(*source, *target, tree, T_local_sensor, limit_m);
  const Observability observability =
      analyse_observability(planes.constraints, planes.length_scale_m, config.min_observability);
  for (int i = 0; i < observability.weak_count; ++i)
    result.weak_directions.push_back(describe_direction(observability, i));
  Eigen::Isometry3d T_local_refined = T_world_sensor;
  T_local_refined.translation() -= origin_world;
  const Eigen::Isometry3d T_local_kept = constrain_correction(T_local_sensor_prior, T_local_refined, observability);
  T_world_sensor = T_local_kept;
  T_world_sensor.pretranslate(origin_world);

  result.converged = true;
  result.T_world_sensor = T_world_sensor;
  result.correction_translation_m =
      (T_world_sensor.translation() - T_world_sensor_prior.translation()).norm();
  result.correction_rotation_deg =
      rotation_angle_deg(Eigen::Isometry3d(T_world_sensor.linear() * T_world_sensor_prior.linear().transpose()));
  return result;
}

}  // namespace fvx::registration
