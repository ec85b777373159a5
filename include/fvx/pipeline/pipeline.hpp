#pragma once
/// \file
/// Stage `pipeline`: one call per recorded or simulated scan, in the order of the paper's
/// §IV steps 1–7 — filter the scan, register it to the map's accumulated cloud, integrate it,
/// update frontiers and voids from the change set, pair them, and search the next best view.
/// `explore` and `replay` both run their loops through run_step().
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/frontiers/frontiers.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/registration/registration.hpp"
#include "fvx/registration/target_cloud.hpp"
#include "fvx/scan/scan.hpp"
#include "fvx/voids/voids.hpp"

namespace fvx::pipeline {

struct Config {
  double resolution_m = 0.025;                     ///< map cell edge, metres (the paper: 2.5 cm)
  std::optional<Eigen::AlignedBox3d> bounds_m;     ///< search space S; default: the known cells' box
  scan::FilterConfig filter;                       ///< depth limits and downsampling of each scan
  /// Rays longer than this are cut and their end is not marked occupied, metres; +infinity:
  /// no limit (fvx integrate's default). Unset: the sensor's depth_max_m (nbv.sensor).
  std::optional<double> max_range_m;
  bool register_scans = false;                     ///< step 2; off when the poses are exact
  registration::Config registration;
  voids::ClusterConfig clusters;                   ///< Eq. 2 region growing
  /// The searched object's smallest extent, metres: only void cells in an all-void cube
  /// that always fits it count (min_void_width_cells()). 0: every void cell (the paper).
  double target_size_m = 0.0;
  /// The voids' hull from the occupied cells in bounds_m only (surfaces outside S, a room's
  /// walls, do not make the air in S a void); false: from every occupied cell (the paper's
  /// accumulated cloud). Without bounds_m the two agree.
  bool hull_in_bounds = false;
  /// Points beyond the sensor's depth limit are kept and clear their ray up to max_range_m
  /// without an endpoint (OctoMap's maxrange), as a laser's max-range returns do; false:
  /// the filter drops them (a Kinect's pixels without depth carry no ray).
  bool clear_beyond_range = false;
  /// OctoMap's discretised insertion (map::OccupancyMap::integrate): one ray per distinct
  /// endpoint cell, to its centre; faster, and a slightly different map. false: exact.
  bool discretize = false;
  nbv::Config nbv;                                 ///< the search, its sensor model and strategy
  /// Steps 4–6, frontiers, voids and frontier-voids; false: the step ends with the map
  /// (fvx integrate), and the search is off too.
  bool analyse = true;
  /// Step 7, the next-best-view search; false: the step ends with frontiers and voids (its
  /// nbv result is empty, with the reason "not searched").
  bool search = true;
  /// The cube width, cells, that target_size_m fills at resolution_m
  /// (voids::void_width_for_target; frontier_voids::analyse); 1 for target size 0.
  int min_void_width_cells() const;
  /// For the loops, once the search's sensor and seed are set: the scan filter keeps the
  /// sensor's depth range (what the search models is what is integrated), region growing
  /// takes the search's seed, and the full fan rescores max(top, N) + 10 screened poses
  /// unless rescored_poses is set: the views the loops take are those of a search that
  /// described every valid pose, for a third less scoring (README, issue 15). One call
  /// instead of copies in each command.
  void tie_to_search();
  std::vector<std::string> validate() const;
};

/// Every setting of the step, its stages' configs nested, as a report echoes it ("nbv" only
/// when the step searches).
Json config_json(const Config& c);

/// What persists between steps: the map, the incremental frontier and void sets, and the
/// accumulated cloud that scans are registered to.
struct State {
  explicit State(double resolution_m) : map(resolution_m) {}
  /// Continues `existing`; with registration, its occupied cell centres seed the target
  /// (cell centres shift surfaces by up to half a cell, so scan points join them as they come).
  State(map::OccupancyMap existing, const Config& config);
  map::OccupancyMap map;
  frontiers::FrontierSet frontier_set;
  voids::VoidSet void_set;
  /// The scans integrated so far, one point per cell of half the registration voxel.
  registration::TargetCloud registration_target;
  /// Void cells a scan was expected to reveal (taken at a chosen view) that stayed unknown:
  /// hidden from there, they leave U (nbv::PreparedSearch's hidden_void_cells). Key order.
  std::vector<map::VoxelKey> hidden_void_cells;
  /// Where the loop's views were taken (world frame, as the loop knows them): the search
  /// ranks only poses that repeat none of them (nbv::PreparedSearch's taken_views).
  std::vector<Eigen::Isometry3d> taken_views;
  int steps = 0;
  /// The last step updated frontier_set and void_set (Config::analyse); otherwise the next
  /// step that analyses rebuilds them from the map.
  bool analysed = false;
};

struct Timing {
  double registration_s = 0, integration_s = 0, frontiers_voids_s = 0, search_s = 0;
};

struct StepResult {
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();  ///< the pose integrated at
  std::optional<registration::Result> registration;  ///< when attempted
  scan::FilterStats filtered;
  map::IntegrationCounts integration;                ///< what step 3 changed
  std::size_t expected_revealed = 0;                 ///< of the expected void cells, now known
  std::size_t expected_hidden = 0;                   ///< … still unknown (added to State::hidden_void_cells)
  frontier_voids::Analysis analysis;                 ///< after the scan
  bool searched = false;                             ///< step 7 ran (Config::search)
  nbv::Result nbv;                                   ///< the next best views
  Timing timing;
};

/// Steps 1–6 of run_step (filter, register, integrate, frontiers and voids, frontier-voids):
/// the result has no search (searched false, nbv empty).
StepResult integrate_step(State& state, scan::Scan scan, const Config& config);

/// Right after integrate_step: the cells of `expected_void_cells` (the void cells the scan
/// was expected to reveal, taken at a chosen view) that it left unknown are hidden from then
/// on (State::hidden_void_cells); counted in r.expected_revealed and r.expected_hidden.
void mark_hidden(State& state, const std::vector<map::VoxelKey>& expected_void_cells, StepResult& r);

/// Step 7 with what it reads of the map copied (nbv::PreparedSearch), and the hidden void
/// cells and taken views so far: the state may take the next scan while run() goes on.
/// r.analysis must outlive it.
nbv::PreparedSearch prepare_search(const State& state, const StepResult& r, const std::optional<nbv::Reach>& reach,
                                   const Config& config);

/// One step of §IV: `scan` (sensor-frame points and their pose prior) goes into `state`;
/// returns the pose used, the analysis and the next best views. A scan with no point left
/// after filtering (a sensor facing a surface nearer than its minimum depth) changes nothing.
/// `expected_void_cells`: when the scan was taken at a view the search chose, the void cells
/// it was expected to see (nbv::View::seen_void_cells); those it left unknown are hidden.
/// integrate_step, mark_hidden, then the search (when config.search), in this order.
StepResult run_step(State& state, scan::Scan scan, const std::optional<nbv::Reach>& reach, const Config& config,
                    const std::vector<map::VoxelKey>* expected_void_cells = nullptr);

/// The loop's engine: the validated config, the arm's reach and the state between steps
/// (the map, the frontier and void sets, the registration target, the hidden void cells).
/// fvx explore and fvx integrate (integrate_files) run through it; fvx replay uses the step's
/// parts above (integrate_step, mark_hidden, prepare_search) to overlap a view's search
/// with the next scan.
class Pipeline {
 public:
  /// UsageError listing every problem of `config`. `reach` (with the capability map and arm
  /// it points to) must outlive the pipeline.
  Pipeline(Config config, std::optional<nbv::Reach> reach);
  /// Continues `existing` (State's constructor: its occupied cells seed registration).
  Pipeline(Config config, std::optional<nbv::Reach> reach, map::OccupancyMap existing);
  /// run_step with this view's own seed, config.nbv.seed + the steps so far, so that each
  /// view's search draws its own random numbers (the same for the same seed).
  StepResult step(scan::Scan scan, const std::vector<map::VoxelKey>* expected_void_cells = nullptr);
  /// The next scan is taken at T_world_sensor (State::taken_views): from the step after it
  /// on, the search passes over poses that repeat it.
  void taken_at(const Eigen::Isometry3d& T_world_sensor) { state_.taken_views.push_back(T_world_sensor); }
  const State& state() const { return state_; }
  const map::OccupancyMap& map() const { return state_.map; }
  const Config& config() const { return config_; }

 private:
  Config config_;
  std::optional<nbv::Reach> reach_;
  State state_;
};

}  // namespace fvx::pipeline
