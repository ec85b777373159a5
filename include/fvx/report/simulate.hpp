#pragma once
/// \file
/// What `fvx simulate` reports: the virtual Kinect's settings, the frames written, and the
/// scene's ground truth.
#include <string>
#include <vector>

#include "fvx/core/json.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "fvx/sim/ray_caster.hpp"
#include "fvx/sim/recording.hpp"

namespace fvx::report {

Json simulate_config_json(const sim::SensorConfig& sensor, sim::Backend backend, sim::FrameFormat format);
Json frames_json(const std::vector<sim::RecordedFrame>& frames);
/// The ground truth saved at `path` over `region`: cells and volumes, solid and free; the
/// free volume of each of the scene's containers; its target.
Json ground_truth_json(const sim::GroundTruth& gt, const std::string& path, const Eigen::AlignedBox3d& region,
                       const sim::Scene& scene);

}  // namespace fvx::report
