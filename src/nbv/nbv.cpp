#include "fvx/nbv/nbv.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "fvx/core/error.hpp"
#include "fvx/core/stopwatch.hpp"
#include "fvx/viewpoints/orientations.hpp"
#include "search.hpp"

namespace fvx::nbv {

const char* to_string(Strategy s) {
  switch (s) {
    case Strategy::FrontierVoid: return "frontier-void";
    case Strategy::Exhaustive: return "exhaustive";
    case Strategy::Frontier: return "frontier";
    case Strategy::Random: return "random";
  }
  return "?";
}

Strategy parse_strategy(const std::string& name, const std::string& what) {
  for (Strategy s : {Strategy::FrontierVoid, Strategy::Exhaustive, Strategy::Frontier, Strategy::Random})
    if (name == to_string(s)) return s;
  throw UsageError(what + " '" + name + "': expected frontier-void, exhaustive, frontier or random");
}

const char* to_string(Exterior mode) {
  switch (mode) {
    case Exterior::Unknown: return "unknown";
    case Exterior::View: return "view";
    case Exterior::Free: return "free";
  }
  return "?";
}

Exterior parse_exterior(const std::string& name, const std::string& what) {
  for (const Exterior m : {Exterior::Unknown, Exterior::View, Exterior::Free})
    if (name == to_string(m)) return m;
  throw UsageError(what + " '" + name + "': expected unknown, view or free");
}

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems = sensor.validate();
  if (ray_cols < 1 || ray_rows < 1) problems.push_back("ray_cols and ray_rows must be >= 1");
  if (coarse_ray_cols < 0 || coarse_ray_rows < 0 || (coarse_ray_cols == 0) != (coarse_ray_rows == 0))
    problems.push_back("coarse_ray_cols and coarse_ray_rows must both be >= 1, or both 0 (off)");
  if (valid_poses < 1) problems.push_back("valid_poses (N) must be >= 1");
  if (rescored_poses < 0) problems.push_back("rescored_poses must be >= 0");
  if (orientations_per_cell < 1) problems.push_back("orientations_per_cell must be >= 1");
  if (!(jitter_deg >= 0.0 && jitter_deg <= 90.0)) problems.push_back("jitter_deg must be in [0, 90]");
  if (!(min_separation_m >= 0.0 && min_separation_m <= 10.0)) problems.push_back("min_separation_m must be in [0, 10] m");
  if (!(clearance_m >= 0.0 && clearance_m <= 2.0)) problems.push_back("clearance_m must be in [0, 2] m");
  if (view_bounds_m && (view_bounds_m->isEmpty() || !view_bounds_m->min().allFinite() || !view_bounds_m->max().allFinite()))
    problems.push_back("view_bounds_m must be a finite, non-empty box");
  if (refine_poses < 0) problems.push_back("refine_poses must be >= 0");
  if (polish_poses < 0 || polish_rolls < 1 || polish_rolls > 360)
    problems.push_back("polish_poses must be >= 0 and polish_rolls in [1, 360]");
  if (climb_rounds < 0 || climb_rounds > 100 || !(climb_step_m > 0.0 && climb_step_m <= 1.0) ||
      !(climb_angle_deg > 0.0 && climb_angle_deg <= 45.0))
    problems.push_back("climb_rounds must be in [0, 100], climb_step_m in (0, 1] m, climb_angle_deg in (0, 45]");
  if (!(refine_step_m > 0.0 && refine_step_m <= refine_max_m && refine_max_m <= 10.0))
    problems.push_back("refine_step_m and refine_max_m must satisfy 0 < step <= max <= 10 m");
  if (exhaustive_rolls < 1) problems.push_back("exhaustive_rolls must be >= 1");
  if (random_tries < 1) problems.push_back("random_tries must be >= 1");
  if (top < 1) problems.push_back("top must be >= 1");
  if (max_utility_vectors < 7) problems.push_back("max_utility_vectors must be >= 7");
  if (unknown_depth_cells < 0) problems.push_back("unknown_depth_cells must be >= 0");
  return problems;
}

