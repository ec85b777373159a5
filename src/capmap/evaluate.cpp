#include "fvx/capmap/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "fvx/capmap/viewing_ik.hpp"

namespace fvx::capmap {

namespace {

constexpr double kZ95 = 1.959963984540054;  // the normal quantile of a two-sided 95 % interval

/// Wilson's score interval for k of n: centre ± half-width, both in [0, 1].
std::pair<double, double> wilson(int k, int n) {
  if (n == 0) return {0.0, 1.0};
  const double p = double(k) / n, z2 = kZ95 * kZ95, denominator = 1.0 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denominator;
  const double half = kZ95 * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / denominator;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

/// IK from restarts towards the voxel centre and the bit's direction; confirmed when the best
/// configuration's pose lies in the bit (an fk-witness bit promises some pose there).
bool confirm_witness_bit(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int d, std::mt19937_64& rng) {
  IkConfig ik;
  ik.position_tolerance_m = 0.25 * map.header().voxel_m;
  ik.angle_tolerance_rad = 0.25 * map.directions().mean_spacing_rad();
  const IkResult r = solve_in_region(map, arm, voxel, d, map.center_of(voxel), ik, rng);
  return r.reached && in_bit(map, voxel, d, arm.fk(r.q).translation(), arm.viewing_direction(r.q));
}

bool confirm_centre_bit(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int d, std::mt19937_64& rng) {
  const CapabilityHeader& h = map.header();
  IkConfig ik;
  ik.position_tolerance_m = h.position_tolerance_m + std::sqrt(3.0) * h.voxel_m / 2;
  ik.angle_tolerance_rad = h.angle_tolerance_rad + 0.5 * map.directions().mean_spacing_rad();
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  const Eigen::Vector3d p = map.center_of(voxel) + h.voxel_m * Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  return solve_viewing_ik(arm, p, map.directions()[d], ik, rng).reached;
}

}  // namespace

double Share::low() const { return wilson(hits, queries).first; }
double Share::high() const { return wilson(hits, queries).second; }

Evaluation evaluate(const CapabilityMap& map, const Arm& arm, int samples, std::uint64_t seed) {
  const CapabilityHeader& h = map.header();
  std::mt19937_64 rng(seed);
  Evaluation e;
  std::vector<std::pair<std::int64_t, int>> bits;
  for (const auto& [voxel, words] : map.voxels())
    for (int d = 0; d < h.directions; ++d)
      if (words[std::size_t(d / 64)] >> (d % 64) & 1u) bits.emplace_back(voxel, d);
  const bool witness = h.method == "fk-witness";
  for (int i = 0; i < samples && !bits.empty(); ++i, ++e.precision.queries) {
    const auto& [voxel, d] = bits[std::size_t(rng() % bits.size())];
    e.precision.hits += witness ? confirm_witness_bit(map, arm, voxel, d, rng) : confirm_centre_bit(map, arm, voxel, d, rng);
  }
  e.recall_by_height.resize(h.dims[2]);
  for (std::size_t z = 0; z < e.recall_by_height.size(); ++z) {
    e.recall_by_height[z].z_min_m = h.origin_m.z() + double(z) * h.voxel_m;
    e.recall_by_height[z].z_max_m = e.recall_by_height[z].z_min_m + h.voxel_m;
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < samples; ++i, ++e.recall.queries) {
    Eigen::VectorXd q(arm.dof());
    for (int j = 0; j < arm.dof(); ++j) q[j] = arm.lower_rad()[j] + unit(rng) * (arm.upper_rad()[j] - arm.lower_rad()[j]);
    const Eigen::Vector3d p = arm.fk(q).translation();
    const bool found = map.reachable(p, arm.viewing_direction(q));
    e.recall.hits += found;
    const std::int64_t voxel = map.voxel_of(p);
    if (voxel < 0) continue;
    Share& band = e.recall_by_height[std::size_t(voxel / (std::int64_t(h.dims[0]) * h.dims[1]))].recall;
    ++band.queries;
    band.hits += found;
  }
  return e;
}

}  // namespace fvx::capmap
