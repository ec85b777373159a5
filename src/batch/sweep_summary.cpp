// The merge of a sweep (sweep.hpp): the runs' explore reports → the evaluation's tables and
// the coverage plot. Every number written here but timing.csv's comes from the runs' results,
// never from a clock, so the same plan merges into the same bytes wherever its tasks ran.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fvx/batch/sweep.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// One run, as the tables need it.
struct Run {
  std::string scene, planner, seed;
  json results;
  std::vector<double> coverage;  ///< void_known_fraction after each view, carried to max_views
};

std::string fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

/// The lower median (the middle of an odd count; of two middles the lower).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[(v.size() - 1) / 2];
}

double quantile(std::vector<double> v, double f) {
  std::sort(v.begin(), v.end());
  return v[std::size_t(f * double(v.size() - 1))];
}

Run read_run(const Task& task, int& max_views) {
  const std::string id = fs::path(task.output).stem().string();
  const std::size_t a = id.find('_'), b = id.rfind('_');
  Run run{id.substr(0, a), id.substr(a + 1, b - a - 1), id.substr(b + 1), {}, {}};
  if (!fs::is_regular_file(task.output)) throw FileError(task.output, "this run of the sweep is missing (" + id + ")");
  try {
    std::ifstream in(task.output);
    const json report = json::parse(in);
    run.results = report.at("results");
    const int views = report.at("config").at("max_views").get<int>();
    if (max_views && views != max_views) throw FileError(task.output, "its runs stop after other view counts than the first's");
    max_views = views;
    for (const char* key : {"views", "end", "utility_exhausted", "observable_void_cells", "observable_target_cells"})
      (void)run.results.at(key);  // the tables read these without a check
    (void)run.results.at("end").get<std::string>();
    for (const json& row : run.results.at("rows")) {
      (void)row.at("view").get<int>();
      (void)row.at("known_fraction").get<double>();
      run.coverage.push_back(row.at("void_known_fraction").get<double>());
    }
  } catch (const json::exception& e) {
    throw FileError(task.output, std::string("not an fvx explore report: ") + e.what());
  }
  if (run.coverage.empty()) throw FileError(task.output, "an explore report without views");
  run.coverage.resize(std::size_t(max_views), run.coverage.back());
  return run;
}

std::string views_to(const Run& r, double share) {
  for (const json& row : r.results["rows"])
    if (row["void_known_fraction"].get<double>() >= share) return row["view"].dump();
  return "";
}

std::string target_seen_at(const Run& r) {
  for (const json& row : r.results["rows"])
    if (row.contains("target_seen") && row["target_seen"] == true) return row["view"].dump();
  return "";
}

/// "" when the scene has no target or it was not judged; "yes" when at least 5 of its cells
/// are observable (the explore loop's own rule), else "no".
std::string target_observable(const Run& r) {
  const json& t = r.results["observable_target_cells"];
  return t.is_null() ? "" : t.get<double>() >= 5 ? "yes" : "no";
}

double auc(const Run& r) {
  double sum = 0;
  for (const double c : r.coverage) sum += c;
  return sum / double(r.coverage.size());
}

std::string runs_csv(const std::vector<Run>& runs) {
  std::string out = "scene,planner,seed,views,end,utility_exhausted,observable_void_cells,target_observable,"
                    "target_seen_at,views_to_95,void_known_final,known_final,auc\n";
  for (const Run& r : runs) {
    std::string end = r.results["end"].get<std::string>();
    std::replace(end.begin(), end.end(), ',', ';');
    out += r.scene + "," + r.planner + "," + r.seed + "," + r.results["views"].dump() + "," + end + "," +
           r.results["utility_exhausted"].dump() + "," + r.results["observable_void_cells"].dump() + "," +
           target_observable(r) + "," + target_seen_at(r) + "," + views_to(r, 0.95) + "," +
           r.results["rows"].back()["void_known_fraction"].dump() + "," +
           r.results["rows"].back()["known_fraction"].dump() + "," + fixed(auc(r), 4) + "\n";
  }
  return out;
}

