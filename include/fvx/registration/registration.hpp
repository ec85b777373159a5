#pragma once
/// \file
/// Stage `registration` (paper §IV step 2): align a new scan to the map's accumulated cloud
/// with PCL, starting from its pose prior. PCL stays in the .cpp.
#include "fvx/core/json.hpp"
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace fvx::registration {

enum class Method {
  Gicp,  ///< generalized ICP (plane-to-plane); default: converges where point-to-point stalls
  Icp,   ///< PCL point-to-point ICP
};
const char* to_string(Method method);
/// "gicp" or "icp"; throws UsageError naming `what` otherwise.
Method parse_method(const std::string& text, const std::string& what);

struct Config {
  Method method = Method::Gicp;
  /// Downsampling voxel of the coarse pass (source and target), metres; 0 disables it.
  /// Default 0.05 (0.15 s per Kinect frame with GICP).
  double voxel_m = 0.05;
  /// Coarse pass: pairs farther apart than this are not correspondences, metres. It bounds
  /// the pose error that can be corrected in one step (a 10° error moves a point at 2 m by
  /// 0.35 m; iterations recover more). Larger limits pair unseen parts of the scan with
  /// wrong partners: on the box-room sample 0.5 m pulled perfect priors 8 cm off, 0.3 m kept
  /// them within 3 mm. Default 0.3.
  double max_correspondence_m = 0.3;
  /// Fine pass, from the coarse result: the correspondence limit, metres. Points of the scan
  /// that the map has not seen yet find a wrong partner within the coarse limit and bias the
  /// coarse pass by centimetres; the fine pass ignores them. Also the limit for fitness and
  /// inliers. Default 0.1; a value >= max_correspondence_m runs one pass.
  double fine_correspondence_m = 0.1;
  /// Scale σ of the fine pass's Geman–McClure kernel, metres: residuals well beyond it
  /// (parts of the scan the map has not seen) stop pulling. Default 0.02, above Kinect noise
  /// at 3 m.
  double robust_scale_m = 0.02;
  /// Downsampling voxel of the fine pass, metres; 0 disables it. At the coarse voxel, plane
  /// edges sampled by 5 cm voxels biased translations by 1–3 cm on the box-room sample; at
  /// 2.5 cm the error stayed under 3 mm. Default 0.025.
  double fine_voxel_m = 0.025;
  /// Iteration cap; stopping at the cap counts as not converged. Default 60.
  int max_iterations = 60;
  /// Convergence: the update's translation is below this, metres. Default 1e-4.
  double translation_epsilon_m = 1e-4;
  /// Convergence: the update's rotation is below this, radians. Default 1e-4.
  double rotation_epsilon_rad = 1e-4;
  /// Directions of the correction whose information per constraint (observability.hpp) is
  /// below this are left at the prior. Default 0.005: a room seen from the side whose far
  /// walls the map lacks scored 0.0001–0.005 along its unseen axis (and drifted 2 cm there);
  /// real Kinect frames of cluttered scenes scored 0.006 and more in every direction.
  double min_observability = 0.005;
  /// Fewer source or target points than this after downsampling: registration is skipped.
  int min_points = 30;

  std::vector<std::string> validate() const;
};

/// Every setting, as a report echoes it.
Json config_json(const Config& c);

struct Result {
  /// Refined pose; the prior when not converged.
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  bool converged = false;          ///< stopped by the epsilons before the iteration cap
  int iterations = 0;              ///< iterations the solver ran
  double fitness_rmse_m = 0.0;     ///< RMS distance of aligned source points to their nearest
                                   ///< target point, over pairs within fine_correspondence_m
  double inlier_fraction = 0.0;    ///< share of source points with such a pair
  double correction_translation_m = 0.0;  ///< |t(refined) − t(prior)|
  double correction_rotation_deg = 0.0;   ///< angle of R(refined)·R(prior)ᵀ
  std::size_t source_points = 0;   ///< after downsampling for the last pass
  std::size_t target_points = 0;   ///< after cropping and downsampling for the last pass
  /// Directions the geometry barely constrains ("translation along (1, 0, 0)"), world
  /// axes; the correction along them was dropped and the pose kept its prior there.
  std::vector<std::string> weak_directions;
  /// Where the fine pass started from that won: "prior" or "coarse".
  std::string fine_start;
  std::string problem;             ///< why it did not converge; empty when it did
};

/// Aligns `points_sensor` (sensor frame) to `target_world` (world frame) from
/// `T_world_sensor_prior`. The target is cropped to the prior-placed source's bounding box
/// grown by max_correspondence_m. Work is done relative to the prior's position so that
/// PCL's float arithmetic keeps millimetres far from the world origin.
Result align(const std::vector<Eigen::Vector3d>& points_sensor,
             const Eigen::Isometry3d& T_world_sensor_prior,
             const std::vector<Eigen::Vector3f>& target_world, const Config& config);

}  // namespace fvx::registration
