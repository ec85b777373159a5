#include "fvx/capmap/build.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "fvx/capmap/sample_shards.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::capmap {

const char* to_string(BuildMethod method) {
  switch (method) {
    case BuildMethod::FkWitness: return "fk-witness";
    case BuildMethod::FkSeededIk: return "fk-seeded-ik";
    case BuildMethod::ExhaustiveIk: return "exhaustive-ik";
  }
  return "?";
}

BuildMethod parse_build_method(const std::string& name, const std::string& what) {
  for (const BuildMethod m : {BuildMethod::FkWitness, BuildMethod::FkSeededIk, BuildMethod::ExhaustiveIk})
    if (name == to_string(m)) return m;
  throw UsageError(what + " '" + name + "': expected fk-witness, fk-seeded-ik or exhaustive-ik");
}

const char* to_string(MapLayout layout) { return layout == MapLayout::Turn ? "turn" : "grid"; }

MapLayout parse_map_layout(const std::string& name, const std::string& what) {
  if (name == "grid") return MapLayout::Grid;
  if (name == "turn") return MapLayout::Turn;
  throw UsageError(what + " '" + name + "': expected grid or turn");
}

const char* to_string(ShardSplit split) { return split == ShardSplit::Samples ? "samples" : "slab"; }

ShardSplit parse_shard_split(const std::string& name, const std::string& what) {
  if (name == "slab") return ShardSplit::Slab;
  if (name == "samples") return ShardSplit::Samples;
  throw UsageError(what + " '" + name + "': expected slab or samples");
}

void parse_shard(const std::string& text, const std::string& what, BuildConfig& config) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) throw UsageError(what + ": expected I/N, e.g. 3/8");
  config.shard_count = std::uint32_t(parse_int_in(text.substr(slash + 1), what + " N", 1, 100000));
  config.shard_index = std::uint32_t(parse_int_in(text.substr(0, slash), what + " I", 1, config.shard_count)) - 1;
}

std::vector<std::string> BuildConfig::validate() const {
  std::vector<std::string> problems;
  if (!(voxel_m > 0.0) || !std::isfinite(voxel_m)) problems.push_back("voxel_m must be > 0 m");
  if (directions < 1 || directions > 4096) problems.push_back("directions must be 1 to 4096");
  if (!(position_tolerance_m > 0.0)) problems.push_back("position_tolerance_m must be > 0 m");
  if (!(angle_tolerance_rad >= 0.0 && angle_tolerance_rad < M_PI)) problems.push_back("angle_tolerance_rad must be in [0, pi)");
  if (ik_restarts < 0) problems.push_back("ik_restarts must be >= 0");
  if (workspace_samples < 10) problems.push_back("workspace_samples must be at least 10");
  if (!(target_recall > 0.0 && target_recall <= 1.0)) problems.push_back("target_recall must be in (0, 1]");
  if (turns_per_fk < 1 || turns_per_fk > 4096) problems.push_back("turns_per_fk must be 1 to 4096");
  if (shard_count < 1 || shard_index >= shard_count) problems.push_back("shard_index must be below shard_count");
  if (layout == MapLayout::Turn && method != BuildMethod::FkWitness) problems.push_back("the turn layout needs the fk-witness method");
  if (shard_split == ShardSplit::Samples && (method != BuildMethod::FkWitness || layout != MapLayout::Grid || !fk_samples))
    problems.push_back("samples shards need the fk-witness method, the grid layout and a budget (fk_samples, --fk-samples)");
  return problems;
}

std::uint64_t seed_mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a ^ (b + 0x9E3779B97F4A7C15ull + (a << 6) + (a >> 2));
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

namespace {

struct Candidate {
  std::int64_t voxel;
  int direction;
  Eigen::VectorXd seed_q;  ///< empty: start from random configurations only
};

}  // namespace

