// Samples shards: a round's record and the merge's replay of the stop rule (sample_shards.hpp).
#include "fvx/capmap/sample_shards.hpp"

#include <algorithm>
#include <string>

#include "fvx/capmap/build.hpp"
#include "fvx/core/error.hpp"

namespace fvx::capmap {

namespace {

bool is_set(const std::vector<std::uint64_t>& set, std::int64_t b) {
  return set[std::size_t(b) / 64] >> (b % 64) & 1u;
}

}  // namespace

SampleRound sample_round(const std::vector<std::int64_t>& landed, const std::vector<std::uint64_t>& set) {
  SampleRound r;
  std::vector<std::int64_t> fresh;
  for (const std::int64_t b : landed) {
    if (b == kNotDrawn) continue;
    ++r.samples;
    if (b < 0) continue;
    if (is_set(set, b)) ++r.known;
    else fresh.push_back(b);
  }
  std::sort(fresh.begin(), fresh.end());
  for (std::size_t i = 0; i < fresh.size();) {  // runs of one bit: (bit, how many)
    std::size_t j = i;
    while (j < fresh.size() && fresh[j] == fresh[i]) ++j;
    r.fresh.emplace_back(fresh[i], std::uint32_t(j - i));
    i = j;
  }
  return r;
}

std::vector<std::uint64_t> replay_sample_rounds(const std::vector<const std::vector<SampleRound>*>& shards,
                                                std::size_t bits, double target_recall, std::uint64_t budget) {
  const std::size_t rounds = shards.front()->size();
  std::uint64_t drawn = 0;
  for (const auto* s : shards) {
    if (s->size() != rounds) throw Error("the samples shards hold other numbers of rounds; they cannot be merged");
    for (const SampleRound& r : *s) drawn += r.samples;
  }
  if (drawn != budget)
    throw Error("the samples shards drew " + std::to_string(drawn) + " configurations, not the budget of " +
                std::to_string(budget));
  std::vector<std::uint64_t> set((bits + 63) / 64, 0);
  for (std::size_t round = 0; round < rounds; ++round) {
    std::uint64_t samples = 0, known = 0;
    for (const auto* s : shards) {
      const SampleRound& r = (*s)[round];
      samples += r.samples, known += r.known;
      for (const auto& [b, count] : r.fresh) {
        if (b < 0 || std::size_t(b) >= bits) throw Error("a samples shard names a bit outside the grid");
        if (is_set(set, b)) known += count;
      }
    }
    if (samples > kWitnessRound) throw Error("a round of the samples shards holds more than 2^18 configurations");
    for (const auto* s : shards)
      for (const auto& [b, count] : (*s)[round].fresh) set[std::size_t(b) / 64] |= std::uint64_t(1) << (b % 64);
    if (round > 0 && samples && double(known) / double(samples) >= target_recall) break;  // as build_witnesses stops
  }
  return set;
}

}  // namespace fvx::capmap
