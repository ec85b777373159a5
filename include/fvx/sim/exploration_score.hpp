#pragma once
/// \file
/// Scores a map against a scene's ground truth during an exploration: how much of the
/// observable empty space of the search space is known, and whether the hidden target was
/// seen.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "fvx/io/intrinsics.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "fvx/sim/scene.hpp"

namespace fvx::sim {

class ExplorationScore {
 public:
  /// Occupied map cells inside the target box (above its lowest cell, the floor it stands
  /// on) needed to count the target as seen.
  static constexpr std::size_t kTargetCellsSeen = 5;

  /// `gt` must cover the search space. Observable cells: cells of the search space that are
  /// empty in the ground truth and connected through empty cells (6-connectivity, within
  /// the ground truth's region) to the region's border — the air a sensor outside can reach
  /// with a ray. A sealed cavity is not observable; neither is a cell that only a sensor
  /// inside the search space could see, which no planner is denied here.
  /// Observable void cells: the observable cells inside the convex hull of the ground
  /// truth's solid cell centres in S — the voids' own rule (voids::void_cells: unknown cells
  /// inside the hull of the occupied cells) applied to the complete scene: what a map that
  /// knew every surface of S and nothing else would call void.
  ExplorationScore(const GroundTruth& gt, const Eigen::AlignedBox3d& search_space_m,
                   std::optional<Eigen::AlignedBox3d> target_m);

  /// Keeps only the observable cells that a sensor at one of `T_world_sensor` would reveal:
  /// cells a ray (rays_sensor, scaled to depth 1) crosses before it hits a solid cell at a
  /// depth within [depth_min_m, depth_max_m] — the Kinect's own rule, on the ground truth.
  /// With the poses an arm can reach, this is what that arm can observe at all. Poses
  /// outside the ground truth's region see nothing: make the region hold them.
  void restrict_to_views(const GroundTruth& gt, const std::vector<Eigen::Isometry3d>& T_world_sensor,
                         const std::vector<Eigen::Vector3d>& rays_sensor, double depth_min_m, double depth_max_m,
                         unsigned threads = 0);

  /// The target's surface cells (in its box above its lowest cell) that some of the poses
  /// would measure with the full image: per pose, pixel rays through the target box's image
  /// (at most 16 × 16, evenly spread) cast on the scene's mesh as the renderer does; a first
  /// hit within [depth_min_m, depth_max_m] marks the cell (edge `resolution_m`) holding the
  /// point, as the map's integration would. Adds to what restrict_to_views' coarse fan found:
  /// a fan of 20 × 15 rays passes between the cells of a small target.
  void restrict_target_to_views(const RayCaster& caster, const std::vector<Eigen::Isometry3d>& T_world_sensor,
                                const io::Intrinsics& intrinsics, double depth_min_m, double depth_max_m,
                                double resolution_m, unsigned threads = 0);

  std::size_t observable_cells() const { return observable_.size(); }
  /// The observable cells' centres (world frame), in the order the constructor found them.
  const std::vector<Eigen::Vector3d>& observable_centres_m() const { return observable_; }
  /// Observable cells inside the hull of the scene's surfaces in S (see the constructor).
  std::size_t observable_void_cells() const;
  /// Those cells' centres (world frame), in the order the constructor found them.
  std::vector<Eigen::Vector3d> observable_void_centres_m() const;
  /// After restrict_to_views: the target's surface cells (in its box above its lowest cell)
  /// that some of those poses would measure. 0: no pose of the arm can see the target; empty
  /// without a target (no warning is due then).
  std::optional<std::size_t> observable_target_cells() const { return observable_target_cells_; }
  /// Observable cells the map knows (free or occupied), as a share of all observable cells.
  double known_fraction(const map::OccupancyMap& map) const;
  /// Observable void cells the map knows, as a share of all of them (1 when there are none):
  /// the exploration's headline, since the paper's method looks for exactly those cells.
  double void_known_fraction(const map::OccupancyMap& map) const;
  /// Occupied map cells in the target box above its lowest cell (0 without a target).
  std::size_t target_cells_seen(const map::OccupancyMap& map) const;
  bool target_seen(const map::OccupancyMap& map) const { return target_cells_seen(map) >= kTargetCellsSeen; }

 private:
  std::vector<Eigen::Vector3d> observable_;  ///< cell centres, world frame
  std::vector<bool> in_hull_;                ///< per observable cell: inside the scene's hull
  std::optional<Eigen::AlignedBox3d> target_m_;
  std::optional<std::size_t> observable_target_cells_;
};

}  // namespace fvx::sim
