#include <nlohmann/json.hpp>

#include "fvx/pipeline/pipeline.hpp"

namespace fvx::pipeline {

Json config_json(const Config& c) {
  Json j = {{"resolution_m", c.resolution_m},
          {"bounds_m", bounds_json(c.bounds_m)},
          {"filter", scan::config_json(c.filter)},
          // Unset: the sensor's farthest depth; +infinity: no limit.
          {"max_range_m", c.max_range_m ? finite_or_null(*c.max_range_m) : Json(c.nbv.sensor.depth_max_m)},
          {"register_scans", c.register_scans},
          {"registration", registration::config_json(c.registration)},
          {"clusters", voids::config_json(c.clusters)},
          {"target_size_m", c.target_size_m},
          {"hull_in_bounds", c.hull_in_bounds},
          {"clear_beyond_range", c.clear_beyond_range},
          {"discretize", c.discretize},
          {"min_void_width_cells", c.min_void_width_cells()},
          {"analyse", c.analyse},
          {"search", c.search}};
  if (c.search) j["nbv"] = nbv::config_json(c.nbv);
  return j;
}

}  // namespace fvx::pipeline