std::string coverage_csv(const std::vector<Run>& runs) {
  std::string out = "scene,planner,seed,view,void_known_fraction\n";
  for (const Run& r : runs)
    for (std::size_t v = 0; v < r.coverage.size(); ++v)
      out += r.scene + "," + r.planner + "," + r.seed + "," + std::to_string(v + 1) + "," + json(r.coverage[v]).dump() + "\n";
  return out;
}

std::string timing_csv(const std::vector<Run>& runs) {
  std::string out = "scene,planner,seed,search_s_median,search_s_total\n";
  for (const Run& r : runs) {
    std::vector<double> s;
    for (const json& row : r.results["rows"])
      if (row.contains("timing_s") && row["timing_s"].contains("search")) s.push_back(row["timing_s"]["search"].get<double>());
    double total = 0;
    for (const double x : s) total += x;
    out += r.scene + "," + r.planner + "," + r.seed + "," + (s.empty() ? "," : fixed(median(s), 4) + "," + fixed(total, 3)) + "\n";
  }
  return out;
}

/// The planner labels in the order of the plan (its first scene's tasks).
std::vector<std::string> planner_order(const std::vector<Run>& runs) {
  std::vector<std::string> order;
  for (const Run& r : runs)
    if (std::find(order.begin(), order.end(), r.planner) == order.end()) order.push_back(r.planner);
  return order;
}

/// summary.md and summary.csv: per planner. Views to 95 %: the median over runs, a run that
/// never got there counting as max_views + 1 (shown as ">max"). AUC: the mean coverage over
/// the views; the first planner's is compared with each other's on the same scene and seed.
std::pair<std::string, std::string> summary(const std::vector<Run>& runs, int max_views) {
  const std::vector<std::string> order = planner_order(runs);
  std::map<std::string, double> auc_of;  // "planner|scene|seed"
  for (const Run& r : runs) auc_of[r.planner + "|" + r.scene + "|" + r.seed] = auc(r);
  std::string md = "| planner | runs | views to 95 % of the void (median) | reached 95 % | ended with utility 0 | target seen "
                   "where observable | mean AUC | " + order[0] + " AUC higher |\n|---|---|---|---|---|---|---|---|\n";
  std::string csv = "planner,runs,views_to_95_median,reached_95,ended_utility_0,target_observable,target_seen,auc_mean,"
                    "first_auc_higher,runs_compared\n";
  for (const std::string& p : order) {
    std::vector<double> v95;
    int n = 0, reached = 0, ended = 0, observable = 0, seen = 0, higher = 0, compared = 0;
    double auc_sum = 0;
    for (const Run& r : runs) {
      if (r.planner != p) continue;
      const std::string v = views_to(r, 0.95);
      ++n, reached += !v.empty(), ended += r.results["utility_exhausted"] == true, auc_sum += auc(r);
      v95.push_back(v.empty() ? max_views + 1 : std::stod(v));
      if (target_observable(r) == "yes") ++observable, seen += !target_seen_at(r).empty();
      const auto first = auc_of.find(order[0] + "|" + r.scene + "|" + r.seed);
      if (p != order[0] && first != auc_of.end()) ++compared, higher += first->second > auc(r);
    }
    const double m = median(v95);
    const std::string m_text = m > max_views ? ">" + std::to_string(max_views) : fixed(m, 0);
    const std::string of = "/" + std::to_string(n);
    md += "| " + p + " | " + std::to_string(n) + " | " + m_text + " | " + std::to_string(reached) + of + " | " +
          std::to_string(ended) + of + " | " + std::to_string(seen) + "/" + std::to_string(observable) + " | " +
          fixed(auc_sum / n, 3) + " | " + (p == order[0] ? "-" : std::to_string(higher) + "/" + std::to_string(compared)) + " |\n";
    csv += p + "," + std::to_string(n) + "," + m_text + "," + std::to_string(reached) + "," + std::to_string(ended) + "," +
           std::to_string(observable) + "," + std::to_string(seen) + "," + fixed(auc_sum / n, 4) + "," +
           std::to_string(higher) + "," + std::to_string(compared) + "\n";
  }
  return {md, csv};
}

