// The registration stage's names and config checks; align() itself is in registration.cpp,
// inside fvx-heavy.so with PCL (src/heavy/api.hpp).
#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/registration/registration.hpp"

namespace fvx::registration {

const char* to_string(Method method) { return method == Method::Gicp ? "gicp" : "icp"; }

Method parse_method(const std::string& text, const std::string& what) {
  if (text == "gicp") return Method::Gicp;
  if (text == "icp") return Method::Icp;
  throw UsageError(what + ": '" + text + "' is not a registration method; use gicp or icp");
}

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems;
  if (!(voxel_m >= 0.0) || !std::isfinite(voxel_m)) problems.push_back("voxel_m must be >= 0 m");
  if (!(fine_voxel_m >= 0.0) || !std::isfinite(fine_voxel_m)) problems.push_back("fine_voxel_m must be >= 0 m");
  if (!(robust_scale_m > 0.0) || !std::isfinite(robust_scale_m)) problems.push_back("robust_scale_m must be > 0 m");
  if (!(max_correspondence_m > 0.0) || !std::isfinite(max_correspondence_m))
    problems.push_back("max_correspondence_m must be > 0 m");
  if (!(fine_correspondence_m > 0.0) || !std::isfinite(fine_correspondence_m))
    problems.push_back("fine_correspondence_m must be > 0 m");
  if (max_iterations < 1) problems.push_back("max_iterations must be >= 1");
  if (!(translation_epsilon_m > 0.0)) problems.push_back("translation_epsilon_m must be > 0 m");
  if (!(rotation_epsilon_rad > 0.0)) problems.push_back("rotation_epsilon_rad must be > 0 rad");
  if (min_points < 3) problems.push_back("min_points must be >= 3");
  return problems;
}

}  // namespace fvx::registration
