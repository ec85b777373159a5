#include "fvx/capmap/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fvx/capmap/viewing_ik.hpp"

namespace fvx::capmap {

namespace {

constexpr double kZ95 = 1.959963984540054;  // the normal quantile of a two-sided 95 % interval
/// Configurations drawn to find IK starts near the queried witness bits (starts_in_voxels):
/// 256 per non-empty voxel of the map, at least 2^20 and at most 2^24 (about 1–16 s of
/// forward kinematics for a 5-joint arm); and the starts kept per bit. With 2^20 for every
/// map, the youBot's map at 2.5 cm (22 005 voxels) was confirmed at 0.986, at 2^22 at 0.995.
std::size_t start_pool(const CapabilityMap& map) {
  return std::clamp<std::size_t>(256 * map.voxel_count(), std::size_t(1) << 20, std::size_t(1) << 24);
}
constexpr std::size_t kStartsPerBit = 4;

/// Wilson's score interval for k of n: centre ± half-width, both in [0, 1].
std::pair<double, double> wilson(int k, int n) {
  if (n == 0) return {0.0, 1.0};
  const double p = double(k) / n, z2 = kZ95 * kZ95, denominator = 1.0 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denominator;
  const double half = kZ95 * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / denominator;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

/// Configurations to start the IK of each queried witness bit from: of start_pool() configurations
/// drawn uniformly within the joint limits (a generator of its own, independent of the
/// build's), the kStartsPerBit whose poses lie in the bit's voxel with their axes nearest the
/// bit's direction, nearest first (fewer when fewer lie in the voxel). Bits at the edge of
/// what the arm reaches (near singular or limit configurations) are small targets for
/// descents from random starts; a pose already in the voxel is a start close to them.
std::vector<std::vector<Eigen::VectorXd>> starts_in_voxels(const CapabilityMap& map, const Arm& arm,
                                                           const std::vector<std::pair<std::int64_t, int>>& queries,
                                                           std::uint64_t seed) {
  std::unordered_multimap<std::int64_t, std::size_t> by_voxel;
  for (std::size_t i = 0; i < queries.size(); ++i) by_voxel.emplace(queries[i].first, i);
  std::vector<std::vector<std::pair<double, Eigen::VectorXd>>> best(queries.size());
  std::mt19937_64 rng(seed ^ 0x5EEDF00DCAFEull);
  for (std::size_t s = 0, pool = start_pool(map); s < pool; ++s) {
    const Eigen::VectorXd q = arm.random_configuration(rng);
    const Eigen::Isometry3d T = arm.fk(q);
    const auto [first, last] = by_voxel.equal_range(map.voxel_of(T.translation()));
    if (first == last) continue;
    const Eigen::Vector3d d = T.linear() * arm.config().viewing_axis_sensor;
    for (auto it = first; it != last; ++it) {
      auto& kept = best[it->second];
      const double dot = d.dot(map.directions()[queries[it->second].second]);
      if (kept.size() == kStartsPerBit && dot <= kept.back().first) continue;
      if (kept.size() == kStartsPerBit) kept.pop_back();
      kept.insert(std::find_if(kept.begin(), kept.end(), [&](const auto& k) { return k.first < dot; }), {dot, q});
    }
  }
  std::vector<std::vector<Eigen::VectorXd>> starts(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i)
    for (const auto& [dot, start] : best[i]) starts[i].push_back(start);
  return starts;
}

/// IK into the bit (solve_in_region) from each of `starts`, then from random restarts;
/// confirmed when a configuration found lies in it (an fk-witness bit promises some pose
/// there).
bool confirm_witness_bit(const CapabilityMap& map, const Arm& arm, std::int64_t voxel, int d,
                         const std::vector<Eigen::VectorXd>& starts, std::mt19937_64& rng) {
  IkConfig from_start;
  from_start.restarts = 0;
  for (const Eigen::VectorXd& start : starts)
    if (solve_in_region(map, arm, voxel, d, from_start, rng, &start).reached) return true;
  return solve_in_region(map, arm, voxel, d, IkConfig{}, rng).reached;
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
  std::vector<std::pair<std::int64_t, int>> queries;
  for (int i = 0; i < samples && !bits.empty(); ++i) queries.push_back(bits[std::size_t(rng() % bits.size())]);
  const bool witness = h.method == "fk-witness";
  const std::vector<std::vector<Eigen::VectorXd>> starts =
      witness ? starts_in_voxels(map, arm, queries, seed) : std::vector<std::vector<Eigen::VectorXd>>(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i, ++e.precision.queries) {
    const auto& [voxel, d] = queries[i];
    e.precision.hits += witness ? confirm_witness_bit(map, arm, voxel, d, starts[i], rng)
                                : confirm_centre_bit(map, arm, voxel, d, rng);
  }
  e.recall_by_height.resize(h.dims[2]);
  for (std::size_t z = 0; z < e.recall_by_height.size(); ++z) {
    e.recall_by_height[z].z_min_m = h.origin_m.z() + double(z) * h.voxel_m;
    e.recall_by_height[z].z_max_m = e.recall_by_height[z].z_min_m + h.voxel_m;
  }
  for (int i = 0; i < samples; ++i, ++e.recall.queries) {
    const Eigen::Isometry3d T = arm.fk(arm.random_configuration(rng));
    const Eigen::Vector3d p = T.translation();
    const bool found = map.reachable(p, T.linear() * arm.config().viewing_axis_sensor);
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
