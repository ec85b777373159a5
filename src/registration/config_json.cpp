#include <nlohmann/json.hpp>

#include "fvx/registration/registration.hpp"

namespace fvx::registration {

Json config_json(const Config& c) {
  return {{"method", to_string(c.method)},
          {"voxel_m", c.voxel_m},
          {"max_correspondence_m", c.max_correspondence_m},
          {"fine_correspondence_m", c.fine_correspondence_m},
          {"fine_voxel_m", c.fine_voxel_m},
          {"min_observability", c.min_observability},
          {"robust_scale_m", c.robust_scale_m},
          {"max_iterations", c.max_iterations},
          {"translation_epsilon_m", c.translation_epsilon_m},
          {"rotation_epsilon_rad", c.rotation_epsilon_rad},
          {"min_points", c.min_points}};
}

}  // namespace fvx::registration
