#include "fvx/pipeline/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <iterator>
#include <limits>

#include "fvx/core/error.hpp"
#include "fvx/core/stopwatch.hpp"
#include "fvx/voids/width.hpp"

namespace fvx::pipeline {

int Config::min_void_width_cells() const { return voids::void_width_for_target(target_size_m, resolution_m); }

void Config::tie_to_search() {
  filter.depth_min_m = nbv.sensor.depth_min_m;
  filter.depth_max_m = clear_beyond_range ? std::numeric_limits<double>::infinity() : nbv.sensor.depth_max_m;
  clusters.seed = nbv.seed;
  if (nbv.rescored_poses == 0) nbv.rescored_poses = std::max(nbv.top, nbv.valid_poses) + nbv::Config::kRescoredBeyondTop;
}

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems;
  if (!(resolution_m > 0.0 && resolution_m <= 10.0)) problems.push_back("resolution_m must be in (0, 10] m");
  if (bounds_m && (bounds_m->isEmpty() || !bounds_m->min().allFinite() || !bounds_m->max().allFinite()))
    problems.push_back("bounds_m must be a finite, non-empty box");
  if (search && !analyse) problems.push_back("search needs analyse (frontiers and voids)");
  if (max_range_m && !(*max_range_m > 0.0)) problems.push_back("max_range_m must be > 0");
  if (!(target_size_m >= 0.0 && target_size_m <= 10.0))
    problems.push_back("target_size_m must be in [0, 10] m");
  else if (resolution_m > 0.0 && min_void_width_cells() > 16)
    problems.push_back("target_size_m is " + std::to_string(min_void_width_cells()) +
                       " cells wide here: at most 17 cells (min_void_width_cells 16)");
  for (const auto& p : filter.validate()) problems.push_back("filter: " + p);
  if (register_scans)
    for (const auto& p : registration.validate()) problems.push_back("registration: " + p);
  for (const auto& p : nbv.validate()) problems.push_back("nbv: " + p);
  return problems;
}

State::State(map::OccupancyMap existing, const Config& config) : map(std::move(existing)) {
  if (config.register_scans) {
    registration_target = registration::TargetCloud(config.registration.voxel_m / 2);
    registration_target.add(map.occupied_centers());
  }
}

namespace {

/// Step 2: the scan registered to the points integrated so far (its pose prior otherwise).
void register_scan(const State& state, scan::Scan& scan, const Config& config, StepResult& r) {
  Stopwatch t0;
  if (config.register_scans && !state.registration_target.empty() && r.filtered.kept > 0) {
    r.registration = registration::align(scan.points_sensor, scan.T_world_sensor, state.registration_target.points(),
                                         config.registration);
    if (r.registration->converged) scan.T_world_sensor = r.registration->T_world_sensor;
  }
  r.T_world_sensor = scan.T_world_sensor;
  r.timing.registration_s = t0.seconds();
}

/// Step 3: the scan into the map; returns the change set that drives the incremental updates.
map::Integration integrate_scan(State& state, const scan::Scan& scan, const Config& config, StepResult& r) {
  Stopwatch t0;
  const double range_m = config.max_range_m.value_or(config.nbv.sensor.depth_max_m);
  map::Integration integration =
      state.map.integrate(scan::to_world(scan), scan.T_world_sensor.translation().cast<float>(), range_m,
                          config.discretize);
  r.integration = map::counts(integration);
  if (config.register_scans) {
    // Half the registration voxel keeps surfaces where they are (see fvx integrate).
    if (state.registration_target.empty())
      state.registration_target = registration::TargetCloud(config.registration.voxel_m / 2);
    state.registration_target.add(scan.T_world_sensor, scan.points_sensor);
  }
  r.timing.integration_s = t0.seconds();
  return integration;
}

/// §IV-A, §IV-B: frontiers and voids from the change set (rebuilt when the last step did not
/// analyse: the sets are behind the map then), then their pairs, the frontier-voids.
void update_frontiers_and_voids(State& state, const map::Integration& integration, const Config& config, StepResult& r) {
  Stopwatch t0;
  if (config.analyse) {
    // The two sets read the map and nothing of each other: the frontiers on another core.
    std::future<void> frontiers_done = std::async(std::launch::async, [&] {
      if (state.analysed) state.frontier_set.update(state.map, integration.changes);
      else state.frontier_set.rebuild(state.map);
    });
    if (state.analysed) state.void_set.update(state.map, integration.changes);
    else state.void_set.rebuild(state.map, config.hull_in_bounds ? config.bounds_m : std::nullopt);
    frontiers_done.get();
    r.analysis = frontier_voids::analyse(state.map, state.frontier_set, &state.void_set, config.bounds_m,
                                         config.clusters, config.min_void_width_cells());
  }
  state.analysed = config.analyse;
  r.timing.frontiers_voids_s = t0.seconds();
}

}  // namespace