namespace {

/// Step 1: the map's header; its grid covers the workspace that FK samples reach, voxel
/// centres on the lattice k·v.
CapabilityHeader header_for(const Arm& arm, const BuildConfig& config, const DirectionSet& directions) {
  const double v = config.voxel_m;
  std::mt19937_64 rng(seed_mix(config.seed, 1));
  Eigen::AlignedBox3d reach;
  for (std::size_t i = 0; i < config.workspace_samples; ++i) reach.extend(arm.fk(arm.random_configuration(rng)).translation());
  CapabilityHeader h;
  const ArmConfig& ac = arm.config();
  h.base_link = ac.base_link;
  h.tip_link = ac.tip_link;
  const Eigen::Vector3d rpy = rpy_of(ac.T_tip_sensor.linear());
  h.mount_xyz_rpy = {ac.T_tip_sensor.translation().x(), ac.T_tip_sensor.translation().y(),
                     ac.T_tip_sensor.translation().z(), rpy.x(), rpy.y(), rpy.z()};
  h.viewing_axis = ac.viewing_axis_sensor;
  h.urdf_hash = arm.urdf_hash();
  h.voxel_m = v;
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor(reach.min()[a] / v + 0.5) - 1.0, hi = std::floor(reach.max()[a] / v + 0.5) + 1.0;
    h.origin_m[a] = (lo - 0.5) * v;
    h.dims[std::size_t(a)] = std::uint32_t(hi - lo + 1.0);
  }
  h.directions = config.directions;
  h.position_tolerance_m = config.position_tolerance_m;
  h.angle_tolerance_rad = config.angle_tolerance_rad > 0 ? config.angle_tolerance_rad : 0.5 * directions.mean_spacing_rad();
  h.method = to_string(config.method);
  h.seed = config.seed;
  h.shard_index = config.shard_index;
  h.shard_count = config.shard_count;
  if (config.shard_split == ShardSplit::Samples)
    h.shard_split = "samples", h.target_recall = config.target_recall, h.fk_samples = config.fk_samples;
  h.fvx_version = version();
  if (config.layout == MapLayout::Turn) h.layout = "turn", h.turn = TurnFrame::of(arm, v, config.directions);
  return h;
}

/// The voxels of this shard's z-slab, [first, end) in index order: shards split the z layers.
std::pair<std::int64_t, std::int64_t> shard_voxels(const CapabilityHeader& h, const BuildConfig& config) {
  const std::int64_t layer = std::int64_t(h.dims[0]) * h.dims[1];
  return {std::int64_t(h.dims[2] * config.shard_index / config.shard_count) * layer,
          std::int64_t(h.dims[2] * (config.shard_index + 1) / config.shard_count) * layer};
}

/// Step 2: the bits to check in this shard's z-slab — every bit (exhaustive), or those the
/// FK samples propose, each with the first seed configuration that proposed it.
std::vector<Candidate> candidates_for(const Arm& arm, const BuildConfig& config, const DirectionSet& directions,
                                      const CapabilityMap& map) {
  const CapabilityHeader& h = map.header();
  const auto [first, end] = shard_voxels(h, config);
  std::vector<Candidate> candidates;
  if (config.method == BuildMethod::ExhaustiveIk) {
    for (std::int64_t voxel = first; voxel < end; ++voxel)
      for (int d = 0; d < directions.size(); ++d) candidates.push_back({voxel, d, {}});
    return candidates;
  }
  std::map<std::pair<std::int64_t, int>, Eigen::VectorXd> proposed;
  std::mt19937_64 fk_rng(seed_mix(config.seed, 2));
  for (std::size_t i = 0, n = config.fk_samples ? config.fk_samples : 400000; i < n; ++i) {
    const Eigen::VectorXd q = arm.random_configuration(fk_rng);
    const Eigen::Isometry3d T = arm.fk(q);
    const std::int64_t voxel = map.voxel_of(T.translation());
    if (voxel < first || voxel >= end) continue;
    // Every direction within the angle tolerance of the sampled one, not only the nearest:
    // IK may reach each of them, and proposing only the nearest cost 20 % of the recall.
    for (const int d : directions.within(T.linear() * arm.config().viewing_axis_sensor, h.angle_tolerance_rad))
      proposed.emplace(std::make_pair(voxel, d), q);
  }
  for (auto& [bit, q] : proposed) candidates.push_back({bit.first, bit.second, std::move(q)});
  return candidates;
}

