#include "fvx/viewpoints/orientations.hpp"

#include <cmath>

#include "fvx/viewpoints/fov.hpp"

namespace fvx::viewpoints {

std::vector<Eigen::Matrix3d> sample_orientations(const Eigen::Vector3d& position_m,
                                                 const std::vector<Eigen::Vector3d>& targets_m, int count,
                                                 double jitter_rad, std::mt19937_64& rng, bool exact_first) {
  std::vector<Eigen::Vector3d> directions;
  for (const Eigen::Vector3d& t : targets_m)
    if ((t - position_m).norm() > 1e-9) directions.push_back((t - position_m).normalized());
  std::vector<Eigen::Matrix3d> rotations;
  if (directions.empty()) return rotations;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3d& d = directions[std::size_t(k) % directions.size()];
    const bool first_of_target = std::size_t(k) < directions.size();
    // Draw all three numbers for every sample, so that a sample's draw does not depend on
    // whether an earlier one was exact.
    const double tilt = jitter_rad * unit(rng), azimuth = 2.0 * M_PI * unit(rng), roll = M_PI * unit(rng);
    Eigen::Matrix3d R = look_along(d, 0.0);
    if (!(exact_first && first_of_target)) {
      const Eigen::Vector3d axis = R * Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0.0);
      R = Eigen::AngleAxisd(tilt, axis).toRotationMatrix() * R;
    }
    rotations.push_back(R * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  }
  return rotations;
}

}  // namespace fvx::viewpoints
