#include "fvx/report/integrate.hpp"

#include <nlohmann/json.hpp>

#include "fvx/io/intrinsics.hpp"

namespace fvx::report {

Json integrate_config_json(const pipeline::Config& config, const scan::LoadConfig& load, const map::OccupancyMap& map) {
  Json c = pipeline::config_json(config);
  c["pose"] = load.pose ? pose_json(*load.pose) : Json(nullptr);
  c["use_viewpoint"] = load.use_viewpoint;
  c["pose_format"] = io::to_string(load.pose_format);
  c["max_time_diff_s"] = load.max_time_diff_s;
  c["intrinsics"] = load.intrinsics ? io::intrinsics_json(*load.intrinsics) : Json(nullptr);
  const map::SensorModel model = map.sensor_model();
  c["sensor_model"] = {{"prob_hit", model.prob_hit},
                       {"prob_miss", model.prob_miss},
                       {"clamp_min", model.clamp_min},
                       {"clamp_max", model.clamp_max},
                       {"occupancy_threshold", model.occupancy_threshold}};
  return c;
}

Json map_json(const map::Stats& s) {
  Json j = {{"resolution_m", s.resolution_m},
            {"nodes", s.nodes},
            {"free_leaves", s.free_leaves},
            {"occupied_leaves", s.occupied_leaves},
            {"free_volume_m3", s.free_volume_m3},
            {"occupied_volume_m3", s.occupied_volume_m3}};
  j["known_bounds_m"] = s.empty ? Json(nullptr)
                                : Json{{"min", vec_json(s.known_min_m)}, {"max", vec_json(s.known_max_m)}};
  return j;
}

Json registration_json(const registration::Result& r) {
  Json j = {{"attempted", true},
            {"converged", r.converged},
            {"iterations", r.iterations},
            {"fitness_rmse_m", r.fitness_rmse_m},
            {"inlier_fraction", r.inlier_fraction},
            {"source_points", r.source_points},
            {"target_points", r.target_points},
            {"correction", {{"translation_m", r.correction_translation_m},
                            {"rotation_deg", r.correction_rotation_deg}}}};
  j["weak_directions"] = r.weak_directions;
  if (!r.fine_start.empty()) j["fine_start"] = r.fine_start;
  if (!r.problem.empty()) j["problem"] = r.problem;
  return j;
}

Json integration_json(const map::IntegrationCounts& c) {
  return {{"changed_cells", c.changed_cells},
          {"became_free", c.became_free},
          {"became_occupied", c.became_occupied},
          {"free_updates", c.free_updates},
          {"occupied_updates", c.occupied_updates},
          {"points_beyond_range", c.points_beyond_range},
          {"points_out_of_map", c.points_out_of_map}};
}

Json integrated_scan_json(const pipeline::IntegratedScan& s, bool registering, bool timing) {
  const pipeline::StepResult& r = s.step;
  const scan::FilterStats& filtered = r.filtered;
  Json entry = {{"file", s.path}, {"pose_source", scan::to_string(s.pose_source)}};
  entry["points"] = {{"input", filtered.input},   {"non_finite", filtered.non_finite},
                     {"out_of_depth", filtered.out_of_depth}, {"merged", filtered.merged},
                     {"kept", filtered.kept}};
  entry["prior"] = pose_json(s.T_world_sensor_prior);
  if (r.registration)
    entry["registration"] = registration_json(*r.registration);
  else
    entry["registration"] = {
        {"attempted", false},
        {"reason", registering ? "nothing to register to yet (first scan of an empty map)" : "--no-register"}};
  entry["T_world_sensor"] = pose_json(r.T_world_sensor);
  entry["integration"] = integration_json(r.integration);
  if (timing)
    entry["timing_s"] = {{"load", s.load_s}, {"registration", r.timing.registration_s},
                         {"integration", r.timing.integration_s}};
  return entry;
}

}  // namespace fvx::report
