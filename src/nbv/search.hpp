#pragma once
// What the three strategies share: the grid, the position and orientation checks, scoring in
// parallel and the ranking. Private to src/nbv/.
#include <functional>
#include <limits>
#include <memory>

#include "fvx/map/dense_grid.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/utility/utility.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::nbv::detail {

constexpr std::size_t kNoCell = std::numeric_limits<std::size_t>::max();

/// A pose to score, with where it came from.
struct Pose {
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  /// Grid index of its viewpoint cell (stepped back: of the pose it stepped back from),
  /// where util(c) and the contributing frontier-voids are read.
  std::size_t cell = kNoCell;
  Eigen::VectorXd joints_rad;
  std::size_t stepped_back_from = kNoCell;  ///< refinement: the pose (index) it stepped back from
  std::size_t polished_from = kNoCell;      ///< polish: the pose (index) it was turned or moved from
};

/// Candidate cells in value order (descending; ties: index order), sorted as they are read:
/// a search reads a few dozen of a real map's millions of candidates, so each read past the
/// sorted part sorts the next chunk (nth_element, then sort; chunks double), in the order a
/// full sort gives. Measured on a 17 M-cell grid (slambook at 2.5 cm, 1.8 M candidates):
/// pruning took 0.34 s with a full sort, 0.035 s with this, the same views.
class CandidateOrder {
 public:
  CandidateOrder(std::vector<std::size_t> cells, const core::LargeVector<double>& value)
      : cells_(std::move(cells)), value_(&value) {}
  std::size_t size() const { return cells_.size(); }
  bool empty() const { return cells_.empty(); }
  /// The i-th cell in order; i < size().
  std::size_t operator[](std::size_t i);

 private:
  std::vector<std::size_t> cells_;
  const core::LargeVector<double>* value_;
  std::size_t sorted_ = 0;  ///< cells_[0, sorted_) are in their final order
};

struct Search {
  /// `hidden_void_cells`: void cells a taken view left unknown; they leave U (and u_i).
  Search(const map::OccupancyMap& map, const frontier_voids::Analysis& analysis, const std::optional<Reach>& reach,
         const Config& config, const std::vector<map::VoxelKey>& hidden_void_cells);

  /// No occupied cell centre within Config::clearance_m of the eye at p_world, in `cell`.
  bool clear_of_occupied(const map::VoxelKey& cell, const Eigen::Vector3d& p_world) const;
  /// Position checks in the paper's order, each counted in `pruning` when it fails.
  bool keep_position(const map::VoxelKey& cell, const Eigen::Vector3d& p_world, Pruning& pruning) const;
  /// The cells with a value > 0 that pass keep_position, by value (descending; ties: index
  /// order), each recorded in result.utility_field (Config::keep_utility_field) and counted
  /// in result.pruning. `value` must outlive the order.
  CandidateOrder prune(const core::LargeVector<double>& value, Result& result) const;
  /// Orientation checks: the capability map's bit, then IK when an arm is given (its
  /// restarts seeded by `pose_seed`); fills pose.joints_rad.
  bool keep_orientation(Pose& pose, std::uint64_t pose_seed, Pruning& pruning) const;

