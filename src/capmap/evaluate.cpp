#include "fvx/capmap/evaluate.hpp"

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "fvx/capmap/viewing_ik.hpp"

namespace fvx::capmap {

Evaluation evaluate(const CapabilityMap& map, const Arm& arm, int samples, std::uint64_t seed) {
  const CapabilityHeader& h = map.header();
  std::mt19937_64 rng(seed);
  Evaluation e;
  std::vector<std::pair<std::int64_t, int>> bits;
  for (const auto& [voxel, words] : map.voxels())
    for (int d = 0; d < h.directions; ++d)
      if (words[std::size_t(d / 64)] >> (d % 64) & 1u) bits.emplace_back(voxel, d);
  IkConfig ik;
  ik.position_tolerance_m = h.position_tolerance_m + std::sqrt(3.0) * h.voxel_m / 2;
  ik.angle_tolerance_rad = h.angle_tolerance_rad + 0.5 * map.directions().mean_spacing_rad();
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  for (int i = 0; i < samples && !bits.empty(); ++i, ++e.precision_queries) {
    const auto& [voxel, d] = bits[std::size_t(rng() % bits.size())];
    const Eigen::Vector3d p = map.center_of(voxel) + h.voxel_m * Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    e.confirmed += solve_viewing_ik(arm, p, map.directions()[d], ik, rng).reached;
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < samples; ++i, ++e.recall_queries) {
    Eigen::VectorXd q(arm.dof());
    for (int j = 0; j < arm.dof(); ++j) q[j] = arm.lower_rad()[j] + unit(rng) * (arm.upper_rad()[j] - arm.lower_rad()[j]);
    e.found += map.reachable(arm.fk(q).translation(), arm.viewing_direction(q));
  }
  return e;
}

}  // namespace fvx::capmap
