#pragma once
/// \file
/// Samples shards of the fk-witness build (ShardSplit::Samples): what a shard records of each
/// round, and the merge's replay of the build's stop rule over the union of the shards.
#include <cstdint>
#include <vector>

#include "fvx/capmap/capability_map.hpp"

namespace fvx::capmap {

/// A `landed` entry for a configuration that another shard draws (−1: outside the grid).
constexpr std::int64_t kNotDrawn = -2;

/// The record of one round (SampleRound): `landed` holds each configuration's bit (−1 outside
/// the grid, kNotDrawn for another shard's), `set` the bits set before the round (64 a word).
SampleRound sample_round(const std::vector<std::int64_t>& landed, const std::vector<std::uint64_t>& set);

/// The bits one process sets (64 a word, `bits` in all): the shards' rounds in order, each
/// round's estimate = its configurations on bits set before it / its configurations, until a
/// round after the first reaches `target_recall` or the rounds end. Error when the shards
/// hold other round counts, a round of more than kWitnessRound configurations, bits outside
/// the grid, or not `budget` configurations in all.
std::vector<std::uint64_t> replay_sample_rounds(const std::vector<const std::vector<SampleRound>*>& shards,
                                                std::size_t bits, double target_recall, std::uint64_t budget);

}  // namespace fvx::capmap
