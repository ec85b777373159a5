#include <nlohmann/json.hpp>

#include "fvx/session/replay.hpp"
#include "fvx/session/session.hpp"

namespace fvx::session {

Json config_json(const ExploreConfig& c) {
  return {{"T_world_sensor_start", pose_json(c.T_world_sensor_start)},
          {"max_views", c.max_views},
          {"pose_noise", {{"sigma_m", c.pose_noise_m}, {"sigma_deg", c.pose_noise_deg}}},
          {"seed", c.seed},
          {"pipeline", pipeline::config_json(c.pipeline)}};
}

Json config_json(const ReplayConfig& c) {
  return {{"last_view", c.last_view < 0 ? Json(nullptr) : Json(c.last_view + 1)},
          {"search_every", c.search_every},
          {"pipeline", pipeline::config_json(c.pipeline)}};
}

}  // namespace fvx::session
