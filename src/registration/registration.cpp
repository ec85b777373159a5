#include "fvx/registration/registration.hpp"

#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <future>

#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/registration/observability.hpp"
#include "nearest.hpp"
#include "point_to_plane.hpp"

namespace fvx::registration {

namespace {

// Cloud is declared in point_to_plane.hpp.

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

/// The coarse pass: PCL's GICP or ICP with correspondences up to max_correspondence_m.
bool coarse_pass(const Config& config, const Cloud::Ptr& source, const Cloud::Ptr& target,
                 Eigen::Matrix4f& T_inout, int& iterations) {
  if (config.method == Method::Gicp) {
    CountingRegistration<pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> gicp;
    gicp.setSearchMethodTarget(std::make_shared<NanoflannSearch>());
    gicp.setSearchMethodSource(std::make_shared<NanoflannSearch>());
    // GICP compares each matrix entry's change with the epsilons: metres and radians.
    gicp.setTransformationEpsilon(config.translation_epsilon_m);
    gicp.setRotationEpsilon(config.rotation_epsilon_rad);
    return run_pass(gicp, config, config.max_correspondence_m, source, target, T_inout, iterations);
  }
  CountingRegistration<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> icp;
  icp.setSearchMethodTarget(std::make_shared<NanoflannSearch>());
  icp.setSearchMethodSource(std::make_shared<NanoflannSearch>());
  // ICP's criteria compare the *squared* translation step and the cosine of the rotation
  // step; with the metre value it stopped after two iterations, 0.8° off.
  icp.setTransformationEpsilon(config.translation_epsilon_m * config.translation_epsilon_m);
  icp.getConvergeCriteria()->setRotationThreshold(std::cos(config.rotation_epsilon_rad));
  return run_pass(icp, config, config.max_correspondence_m, source, target, T_inout, iterations);
}

/// The scan (sensor frame) and the target cropped to the prior-placed scan's bounding box grown
/// by max_correspondence_m, in the local frame (world axes, origin at the prior position).
std::pair<Cloud::Ptr, Cloud::Ptr> local_clouds(const std::vector<Eigen::Vector3d>& points_sensor,
                                               const Eigen::Isometry3d& T_local_sensor_prior,
                                               const std::vector<Eigen::Vector3f>& target_world,
                                               const Eigen::Vector3d& origin_world, const Config& config) {
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
  return {source, target};
}

/// The fine pass's settings; its length scale of observability is the median range of the
/// scan's points.
FineConfig fine_config(const Cloud& source_fine, const Config& config) {
  std::vector<float> ranges;
  for (const auto& p : source_fine.points) ranges.push_back(p.getVector3fMap().norm());
  std::nth_element(ranges.begin(), ranges.begin() + long(ranges.size() / 2), ranges.end());
  const double length_scale_m = std::max(0.5, double(ranges[ranges.size() / 2]));
  return FineConfig{float(config.fine_correspondence_m), config.robust_scale_m, config.max_iterations,
                    config.translation_epsilon_m, config.rotation_epsilon_rad, config.min_observability,
                    length_scale_m};
}

/// Fitness against the fine target, the same measure for both methods: fills
/// result.inlier_fraction and fitness_rmse_m, returns the inlier count.
std::size_t measure_fitness(const Cloud& source_fine, const TargetSurface& surface, const Eigen::Matrix4f& T_local_sensor,
                            const Config& config, Result& result) {
  double sum_sq = 0.0;
  std::size_t inliers = 0;
  const float limit_sq = float(config.fine_correspondence_m * config.fine_correspondence_m);
  for (const auto& p : source_fine.points) {
    const Eigen::Vector3f q = (T_local_sensor * Eigen::Vector4f(p.x, p.y, p.z, 1.0f)).head<3>();
    float distance_sq = 0;
    if (surface.nearest(q, limit_sq, distance_sq) >= 0) {
      sum_sq += distance_sq;
      ++inliers;
    }
  }
  result.inlier_fraction = double(inliers) / double(source_fine.size());
  result.fitness_rmse_m = inliers ? std::sqrt(sum_sq / double(inliers)) : 0.0;
  return inliers;
}

/// Reports the directions the geometry does not constrain at the result (float solver pose
/// T_local_sensor) and keeps the prior along them (observability.hpp); the fine pass already
/// did not move along weak ones. Returns the refined pose so constrained, local frame.
Eigen::Isometry3d keep_prior_along_weak_directions(const Cloud& source_fine, const TargetSurface& surface,
                                                   const Eigen::Matrix4f& T_local_sensor,
                                                   const Eigen::Isometry3d& T_local_sensor_prior,
                                                   const Eigen::Isometry3d& T_local_refined, const Config& config,
                                                   Result& result) {
  double observed_length_m = 1.0;
  const auto planes = plane_constraints(source_fine, surface, T_local_sensor, float(config.fine_correspondence_m),
                                        observed_length_m);
  const Observability observability = analyse_observability(planes, observed_length_m, config.min_observability);
  for (int i = 0; i < observability.weak_count; ++i)
    result.weak_directions.push_back(describe_direction(observability, i));
  return constrain_correction(T_local_sensor_prior, T_local_refined, observability);
}

/// Coarse pass from the prior; then the robust fine pass from the prior and from the coarse
/// result, keeping the lower robust cost (point_to_plane.hpp says why). Adds the iterations
/// and the fine start to `result`; `stopped`: the chosen passes stopped by the epsilons.
/// Returns the chosen pose, local frame.
Eigen::Matrix4f coarse_then_fine(const Config& config, const Cloud::Ptr& source_coarse, const Cloud::Ptr& target_coarse,
                                 const Cloud& source_fine, const TargetSurface& surface,
                                 const Eigen::Matrix4f& T_prior, Result& result, bool& stopped) {
  const FineConfig fine = fine_config(source_fine, config);
  // The fine pass from the prior needs neither the coarse pass nor its result: it runs on
  // another core beside them, with the same arithmetic (the same pose on any core count).
  std::future<FineFit> prior_pass =
      std::async(std::launch::async, [&] { return refine_point_to_plane(source_fine, surface, T_prior, fine); });
  Eigen::Matrix4f T_coarse = T_prior;
  const bool coarse_stopped = coarse_pass(config, source_coarse, target_coarse, T_coarse, result.iterations);
  const FineFit from_coarse = refine_point_to_plane(source_fine, surface, T_coarse, fine);
  const FineFit from_prior = prior_pass.get();
  const auto [cost_prior, cost_coarse] =
      compare_on_common_points(source_fine, surface, from_prior.T_local_sensor, from_coarse.T_local_sensor, fine);
  // The prior stands unless the data clearly prefers the coarse result: where both fit about
  // equally (parallel walls 9 cm apart in the crates scene aliased a 9 cm slide to within
  // 1 %), moving is a guess; a wrong prior costs several times more than a right one.
  const bool prior_wins = cost_prior <= 1.1 * cost_coarse;
  const FineFit& best = prior_wins ? from_prior : from_coarse;
  result.iterations += best.iterations;
  result.fine_start = prior_wins ? "prior" : "coarse";
  stopped = best.converged && (prior_wins || coarse_stopped);
  return best.T_local_sensor;
}

}  // namespace

Result align(const std::vector<Eigen::Vector3d>& points_sensor,
             const Eigen::Isometry3d& T_world_sensor_prior,
             const std::vector<Eigen::Vector3f>& target_world, const Config& config) {
  throw_if_problems("registration", config.validate());
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  Result result;
  result.T_world_sensor = T_world_sensor_prior;

  // The "local" frame: world axes, origin at the prior sensor position.
  const Eigen::Vector3d origin_world = T_world_sensor_prior.translation();
  Eigen::Isometry3d T_local_sensor_prior = T_world_sensor_prior;
  T_local_sensor_prior.translation().setZero();

  const auto [source, target] = local_clouds(points_sensor, T_local_sensor_prior, target_world, origin_world, config);

  const Cloud::Ptr source_coarse = downsample(source, config.voxel_m), target_coarse = downsample(target, config.voxel_m);
  const Cloud::Ptr source_fine = downsample(source, config.fine_voxel_m), target_fine = downsample(target, config.fine_voxel_m);
  result.source_points = source_fine->size();
  result.target_points = target_fine->size();
  for (const Cloud::Ptr& cloud : {source_coarse, target_coarse, source_fine, target_fine}) {
    if (cloud->size() < std::size_t(config.min_points)) {
      result.problem = "too few points to register (source " + std::to_string(source_coarse->size()) +
                       ", target near the prior " + std::to_string(target_coarse->size()) + ")";
      return result;
    }
  }

  const TargetSurface surface(target_fine);
  bool stopped = false;
  const Eigen::Matrix4f T_local_sensor =
      coarse_then_fine(config, source_coarse, target_coarse, *source_fine, surface,
                       T_local_sensor_prior.matrix().cast<float>(), result, stopped);

  const std::size_t inliers = measure_fitness(*source_fine, surface, T_local_sensor, config, result);

  Eigen::Isometry3d T_world_sensor(T_local_sensor.cast<double>());
  T_world_sensor.pretranslate(origin_world);
  if (!T_local_sensor.allFinite()) {
    result.problem = "the solver returned a non-finite transform";
    return result;
  }
  // The float matrix is near-orthonormal; make it exact.
  T_world_sensor.linear() = Eigen::Quaterniond(T_world_sensor.rotation()).normalized().toRotationMatrix();
  if (!stopped) {
    result.problem = "no convergence within " + std::to_string(config.max_iterations) + " iterations per pass";
    return result;
  }
  if (inliers == 0) {
    result.problem = "no source point lies within the correspondence limit of the target";
    return result;
  }
  Eigen::Isometry3d T_local_refined = T_world_sensor;
  T_local_refined.translation() -= origin_world;
  T_world_sensor = keep_prior_along_weak_directions(*source_fine, surface, T_local_sensor, T_local_sensor_prior,
                                                    T_local_refined, config, result);
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
