#pragma once
/// \file
/// Replay (paper §V, offline): a recorded sequence of scans run through the same step as the
/// closed loop — register, integrate, frontiers and voids, next best view — the same as one
/// call of pipeline::run_step() per scan, in order. The sensor went where the recording says, not
/// where the planner would have sent it; each view reports both.
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fvx/pipeline/pipeline.hpp"
#include "fvx/scan/scan.hpp"
#include "fvx/session/session.hpp"

namespace fvx::session {

/// One recorded scan. `load` reads it when its turn comes, so that a missing or corrupt file
/// stops the replay there, after the views before it are done.
struct RecordedScan {
  std::string name;                                  ///< the file, as errors name it
  std::function<scan::Scan()> load;                  ///< sensor-frame points and the pose prior
  /// Simulated sessions: where the sensor really was (what "taken" means for the planner's
  /// choice, as in the explore loop). Empty: the pose the scan was integrated at.
  std::optional<Eigen::Isometry3d> T_world_sensor_true;
};

struct ReplayConfig {
  pipeline::Config pipeline;  ///< the map, registration and the planner; nbv.seed + view per view
  int last_view = -1;         ///< replay views 0..last_view (−1: all)
  /// Search the next best view after every search_every-th view (1: each, 0: never; the
  /// others end with frontiers and voids, as pipeline::Config::search = false).
  int search_every = 1;
  std::vector<std::string> validate() const;
};

/// The replay's settings and the step's (pipeline::config_json), as a report echoes them.
Json config_json(const ReplayConfig& c);

struct ReplayView {
  int view = 0;
  std::string name;
  pipeline::StepResult step;
  /// The view of step.nbv.views the planner would take next (the explore loop's choice: the
  /// best ranked one not taken already); empty when no view sees a void cell.
  std::optional<std::size_t> chosen;
  /// This scan's logged pose against the view the planner chose at the previous view:
  /// distance between the positions, angle between the optical axes; empty for the first
  /// view or when the previous view had no choice.
  std::optional<double> from_choice_m, from_choice_deg;
  /// This scan was taken at the previous choice (same_view): the choice's void cells it left
  /// unknown became hidden, as in the explore loop.
  bool at_choice = false;
  /// Of the previous view's void cells, how many this scan made known (0 for the first view).
  std::size_t revealed_void_cells = 0;
  double known_m3 = 0.0;  ///< known (free or occupied) volume inside the search space
  double void_m3 = 0.0;   ///< void volume (step.analysis.void_cells · R³)
};

/// Runs the scans in order. `on_map` gets each view's number and the state right after its
/// scan is integrated and analysed (the map, before the next scan changes it), on a thread of
/// its own while the view's search is prepared: it must only read the state; `on_view` then
/// gets the view with its search, after on_map of the view and before on_map of the next
/// one. The search of view i runs while scan i + 1 is registered, integrated and analysed;
/// the results are those of one pipeline::run_step() per scan. A scan that fails to load
/// throws Error naming the view and the file (on_view has had every view before it).
void replay(const std::vector<RecordedScan>& scans, const std::optional<nbv::Reach>& reach, const ReplayConfig& config,
            const std::function<void(int view, const pipeline::State&)>& on_map,
            const std::function<void(const ReplayView&)>& on_view);

/// The known volume of `map` inside `box`, m³ (leaves clipped to the box).
double known_volume_m3(const map::OccupancyMap& map, const Eigen::AlignedBox3d& box);

}  // namespace fvx::session
