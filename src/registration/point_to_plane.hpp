#pragma once
// Private to the registration stage: the fine pass, a robust point-to-plane Gauss–Newton
// (iteratively reweighted least squares with the Geman–McClure kernel) against the target's
// local planes. GICP's plane-to-plane cost has no robust kernel: the parts of a scan the map
// has not seen pull it towards more overlap, centimetres off the truth on the bundled
// scenes. With a robust kernel they saturate instead, and the true pose has the lower cost.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "fvx/registration/observability.hpp"

namespace fvx::registration {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// Target points with their local planes (PCA of the 12 nearest target points). Neighbours
/// come from a nanoflann k-d tree (nearest.hpp says why).
class TargetSurface {
 public:
  explicit TargetSurface(const Cloud::ConstPtr& cloud);
  ~TargetSurface();
  /// Index of the nearest target point within sqrt(limit_sq), or -1.
  int nearest(const Eigen::Vector3f& q, float limit_sq, float& distance_sq) const;
  /// nearest(), given a target point `hint` (or -1) that is probably near q: the search
  /// starts with the hint's distance as its bound, which no nearer point can exceed, so
  /// that it prunes from the first node instead of from the first leaf. Between Gauss–
  /// Newton iterations a source point's partner rarely moves by more than a neighbour.
  int nearest_near(const Eigen::Vector3f& q, float limit_sq, int hint, float& distance_sq) const;
  const Cloud& cloud() const { return *cloud_; }
  bool planar(int i) const { return planar_[std::size_t(i)] != 0; }
  const Eigen::Vector3f& normal(int i) const { return normals_[std::size_t(i)]; }

 private:
  struct Tree;
  Cloud::ConstPtr cloud_;
  std::unique_ptr<Tree> tree_;
  std::vector<Eigen::Vector3f> normals_;
  std::vector<std::uint8_t> planar_;
};

struct FineConfig {
  float limit_m;          ///< correspondence limit
  double scale_m;         ///< Geman–McClure scale σ
  int max_iterations;
  double translation_epsilon_m;
  double rotation_epsilon_rad;
  double min_observability;  ///< steps are taken only along directions at least this strong
  double length_scale_m;     ///< rotation ↔ translation units of the observability analysis
};

struct FineFit {
  Eigen::Matrix4f T_local_sensor = Eigen::Matrix4f::Identity();
  double cost = 1.0;   ///< mean robust cost, see robust_cost()
  int iterations = 0;
  bool converged = false;
};

/// Mean over all source points of ρ(r) = r² / (σ² + r²): r is the distance to the target's
/// plane where the nearest target point is planar, to that point otherwise; a point without
/// a partner within the limit costs 1, the most any point can.
double robust_cost(const Cloud& source, const TargetSurface& target, const Eigen::Matrix4f& T, const FineConfig& c);

/// Robust costs of two poses over the source points matched at both (mean ρ(r) over that
/// common set). A cost that charges unmatched points rewards overlap: a scan's floor beyond
/// the map's edge is unmatched at the true pose and matched (on the same plane) once the
/// pose slides towards the map, so the slid pose looked cheaper by every whole-scan cost.
/// Returns {1, 1} when fewer than 30 points are common.
std::pair<double, double> compare_on_common_points(const Cloud& source, const TargetSurface& target,
                                                   const Eigen::Matrix4f& T_a, const Eigen::Matrix4f& T_b,
                                                   const FineConfig& c);

/// Iterates from `T_start` until the update is below the epsilons or the cap is reached. Each
/// Gauss–Newton step is solved only in the directions the matched planes constrain
/// (information per point >= min_observability, Zhang et al. 2016): along the others the
/// pose does not move, where it would otherwise drift, match aliased surfaces, and end up
/// somewhere that merely looks constrained.
FineFit refine_point_to_plane(const Cloud& source, const TargetSurface& target,
                              const Eigen::Matrix4f& T_start, const FineConfig& c);

/// Point-to-plane constraints of the aligned source (points matched to planar target points),
/// and the median range of those points (the length scale of Observability).
std::vector<PlaneConstraint> plane_constraints(const Cloud& source, const TargetSurface& target,
                                               const Eigen::Matrix4f& T, float limit_m, double& length_scale_m);

}  // namespace fvx::registration