/// The bit of the sensor pose `T_base_sensor`: (voxel, nearest direction) as one number, −1
/// outside. The banded search finds nearest()'s direction with about a quarter of its dot
/// products (the brute force was a third of a youBot build's time, measured with perf).
std::int64_t witness_bit(const Arm& arm, const CapabilityMap& map, const Eigen::Isometry3d& T_base_sensor) {
  const std::int64_t voxel = map.voxel_of(T_base_sensor.translation());
  if (voxel < 0) return -1;
  return voxel * map.directions().size() +
         map.directions().nearest_banded(T_base_sensor.linear() * arm.config().viewing_axis_sensor);
}

/// Witnesses [i, end) of a chunk from `rng`. Without a revolute first joint, one configuration
/// each. With one, groups of `turns_per_fk`: a configuration, then the first joint drawn again
/// for each further witness; the group's poses are one FK at q₀ = 0 turned about the joint's
/// axis to each q₀ (use_first_joint_turn), or one FK each (the oracle of the turn).
void draw_witnesses(const Arm& arm, const BuildConfig& config, const CapabilityMap& map, std::mt19937_64& rng,
                    std::size_t i, std::size_t end, std::int64_t* landed, std::size_t& fk_evaluations) {
  const std::optional<FirstJointAxis>& axis = arm.first_joint_axis();
  std::vector<double> q0(std::size_t(config.turns_per_fk));
  while (i < end) {
    Eigen::VectorXd q = arm.random_configuration(rng);
    const std::size_t group = axis ? std::min(end - i, std::size_t(config.turns_per_fk)) : 1;
    q0[0] = q[0];
    for (std::size_t k = 1; k < group; ++k) q0[k] = arm.random_joint_rad(0, rng);
    if (axis && config.use_first_joint_turn) {
      q[0] = 0.0;
      const Eigen::Isometry3d T_at_zero = arm.fk(q);
      ++fk_evaluations;
      for (std::size_t k = 0; k < group; ++k) landed[i + k] = witness_bit(arm, map, axis->turn(T_at_zero, q0[k]));
    } else {
      for (std::size_t k = 0; k < group; ++k) {
        q[0] = q0[k];
        landed[i + k] = witness_bit(arm, map, arm.fk(q));
        ++fk_evaluations;
      }
    }
    i += group;
  }
}

/// The fk-witness build: rounds of FK samples set the bits they land in, on all cores, until
/// a round's share of samples on bits set before it reaches the target recall. A samples
/// shard draws only its chunks (g ≡ I−1 mod N, g counted over the whole budget), keeps every
/// round's record for the merge and does not stop before the budget: it cannot see the
/// other shards' bits.
void build_witnesses(const Arm& arm, const BuildConfig& config, CapabilityMap& map, BuildStats& s,
                     const std::function<void(std::size_t, std::size_t)>& progress, const std::atomic<bool>* cancel) {
  const CapabilityHeader& h = map.header();
  const std::int64_t directions = h.directions;
  const std::size_t bits = std::size_t(h.dims[0]) * h.dims[1] * h.dims[2] * std::size_t(directions);
  std::vector<std::uint64_t> set((bits + 63) / 64, 0);  // every bit of the grid, for the estimate
  const std::size_t limit = config.fk_samples ? config.fk_samples : std::size_t(1) << 27;
  constexpr std::size_t kChunk = 4096;  // a generator per chunk: thread-count independent
  const unsigned threads = core::worker_count(config.threads);
  const bool by_samples = config.shard_split == ShardSplit::Samples;
  std::vector<SampleRound> rounds;
  std::size_t drawn = 0, first_chunk = 0;  // over all shards; the round's first chunk's number
  for (std::size_t round = 0; drawn < limit && !(cancel && cancel->load()); ++round) {
    const std::size_t n = std::min(kWitnessRound, limit - drawn), chunks = (n + kChunk - 1) / kChunk;
    std::vector<std::int64_t> landed(n, kNotDrawn);
    std::atomic<std::size_t> next{0}, fk_evaluations{0};
    auto work = [&] {
      std::size_t evaluations = 0;
      for (std::size_t c; (c = next.fetch_add(1)) < chunks;) {
        if (by_samples && (first_chunk + c) % config.shard_count != config.shard_index) continue;
        std::mt19937_64 rng(seed_mix(seed_mix(config.seed, 3 + round), c));
        draw_witnesses(arm, config, map, rng, c * kChunk, std::min(n, (c + 1) * kChunk), landed.data(), evaluations);
      }
      fk_evaluations += evaluations;
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    const SampleRound r = sample_round(landed, set);
    for (const std::int64_t b : landed)
      if (b >= 0) set[std::size_t(b) / 64] |= std::uint64_t(1) << (b % 64);
    drawn += n, first_chunk += chunks;
    s.fk_samples += r.samples;
    s.fk_evaluations += fk_evaluations.load();
    if (progress) progress(drawn, limit);
    if (by_samples) {
      rounds.push_back(r);
      continue;
    }
    if (round > 0) s.estimated_recall = double(r.known) / double(n);
    if (round > 0 && s.estimated_recall >= config.target_recall) break;
  }
  if (by_samples) {  // the rounds, not bits: the merge decides which bits the build keeps
    for (const std::uint64_t w : set) s.reached += std::size_t(__builtin_popcountll(w));
    map.set_sample_rounds(std::move(rounds));
    return;
  }
  const auto [first, end] = shard_voxels(h, config);
  for (std::int64_t b = first * directions; b < end * directions; ++b)
    if (set[std::size_t(b) / 64] >> (b % 64) & 1u) {
      map.set(b / directions, int(b % directions));
      ++s.reached;
    }
}

}  // namespace

