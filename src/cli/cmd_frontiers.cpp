// fvx frontiers — a map → its frontier cells and clusters (paper §IV-A).
#include "analysis_output.hpp"
#include "command_table.hpp"
#include "common_options.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/stopwatch.hpp"
#include "fvx/report/picture3d.hpp"

namespace fvx::cli {

const CommandSpec kFrontiersSpec = {
    "frontiers",
    "MAP.bt|MAP.ot [-o REPORT.json] [options]",
    "a map's frontier cells (free next to unknown) and their clusters",
    options({{
        {"output", 'o', "FILE", "write the JSON report to FILE instead of stdout", "-"},
        {"bounds", 0, "x0,y0,z0,x1,y1,z1", "search space, metres (default: the box of the known cells)",
         "/config/bounds_m"},
        {"cloud", 0, "FILE", "frontier cells as a coloured cloud, .ply or .pcd (red)", "-"},
        {"by-cluster", 0, nullptr, "colour the cloud by cluster instead", "-"},
        {"timing", 0, nullptr, "add the time of loading the map and of the analysis (seconds) to the report", "-"},
        {"help", 'h', nullptr, "show this help", "-"},
    }, report::picture_options(false, "a 3-D picture of the search space: occupied (grey) and frontier (red) cells", "a top view of occupied (grey) and frontier (red) cells")})};

int run_frontiers(const Args& args) {
  if (args.positional.size() != 1)
    throw UsageError("fvx frontiers: give one map (.bt or .ot), got " + std::to_string(args.positional.size()));
  const auto bounds = parse_bounds(args);
  const report::PictureRequest pictures = report::read_picture_options(args);
  Stopwatch clock;
  const map::OccupancyMap map = map::OccupancyMap::load(args.positional[0]);
  const double load_s = clock.lap();
  frontier_voids::Analysis a = frontier_voids::analyse_map(map, bounds, voids::ClusterConfig{}, 1, false);
  const double analysis_s = clock.lap();
  if (args.has("cloud")) write_cells_cloud(args.get("cloud"), map, a, false, args.has("by-cluster"));

  Json report = new_report("frontiers");
  report["config"] = {{"bounds_m", bounds ? bounds_json(*bounds) : Json(nullptr)},
                      {"definition", "free cells with an unknown face-neighbour; clusters 26-connected"}};
  report["inputs"] = {{"map", args.positional[0]}, {"resolution_m", map.resolution_m()}};
  report["results"] = frontiers_results_json(a);
  if (a.frontier_cells.empty() && a.warnings.empty()) a.warnings.push_back("no frontier cell in the search space");
  report["results"]["picture"] = report::write_analysis_pictures(pictures, map, a, false);
  if (args.has("timing")) report["results"]["timing_s"] = {{"load", load_s}, {"analysis", analysis_s}};
  report["warnings"] = a.warnings;
  write_report(report, args.has("output") ? args.get("output") : "");
  return core::end_process(0);
}

}  // namespace fvx::cli
