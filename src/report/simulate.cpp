#include "fvx/report/simulate.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

#include "fvx/io/intrinsics.hpp"

namespace fvx::report {

Json simulate_config_json(const sim::SensorConfig& sensor, sim::Backend backend, sim::FrameFormat format) {
  return {{"intrinsics", io::intrinsics_json(sensor.intrinsics)},
          {"depth_min_m", sensor.depth_min_m},
          {"depth_max_m", sensor.depth_max_m},
          {"noise_m_per_m2", sensor.noise_m_per_m2},
          {"quantize_disparity", sensor.quantize_disparity},
          {"dropout_incidence_deg", sensor.dropout_incidence_deg},
          {"seed", sensor.seed},
          {"backend", sim::to_string(backend)},
          {"threads", sensor.threads},
          {"output_format", format == sim::FrameFormat::DepthPng ? "png" : "pcd"}};
}

Json frames_json(const std::vector<sim::RecordedFrame>& frames) {
  Json out = Json::array();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const sim::RecordedFrame& f = frames[i];
    out.push_back({{"index", i}, {"file", f.file}, {"T_world_sensor", pose_json(f.T_world_sensor)},
                   {"pixels", {{"valid", f.valid}, {"no_surface", f.no_surface},
                               {"too_near", f.too_near}, {"grazing", f.grazing}}}});
  }
  return out;
}

Json ground_truth_json(const sim::GroundTruth& gt, const std::string& path, const Eigen::AlignedBox3d& region,
                       const sim::Scene& scene) {
  const double cell_m3 = std::pow(gt.resolution_m(), 3);
  Json containers = Json::array();
  for (const auto& c : scene.info.containers)
    containers.push_back({{"name", c.name}, {"box", bounds_json(c.box)},
                          {"free_volume_dm3", gt.free_volume_m3(c.box) * 1e3}});
  Json result = {{"file", path},
                 {"resolution_m", gt.resolution_m()},
                 {"region", bounds_json(region)},
                 {"solid_cells", gt.solid_cells()},
                 {"free_cells", gt.free_cells()},
                 {"solid_volume_m3", double(gt.solid_cells()) * cell_m3},
                 {"free_volume_m3", double(gt.free_cells()) * cell_m3},
                 {"containers", containers}};
  if (scene.info.target)
    result["target"] = {{"name", scene.info.target->name}, {"box", bounds_json(scene.info.target->box)}};
  return result;
}

}  // namespace fvx::report
