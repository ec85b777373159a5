#pragma once
/// \file
/// `fvx integrate` as a library call: recorded scan files through the step with the search
/// and the analysis off (§IV steps 1–3: filter, register, integrate), one after another.
#include <functional>
#include <string>
#include <vector>

#include "fvx/pipeline/pipeline.hpp"
#include "fvx/scan/load.hpp"

namespace fvx::pipeline {

/// What one scan file did to the map.
struct IntegratedScan {
  std::string path;
  scan::PoseSource pose_source = scan::PoseSource::Identity;
  Eigen::Isometry3d T_world_sensor_prior = Eigen::Isometry3d::Identity();
  double load_s = 0.0;  ///< reading the file, seconds
  StepResult step;      ///< integrate_step's result: filter counts, registration, pose, changes
};

/// Loads each scan of `plan` (scan::load_scan with `load`) and runs the pipeline's step on
/// it (its config's analyse and search must be off); `on_scan(i, scan)` after each. Appends
/// loading warnings and one for each registration that did not converge (the scan is then
/// integrated at its prior) to `warnings`. Error naming the file when a scan holds no point,
/// no finite point, or none within the depth limits.
void integrate_files(Pipeline& pipeline, const scan::ScanPlan& plan, const scan::LoadConfig& load,
                     std::vector<std::string>& warnings,
                     const std::function<void(std::size_t, const IntegratedScan&)>& on_scan);

}  // namespace fvx::pipeline