StepResult integrate_step(State& state, scan::Scan scan, const Config& config) {
  throw_if_problems("pipeline", config.validate());
  StepResult r;
  // Step 1: the scan without NaNs, within the sensor's depths. A scan may measure nothing
  // (every surface nearer than the minimum depth): the map stays as it is then.
  r.filtered = scan::filter(scan, config.filter);
  register_scan(state, scan, config, r);                                        // step 2
  const map::Integration integration = integrate_scan(state, scan, config, r);  // step 3
  update_frontiers_and_voids(state, integration, config, r);                    // steps 4–6
  r.nbv.reason = "not searched";
  ++state.steps;
  return r;
}

void mark_hidden(State& state, const std::vector<map::VoxelKey>& expected_void_cells, StepResult& r) {
  std::vector<map::VoxelKey> hidden;
  map::StateReader read(state.map);
  for (const map::VoxelKey& k : expected_void_cells)
    if (read(k) == map::VoxelState::Unknown) hidden.push_back(k);
  r.expected_hidden = hidden.size();
  r.expected_revealed = expected_void_cells.size() - hidden.size();
  std::vector<map::VoxelKey> merged;
  std::set_union(state.hidden_void_cells.begin(), state.hidden_void_cells.end(), hidden.begin(), hidden.end(),
                 std::back_inserter(merged));
  state.hidden_void_cells = std::move(merged);
}

nbv::PreparedSearch prepare_search(const State& state, const StepResult& r, const std::optional<nbv::Reach>& reach,
                                   const Config& config) {
  return nbv::PreparedSearch(state.map, r.analysis, reach, config.nbv, state.hidden_void_cells, state.taken_views);
}

StepResult run_step(State& state, scan::Scan scan, const std::optional<nbv::Reach>& reach, const Config& config,
                    const std::vector<map::VoxelKey>* expected_void_cells) {
  StepResult r = integrate_step(state, std::move(scan), config);
  if (expected_void_cells) mark_hidden(state, *expected_void_cells, r);
  if (config.search) {  // step 7, §IV-C
    Stopwatch t0;
    nbv::PreparedSearch search = prepare_search(state, r, reach, config);
    search.utility();            // Algorithm 1: utility vectors accumulated in free cells
    r.nbv = search.viewpoints();  // pruning, orientations, U by ray casting, c* = argmax U (Eq. 3)
    r.searched = true;
    r.timing.search_s = t0.seconds();
  }
  return r;
}

Pipeline::Pipeline(Config config, std::optional<nbv::Reach> reach)
    : config_(std::move(config)), reach_(std::move(reach)), state_(config_.resolution_m) {
  throw_if_problems("pipeline", config_.validate());
}

Pipeline::Pipeline(Config config, std::optional<nbv::Reach> reach, map::OccupancyMap existing)
    : config_(std::move(config)), reach_(std::move(reach)), state_(std::move(existing), config_) {
  throw_if_problems("pipeline", config_.validate());
}

StepResult Pipeline::step(scan::Scan scan, const std::vector<map::VoxelKey>* expected_void_cells) {
  Config view_config = config_;
  view_config.nbv.seed = config_.nbv.seed + std::uint64_t(state_.steps);
  return run_step(state_, std::move(scan), reach_, view_config, expected_void_cells);
}

}  // namespace fvx::pipeline