  /// A sampled rotation at candidate cell `cell` (centre p): snapped to the arm's reach, and
  /// appended to `poses` if keep_orientation() accepts it (IK seeded by the sample count).
  void add_pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R, std::size_t cell, Pruning& pruning,
                std::vector<Pose>& poses) const;

  /// The targets each pose sees (U with the void scorer), on config.threads threads (the
  /// same on any count); counts the poses, rays, cells visited and poses seeing nothing.
  /// `coarse` (screen_fan()): its rays in place of the scorer's own, and each pose's value
  /// its estimate of the full fan's U, rounded.
  std::vector<std::size_t> score(const viewpoints::FovScorer& scorer, const std::vector<Pose>& poses,
                                 Result& result, const viewpoints::CoarseFan* coarse = nullptr) const;
  /// Ranks by `score` (descending; ties: generation order), drops zeros and poses `accept`
  /// refuses (when given; it may fill the joints or move the pose), keeps config.top and
  /// describes each view (U with the full fan, void cells seen per cluster, contributors,
  /// joints); the described U ranks the views (frontier strategy: `score`). Screened
  /// (screen_fan(): `score` came from the coarse fan), a few more than config.top views
  /// are described.
  /// Poses that repeat a taken view (repeats_taken) are passed over, counted in `pruning`.
  std::vector<View> rank(std::vector<Pose>& poses, const std::vector<std::size_t>& score, Pruning& pruning,
                         const core::LargeVector<double>* util_m3, const utility::Field* field,
                         const std::function<bool(Pose&, std::size_t)>& accept = nullptr) const;
  /// The pose is the same view (same_view) as one in taken_views.
  bool repeats_taken(const Eigen::Isometry3d& T_world_sensor) const;
  /// Pose `i` as a view: U with the full fan, the field's value and contributors at its
  /// cell; the void cells seen go to `seen` (grid indices, ascending).
  View describe(const Pose& pose, std::size_t i, const core::LargeVector<double>* util_m3,
                const utility::Field* field, viewpoints::FovScorer::Workspace& ws,
                std::vector<std::size_t>& seen) const;
  /// Fills v.seen_void_cells and v.voids_seen from `seen` (grid indices, ascending): only for
  /// the views rank() keeps, as a real map's view sees 10^5 cells.
  void name_seen(View& v, const std::vector<std::size_t>& seen) const;
  /// fn(i, a thread's workspace) for i in [0, n), on config.threads threads (0: all cores);
  /// progress reported as `stage` when given.
  void parallel(std::size_t n, const std::function<void(std::size_t, viewpoints::FovScorer::Workspace&)>& fn,
                const char* stage = nullptr) const;
  /// The coarse fan that screens the frontier-void and exhaustive strategies' poses
  /// (Config::coarse_ray_cols), or null: every pose with the full fan.
  const viewpoints::CoarseFan* screen_fan() const { return fan_coarse.rays.empty() ? nullptr : &fan_coarse; }
  /// Exhaustive strategy, screened: a fan half as fine as the coarse one each way, which
  /// picks the poses the coarse fan scores (reference.cpp); null: none.
  const viewpoints::CoarseFan* prescreen_fan() const {
    return fan_prescreen.rays.empty() ? nullptr : &fan_prescreen;
  }

  /// Scoring's per-thread scratch (a bit per grid cell), kept across score() and rank()
  /// calls: a fresh one costs the kernel zeroed pages. Each score() leaves its bits clear.
  mutable std::vector<viewpoints::FovScorer::Workspace> workspaces;

  bool any_hidden = false;  ///< some void cell is hidden: u_i must be recounted (visible_utility)
  /// Whether the eye may stand in grid cell `i`: a free cell, or (Config::exterior) an
  /// unknown one outside the voids' hull.
  bool may_stand_in(std::size_t i) const {
    return grid.state_at(i) == map::VoxelState::Free || (!exterior_view.empty() && exterior_view[i]);
  }
  /// Config::exterior: marks the grid's unknown cells outside the voids' hull in
  /// exterior_view (and, with Exterior::Free, makes them free).
  void mark_exterior();
  core::LargeVector<std::uint8_t> void_mask() const;
  /// NearUnknown::Hidden's blocking cells (grid indices): the hidden cells, and every cell of
  /// a void (one a frontier touches) that holds a hidden cell. Read before the hidden cells
  /// leave void_label.
  std::vector<std::size_t> blocking_cells(const std::vector<map::VoxelKey>& hidden_void_cells) const;
  /// A copy of the analysis with each frontier-void's u_i counting only the void cells U
  /// counts (the hidden void cells left out).
  frontier_voids::Analysis visible_utility() const;

  /// With an arm, turns the rotation's optical axis to the nearest direction the capability
  /// map reaches at p, if the aim stays inside the image (a 5-DOF arm reaches only an arc of
  /// directions, so most raw samples would be refused). Without one: R unchanged.
  Eigen::Matrix3d snap_to_reach(const Eigen::Vector3d& p_world, const Eigen::Matrix3d& R) const;

  // The map is read in the constructor only (the grid, the distance transform, the frontier
  // strategy's unknown sides): fvx replay integrates the next scan while a search runs.
  const frontier_voids::Analysis& a;
  const std::optional<Reach>& reach;
  const Config& config;
  Eigen::AlignedBox3d known_m;                   ///< the box of the map's known cells (empty map: empty)
  Eigen::AlignedBox3d view_bounds_m;
  /// Where keep_position can hold: the view bounds, within the box of the arm's reachable
  /// voxels. Algorithm 1's field is read only here.
  Eigen::AlignedBox3d candidate_box_m;
  map::DenseGrid grid;
  core::LargeVector<std::int32_t> void_label;         ///< per grid cell: void cluster id, −1 elsewhere
  /// Per grid cell: to the nearest occupied cell, cells²; +infinity beyond the clearance + 1 cell.
  core::LargeVector<float> occupied_distance_sq;
  /// Per cell, 1 where a viewpoint may stand in an unknown cell outside the voids' hull
  /// (Config::exterior); empty with Exterior::Unknown.
  core::LargeVector<std::uint8_t> exterior_view;
  std::vector<Eigen::Vector3d> rays_sensor;
  viewpoints::CoarseFan fan_coarse;     ///< screen_fan(); no rays: off
  viewpoints::CoarseFan fan_prescreen;  ///< prescreen_fan(); no rays: none
  double half_fov_rad = 0.0;                     ///< the smaller half-angle of the image
  std::unique_ptr<viewpoints::FovScorer> void_scorer;
  /// Strategy Frontier: the largest frontier cluster (ties: the lower id), and per cell of it
  /// the sum of the unit steps to its unknown face-neighbours (zero: none), read from the map.
  const frontiers::Cluster* frontier_target = nullptr;
  std::vector<Eigen::Vector3d> toward_unknown;
  /// Where the loop's views were taken (PreparedSearch): copied, as the loop goes on.
  std::vector<Eigen::Isometry3d> taken_views;
};

/// A pose at p_world with rotation R that serves the same cell as `from` (index from_index).
Pose moved(const Pose& from, const Eigen::Vector3d& p_world, const Eigen::Matrix3d& R, std::size_t from_index);
/// After the N sampled poses are scored: the refinement (stepping back), the polish (other
/// rolls) and the climb (refine.cpp, Config); appends the new poses and their U.
void refine(const Search& s, std::vector<Pose>& poses, std::vector<std::size_t>& U, Result& result);

/// Algorithm 1 (utility::accumulate) over the search's grid, timed into `result`.
utility::Field accumulate_field(const Search& s, Result& result);
/// The paper's method after Algorithm 1: pruning, orientations, U (Eq. 3), refinement.
Result select_frontier_void(Search& s, const utility::Field& field, Result result);
Result select_exhaustive(Search& s, Result result);
Result select_frontier(Search& s, Result result);
Result select_random(Search& s, Result result);

}  // namespace fvx::nbv::detail
