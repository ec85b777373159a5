#pragma once
/// \file
/// What fvx explore and fvx replay report of a session, one form for both: the per-view rows
/// (a table on stdout or JSON), each view's own report, and the volume plot.
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "fvx/session/rows.hpp"
#include "fvx/session/session.hpp"
#include "fvx/sim/exploration_score.hpp"
#include "fvx/core/json.hpp"
#include "fvx/pipeline/pipeline.hpp"
#include "fvx/report/table.hpp"

namespace fvx::report {

/// A row as JSON; its times ("timing_s") only with `timing`, so that reports repeat byte for
/// byte without it.
Json row_json(const session::ViewRow& row, bool timing);
Json rows_json(const std::vector<session::ViewRow>& rows, bool timing);

/// The rows as a markdown or csv table with these columns (names as in the header): view,
/// integration_s, search_s, void_cells, utility_dm3, map_void_cells, known_pct, target_seen,
/// revealed, u_in_solid, fitness_m, next_m, next_deg, known_dm3.
void print_rows(const std::vector<session::ViewRow>& rows, const std::vector<std::string>& columns, Format format,
                std::ostream& out);

/// A view's report: `inputs`, the search's results with the pose integrated at, the rank of
/// the chosen view and the row; the analysis's warnings.
Json view_report(const std::string& command, Json inputs, const pipeline::StepResult& step,
                 const std::optional<std::size_t>& chosen, const session::ViewRow& row, double R,
                 const std::vector<std::string>& joint_names, nbv::Strategy strategy, bool timing);

/// An explore view's report: view_report with the scene, the view's files, and the poses
/// recorded (the prior) and true.
Json explore_view_report(const std::string& scene, const session::ViewRecord& v, const session::ManifestView& files,
                         const session::ViewRow& row, double R, const std::vector<std::string>& joint_names,
                         nbv::Strategy strategy, bool timing);
/// An explore run's results: its session folder, views, how the loop ended, what the arm can
/// observe (ground truth), and the rows.
Json explore_results_json(const std::string& dir, const session::ExploreResult& result,
                          const sim::ExplorationScore& score, const std::vector<session::ViewRow>& rows, bool timing);

/// Known and void volume in the search space after each of `rows`, as a line plot (PNG).
void write_volume_plot(const std::string& path, const std::string& title, const std::vector<session::ViewRow>& rows);

}  // namespace fvx::report
