// Samples shards of the fk-witness build: merged, they are the one-process build's file byte
// for byte, whether the stop rule or the budget ends the build, on any thread count and
// merge order; their file reads back as written; foreign, missing and corrupt shards are
// refused.
#include <gtest/gtest.h>

#include <cstring>

#include "capmap_fixtures.hpp"
#include "fvx/capmap/sample_shards.hpp"
#include "fvx/core/error.hpp"

namespace fvx::capmap {
namespace {

using fixtures::bytes_of;

BuildConfig fvx_arm_build(std::size_t budget) {
  BuildConfig c;  // the fvx arm at 10 cm, 50 directions: a few rounds, under a second
  c.voxel_m = 0.1;
  c.directions = 50;
  c.fk_samples = budget;
  return c;
}

/// `count` samples shards of `config`, `threads` each, merged in reverse order, saved.
void merge_shards(const Arm& arm, BuildConfig config, std::uint32_t count, unsigned threads, const std::string& path) {
  std::vector<CapabilityMap> shards;
  config.shard_split = ShardSplit::Samples, config.shard_count = count, config.threads = threads;
  for (std::uint32_t i = count; i-- > 0;) {
    config.shard_index = i;
    shards.push_back(build_capability_map(arm, config));
  }
  CapabilityMap::merge(shards).save(path);
}

TEST(SampleShards, MergedTheyAreTheOneProcessBuildWhetherTheStopOrTheBudgetEndsIt) {
  const test::TempDir dir;
  const Arm arm = fixtures::fvx_arm();
  BuildStats adaptive;
  build_capability_map(arm, fvx_arm_build(0), &adaptive).save(dir / "default.fcm");
  ASSERT_GE(adaptive.fk_samples, 2 * kWitnessRound) << "the stop should come after a few rounds";
  // A budget beyond the stop (a partial last round), and one that ends two and a bit rounds in.
  for (const std::size_t budget : {adaptive.fk_samples + 2 * kWitnessRound + 12345, 2 * kWitnessRound + 777}) {
    BuildStats one;
    build_capability_map(arm, fvx_arm_build(budget), &one).save(dir / "one.fcm");
    const bool stopped = one.fk_samples < budget;
    EXPECT_EQ(stopped, budget > adaptive.fk_samples) << budget;
    for (const auto& [count, threads] : {std::pair<std::uint32_t, unsigned>{3, 1}, {67, 2}}) {  // 67: more than a round's 64 chunks
      merge_shards(arm, fvx_arm_build(budget), count, threads, dir / "merged.fcm");
      EXPECT_TRUE(bytes_of(dir / "merged.fcm") == bytes_of(dir / "one.fcm"))
          << count << " shards of a budget of " << budget << (stopped ? " (stopped)" : " (budget)");
    }
    if (stopped) {
      EXPECT_TRUE(bytes_of(dir / "one.fcm") == bytes_of(dir / "default.fcm")) << "the stop came in the budget";
    }
  }
}

TEST(SampleShards, AShardReadsBackAsWrittenAndForeignOrMissingShardsAreRefused) {
  const test::TempDir dir;
  const Arm arm = fixtures::fvx_arm();
  BuildConfig c = fvx_arm_build(3 * kWitnessRound);
  c.shard_split = ShardSplit::Samples, c.shard_count = 2;
  const CapabilityMap first = build_capability_map(arm, c);
  first.save(dir / "s1.fcm");
  const CapabilityMap loaded = CapabilityMap::load(dir / "s1.fcm");
  loaded.save(dir / "again.fcm");
  EXPECT_TRUE(bytes_of(dir / "s1.fcm") == bytes_of(dir / "again.fcm"));
  EXPECT_EQ(std::uint8_t(bytes_of(dir / "s1.fcm")[8]), 4u) << "format version 4";
  EXPECT_EQ(loaded.voxel_count(), 0u) << "rounds, not bits";
  ASSERT_EQ(loaded.sample_rounds().size(), 3u);
  for (std::size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(loaded.sample_rounds()[r].samples, first.sample_rounds()[r].samples);
    EXPECT_EQ(loaded.sample_rounds()[r].known, first.sample_rounds()[r].known);
    EXPECT_EQ(loaded.sample_rounds()[r].fresh, first.sample_rounds()[r].fresh);
  }
  EXPECT_GT(first.sample_rounds()[2].known, 0u);
  EXPECT_FALSE(first.sample_rounds()[0].fresh.empty());

  EXPECT_THROW(CapabilityMap::merge({first}), Error) << "the second shard is missing";
  BuildConfig other = c;
  other.shard_index = 1, other.fk_samples = 4 * kWitnessRound;
  EXPECT_THROW(CapabilityMap::merge({first, build_capability_map(arm, other)}), Error) << "another budget";
  other = c;
  other.shard_index = 1, other.shard_split = ShardSplit::Slab;
  EXPECT_THROW(CapabilityMap::merge({first, build_capability_map(arm, other)}), Error) << "a slab shard";
  BuildConfig no_budget = c, ik = c, turn = c;  // what samples shards cannot be
  no_budget.fk_samples = 0, ik.method = BuildMethod::FkSeededIk, turn.layout = MapLayout::Turn;
  for (const BuildConfig& bad : {no_budget, ik, turn}) EXPECT_FALSE(bad.validate().empty());
}

/// `bytes` with the 8-byte FNV-1a checksum recomputed over all but its last 8 bytes.
std::string rechecksummed(std::string bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (std::size_t i = 0; i + 8 < bytes.size(); ++i) hash = (hash ^ std::uint8_t(bytes[i])) * 1099511628211ull;
  std::memcpy(bytes.data() + bytes.size() - 8, &hash, 8);
  return bytes;
}

/// `bytes` (a samples shard) with `from` replaced by `to` in its header JSON, the header's
/// length and the checksum made right again.
std::string with_shard_header_edit(const std::string& bytes, const std::string& from, const std::string& to) {
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  std::string header = bytes.substr(16, length);
  EXPECT_NE(header.find(from), std::string::npos) << from;
  header.replace(header.find(from), from.size(), to);
  length = std::uint32_t(header.size());
  return rechecksummed(bytes.substr(0, 12) + std::string(reinterpret_cast<const char*>(&length), 4) + header +
                       bytes.substr(16 + header.size() - to.size() + from.size()));
}

// Rounds that lie, with a valid checksum: each refused on one line naming the problem.
TEST(SampleShards, CorruptRoundsAreRefusedWithTheirProblem) {
  const test::TempDir dir;
  BuildConfig c = fvx_arm_build(2 * kWitnessRound);
  c.shard_split = ShardSplit::Samples, c.shard_count = 2;
  build_capability_map(fixtures::fvx_arm(), c).save(dir / "s.fcm");
  const std::string good = bytes_of(dir / "s.fcm");
  std::uint32_t header = 0;
  std::memcpy(&header, good.data() + 12, 4);
  // The rounds: count; per round samples, known, bits, the bits' byte length, the bits.
  const std::size_t rounds_at = 16 + header, first_round = rounds_at + 8, bits_at = first_round + 32;
  std::uint64_t fresh = 0, length = 0;
  std::memcpy(&fresh, good.data() + first_round + 16, 8);
  std::memcpy(&length, good.data() + first_round + 24, 8);
  const auto edited = [&](std::size_t at, std::uint64_t value, std::size_t size) {
    std::string b = good;
    std::memcpy(b.data() + at, &value, size);
    return rechecksummed(b);
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {edited(rounds_at, 1u << 30, 8), "truncated"},                       // more rounds than bytes
      {edited(first_round, kWitnessRound + 1, 8), "more configurations"},  // a round too large
      {edited(first_round + 8, kWitnessRound, 8), "more configurations"},  // known beyond the round
      {edited(first_round + 16, length, 8), "more bits than its bytes hold"},
      {edited(first_round + 16, fresh - 1, 8), "do not end with its bits"},
      {edited(first_round + 24, std::uint64_t(1) << 40, 8), "truncated"},
      {edited(bits_at + length - 1, 0x80, 1), "run past its bytes"},  // the last varint goes on
      {with_shard_header_edit(good, "\"directions\":50", "\"directions\":1"), "not bits of the grid"},
      {with_shard_header_edit(good, "\"fk_samples\":524288", "\"fk_samples\":1000"), "more configurations than the budget"},
      {good.substr(0, rounds_at) + good.substr(good.size() - 8), "truncated"},
  };
  for (const auto& [bytes, mention] : cases) {
    std::ofstream(dir / "bad.fcm", std::ios::binary) << bytes;
    try {
      CapabilityMap::load(dir / "bad.fcm");
      ADD_FAILURE() << mention << ": accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace fvx::capmap
