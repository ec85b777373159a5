#pragma once
/// \file
/// Stage `viewpoints`, part 1: the sensor's field of view traced through the map (paper
/// §IV-C). U_i of a pose = the distinct void cells its rays cross; rays of a decimated pixel
/// grid pass free and unknown cells and stop at an occupied cell, at the depth limit or at
/// the grid's edge (ARCHITECTURE.md §3). An unknown cell may hide a surface, so U_i is what
/// the view can reveal at best. A ray that ends on an occupied cell nearer than the sensor's
/// minimum depth measures nothing (a Kinect returns no depth there) and reveals nothing.
/// Optionally (`near_targets_count` false) target cells nearer than the minimum depth do not
/// count either: whether the ray measures anything beyond them is not known, and a surface
/// hidden in the unknown within the minimum depth leaves the whole ray blank.
/// NearUnknown decides what an unknown cell nearer than the minimum depth does to its ray.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "fvx/io/intrinsics.hpp"
#include "fvx/core/large_vector.hpp"
#include "fvx/map/dense_grid.hpp"

namespace fvx::viewpoints {

/// Rays through `cols` × `rows` pixels spread evenly over the image (pixel centres of the
/// decimated grid), sensor optical frame, scaled to z = 1 so that `depth · ray` is the point
/// at depth z.
std::vector<Eigen::Vector3d> ray_fan(const io::Intrinsics& K, int cols, int rows);

/// The area one ray of ray_fan(K, cols, rows) stands for on the plane at 1 m depth, m²
/// (its pixel block's width and height over the focal lengths); at depth z it is z² times this.
double ray_area_at_1m(const io::Intrinsics& K, int cols, int rows);

/// A fan coarser than the scorer's own that screens poses (nbv: 40 × 30 rays for 80 × 60),
/// with what it needs to estimate the finer fan's U from its own hits.
///
/// Why: far from the eye a coarse fan's rays pass between cells that the finer fan's rays
/// cross, so its plain count ranks near poses above far ones that see more. On the replicas'
/// poses its counts were a quarter to all of the full fan's (Spearman ρ 0.57–0.81 against the
/// full U), which dropped the best view out of the poses the full fan rescores.
/// How: rays along a unit direction d that stand for an area a each (at the cell's depth)
/// cross a cell of side c with probability p = min(1, σ/a), σ = c²(|d_x| + |d_y| + |d_z|) the
/// cell's shadow across d (c² along an axis, 1.5 c² on average over directions: Cauchy).
/// A cell the coarse fan counts stands for p_full / p_coarse cells of the full fan (an
/// inverse-probability weight, Horvitz–Thompson), so the sum over its cells estimates the
/// full fan's U: 1 per cell where both fans cross every cell, the ratio of their ray counts
/// where neither does.
struct CoarseFan {
  std::vector<Eigen::Vector3d> rays;  ///< ray_fan()'s, sensor frame, z = 1
  double ray_area_at_1m2 = 0.0;       ///< ray_area_at_1m() of this fan
  double full_ray_area_at_1m2 = 0.0;  ///< … of the fan whose U it estimates
  double cell_m = 0.0;                ///< the grid's resolution

  /// The full fan's expected hits per hit of this fan on a cell whose centre lies depth_m
  /// deep, crossed by a ray whose unit world direction d has shadow_factor = |d_x| + |d_y| +
  /// |d_z| (σ / c²; the scorer takes it once per ray).
  double full_hits_per_hit(double depth_m, double shadow_factor) const;
};
/// `cols` × `rows` rays of K that estimate the U of a `full_cols` × `full_rows` fan on a grid
/// of `cell_m` cells.
CoarseFan coarse_fan(const io::Intrinsics& K, int cols, int rows, int full_cols, int full_rows, double cell_m);

/// R_world_sensor whose optical axis (z) is `direction_world` (any length), turned by
/// `roll_rad` about it. Roll 0 keeps the image upright: its −y axis as close to world +z as
/// the direction allows (looking straight up or down, world +x stands in).
Eigen::Matrix3d look_along(const Eigen::Vector3d& direction_world, double roll_rad);

/// What an unknown cell nearer than the sensor's minimum depth (its centre's depth) does to
/// the ray that crosses it. A surface hidden there ends the ray before the minimum depth, and
/// the Kinect then measures nothing along it: in the suite, 63 of 336 views chosen while such
/// rays counted measured no pixel at all (README, "Exploration over a scene suite").
enum class NearUnknown {
  Ignore,  ///< nothing: the ray counts as if the cell were free
  Void,    ///< a target cell (a void cell) there leaves the ray counting nothing
  Any,     ///< any unknown cell there leaves the ray counting nothing
  /// a blocking cell there (FovScorer::set_blocking: in the loops, a void cell a taken view
  /// was expected to reveal and left unknown, or any cell of its void) leaves the ray counting
  /// nothing: the rule applies where a view has shown that something hides (nbv::Config's
  /// default)
  Hidden,
};
const char* to_string(NearUnknown mode);
/// "ignore", "void", "any" or "hidden"; UsageError naming `what` otherwise.
NearUnknown parse_near_unknown(const std::string& name, const std::string& what);

/// Counts the target cells (void cells, or a frontier cluster's cells) a pose sees.
class FovScorer {
 public:
  /// `target`: per grid cell (DenseGrid index), non-zero where a cell counts. The grid must
  /// outlive the scorer.
  /// `near_targets_count`: false drops targets nearer than depth_min_m (see the file comment).
  FovScorer(const map::DenseGrid& grid, core::LargeVector<std::uint8_t> target, std::vector<Eigen::Vector3d> rays_sensor,
            double depth_max_m, double depth_min_m = 0.0, bool near_targets_count = true);

