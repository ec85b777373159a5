#pragma once
/// \file
/// The per-view table of a session (the paper's Tables I and II, then what a recording or a
/// simulation adds): one row type for `explore` and `replay`, filled from their view records.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "fvx/pipeline/pipeline.hpp"
#include "fvx/session/replay.hpp"
#include "fvx/session/session.hpp"

namespace fvx::session {

/// Simulation only: the view judged against the scene's ground truth (sim::ExplorationScore).
struct TruthColumns {
  double known_fraction = 0;       ///< of the observable empty space of S
  double void_known_fraction = 0;  ///< of the observable void cells (sim::ExplorationScore)
  std::size_t target_cells = 0;    ///< target cells the map holds as occupied
  bool target_seen = false;        ///< at least sim::ExplorationScore::kTargetCellsSeen of them
  std::size_t u_in_solid = 0;      ///< of void_cells, cells inside material
  std::size_t free_in_solid = 0;   ///< free map cells in S inside material
};

struct ViewRow {
  int view = 0;                              ///< 0-based
  std::string scan;                          ///< replay: the scan's file; explore: empty
  std::optional<double> render_s;            ///< explore: the virtual Kinect's time
  pipeline::Timing timing;
  bool searched = true;                      ///< false: --search-every skipped this view's search
  std::size_t void_cells = 0;                ///< the paper's column: U of the chosen next view
  double utility_dm3 = 0;                    ///< void_cells · R³, dm³
  std::size_t map_void_cells = 0;            ///< every void cell of the map in S
  double known_dm3 = 0, void_dm3 = 0;        ///< known and void volume in S
  std::optional<double> registration_fitness_m;
  /// Of this view's void cells, known after the next scan (set by the next view).
  std::optional<std::size_t> revealed;
  /// Replay: the next logged pose against the chosen view (set by the next view).
  std::optional<double> next_m, next_deg;
  std::optional<TruthColumns> truth;         ///< explore: against ground truth
};

/// An explore view's row (without truth); `S` the search space.
ViewRow row_of(const ViewRecord& v, const map::OccupancyMap& map, const Eigen::AlignedBox3d& S);
/// A replay view's row; `R` the map's cell edge, metres.
ViewRow row_of(const ReplayView& v, double R);

/// Appends `row`, and gives the previous row what this view tells of it: the void cells this
/// scan revealed and, for a replay, how far the logged pose was from the chosen one.
void append_row(std::vector<ViewRow>& rows, ViewRow row, std::size_t revealed_by_this_scan,
                std::optional<double> from_choice_m = std::nullopt,
                std::optional<double> from_choice_deg = std::nullopt);

}  // namespace fvx::session
