// The fk-witness build in the turn layout (build.hpp, turn_layout.hpp).
#include <algorithm>
#include <random>
#include <thread>
#include <unordered_set>

#include "fvx/capmap/build.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::capmap {

namespace {

/// A round's draws: each configuration with its first joint at 0, as a witness and its cell.
struct Drawn {
  std::vector<TurnWitness> witnesses;
  std::vector<std::uint64_t> cells;
};

Drawn draw_round(const Arm& arm, const BuildConfig& config, const TurnFrame& frame, const DirectionSet& relative,
                 std::size_t round, std::size_t n) {
  constexpr std::size_t kChunk = 4096;  // a generator per chunk: thread-count independent
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  Drawn drawn{std::vector<TurnWitness>(n), std::vector<std::uint64_t>(n)};
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t c; (c = next.fetch_add(1)) < chunks;) {
      std::mt19937_64 rng(seed_mix(seed_mix(config.seed, 3 + round), c));
      for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
        Eigen::VectorXd q = arm.random_configuration(rng);
        q[0] = 0.0;  // the turn's coordinates do not depend on it
        drawn.witnesses[i] = to_turn_witness(frame, arm.fk(q), arm.config().viewing_axis_sensor);
        drawn.cells[i] = turn_cell(frame, relative, drawn.witnesses[i]);
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < core::worker_count(config.threads); ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  return drawn;
}

}  // namespace

void build_turn_witnesses(const Arm& arm, const BuildConfig& config, CapabilityMap& map, BuildStats& s,
                          const std::function<void(std::size_t, std::size_t)>& progress,
                          const std::atomic<bool>* cancel) {
  const TurnFrame& frame = map.header().turn;
  const DirectionSet relative(frame.relative_directions);
  std::unordered_set<std::uint64_t> held;  // cells with a witness, over the whole space (the estimate)
  std::vector<TurnWitness> kept;           // this shard's: the first witness drawn in each cell
  const std::size_t limit = config.fk_samples ? config.fk_samples : std::size_t(1) << 27;
  for (std::size_t round = 0; s.fk_samples < limit && !(cancel && cancel->load()); ++round) {
    const std::size_t n = std::min(kWitnessRound, limit - s.fk_samples);
    const Drawn drawn = draw_round(arm, config, frame, relative, round, n);
    std::size_t known = 0;  // draws in cells that held a witness before this round
    for (const std::uint64_t cell : drawn.cells) known += held.count(cell);
    for (std::size_t i = 0; i < n; ++i) {
      if (!held.insert(drawn.cells[i]).second) continue;
      const std::int64_t height = turn_height_cell(drawn.cells[i]), count = config.shard_count;
      if ((height % count + count) % count == std::int64_t(config.shard_index)) kept.push_back(drawn.witnesses[i]);
    }
    s.fk_samples += n;
    s.fk_evaluations += n;
    if (round > 0) s.estimated_recall = double(known) / double(n);
    if (progress) progress(s.fk_samples, limit);
    if (round > 0 && s.estimated_recall >= config.target_recall) break;
  }
  map.set_turn_witnesses(std::move(kept));
  for (const auto& [voxel, words] : map.voxels())
    for (const std::uint64_t w : words) s.reached += std::size_t(__builtin_popcountll(w));
}

}  // namespace fvx::capmap
