#pragma once
/// \file
/// Stage `nbv` (paper §IV-C, Algorithm 1 and Eq. 3): the next best view. The utility field
/// (Algorithm 1) is pruned to cells a sensor can occupy — free, clear of obstacles, inside
/// the view bounds, reachable by the arm according to its capability map placed at
/// T_world_base — and sorted by utility; orientations are sampled at the cells in that order,
/// those the arm reaches are scored by tracing the field of view (U = void cells seen), the
/// search stops after N valid poses, and c* = argmax U (Eq. 3).
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/json.hpp"
#include "fvx/capmap/viewing_ik.hpp"
#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/utility/utility.hpp"
#include "fvx/viewpoints/fov.hpp"

namespace fvx::nbv {

enum class Strategy {
  FrontierVoid,  ///< the paper's method
  Exhaustive,    ///< reference: every reachable voxel and direction of the capability map, scored alike
  Frontier,      ///< reference: plain frontier-based — view the largest frontier cluster, no voids
  Random,        ///< reference: a random reachable pose that sees at least one void cell
};
const char* to_string(Strategy s);
/// "frontier-void", "exhaustive", "frontier", "random"; UsageError naming `what` (the option
/// or file it came from) otherwise.
Strategy parse_strategy(const std::string& name, const std::string& what = "--strategy");

/// Where the arm stands and what it can reach. Without one, the sensor flies free.
struct Reach {
  const capmap::CapabilityMap* capmap = nullptr;                 ///< required
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();  ///< the capability map's base in the world
  /// Optional: the arm the map was built for. Each pose must then pass IK, which gives its
  /// joint configuration.
  const capmap::Arm* arm = nullptr;
  capmap::IkConfig ik;
};

/// Unknown cells outside the voids' hull (frontier_voids::Analysis::hull), where no void
/// lies. On scenes without walls a Kinect never clears the air above them (a ray without a
/// return clears nothing), and the views that look into open containers from above stand in
/// that air (README, "Exploration over a scene suite").
/// - Unknown (the paper's): the eye stands in a known free cell; Algorithm 1's rays stop there.
/// - View (the default): a viewpoint may also stand in such a cell (the same clearance from
///   occupied cells), and without view bounds anywhere in the arm's reach within the sensor's
///   range of the search space, not only in the known cells' box;
///   Algorithm 1 is the paper's, so candidates come from its field and their stepped-back,
///   rolled and climbed poses reach the air. What MoveIt's collision checking assumes of
///   unknown space. U still sees the cells as unknown (NearUnknown::Any and
///   unknown_depth_cells cut rays there).
/// - Free: as View, and the cells are free for Algorithm 1's rays and for U.
enum class Exterior { Unknown, View, Free };
const char* to_string(Exterior mode);
/// UsageError naming `what` unless `name` is unknown, view or free.
Exterior parse_exterior(const std::string& name, const std::string& what);

struct Config {
  Strategy strategy = Strategy::FrontierVoid;
  io::DepthCamera sensor;             ///< intrinsics and depths; depth_max_m is s_r. Default Kinect v1
  int ray_cols = 80;                  ///< field-of-view rays across the image (decimated pixel grid)
  int ray_rows = 60;                  ///< … and down it
  /// Screening (not in the paper): the frontier-void strategy scores its sampled, stepped-
  /// back and rolled poses (exhaustive: every pose) with this coarser fan, then scores the
  /// best of them with the full fan (ray_cols × ray_rows) to rank the views it reports.
  /// 0 × 0: every pose with the full fan. A view's U counts what its rays cross, so a
  /// quarter of the rays counts fewer cells, yet ranks poses alike (README, "Screening").
  int coarse_ray_cols = 40;
  int coarse_ray_rows = 30;
  /// Screened, the full fan rescores this many of the best screened poses (passing over
  /// those that repeat a taken view), and the `top` best of them are reported. 0: top +
  /// min(top, 10). The loops rescore N + 10 (Config::tie_to_search in pipeline): the views
  /// they take are then those of a search that described every valid pose (README, issue 15).
  int rescored_poses = 0;
  static constexpr int kRescoredBeyondTop = 10;  ///< the "10" above: poses rescored beyond top
  int valid_poses = 50;               ///< N: the search stops after this many valid poses (paper: 50)
  int orientations_per_cell = 2;      ///< orientations sampled at each candidate cell
  double jitter_deg = 5.0;            ///< tilt of sampled axes around their target, degrees
  double clearance_m = 0.1;           ///< no occupied cell this close to a viewpoint, metres
  /// Cells nearer than this to a viewpoint that already gave a valid pose are passed over,
  /// so that the N poses spread over the useful region instead of piling up in its densest
  /// cells, metres. 0: every cell in utility order.
  double min_separation_m = 0.15;
  /// Refinement (not in the paper): the `refine_poses` best scored poses are stepped back
  /// along their optical axis by refine_step_m up to refine_max_m, and each step that passes
  /// the same pruning and reach checks is scored too. Utility piles up next to the frontier,
  /// where the view cone is narrowest; stepping back widens it. 0: off.
  int refine_poses = 10;
  double refine_step_m = 0.1;
  double refine_max_m = 0.8;
  /// Polish (not in the paper): an orientation's roll about its optical axis is drawn at
  /// random, yet the image is not square, so the same axis at another roll sees other cells
  /// (on real maps the U of one axis moves by 10-15 % with the roll). The `polish_poses`
  /// best poses after refinement are also scored at polish_rolls − 1 more rolls, evenly
  /// over 180° (the image is symmetric under a half turn). 0: off.
  int polish_poses = 3;
  int polish_rolls = 6;
  /// Climb (not in the paper): from each of the polish_poses best poses after the polish (at
  /// least one), each round scores it moved by ±climb_step_m along each world axis and
  /// tilted by ±climb_angle_deg about the image axes, and moves to the best if it sees more;
  /// otherwise its step and tilt halve. 0: off (the default). Measured: it raises the best
  /// U by 1-17 % on real maps, for 0.3 s more scoring there, but it favours whichever field's
  /// candidates start in the higher basin: on a small map with a tenth of its vectors sampled
  /// the sampled path then averaged 91 % of the exact path's best U (100 % without it).
  int climb_rounds = 0;
  double climb_step_m = 0.05;
  double climb_angle_deg = 4.0;
  /// The sensor stays in this box (metres); default: the box of the map's known cells.
  std::optional<Eigen::AlignedBox3d> view_bounds_m;
  int exhaustive_rolls = 2;           ///< exhaustive: rolls per direction (0, 90°, … over 180°)
  int random_tries = 1000;            ///< random: valid poses drawn at most, until one sees a void cell
  /// Count void cells nearer than the sensor's minimum depth in U (the original design's §3:
  /// every void cell crossed), and let Algorithm 1 add utility from the frontier cell on; the
  /// default of every command. false (--far-voids-only): only cells at depth_min_m or beyond
  /// count, and a utility vector adds utility only from depth_min_m beyond its frontier cell
  /// (utility::Config::min_range_m) — a view that close to a hidden surface records nothing.
  /// Measured (README, "One default"): the default finds better single views and the victim
  /// more often; false ends the paper replicas' loops at utility 0 more often.
  bool count_near_void_cells = true;
  /// U counts only the first N unknown cells of each ray (viewpoints::FovScorer::
  /// set_unknown_depth); 0: every void cell a ray crosses (the paper's).
  int unknown_depth_cells = 0;
  /// What an unknown cell nearer than the sensor's minimum depth does to a ray of U
  /// (viewpoints::NearUnknown; README, "Exploration over a scene suite", for the measurement).
  /// `void` raises the suite's coverage most but hides the closed box's view through its
  /// opening from nearer than the minimum depth, and the best view's U on the slambook map
  /// then varies by a factor of two from seed to seed. The default, `hidden`, applies the rule
  /// only to the voids in which a taken view left cells unknown (the loops' hidden cells, given
  /// to the search): evidence that something hides there. A single search has none, so it
  /// counts as `ignore` did; the loops gained on the suite and the replicas (measured against
  /// `ignore`).
  viewpoints::NearUnknown near_unknown = viewpoints::NearUnknown::Hidden;
  /// What the search takes unknown cells outside the voids' hull for (Exterior). View: on the
  /// suite it raised the loop's coverage on the scenes without walls and changed little on
  /// those with walls, whose air the sensor clears (README, "--exterior"); Unknown is the
  /// paper's (scripts/reproduce-tables.sh asks for it).
  Exterior exterior = Exterior::View;
  /// Algorithm 1's accumulation: every utility vector (exact, the paper's) or, above
  /// max_utility_vectors, a stratified sample whose expected field is the exact one
  /// (utility/utility.hpp).
  utility::Accumulation accumulation = utility::Accumulation::Sampled;
  std::size_t max_utility_vectors = utility::Config{}.max_vectors;
  int top = 10;                       ///< ranked views reported
  /// Record every cell with utility in Result::utility_field (for pictures and clouds; on a
  /// real map that is a million cells).
  bool keep_utility_field = false;
  std::uint64_t seed = 1;             ///< orientation jitter, roll and IK restarts
  unsigned threads = 0;               ///< accumulation and scoring threads; 0: all cores (same result)
  /// Called on the calling thread as the search goes: the stage's name, work done, work in
  /// all (0 when unknown). Empty: silent.
  std::function<void(const std::string& stage, std::size_t done, std::size_t total)> progress;