  /// Scratch space of one thread: a bit per grid cell, set for the targets the pose being
  /// scored has counted, so each counts once (a bit stays in the cache on real maps, where a
  /// 32-bit stamp per cell did not), cleared again through `counted`.
  struct Workspace {
    std::vector<std::uint64_t> counted_bits;
    std::vector<std::size_t> counted;      ///< the cells whose bit is set
    std::vector<std::size_t> ray_targets;  ///< targets of the ray being traced
  };

  struct Score {
    std::size_t targets_seen = 0;       ///< U: distinct target cells crossed
    /// Scored with a CoarseFan: its estimate of the full fan's U; otherwise targets_seen.
    double full_fan_estimate = 0.0;
    std::uint64_t cells_visited = 0;    ///< cells the rays walked (for the cells/s figure)
  };
  /// Traces every ray from `T_world_sensor`; when `seen` is given, it receives the grid
  /// indices of the target cells seen, ascending. `coarse`: its rays in place of the
  /// scorer's own, to screen poses (Score::full_fan_estimate).
  Score score(const Eigen::Isometry3d& T_world_sensor, Workspace& workspace, std::vector<std::size_t>* seen = nullptr,
              const CoarseFan* coarse = nullptr) const;

  const map::DenseGrid& grid() const { return grid_; }
  std::size_t ray_count() const { return rays_sensor_.size(); }

  /// Counts only the first `cells` unknown cells of each ray (0: every one, the paper's U).
  /// The first unknown cell a ray reaches through known free cells is revealed for sure
  /// (a surface in it is measured, or the ray passes on and clears it); beyond it, an unknown
  /// cell may hide a surface. A ray cut this way nearer than the minimum depth counts nothing.
  void set_unknown_depth(int cells) { unknown_depth_ = cells; }
  /// What an unknown cell nearer than the minimum depth does to its ray (NearUnknown).
  void set_near_unknown(NearUnknown mode) { near_unknown_ = mode; }
  /// The cells (grid indices) that block a ray nearer than the minimum depth under
  /// NearUnknown::Hidden while they are unknown.
  void set_blocking(const std::vector<std::size_t>& cells);

 private:
  /// The cells of ws.counted, ascending.
  static void ascending(const Workspace& ws, std::vector<std::size_t>& seen);

  const map::DenseGrid& grid_;
  /// Per grid cell: its VoxelState in the low two bits, kTarget when it is a target: the
  /// walk loads one byte per cell.
  core::LargeVector<std::uint8_t> cells_;
  static constexpr std::uint8_t kTarget = 4;
  static constexpr std::uint8_t kBlocking = 8;  ///< set_blocking
  /// The box of the target cells (as cubes, half a cell wider for rounding): a ray is walked
  /// only until it leaves it (or to the minimum depth, where a surface voids the ray), and
  /// not at all when it misses it.
  Eigen::AlignedBox3d target_box_m_;
  std::vector<Eigen::Vector3d> rays_sensor_;
  double depth_max_m_;
  double depth_min_m_;
  double count_from_m_;  ///< targets nearer than this (depth) do not count
  int unknown_depth_ = 0;  ///< unknown cells counted per ray, 0: all
  NearUnknown near_unknown_ = NearUnknown::Ignore;
  double diagonal_m_;  ///< a cell's diagonal
};

}  // namespace fvx::viewpoints