namespace detail {

/// Algorithm 1 over the search's grid, with the loop's hidden void cells left out of u_i.
utility::Field accumulate_field(const Search& s, Result& result) {
  Stopwatch t0;
  utility::Config utility_config;
  if (s.config.progress)
    utility_config.progress = [&](std::size_t done, std::size_t total) {
      if (done % std::max<std::size_t>(1, total / 100) == 0)  // a hundred lines at most
        s.config.progress("utility vectors (Algorithm 1), frontier-voids", done, total);
    };
  utility_config.sensor_range_m = s.config.sensor.depth_max_m;  // s_r
  if (!s.config.count_near_void_cells) utility_config.min_range_m = s.config.sensor.depth_min_m;
  utility_config.threads = s.config.threads;
  utility_config.accumulation = s.config.accumulation;
  utility_config.max_vectors = s.config.max_utility_vectors;
  utility_config.seed = s.config.seed;
  // Pruning reads the field nowhere else (when nothing is left, the field is whole, so that
  // the reason given is pruning's).
  if (!s.candidate_box_m.isEmpty()) utility_config.read_box_m = s.candidate_box_m;
  // Void cells a taken view left hidden no longer count in U; they leave u_i too, or a void
  // that views cannot reveal would keep drawing Algorithm 1's vectors to itself.
  const std::optional<frontier_voids::Analysis> visible =
      s.any_hidden ? std::optional(s.visible_utility()) : std::nullopt;
  utility::Field field = utility::accumulate(s.grid, visible ? *visible : s.a, utility_config);
  result.utility_vectors = field.vectors;
  result.exact_utility_vectors = field.exact_vectors;
  result.timing.accumulation_s = t0.seconds();
  return field;
}

namespace {

/// Orientations at the candidate cells in utility order, aimed at the voids whose utility
/// reached each cell, until N valid poses.
std::vector<Pose> sample_poses(const Search& s, const utility::Field& field, CandidateOrder& candidates,
                               Pruning& pruning) {
  std::mt19937_64 rng(s.config.seed);
  const double jitter_rad = s.config.jitter_deg * M_PI / 180.0;
  std::vector<Pose> poses;
  std::vector<Eigen::Vector3d> used;  // viewpoints that gave a valid pose
  const double separation_sq = s.config.min_separation_m * s.config.min_separation_m;
  for (std::size_t n = 0; n < candidates.size(); ++n) {
    if (poses.size() >= std::size_t(s.config.valid_poses)) break;
    const std::size_t cell = candidates[n];
    const Eigen::Vector3d p = s.grid.center_of(s.grid.key(cell));
    if (std::any_of(used.begin(), used.end(), [&](const Eigen::Vector3d& u) { return (u - p).squaredNorm() < separation_sq; })) {
      ++pruning.too_near_a_tried_cell;
      continue;
    }
    ++pruning.cells_tried;
    // Targets: the centres of the voids whose utility reached the cell, then their extremes.
    std::vector<Eigen::Vector3d> targets, extremes;
    for (const std::int32_t fv : field.contributors[cell]) {
      if (fv < 0) break;
      const auto corners = s.a.void_clusters[std::size_t(s.a.frontier_voids[std::size_t(fv)].void_id)].corners();
      targets.push_back(corners[0]);
      extremes.insert(extremes.end(), corners.begin() + 1, corners.end());
    }
    targets.insert(targets.end(), extremes.begin(), extremes.end());
    const std::size_t before = poses.size();
    for (const Eigen::Matrix3d& R :
         viewpoints::sample_orientations(p, targets, s.config.orientations_per_cell, jitter_rad, rng)) {
      if (poses.size() >= std::size_t(s.config.valid_poses)) break;
      s.add_pose(p, R, cell, pruning, poses);
    }
    if (poses.size() > before) used.push_back(p);
  }
  pruning.valid_poses = poses.size();
  return poses;
}

}  // namespace

// The paper's method (§IV-C): Algorithm 1, pruning, orientations at the cells sorted by
// util(c) until N valid poses, c* = argmax U (Eq. 3).
Result select_frontier_void(Search& s, const utility::Field& field, Result result) {
  Stopwatch t0;
  Pruning& pruning = result.pruning;
  CandidateOrder candidates = s.prune(field.util_m3, result);
  result.timing.pruning_s = t0.seconds();

  t0 = Stopwatch();
  std::vector<Pose> poses = sample_poses(s, field, candidates, pruning);
  result.timing.sampling_s = t0.seconds();

  t0 = Stopwatch();
  std::vector<std::size_t> U = s.score(*s.void_scorer, poses, result, s.screen_fan());
  refine(s, poses, U, result);
  result.views = s.rank(poses, U, pruning, &field.util_m3, &field);
  result.timing.scoring_s = t0.seconds();

  if (!result.views.empty()) return result;
  if (field.cells == 0)
    result.reason = "no utility vector reaches a free cell: every frontier-void's frontier is blocked";
  else if (candidates.empty())
    result.reason = "pruning removed all " + std::to_string(pruning.utility_cells) +
                    " cells with utility (not free, outside the view bounds, too close to an obstacle or "
                    "out of the arm's reach; see pruning)";
  else if (poses.empty())
    result.reason = "no sampled orientation at the " + std::to_string(pruning.cells_tried) +
                    " candidate cells is reachable by the arm";
  else
    result.reason = "none of the " + std::to_string(poses.size()) + " valid poses sees a void cell";
  return result;
}

}  // namespace detail