  std::vector<std::string> validate() const;
};

/// Every setting of the search as a report echoes it (the
/// progress callback and keep_utility_field are not settings of the result).
Json config_json(const Config& c);

struct View {
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  std::size_t void_cells_seen = 0;       ///< U_i
  std::vector<map::VoxelKey> seen_void_cells;  ///< the U_i cells, key order
  std::size_t frontier_cells_seen = 0;   ///< strategy frontier: the largest frontier cluster's cells seen
  double accumulated_utility_m3 = 0.0;   ///< util(c) of Algorithm 1 at the viewpoint's cell; 0 for the others
  /// Strategy frontier: how many of its rays from the largest frontier cluster crossed the
  /// viewpoint's cell (its field in place of Algorithm 1's); 0 for the others.
  double frontier_rays_through_cell = 0.0;
  /// Void clusters the view sees: (void id, cells seen), most cells first.
  std::vector<std::pair<int, std::size_t>> voids_seen;
  /// The frontier-voids whose utility reached the viewpoint's cell (Analysis indices),
  /// largest first (at most utility::kContributors).
  std::vector<int> utility_from;
  Eigen::VectorXd joints_rad;            ///< IK configuration when an arm is given, else empty
  std::size_t pose_index = 0;            ///< order in which the pose was generated
  /// Refinement: the pose_index of the sampled pose this one stepped back from.
  std::optional<std::size_t> stepped_back_from;
  /// Polish and climb: the pose_index of the pose this one was turned or moved from.
  std::optional<std::size_t> polished_from;
};

/// What each step removed or kept, so a user can see why a region got no view.
struct Pruning {
  std::size_t utility_cells = 0;            ///< cells with utility > 0 (exhaustive: capability-map voxels)
  std::size_t not_free = 0;
  std::size_t outside_view_bounds = 0;
  std::size_t too_close_to_obstacle = 0;    ///< an occupied cell within clearance_m
  std::size_t unreachable_position = 0;     ///< no reachable direction in the capability map there
  std::size_t candidate_cells = 0;          ///< left after pruning, sorted by utility
  std::size_t too_near_a_tried_cell = 0;    ///< passed over: within min_separation_m of a viewpoint
  std::size_t cells_tried = 0;              ///< visited in that order until N valid poses
  std::size_t orientations_sampled = 0;
  std::size_t unreachable_orientation = 0;  ///< the capability map has no bit for the direction
  std::size_t ik_failed = 0;                ///< the map's bit was set but IK missed the exact pose
  std::size_t valid_poses = 0;              ///< scored by ray tracing
  std::size_t refinement_steps = 0;         ///< positions stepped back from the best poses
  std::size_t refinement_poses = 0;         ///< … that passed pruning and reach, scored as well
  std::size_t polish_poses = 0;             ///< other rolls and climb steps that passed the checks, scored as well
  std::size_t culled = 0;                   ///< exhaustive: poses with no void cluster in their frustum (U = 0)
  std::size_t seeing_nothing = 0;           ///< valid poses with U = 0
  /// Passed over by the ranking: the same view (same_view) as one the loop already took.
  std::size_t already_taken = 0;
};

struct Timing {
  double grid_s = 0, accumulation_s = 0, pruning_s = 0, sampling_s = 0, scoring_s = 0, total_s = 0;
  std::uint64_t cells_visited = 0;  ///< by the field-of-view rays
  std::size_t rays = 0;             ///< field-of-view rays traced
};

/// A cell of the utility field, for pictures and clouds (the paper's Figure 4).
struct UtilityCell {
  Eigen::Vector3d center_m;
  double utility_m3 = 0.0;
  bool kept = false;  ///< survived pruning
};

struct Result {
  std::vector<View> views;       ///< ranked: U descending, then generation order; at most `top`
  std::size_t poses_scored = 0;
  Pruning pruning;
  Timing timing;
  std::vector<UtilityCell> utility_field;  ///< with Config::keep_utility_field only
  std::size_t utility_vectors = 0;
  std::size_t exact_utility_vectors = 0;  ///< what the exact accumulation traces (sampled: more)
  std::string reason;            ///< why `views` is empty; empty otherwise
};

/// Two sensor poses are the same view within 5 cm and 10° between their optical axes. The
/// loops' searches pass over poses this close to a view already taken: it revealed what it
/// could.
bool same_view(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
/// T is the same view (same_view) as one of `taken`.
bool repeats_taken(const std::vector<Eigen::Isometry3d>& taken, const Eigen::Isometry3d& T);

namespace detail {
struct Search;
}

/// A search whose reading of the map is done: the constructor copies what the search needs
/// (the dense grid, its distance transform, the frontier strategy's unknown sides), so the
/// map may change while run() goes on — fvx replay integrates the next scan meanwhile.
/// `analysis` must outlive it; reach and config are copied. `hidden_void_cells` (key order):
/// void cells that a view already taken looked at without revealing them (something the map
/// does not hold yet blocks them from there); they no longer count in U or u_i. The
/// exploration loop keeps them (pipeline::State); empty for a single search. `taken_views`:
/// where the loop's views were taken (world frame); a pose that is the same view as one of
/// them (same_view) is not ranked, so the views are the best new ones (Pruning::already_taken
/// counts those passed over); empty for a single search.
class PreparedSearch {
 public:
  PreparedSearch(const map::OccupancyMap& map, const frontier_voids::Analysis& analysis, std::optional<Reach> reach,
                 Config config, const std::vector<map::VoxelKey>& hidden_void_cells = {},
                 std::vector<Eigen::Isometry3d> taken_views = {});
  PreparedSearch(PreparedSearch&&) noexcept;
  PreparedSearch& operator=(PreparedSearch&&) noexcept;
  ~PreparedSearch();
  /// Stage `utility` (Algorithm 1): the utility field over the grid, for the frontier-void
  /// strategy (the others have none). Once, before viewpoints().
  void utility();
  /// Stage `viewpoints` and the choice (Eq. 3): pruning, orientations, U by ray casting,
  /// refinement; the ranked views. Once, after utility().
  Result viewpoints();
  /// utility(), then viewpoints().
  Result run();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Selects the next best views for the map analysed in `analysis` (frontiers, voids and
/// frontier-voids within the search space). Deterministic for a given seed, on any number
/// of threads. The same as PreparedSearch(map, analysis, reach, config, …).run().
Result select(const map::OccupancyMap& map, const frontier_voids::Analysis& analysis,
              const std::optional<Reach>& reach, const Config& config,
              const std::vector<map::VoxelKey>& hidden_void_cells = {},
              std::vector<Eigen::Isometry3d> taken_views = {});

}  // namespace fvx::nbv
