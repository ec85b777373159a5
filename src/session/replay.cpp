// A recorded sequence through the closed loop's step, offline (paper §V): the scans go where
// they were taken, and each view says where the planner would have gone instead.
#include "fvx/session/replay.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <memory>

#include "fvx/core/error.hpp"
#include "fvx/core/stopwatch.hpp"

namespace fvx::session {

namespace {

double axis_angle_rad(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::acos(std::clamp(a.linear().col(2).dot(b.linear().col(2)), -1.0, 1.0));
}

}  // namespace

std::vector<std::string> ReplayConfig::validate() const {
  std::vector<std::string> problems = pipeline.validate();
  if (last_view < -1) problems.push_back("last_view must be >= 0, or -1 for all");
  if (search_every < 0) problems.push_back("search_every must be >= 0");
  return problems;
}

double known_volume_m3(const map::OccupancyMap& map, const Eigen::AlignedBox3d& box) {
  const double R = map.resolution_m();
  double volume = 0.0;
  for (const map::Leaf& leaf : map.leaves()) {
    if (leaf.state == map::VoxelState::Unknown) continue;
    const Eigen::Vector3d lo = map.center_of(leaf.min_key) - Eigen::Vector3d::Constant(R / 2);
    const Eigen::AlignedBox3d cube(lo, lo + Eigen::Vector3d::Constant(R * leaf.size_cells));
    const Eigen::AlignedBox3d overlap = cube.intersection(box);
    if (!overlap.isEmpty()) volume += overlap.volume();
  }
  return volume;
}

namespace {

/// A view whose search runs on its own thread while the next scan is integrated. The view
/// sits behind a pointer: the search reads its analysis where it is.
struct InFlight {
  std::unique_ptr<ReplayView> out;
  double prepare_s = 0.0;                          // the grid, on the replay's thread
  std::future<std::pair<nbv::Result, double>> search;  // and the run, seconds; joined before `out` goes
};

/// View `view`'s step: its own seed; the search on every search_every-th view.
pipeline::Config step_config_of(const ReplayConfig& config, int view) {
  pipeline::Config step = config.pipeline;
  step.nbv.seed = config.pipeline.nbv.seed + std::uint64_t(view);
  step.search = config.search_every > 0 && (view + 1) % config.search_every == 0;
  return step;
}

/// The scan (logged at `logged`) against the previous view's choice: taken there, the
/// choice's cells it left unknown are hidden, as in explore (a scan taken elsewhere says
/// nothing about them); and how far from the choice it was taken.
void against_choice(const Eigen::Isometry3d& logged, const std::optional<nbv::View>& chosen, pipeline::State& state,
                    ReplayView& out) {
  if (!chosen) return;
  out.at_choice = nbv::same_view(logged, chosen->T_world_sensor);
  if (out.at_choice) pipeline::mark_hidden(state, chosen->seen_void_cells, out.step);
  out.from_choice_m = (logged.translation() - chosen->T_world_sensor.translation()).norm();
  out.from_choice_deg = axis_angle_rad(logged, chosen->T_world_sensor) * 180.0 / M_PI;
}

/// Starts the view's search (when its step searches) on its own thread; the grid is copied
/// from the map here, so the state may take the next scan meanwhile.
InFlight launch(const pipeline::State& state, std::unique_ptr<ReplayView> out, const std::optional<nbv::Reach>& reach,
                const pipeline::Config& step_config) {
  InFlight f;
  f.out = std::move(out);
  if (!step_config.search) return f;
  Stopwatch t0;
  auto search = std::make_shared<nbv::PreparedSearch>(pipeline::prepare_search(state, f.out->step, reach, step_config));
  f.prepare_s = t0.seconds();
  f.search = std::async(std::launch::async, [search] {
    Stopwatch t1;
    nbv::Result result = search->run();
    return std::make_pair(std::move(result), t1.seconds());
  });
  return f;
}

/// View `out`'s volumes (what it revealed of `previous_voids`, the known and void m³) and the
/// caller's on_map (the CLI saves the .ot there), on a thread of their own: they only read the
/// map, as the search's preparation does, which runs beside them on the core the finished
/// search left (a quarter of a second per view on real maps). Joined before the map changes.
std::future<void> account(const pipeline::State& state, ReplayView& out, std::vector<map::VoxelKey> previous_voids,
                          double resolution_m, const std::function<void(int, const pipeline::State&)>& on_map) {
  return std::async(std::launch::async, [&state, &out, previous = std::move(previous_voids), resolution_m, &on_map] {
    map::StateReader read(state.map);  // the void cells are in key order: each look-up near the last
    for (const map::VoxelKey& k : previous) out.revealed_void_cells += read(k) != map::VoxelState::Unknown;
    out.known_m3 = known_volume_m3(state.map, out.step.analysis.bounds_m);
    out.void_m3 = double(out.step.analysis.void_cells.size()) * std::pow(resolution_m, 3);
    on_map(out.view, state);
  });
}

}  // namespace

void replay(const std::vector<RecordedScan>& scans, const std::optional<nbv::Reach>& reach, const ReplayConfig& config,
            const std::function<void(int, const pipeline::State&)>& on_map,
            const std::function<void(const ReplayView&)>& on_view) {
  throw_if_problems("replay", config.validate());
  const std::size_t count =
      config.last_view < 0 ? scans.size() : std::min(scans.size(), std::size_t(config.last_view) + 1);

  pipeline::State state(config.pipeline.resolution_m);
  std::vector<map::VoxelKey> previous_voids;
  std::optional<nbv::View> chosen;          // the previous view's choice
  // The search of view i runs while scan i + 1 is registered, integrated and analysed: the
  // search (Algorithm 1, scoring) spreads over every core, the steps before it over one, and
  // nothing the search reads is in the map any more (nbv::PreparedSearch). The next scan is
  // read meanwhile too (24 ms per Kinect frame). Errors surface at their own view, as before.
  std::optional<InFlight> in_flight;
  auto finish = [&](InFlight& f) {
    ReplayView& out = *f.out;
    if (f.search.valid()) {
      auto [result, run_s] = f.search.get();
      out.step.nbv = std::move(result);
      out.step.searched = true;
      out.step.timing.search_s = f.prepare_s + run_s;
    }
    out.chosen = first_view_not_taken(out.step.nbv.views, state.taken_views);
    if (out.chosen) chosen = out.step.nbv.views[*out.chosen];
    else chosen.reset();
    on_view(out);
  };
  auto finish_in_flight = [&] {
    if (!in_flight) return;
    InFlight f = std::move(*in_flight);
    in_flight.reset();
    finish(f);
  };
  std::future<scan::Scan> next;
  if (count > 0) next = std::async(std::launch::async, scans[0].load);
  for (std::size_t i = 0; i < count; ++i) {
    const int view = int(i);
    scan::Scan scan;
    try {
      scan = next.get();
      // A sensor facing a wall too near records NaN everywhere (a blank scan, which changes
      // nothing); a file without a single point is broken.
      if (scan.points_sensor.empty()) throw Error("the scan holds no points");
    } catch (const std::exception& e) {
      finish_in_flight();
      throw Error("view " + std::to_string(view) + " (" + scans[i].name + "): " + e.what());
    }
    if (i + 1 < count) next = std::async(std::launch::async, scans[i + 1].load);
    const pipeline::Config step_config = step_config_of(config, view);
    auto out = std::make_unique<ReplayView>();
    out->view = view;
    out->name = scans[i].name;
    // Where the recording says the sensor was: the pose prior, before registration.
    const Eigen::Isometry3d logged = scans[i].T_world_sensor_true.value_or(scan.T_world_sensor);
    try {
      out->step = pipeline::integrate_step(state, std::move(scan), step_config);
    } catch (...) {
      finish_in_flight();
      throw;
    }
    finish_in_flight();  // the previous view's choice decides what this scan hides

    against_choice(logged, chosen, state, *out);
    // Where the view was taken (the recording's, else the registered pose): the search
    // launched below passes over poses that repeat one of these.
    state.taken_views.push_back(scans[i].T_world_sensor_true.value_or(out->step.T_world_sensor));
    auto bookkeeping = account(state, *out, std::move(previous_voids), config.pipeline.resolution_m, on_map);
    previous_voids = out->step.analysis.void_cells;
    in_flight = launch(state, std::move(out), reach, step_config);
    bookkeeping.get();
  }
  finish_in_flight();
}

}  // namespace fvx::session
