#include "fvx/report/session.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <map>

#include "fvx/core/error.hpp"
#include "fvx/io/visual.hpp"
#include "fvx/report/envelope.hpp"
#include "fvx/report/nbv.hpp"

namespace fvx::report {

namespace {

template <typename T>
Json or_null(const std::optional<T>& v) {
  return v ? Json(*v) : Json(nullptr);
}

Json timing_json(const session::ViewRow& r) {
  Json t = Json::object();
  if (r.render_s) t["render"] = *r.render_s;
  t["registration"] = r.timing.registration_s;
  t["integration"] = r.timing.integration_s;
  t["frontiers_voids"] = r.timing.frontiers_voids_s;
  t["search"] = r.searched ? Json(r.timing.search_s) : Json(nullptr);
  return t;
}

using Cell = std::function<std::string(const session::ViewRow&)>;

std::string maybe(const std::optional<double>& v, int digits) { return v ? fixed(*v, digits) : std::string("-"); }

/// Each column of the tables, by its header name.
const std::map<std::string, Cell>& columns() {
  using R = const session::ViewRow&;
  static const std::map<std::string, Cell> table = {
      {"view", [](R r) { return std::to_string(r.view + 1); }},
      // The paper's "integration": octree, frontiers and voids.
      {"integration_s", [](R r) { return fixed(r.timing.integration_s + r.timing.frontiers_voids_s, 3); }},
      {"search_s", [](R r) { return r.searched ? fixed(r.timing.search_s, 3) : "-"; }},
      {"void_cells", [](R r) { return r.searched ? std::to_string(r.void_cells) : "-"; }},
      {"utility_dm3", [](R r) { return r.searched ? fixed(r.utility_dm3, 2) : "-"; }},
      {"map_void_cells", [](R r) { return std::to_string(r.map_void_cells); }},
      {"known_pct", [](R r) { return r.truth ? fixed(100.0 * r.truth->known_fraction, 1) : "-"; }},
      {"void_known_pct", [](R r) { return r.truth ? fixed(100.0 * r.truth->void_known_fraction, 1) : "-"; }},
      {"target_seen", [](R r) { return r.truth ? (r.truth->target_seen ? "yes" : "no") : "-"; }},
      {"revealed", [](R r) { return r.revealed ? std::to_string(*r.revealed) : "-"; }},
      {"u_in_solid", [](R r) { return r.truth ? std::to_string(r.truth->u_in_solid) : "-"; }},
      {"fitness_m", [](R r) { return maybe(r.registration_fitness_m, 4); }},
      {"next_m", [](R r) { return maybe(r.next_m, 3); }},
      {"next_deg", [](R r) { return maybe(r.next_deg, 1); }},
      {"known_dm3", [](R r) { return fixed(r.known_dm3, 1); }},
  };
  return table;
}

}  // namespace

Json row_json(const session::ViewRow& r, bool timing) {
  Json j = {{"view", r.view + 1}};
  if (!r.scan.empty()) j["scan"] = r.scan;
  if (timing) j["timing_s"] = timing_json(r);
  j["void_cells"] = r.searched ? Json(r.void_cells) : Json(nullptr);
  j["utility_dm3"] = r.searched ? Json(r.utility_dm3) : Json(nullptr);
  j["map_void_cells"] = r.map_void_cells;
  j["known_dm3"] = r.known_dm3;
  j["void_dm3"] = r.void_dm3;
  j["registration_fitness_m"] = or_null(r.registration_fitness_m);
  j["revealed_void_cells"] = or_null(r.revealed);
  j["next_distance_m"] = or_null(r.next_m);
  j["next_angle_deg"] = or_null(r.next_deg);
  if (r.truth) {
    j["known_fraction"] = r.truth->known_fraction;
    j["void_known_fraction"] = r.truth->void_known_fraction;
    j["target_cells_seen"] = r.truth->target_cells;
    j["target_seen"] = r.truth->target_seen;
    j["void_cells_in_solid"] = r.truth->u_in_solid;
    j["free_cells_in_solid"] = r.truth->free_in_solid;
  }
  return j;
}

Json rows_json(const std::vector<session::ViewRow>& rows, bool timing) {
  Json j = Json::array();
  for (const auto& r : rows) j.push_back(row_json(r, timing));
  return j;
}

void print_rows(const std::vector<session::ViewRow>& rows, const std::vector<std::string>& header, Format format,
                std::ostream& out) {
  std::vector<const Cell*> cells;
  for (const std::string& name : header) {
    const auto it = columns().find(name);
    FVX_ASSERT(it != columns().end(), "print_rows: no column " + name);
    cells.push_back(&it->second);
  }
  std::vector<std::vector<std::string>> table;
  for (const auto& r : rows) {
    table.emplace_back();
    for (const Cell* cell : cells) table.back().push_back((*cell)(r));
  }
  print_table(header, table, format, out);
}

Json view_report(const std::string& command, Json inputs, const pipeline::StepResult& step,
                 const std::optional<std::size_t>& chosen, const session::ViewRow& row, double R,
                 const std::vector<std::string>& joint_names, nbv::Strategy strategy, bool timing) {
  Json report = new_report(command);
  report["inputs"] = std::move(inputs);
  Json results = nbv_results_json(step.nbv, step.analysis, R, joint_names, strategy, timing);
  results["T_world_sensor_integrated"] = pose_json(step.T_world_sensor);
  results["chosen_rank"] = chosen ? Json(*chosen + 1) : Json(nullptr);
  results["row"] = row_json(row, timing);
  report["results"] = std::move(results);
  report["warnings"] = step.analysis.warnings;
  return report;
}

Json explore_view_report(const std::string& scene, const session::ViewRecord& v, const session::ManifestView& files,
                         const session::ViewRow& row, double R, const std::vector<std::string>& joint_names,
                         nbv::Strategy strategy, bool timing) {
  Json report = view_report("explore", {{"scene", scene}, {"view", v.view}, {"scan", files.scan}, {"map", files.map}},
                            v.step, v.chosen, row, R, joint_names, strategy, timing);
  report["results"]["T_world_sensor_prior"] = pose_json(v.T_world_sensor_prior);
  report["results"]["T_world_sensor_true"] = pose_json(v.T_world_sensor_true);
  return report;
}

Json explore_results_json(const std::string& dir, const session::ExploreResult& result,
                          const sim::ExplorationScore& score, const std::vector<session::ViewRow>& rows, bool timing) {
  const auto target = score.observable_target_cells();
  return {{"session", dir},
          {"views", result.views},
          {"end", result.end},
          {"utility_exhausted", result.utility_exhausted},
          {"observable_cells", score.observable_cells()},
          {"observable_void_cells", score.observable_void_cells()},
          {"observable_target_cells", target ? Json(*target) : Json(nullptr)},
          {"rows", rows_json(rows, timing)}};
}

void write_volume_plot(const std::string& path, const std::string& title, const std::vector<session::ViewRow>& rows) {
  std::vector<double> known, voids;
  for (const session::ViewRow& r : rows) known.push_back(r.known_dm3), voids.push_back(r.void_dm3);
  io::write_line_plot_png(path, title, "view", "dm^3", {{"known", {40, 120, 200}, known}, {"void", {150, 60, 170}, voids}});
}

}  // namespace fvx::report
