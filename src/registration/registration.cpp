#include "fvx/registration/registration.hpp"

#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"

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

/// The coarse pass, then the fine pass from its result.
bool run_schedule(const Config& config, const Cloud::Ptr& source, const Cloud::Ptr& target,
                  Eigen::Matrix4f& T_inout, int& iterations) {
  std::vector<double> limits = {config.max_correspondence_m};
  if (config.fine_correspondence_m < config.max_correspondence_m)
    limits.push_back(config.fine_correspondence_m);
  bool stopped = true;
  for (const double limit : limits) {
    if (config.method == Method::Gicp) {
      CountingRegistration<pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> gicp;
      // GICP compares each matrix entry's change with the epsilons: metres and radians.
      gicp.setTransformationEpsilon(config.translation_epsilon_m);
      gicp.setRotationEpsilon(config.rotation_epsilon_rad);
      stopped &= run_pass(gicp, config, limit, source, target, T_inout, iterations);
    } else {
      CountingRegistration<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> icp;
      // ICP's criteria compare the *squared* translation step and the cosine of the rotation
      // step; with the metre value it stopped after two iterations, 0.8° off.
      icp.setTransformationEpsilon(config.translation_epsilon_m * config.translation_epsilon_m);
      icp.getConvergeCriteria()->setRotationThreshold(std::cos(config.rotation_epsilon_rad));
      stopped &= run_pass(icp, config, limit, source, target, T_inout, iterations);
    }
  }
  return stopped;
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
  source = downsample(source, config.voxel_m);

  Cloud::Ptr target(new Cloud);
  const float margin = float(config.max_correspondence_m);
  box_local.min().array() -= margin;
  box_local.max().array() += margin;
  for (const auto& q : target_world) {
    const Eigen::Vector3f local = (q.cast<double>() - origin_world).cast<float>();
    if (box_local.contains(local)) target->push_back(pcl::PointXYZ(local.x(), local.y(), local.z()));
  }
  target = downsample(target, config.voxel_m);
  result.source_points = source->size();
  result.target_points = target->size();
  if (source->size() < std::size_t(config.min_points) || target->size() < std::size_t(config.min_points)) {
    result.problem = "too few points to register (source " + std::to_string(source->size()) +
                     ", target near the prior " + std::to_string(target->size()) + ")";
    return result;
  }

  Eigen::Matrix4f T_local_sensor = T_local_sensor_prior.matrix().cast<float>();
  const bool stopped = run_schedule(config, source, target, T_local_sensor, result.iterations);

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
  result.converged = true;
  result.T_world_sensor = T_world_sensor;
  result.correction_translation_m =
      (T_world_sensor.translation() - T_world_sensor_prior.translation()).norm();
  result.correction_rotation_deg =
      rotation_angle_deg(Eigen::Isometry3d(T_world_sensor.linear() * T_world_sensor_prior.linear().transpose()));
  return result;
}

}  // namespace fvx::registration