/// coverage.dat (per planner a block: view, median, first and third quartile, in %) and the
/// gnuplot script that draws coverage.png from it.
std::pair<std::string, std::string> plot_files(const std::vector<Run>& runs, int max_views) {
  std::string dat, plot;
  int block = 0;
  for (const std::string& p : planner_order(runs)) {
    dat += "# " + p + "\n";
    for (int v = 0; v < max_views; ++v) {
      std::vector<double> c;
      for (const Run& r : runs)
        if (r.planner == p) c.push_back(100 * r.coverage[std::size_t(v)]);
      dat += std::to_string(v + 1) + " " + fixed(quantile(c, 0.5), 3) + " " + fixed(quantile(c, 0.25), 3) + " " +
             fixed(quantile(c, 0.75), 3) + "\n";
    }
    dat += "\n\n";
    const std::string i = std::to_string(block++), colour = std::to_string(block);
    plot += std::string(plot.empty() ? "plot " : ", \\\n     ") + "'coverage.dat' index " + i +
            " using 1:3:4 with filledcurves lc " + colour + " fs transparent solid 0.2 notitle, '' index " + i +
            " using 1:2 with linespoints lc " + colour + " lw 2 title '" + p + "'";
  }
  const std::string gp = "set terminal pngcairo size 900,560 font \",11\"\nset output \"coverage.png.tmp\"\n"
                         "set title \"Observable void volume known after each view (median; band: quartiles across runs)\"\n"
                         "set xlabel \"view\"; set ylabel \"void known, %\"; set yrange [0:100]; set xrange [1:" +
                         std::to_string(std::max(max_views, 2)) + "]\nset key bottom right; set grid; set xtics 1\n" + plot + "\n";
  return {dat, gp};
}

/// gnuplot draws coverage.png in `folder` (through coverage.png.tmp, renamed when whole).
void draw_plot(const std::string& folder) {
  const std::string q = shell_quote(folder);
  if (std::system(("cd " + q + " && gnuplot coverage.gp 2> coverage.gp.log && mv coverage.png.tmp coverage.png").c_str()) != 0) {
    fs::remove(folder + "/coverage.png.tmp");
    throw FileError(folder + "/coverage.gp", "gnuplot did not draw the coverage plot (Debian package gnuplot; its "
                                             "messages are in coverage.gp.log)");
  }
  fs::remove(folder + "/coverage.gp.log");
}

}  // namespace

void merge_sweep(const Plan& plan) {
  int max_views = 0;
  std::vector<Run> runs;
  for (const Task& t : plan.tasks) runs.push_back(read_run(t, max_views));
  if (runs.empty()) throw FileError(plan.folder, "a sweep plan without runs");
  const auto [dat, gp] = plot_files(runs, max_views);
  const auto [md, csv] = summary(runs, max_views);
  write_text_atomically(plan.folder + "/coverage.dat", dat);
  write_text_atomically(plan.folder + "/coverage.gp", gp);
  draw_plot(plan.folder);
  write_text_atomically(plan.folder + "/runs.csv", runs_csv(runs));
  write_text_atomically(plan.folder + "/coverage.csv", coverage_csv(runs));
  write_text_atomically(plan.folder + "/timing.csv", timing_csv(runs));
  write_text_atomically(plan.folder + "/summary.csv", csv);
  write_text_atomically(plan.result, md);  // last: its existence means the merge is whole
}

}  // namespace fvx::batch
