// A recorded sequence through the closed loop's step, offline (paper §V): the scans go where
// they were taken, and each view says where the planner would have gone instead.
#include "fvx/session/replay.hpp"

#include <algorithm>
#include <cmath>
#include <future>

#include "fvx/core/error.hpp"

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

void replay(const std::vector<RecordedScan>& scans, const std::optional<nbv::Reach>& reach, const ReplayConfig& config,
            const std::function<void(const ReplayView&, const pipeline::State&)>& on_view) {
  const auto problems = config.validate();
  if (!problems.empty()) throw UsageError("replay: " + problems.front());
  const std::size_t count =
      config.last_view < 0 ? scans.size() : std::min(scans.size(), std::size_t(config.last_view) + 1);

  pipeline::State state(config.pipeline.resolution_m);
  std::vector<Eigen::Isometry3d> taken;     // the poses the views were taken at
  std::vector<map::VoxelKey> previous_voids;
  std::optional<nbv::View> chosen;          // the previous view's choice
  // The next scan is read while this one goes through the step: reading and back-projecting
  // a Kinect frame took 24 ms, on a core that registration and the frontier/void update
  // leave idle. Its errors surface at its own view, as before.
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
      throw Error("view " + std::to_string(view) + " (" + scans[i].name + "): " + e.what());
    }
    if (i + 1 < count) next = std::async(std::launch::async, scans[i + 1].load);
    const Eigen::Isometry3d logged = scans[i].T_world_sensor_true.value_or(scan.T_world_sensor);
    // The chosen view's cells stay unknown after a scan taken there: hidden, as in explore.
    // A scan taken elsewhere says nothing about them.
    const bool at_chosen = chosen && same_view(logged, chosen->T_world_sensor);
    const std::vector<map::VoxelKey> expected = at_chosen ? chosen->seen_void_cells : std::vector<map::VoxelKey>{};

    pipeline::Config step_config = config.pipeline;
    step_config.nbv.seed = config.pipeline.nbv.seed + std::uint64_t(view);
    step_config.search = config.search_every > 0 && (view + 1) % config.search_every == 0;
    ReplayView out;
    out.view = view;
    out.name = scans[i].name;
    out.at_choice = at_chosen;
    if (chosen) {
      out.from_choice_m = (logged.translation() - chosen->T_world_sensor.translation()).norm();
      out.from_choice_deg = axis_angle_rad(logged, chosen->T_world_sensor) * 180.0 / M_PI;
    }
    out.step = pipeline::run_step(state, std::move(scan), reach, step_config, at_chosen ? &expected : nullptr);
    for (const map::VoxelKey& k : previous_voids) out.revealed_void_cells += state.map.state(k) != map::VoxelState::Unknown;
    previous_voids = out.step.analysis.void_cells;
    taken.push_back(scans[i].T_world_sensor_true.value_or(out.step.T_world_sensor));

    out.chosen = first_view_not_taken(out.step.nbv.views, taken);
    if (out.chosen) chosen = out.step.nbv.views[*out.chosen];
    else chosen.reset();
    out.known_m3 = known_volume_m3(state.map, out.step.analysis.bounds_m);
    out.void_m3 = double(out.step.analysis.void_cells.size()) * std::pow(config.pipeline.resolution_m, 3);
    on_view(out, state);
  }
}

}  // namespace fvx::session
