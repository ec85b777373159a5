#pragma once
/// \file
/// Void clusters (paper §IV-B, Eq. 1–2): void cells grouped by seeded region growing into
/// ellipsoid-shaped clusters.
///
/// The paper's fit score divides by 4/3·π·λ1·λ2·λ3, which has the wrong unit (λ are
/// variances). fvx uses semi-axes a_j = sqrt(5·λ_j) — a uniformly filled ellipsoid has
/// variance a²/5 along each axis — so that S = N·R³ / (4/3·π·a1·a2·a3) is about 1 for a
/// well-filled ellipsoid (ARCHITECTURE.md §3). λ_j are the eigenvalues of the covariance of
/// the cell centres plus R²/12, each cell's own extent (a cube's variance): a single cell
/// scores 0.89, like any filled box, and flat clusters keep a finite score.
#include "fvx/core/json.hpp"
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::voids {

struct ClusterConfig {
  /// Region growing adds a neighbouring void cell while the fit score stays at or above
  /// this. Default 0.7: boxes (0.89) and ellipsoids (1.0) grow whole, an L of two boxes splits.
  double min_fit_score = 0.7;
  /// Seed of the order in which cells start clusters. Default 1.
  std::uint64_t seed = 1;
  /// Called with ("clustering void cells", cells clustered, cells) each time progress_cells
  /// more are clustered: on maps where that takes long (tens of millions of void cells: a
  /// minute). Neither is part of a report.
  std::function<void(const std::string& stage, std::size_t done, std::size_t total)> progress;
  std::size_t progress_cells = std::size_t(1) << 22;

  std::vector<std::string> validate() const;
};

/// {"min_fit_score", "seed"}, as a report echoes them.
Json config_json(const ClusterConfig& c);

struct VoidCluster {
  int id = 0;
  std::vector<map::VoxelKey> cells;         ///< in key order
  Eigen::Vector3d mean_m = Eigen::Vector3d::Zero();          ///< μ
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();        ///< eigenvectors e_j as columns
  Eigen::Vector3d variances_m2 = Eigen::Vector3d::Zero();    ///< λ_j (with the cell extent)
  Eigen::Vector3d semi_axes_m = Eigen::Vector3d::Zero();     ///< a_j = sqrt(5·λ_j)
  double volume_m3 = 0;                     ///< N·R³: the utility u_i
  double fit_score = 0;                     ///< S_i (Eq. 2)

  /// μ and μ ± a_j·e_j: the points Algorithm 1 casts utility vectors from.
  std::array<Eigen::Vector3d, 7> corners() const;
};

/// Clusters `cells` (key order). Every cell ends in exactly one cluster; ids 0, 1, … follow
/// the clusters' smallest keys, so the same input gives the same clusters.
std::vector<VoidCluster> cluster_voids(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                       const ClusterConfig& config);
/// cluster_voids through a key index whatever the cells' density: its path for cells that
/// fill little of their box, and the oracle of its dense path (labels in the box; tests).
std::vector<VoidCluster> cluster_voids_indexed(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                               const ClusterConfig& config);

}  // namespace fvx::voids