CapabilityMap build_capability_map(const Arm& arm, const BuildConfig& config, BuildStats* stats,
                                   const std::function<void(std::size_t, std::size_t)>& progress,
                                   const std::atomic<bool>* cancel) {
  throw_if_problems("capmap build", config.validate());
  const DirectionSet directions(config.directions);
  CapabilityMap map(header_for(arm, config, directions));
  if (config.method == BuildMethod::FkWitness) {
    BuildStats s;
    if (config.layout == MapLayout::Turn)
      build_turn_witnesses(arm, config, map, s, progress, cancel);
    else
      build_witnesses(arm, config, map, s, progress, cancel);
    if (stats) *stats = s;
    return map;
  }
  const CapabilityHeader& h = map.header();
  const std::vector<Candidate> candidates = candidates_for(arm, config, directions, map);

  // 3. The IK check, on all cores; results land in a per-candidate slot (deterministic).
  IkConfig ik;
  ik.position_tolerance_m = h.position_tolerance_m;
  ik.angle_tolerance_rad = h.angle_tolerance_rad;
  ik.restarts = config.ik_restarts;
  std::vector<std::uint8_t> reached(candidates.size(), 0);
  std::vector<std::size_t> iterations(candidates.size(), 0);
  std::atomic<std::size_t> next{0}, done{0};
  auto work = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < candidates.size();) {
      if (cancel && cancel->load()) return;
      const Candidate& c = candidates[i];
      std::mt19937_64 bit_rng(seed_mix(seed_mix(config.seed, std::uint64_t(c.voxel)), std::uint64_t(c.direction)));
      const IkResult r = solve_viewing_ik(arm, map.center_of(c.voxel), directions[c.direction], ik, bit_rng,
                                          c.seed_q.size() ? &c.seed_q : nullptr);
      reached[i] = r.reached;
      iterations[i] = std::size_t(r.iterations);
      done.fetch_add(1);
    }
  };
  const unsigned threads = core::worker_count(config.threads);
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  if (progress) {
    std::thread worker(work);
    while (done.load() < candidates.size() && !(cancel && cancel->load())) {
      progress(done.load(), candidates.size());
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    worker.join();
    progress(done.load(), candidates.size());
  } else {
    work();
  }
  for (auto& t : pool) t.join();

  BuildStats s;
  s.candidates = candidates.size();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    s.ik_iterations += iterations[i];
    if (!reached[i]) continue;
    map.set(candidates[i].voxel, candidates[i].direction);
    ++s.reached;
  }
  if (stats) *stats = s;
  return map;
}

}  // namespace fvx::capmap
