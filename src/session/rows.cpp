#include "fvx/session/rows.hpp"

#include <cmath>

namespace fvx::session {

namespace {

/// The columns both loops share: times, U of the chosen view, the map's voids.
ViewRow common_row(int view, const pipeline::StepResult& step, const std::optional<std::size_t>& chosen, double R) {
  ViewRow row;
  row.view = view;
  row.timing = step.timing;
  row.searched = step.searched;
  row.void_cells = chosen ? step.nbv.views[*chosen].void_cells_seen : 0;
  row.utility_dm3 = frontier_voids::to_dm3(double(row.void_cells) * R * R * R);
  row.map_void_cells = step.analysis.void_cells.size();
  row.void_dm3 = frontier_voids::to_dm3(double(row.map_void_cells) * R * R * R);
  if (step.registration) row.registration_fitness_m = step.registration->fitness_rmse_m;
  return row;
}

}  // namespace

ViewRow row_of(const ViewRecord& v, const map::OccupancyMap& map, const Eigen::AlignedBox3d& S) {
  ViewRow row = common_row(v.view, v.step, v.chosen, map.resolution_m());
  row.render_s = v.scan_s;
  row.known_dm3 = frontier_voids::to_dm3(known_volume_m3(map, S));
  return row;
}

ViewRow row_of(const ReplayView& v, double R) {
  ViewRow row = common_row(v.view, v.step, v.chosen, R);
  row.scan = v.name;
  row.known_dm3 = frontier_voids::to_dm3(v.known_m3);
  row.void_dm3 = frontier_voids::to_dm3(v.void_m3);
  return row;
}

void append_row(std::vector<ViewRow>& rows, ViewRow row, std::size_t revealed_by_this_scan,
                std::optional<double> from_choice_m, std::optional<double> from_choice_deg) {
  if (!rows.empty()) {
    rows.back().revealed = revealed_by_this_scan;
    rows.back().next_m = from_choice_m;
    rows.back().next_deg = from_choice_deg;
  }
  rows.push_back(std::move(row));
}

}  // namespace fvx::session
