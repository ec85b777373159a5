// The turn layout of capability maps (turn_layout.hpp): the banded nearest direction against
// brute force, witnesses on the planar arm's closed form, determinism across threads and
// shards, the file round trip and its refusals, and agreement with the grid build.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "capmap_fixtures.hpp"
#include "fvx/core/error.hpp"

namespace fvx::capmap {
namespace {

using namespace fixtures;

TEST(DirectionSet, BandedNearestIsTheBruteForceNearest) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  for (const int n : {1, 2, 3, 7, 50, 200, 800, 4096}) {
    const DirectionSet set(n);
    std::vector<Eigen::Vector3d> queries = {Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX()};
    for (int i = 0; i < n; ++i) {
      queries.push_back(set[i]);  // on a direction, and halfway to the next (near-ties)
      if (i + 1 < n) queries.push_back((set[i] + set[i + 1]).normalized());
    }
    for (int i = 0; i < 20000; ++i) queries.push_back(Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized());
    // Rotated unit axes, as the fk-witness build asks: off unit length by rounding.
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Quaterniond turn = Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
      queries.push_back(turn.toRotationMatrix() * Eigen::Vector3d::UnitZ());
      queries.push_back((1.0 + 1e-14 * normal(rng)) * queries.back());  // and a little more
    }
    int wrong = 0;
    for (const Eigen::Vector3d& q : queries) {
      const int expected = set.nearest(q);
      const int hint = int(rng() % std::uint64_t(n + 1)) - 1;  // −1: none
      wrong += set.nearest_banded(q) != expected || set.nearest_banded(q, hint) != expected;
    }
    EXPECT_EQ(wrong, 0) << n << " directions";
  }
}

BuildConfig planar_turn_build() {
  BuildConfig config;
  config.layout = MapLayout::Turn;
  config.voxel_m = 0.05;
  config.directions = 60;
  config.threads = 1;
  return config;
}

// Every bit painted is a turn of a witness within the joint's limits, so on the planar arm
// (first joint about y, a full turn) no bit lies farther from the closed-form reachable set
// than its voxel's half diagonal with a direction in its cell — the grid build's bound.
TEST(TurnLayout, PlanarArmBitsLieOnTheClosedFormAndBuildsAreDeterministic) {
  const test::TempDir dir;
  const Arm arm = planar_arm();
  BuildStats stats;
  const CapabilityMap map = build_capability_map(arm, planar_turn_build(), &stats);
  EXPECT_EQ(map.header().layout, "turn");
  ASSERT_GT(map.turn_witnesses().size(), 50u);
  ASSERT_GT(stats.reached, 100u);
  EXPECT_GE(stats.estimated_recall, 0.995);
  const double cell_rad = 1.5 * map.directions().mean_spacing_rad();
  std::size_t far = 0;
  for (const auto& [voxel, bits] : map.voxels())
    for (int d = 0; d < map.directions().size(); ++d)
      far += map.reachable(voxel, d) &&
             closed_form_distance(map.center_of(voxel), map.directions()[d], cell_rad) > std::sqrt(3.0) * 0.05 / 2;
  EXPECT_EQ(far, 0u);
  expect_thread_and_shard_independent(arm, planar_turn_build(), dir);
}

// The file keeps the witnesses: loading expands them into the same bits, saving again writes
// the same bytes.
TEST(TurnLayout, SaveLoadKeepsWitnessesAndBits) {
  const test::TempDir dir;
  const CapabilityMap map = build_capability_map(planar_arm(), planar_turn_build());
  map.save(dir / "turn.fcm");
  const CapabilityMap loaded = CapabilityMap::load(dir / "turn.fcm");
  EXPECT_EQ(loaded.header().layout, "turn");
  EXPECT_EQ(loaded.turn_witnesses().size(), map.turn_witnesses().size());
  EXPECT_TRUE(loaded.voxels() == map.voxels());
  loaded.save(dir / "again.fcm");
  EXPECT_TRUE(bytes_of(dir / "turn.fcm") == bytes_of(dir / "again.fcm"));
  EXPECT_EQ(std::uint8_t(bytes_of(dir / "turn.fcm")[8]), 3u) << "format version 3";
}

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

