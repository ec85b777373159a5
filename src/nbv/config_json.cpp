#include <nlohmann/json.hpp>

#include "fvx/nbv/nbv.hpp"

namespace fvx::nbv {

Json config_json(const Config& c) {
  return {{"strategy", to_string(c.strategy)},
          {"sensor", io::camera_json(c.sensor)},
          {"rays", {c.ray_cols, c.ray_rows}},
          {"coarse_rays", {c.coarse_ray_cols, c.coarse_ray_rows}},
          {"rescored_poses", c.rescored_poses},
          {"valid_poses", c.valid_poses},
          {"orientations_per_cell", c.orientations_per_cell},
          {"jitter_deg", c.jitter_deg},
          {"clearance_m", c.clearance_m},
          {"min_separation_m", c.min_separation_m},
          {"refine_poses", c.refine_poses},
          {"refine_step_m", c.refine_step_m},
          {"refine_max_m", c.refine_max_m},
          {"polish_poses", c.polish_poses},
          {"polish_rolls", c.polish_rolls},
          {"climb_rounds", c.climb_rounds},
          {"climb_step_m", c.climb_step_m},
          {"climb_angle_deg", c.climb_angle_deg},
          {"view_bounds_m", bounds_json(c.view_bounds_m)},
          {"exhaustive_rolls", c.exhaustive_rolls},
          {"random_tries", c.random_tries},
          {"count_near_void_cells", c.count_near_void_cells},
          {"unknown_depth_cells", c.unknown_depth_cells},
          {"near_unknown", viewpoints::to_string(c.near_unknown)},
          {"exterior", to_string(c.exterior)},
          {"accumulation", utility::to_string(c.accumulation)},
          {"max_utility_vectors", c.max_utility_vectors},
          {"top", c.top},
          {"seed", c.seed},
          {"threads", c.threads}};
}

}  // namespace fvx::nbv
