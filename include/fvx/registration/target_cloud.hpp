#pragma once
/// \file
/// The cloud that new scans are registered to (paper §IV step 2): the points of the scans
/// integrated so far, one per cell of a fixed world grid (the mean of the points that fell in
/// it). Kept per cell, its size grows with the surface seen, not with the number of scans:
/// appended per scan, 211 Redwood frames made 3 M points that every registration cropped and
/// resampled again (0.1 s per frame at the start of the sequence, 0.3 s and more at its end).
#include <Eigen/Geometry>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace fvx::registration {

class TargetCloud {
 public:
  /// `cell_m` > 0: one point per cell of that edge (world grid); 0: every point is kept.
  explicit TargetCloud(double cell_m = 0.0);
  /// Adds finite `points_sensor` placed by `T_world_sensor`.
  void add(const Eigen::Isometry3d& T_world_sensor, const std::vector<Eigen::Vector3d>& points_sensor);
  /// Adds finite world points.
  void add(const std::vector<Eigen::Vector3f>& points_world);
  /// World frame, one per cell in the order the cells were first seen.
  const std::vector<Eigen::Vector3f>& points() const { return means_; }
  bool empty() const { return means_.empty(); }
  double cell_m() const { return cell_m_; }

 private:
  void add_point(const Eigen::Vector3d& p_world);
  struct CellHash {
    std::size_t operator()(const Eigen::Vector3i& k) const {
      return std::size_t(std::uint32_t(k.x())) * 73856093u ^ std::size_t(std::uint32_t(k.y())) * 19349663u ^
             std::size_t(std::uint32_t(k.z())) * 83492791u;
    }
  };
  struct CellEqual {
    bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const { return a == b; }
  };
  double cell_m_;
  std::unordered_map<Eigen::Vector3i, std::uint32_t, CellHash, CellEqual> cells_;  ///< cell → index
  std::vector<Eigen::Vector3d> sums_;
  std::vector<std::uint32_t> counts_;
  std::vector<Eigen::Vector3f> means_;
};

}  // namespace fvx::registration
