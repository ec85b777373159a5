// fvx voids — a map → void clusters (ellipsoids), frontier clusters and frontier-voids with
// their utility (paper §IV-B).
#include "analysis_output.hpp"
#include "command_table.hpp"
#include "common_options.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/stopwatch.hpp"
#include "fvx/report/picture3d.hpp"

namespace fvx::cli {

const CommandSpec kVoidsSpec = {
    "voids",
    "MAP.bt|MAP.ot [-o REPORT.json] [options]",
    "a map's voids (unknown inside the hull), their ellipsoids, and frontier-voids with utility",
    options({{
        {"output", 'o', "FILE", "write the JSON report to FILE instead of stdout", "-"},
        {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space, metres (default: the box of the known cells)",
         "/config/bounds_m"},
        void_hull_option("/config/hull_in_bounds"),
        min_fit_score_option("/config/min_fit_score", "region growing keeps a cluster's fit score (Eq. 2) at or above S"),
        seed_option("/config/seed", "order of the region-growing seeds", voids::ClusterConfig{}.seed),
        {"cloud", 0, "FILE", "frontier (red) and void (violet) cells as a coloured cloud, .ply or .pcd", "-"},
        {"by-cluster", 0, nullptr, "colour the cloud by cluster instead", "-"},
        {"ellipsoids", 0, "FILE.ply", "the void clusters' ellipsoids as a mesh", "-"},
        {"timing", 0, nullptr, "add the time of loading the map and of the analysis (seconds) to the report", "-"},
        {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
        {"help", 'h', nullptr, "show this help", "-"},
    }, report::picture_options(false, "a 3-D picture of the search space: occupied (grey), frontier (red) and void (violet) cells, the void ellipsoids", "a top view of occupied (grey), frontier (red) and void (violet) cells")})};

int run_voids(const Args& args) {
  if (args.positional.size() != 1)
    throw UsageError("fvx voids: give one map (.bt or .ot), got " + std::to_string(args.positional.size()));
  const auto bounds = parse_bounds(args);
  const report::PictureRequest pictures = report::read_picture_options(args);
  voids::ClusterConfig config;
  args.read("min-fit-score", config.min_fit_score);
  args.read("seed", config.seed);
  const bool hull_in_bounds = parse_void_hull(args, false);
  Stopwatch clock;
  const map::OccupancyMap map = map::OccupancyMap::load(args.positional[0]);
  const double load_s = clock.lap();
  Progress progress(args.has("progress"));
  progress.update("fvx voids: frontiers, voids and frontier-voids of " + args.positional[0]);
  config.progress = [&](const std::string& stage, std::size_t done, std::size_t total) {
    progress.update("fvx voids: " + stage + " " + std::to_string(done) + "/" + std::to_string(total));
  };
  frontier_voids::Analysis a = frontier_voids::analyse_map(map, bounds, config, 1, true, hull_in_bounds);
  progress.finish();
  const double analysis_s = clock.lap();
  if (args.has("cloud")) write_cells_cloud(args.get("cloud"), map, a, true, args.has("by-cluster"));
  if (args.has("ellipsoids")) write_ellipsoids(args.get("ellipsoids"), a.void_clusters);

  const double R = map.resolution_m();
  Json report = new_report("voids");
  report["config"] = {{"bounds_m", bounds ? bounds_json(*bounds) : Json(nullptr)},
                      {"hull_in_bounds", hull_in_bounds},
                      {"min_fit_score", config.min_fit_score},
                      {"seed", config.seed},
                      {"definition", "voids: unknown cells inside the convex hull of the occupied cell "
                                     "centres (in the search space, with hull_in_bounds); frontier-voids: frontier clusters face- or edge-adjacent"}};
  report["inputs"] = {{"map", args.positional[0]}, {"resolution_m", R}};
  report["results"] = voids_results_json(a, R);
  if (a.void_cells.empty() && a.warnings.empty()) a.warnings.push_back("no void cell in the search space");
  report["results"]["picture"] = report::write_analysis_pictures(pictures, map, a, true);
  if (args.has("timing")) report["results"]["timing_s"] = {{"load", load_s}, {"analysis", analysis_s}};
  report["warnings"] = a.warnings;
  write_report(report, args.has("output") ? args.get("output") : "");
  return core::end_process(0);
}

}  // namespace fvx::cli
