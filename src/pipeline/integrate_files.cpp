#include "fvx/pipeline/integrate_files.hpp"

#include <nlohmann/json.hpp>

#include "fvx/core/error.hpp"
#include "fvx/core/stopwatch.hpp"

namespace fvx::pipeline {

namespace {

/// A scan that leaves nothing to integrate is an input error, not an empty step.
void check_points(const std::string& path, const scan::FilterStats& filtered) {
  if (filtered.input == 0) throw Error(path + ": the scan holds no points");
  if (filtered.non_finite == filtered.input) throw Error(path + ": the scan holds no finite points (all NaN)");
  if (filtered.kept == 0) throw Error(path + ": no point is left after the depth limits (--depth-min/--depth-max)");
}

}  // namespace

void integrate_files(Pipeline& pipeline, const scan::ScanPlan& plan, const scan::LoadConfig& load,
                     std::vector<std::string>& warnings,
                     const std::function<void(std::size_t, const IntegratedScan&)>& on_scan) {
  FVX_ASSERT(!pipeline.config().analyse && !pipeline.config().search,
             "integrate_files: the analysis and the search must be off");
  for (std::size_t i = 0; i < plan.scans.size(); ++i) {
    IntegratedScan out;
    out.path = plan.scans[i].path;
    Stopwatch clock;
    scan::Scan s = scan::load_scan(plan.scans[i], load, warnings);
    out.load_s = clock.lap();
    out.T_world_sensor_prior = s.T_world_sensor;
    out.pose_source = s.pose_source;
    out.step = pipeline.step(std::move(s));
    check_points(out.path, out.step.filtered);
    if (out.step.registration && !out.step.registration->converged)
      warnings.push_back(out.path + ": registration did not converge (" + out.step.registration->problem +
                         "); the scan is integrated at its pose prior");
    on_scan(i, out);
  }
}

}  // namespace fvx::pipeline