/// Writes `body` (a file without its checksum) with a valid checksum, then expects load() to
/// refuse it with a message containing `expected`.
void expect_refused(const test::TempDir& dir, std::string body, const std::string& expected) {
  const std::uint64_t sum = fnv1a(body);
  body.append(reinterpret_cast<const char*>(&sum), 8);
  std::ofstream(dir / "bad.fcm", std::ios::binary) << body;
  try {
    CapabilityMap::load(dir / "bad.fcm");
    ADD_FAILURE() << "loaded; expected: " << expected;
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(TurnLayout, CorruptFilesAreRefusedWithTheirProblem) {
  const test::TempDir dir;
  BuildConfig config = planar_turn_build();
  config.fk_samples = 2000;
  build_capability_map(planar_arm(), config).save(dir / "turn.fcm");
  const std::string file = bytes_of(dir / "turn.fcm"), body = file.substr(0, file.size() - 8);
  std::uint32_t header_size;
  std::memcpy(&header_size, body.data() + 12, 4);
  const std::size_t first = 16 + header_size + 8;  // the first witness's radius
  const auto with_float = [&](std::size_t at, float value) {
    std::string b = body;
    std::memcpy(&b[at], &value, 4);
    return b;
  };
  std::string newer = body;
  newer[8] = 5;
  expect_refused(dir, newer, "format version 5; this fvx reads versions 1 to 4");
  newer[8] = 4;  // a samples shard's version
  expect_refused(dir, newer, "layout 'turn' in a version 4 file");
  std::string as_grid = body;
  as_grid[8] = 2;
  expect_refused(dir, as_grid, "layout 'turn' in a version 2 file");
  expect_refused(dir, with_float(first, NAN), "not a finite pose with a unit direction");
  expect_refused(dir, with_float(first + 12, 3.0f), "not a finite pose with a unit direction");
  expect_refused(dir, with_float(first, 1e30f), "too far from the axis");
  std::string twice = body + body.substr(first, 24);  // the first witness again
  const std::uint64_t count = (body.size() - first) / 24 + 1;
  std::memcpy(&twice[first - 8], &count, 8);
  expect_refused(dir, twice, "two turn witnesses share a reduced cell");
  expect_refused(dir, body.substr(0, body.size() - 5), "truncated");
}

// The turn layout and the grid sample the same reachable set through different cells, so
// their bits differ where a cell straddles its edge; each must find nearly all of the
// other's bits. Measured at 10 cm: the turn map holds 92.8 % of the grid's bits, the grid
// 94.1 % of the turn's (at 5 cm on the three arms: README).
TEST(TurnLayout, TheFvxArmsTurnMapAgreesWithItsGridMap) {
  const Arm arm = fvx_arm();
  BuildConfig config;
  config.voxel_m = 0.1;
  const CapabilityMap grid = build_capability_map(arm, config);
  config.layout = MapLayout::Turn;
  const CapabilityMap turn = build_capability_map(arm, config);
  std::size_t both = 0, grid_bits = 0, turn_bits = 0;
  for (const auto& [voxel, words] : grid.voxels())
    for (int d = 0; d < grid.directions().size(); ++d) grid_bits += grid.reachable(voxel, d), both += grid.reachable(voxel, d) && turn.reachable(voxel, d);
  for (const auto& [voxel, words] : turn.voxels())
    for (int d = 0; d < turn.directions().size(); ++d) turn_bits += turn.reachable(voxel, d);
  std::printf("fvx arm, 10 cm: grid %zu bits, turn %zu bits (%zu witnesses), %zu in both\n", grid_bits, turn_bits,
              turn.turn_witnesses().size(), both);
  EXPECT_GE(double(both), 0.9 * double(grid_bits));
  EXPECT_GE(double(both), 0.9 * double(turn_bits));
}

TEST(TurnLayout, ArmsWithoutARevoluteFirstJointAndIkMethodsAreRefused) {
  const char* prismatic = R"(<robot name="slide">
    <link name="base"/><link name="carriage"/><link name="sensor"/>
    <joint name="slide" type="prismatic"><parent link="base"/><child link="carriage"/>
      <axis xyz="1 0 0"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
    <joint name="tilt" type="revolute"><parent link="carriage"/><child link="sensor"/>
      <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </robot>)";
  BuildConfig config = planar_turn_build();
  EXPECT_THROW(build_capability_map(Arm::from_urdf_string(prismatic, {"base", "sensor"}, "slide"), config), Error);
  config.method = BuildMethod::FkSeededIk;
  EXPECT_FALSE(config.validate().empty());
}

TEST(EvaluateCapabilityMap, TheFvxArmsTurnMapHasRecallAtPrecision) {
  expect_recall_at_precision(fvx_arm(), "fvx arm, turn layout", MapLayout::Turn);
}

TEST(EvaluateCapabilityMapRealData, YoubotAndSo101TurnMapsHaveRecallAtPrecision) {
  FVX_REAL_DATA_OR_SKIP(youbot, "arms/youbot_arm.urdf");
  FVX_REAL_DATA_OR_SKIP(so101, "arms/so101_arm.urdf");
  expect_recall_at_precision(Arm::from_urdf(youbot, {"base_link", "arm_link_5"}), "youBot, turn layout", MapLayout::Turn);
  expect_recall_at_precision(Arm::from_urdf(so101, {"base_link", "gripper_frame_link"}), "SO-101, turn layout",
                             MapLayout::Turn);
}

}  // namespace
}  // namespace fvx::capmap