struct PreparedSearch::State {
  Stopwatch start;
  std::optional<Reach> reach;  // the search refers to these two
  Config config;
  Result result;
  std::unique_ptr<detail::Search> search;  // empty: result says why there is nothing to search
  std::optional<utility::Field> field;     // after utility(), for the frontier-void strategy
  bool accumulated = false, ran = false;
};

PreparedSearch::PreparedSearch(const map::OccupancyMap& map, const frontier_voids::Analysis& analysis,
                               std::optional<Reach> reach, Config config,
                               const std::vector<map::VoxelKey>& hidden_void_cells,
                               std::vector<Eigen::Isometry3d> taken_views)
    : state_(std::make_unique<State>()) {
  State& st = *state_;
  st.start = Stopwatch();
  st.reach = std::move(reach);
  st.config = std::move(config);
  const auto problems = st.config.validate();
  throw_if_problems("nbv", problems);
  if (st.reach && !st.reach->capmap) throw UsageError("nbv: a reach without a capability map");
  if (st.config.strategy == Strategy::Exhaustive && !st.reach)
    throw UsageError("strategy exhaustive enumerates the capability map's voxels and directions: give one");
  // What the analysis already says: no view can help.
  const bool any_open_void = std::any_of(analysis.frontier_voids.begin(), analysis.frontier_voids.end(),
                                         [](const auto& fv) { return !fv.enclosed(); });
  const Strategy strategy = st.config.strategy;
  if ((strategy == Strategy::FrontierVoid || strategy == Strategy::Exhaustive) && !any_open_void) {
    st.result.reason = analysis.void_cells.empty()
                           ? "no void cell in the search space: nothing is left to look into"
                           : "every void is enclosed: no frontier touches one, so no view can see into it";
    return;
  }
  if (strategy == Strategy::Frontier && analysis.frontier_clusters.empty()) {
    st.result.reason = "no frontier cell in the search space";
    return;
  }
  Stopwatch t0;
  if (st.config.progress) st.config.progress("dense grid and distance transform", 0, 0);
  st.search = std::make_unique<detail::Search>(map, analysis, st.reach, st.config, hidden_void_cells);
  st.search->taken_views = std::move(taken_views);
  st.result.timing.grid_s = t0.seconds();
}

PreparedSearch::PreparedSearch(PreparedSearch&&) noexcept = default;
PreparedSearch& PreparedSearch::operator=(PreparedSearch&&) noexcept = default;
PreparedSearch::~PreparedSearch() = default;

void PreparedSearch::utility() {
  FVX_ASSERT(state_ && !state_->accumulated, "PreparedSearch::utility: once, before viewpoints()");
  State& st = *state_;
  st.accumulated = true;
  if (st.search && st.config.strategy == Strategy::FrontierVoid)
    st.field = detail::accumulate_field(*st.search, st.result);
}

Result PreparedSearch::viewpoints() {
  FVX_ASSERT(state_ && state_->accumulated && !state_->ran, "PreparedSearch::viewpoints: once, after utility()");
  State& st = *state_;
  st.ran = true;
  if (!st.search) return std::move(st.result);
  Result result = std::move(st.result);
  switch (st.config.strategy) {
    case Strategy::FrontierVoid: result = detail::select_frontier_void(*st.search, *st.field, std::move(result)); break;
    case Strategy::Exhaustive: result = detail::select_exhaustive(*st.search, std::move(result)); break;
    case Strategy::Frontier: result = detail::select_frontier(*st.search, std::move(result)); break;
    case Strategy::Random: result = detail::select_random(*st.search, std::move(result)); break;
  }
  st.field.reset();
  if (result.views.empty() && result.pruning.already_taken > 0)
    result.reason = "every view found repeats one already taken (" + std::to_string(result.pruning.already_taken) +
                    " passed over)";
  result.timing.total_s = st.start.seconds();
  return result;
}

Result PreparedSearch::run() {
  utility();
  return viewpoints();
}

Result select(const map::OccupancyMap& map, const frontier_voids::Analysis& analysis, const std::optional<Reach>& reach,
              const Config& config, const std::vector<map::VoxelKey>& hidden_void_cells,
              std::vector<Eigen::Isometry3d> taken_views) {
  return PreparedSearch(map, analysis, reach, config, hidden_void_cells, std::move(taken_views)).run();
}

bool same_view(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  constexpr double kSamePosition_m = 0.05;
  constexpr double kSameDirection_rad = 10.0 * M_PI / 180.0;
  return (a.translation() - b.translation()).norm() < kSamePosition_m &&
         a.linear().col(2).dot(b.linear().col(2)) > std::cos(kSameDirection_rad);
}

bool repeats_taken(const std::vector<Eigen::Isometry3d>& taken, const Eigen::Isometry3d& T) {
  return std::any_of(taken.begin(), taken.end(), [&](const Eigen::Isometry3d& T_taken) { return same_view(T_taken, T); });
}

}  // namespace fvx::nbv
