// Building capability maps: a planar arm whose reachable set is known in closed form,
// determinism across threads and shards, precision against IK on the fvx arm.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "fvx/capmap/build.hpp"
#include "fvx/capmap/evaluate.hpp"
#include "capmap_fixtures.hpp"
#include "test_support.hpp"

namespace fvx::capmap {
namespace {

using namespace fixtures;

TEST(BuildCapabilityMap, PlanarArmMatchesTheClosedForm) {
  const Arm arm = planar_arm();
  BuildConfig config;
  config.method = BuildMethod::FkSeededIk;
  config.voxel_m = 0.05;
  config.directions = 100;
  config.fk_samples = 100000;
  BuildStats stats;
  const CapabilityMap map = build_capability_map(arm, config, &stats);
  const double tol_p = map.header().position_tolerance_m, tol_a = map.header().angle_tolerance_rad;
  ASSERT_GT(stats.reached, 100u);
  std::size_t false_positives = 0, truly_reachable = 0, found = 0;
  for (const auto& [voxel, bits] : map.voxels())
    for (int d = 0; d < map.directions().size(); ++d)
      if (map.reachable(voxel, d) &&
          closed_form_distance(map.center_of(voxel), map.directions()[d], tol_a + 1e-6) > tol_p + 1e-4)
        ++false_positives;
  // Recall over the plane y = 0: bits reachable with half the tolerances to spare.
  for (std::int64_t voxel = 0; voxel < std::int64_t(map.header().dims[0]) * map.header().dims[1] * map.header().dims[2]; ++voxel) {
    const Eigen::Vector3d c = map.center_of(voxel);
    if (std::abs(c.y()) > 1e-9) continue;
    for (int d = 0; d < map.directions().size(); ++d) {
      if (closed_form_distance(c, map.directions()[d], tol_a / 2) > tol_p / 2) continue;
      ++truly_reachable;
      found += map.reachable(voxel, d);
    }
  }
  std::printf("planar arm: %zu bits set, %zu false positives; recall %zu of %zu\n", stats.reached, false_positives,
              found, truly_reachable);
  EXPECT_EQ(false_positives, 0u);
  ASSERT_GT(truly_reachable, 50u);
  EXPECT_GE(double(found), 0.9 * double(truly_reachable));
}

TEST(BuildCapabilityMap, SameSeedSameBytesOnAnyThreadCountAndShardsMergeToIt) {
  const test::TempDir dir;
  const Arm arm = planar_arm();
  BuildConfig config;
  config.method = BuildMethod::FkSeededIk;
  config.voxel_m = 0.05;
  config.directions = 60;
  config.fk_samples = 20000;
  config.threads = 1;
  expect_thread_and_shard_independent(arm, config, dir);
  config.seed = 2;
  build_capability_map(arm, config).save(dir / "seed2.fcm");
  EXPECT_TRUE(bytes_of(dir / "seed2.fcm") != bytes_of(dir / "one.fcm")) << "the seed changes nothing";
}

/// The fvx arm's fk-seeded-ik map at 15 cm and 50 directions: coarse, built in about a second.
BuildConfig coarse_fvx_arm_build() {
  BuildConfig config;
  config.method = BuildMethod::FkSeededIk;
  config.voxel_m = 0.15;
  config.directions = 50;
  config.fk_samples = 30000;
  return config;
}

TEST(BuildCapabilityMap, BitsOfTheFvxArmAreConfirmedByIk) {
  const Arm arm = fvx_arm();
  const BuildConfig config = coarse_fvx_arm_build();
  const CapabilityMap map = build_capability_map(arm, config);
  ASSERT_GT(map.voxel_count(), 100u);
  // Precision: random queries the map calls reachable, checked by IK at the query itself
  // (not the voxel centre), with the map's tolerances widened by the voxel and direction
  // quantisation.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-0.5, 0.5);
  IkConfig ik;
  ik.position_tolerance_m = map.header().position_tolerance_m + std::sqrt(3.0) * config.voxel_m / 2;
  ik.angle_tolerance_rad = map.header().angle_tolerance_rad + map.directions().mean_spacing_rad();
  int said_yes = 0, confirmed = 0;
  for (const auto& [voxel, bits] : map.voxels()) {
    if (said_yes >= 150) break;
    const auto dirs = map.reachable_directions(map.center_of(voxel));
    const Eigen::Vector3d p = map.center_of(voxel) + config.voxel_m * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    const Eigen::Vector3d d = map.directions()[dirs[dirs.size() / 2]];
    if (!map.reachable(p, d)) continue;
    ++said_yes;
    confirmed += solve_viewing_ik(arm, p, d, ik, rng).reached;
  }
  std::printf("fvx arm: %d of %d queries the map calls reachable are reached by IK\n", confirmed, said_yes);
  EXPECT_GE(confirmed, said_yes * 95 / 100);
}

// fvx capmap eval's figures: a map built from the arm is precise and finds most FK poses, the
// same seed gives the same figures, and a map without a bit has no precision query and
// recall 0.
TEST(EvaluateCapabilityMap, ABuiltMapIsPreciseAndAnEmptyOneFindsNothing) {
  const Arm arm = fvx_arm();
  const BuildConfig config = coarse_fvx_arm_build();
  const CapabilityMap map = build_capability_map(arm, config);
  const Evaluation e = evaluate(map, arm, 300, 7);
  EXPECT_EQ(e.precision.queries, 300);
  EXPECT_EQ(e.recall.queries, 300);
  EXPECT_GE(e.precision.value(), 0.9);
  EXPECT_GE(e.recall.value(), 0.3);
  const Evaluation again = evaluate(map, arm, 300, 7);
  EXPECT_EQ(again.precision.hits, e.precision.hits);
  EXPECT_EQ(again.recall.hits, e.recall.hits);
  const Evaluation empty = evaluate(CapabilityMap(map.header()), arm, 300, 7);
  EXPECT_EQ(empty.precision.queries, 0);
  EXPECT_EQ(empty.recall.hits, 0);
  EXPECT_EQ(empty.recall.value(), 0.0);
}

// fk-witness: every bit has a configuration behind it, so on the planar arm no bit lies
// farther from the closed-form reachable set than its voxel's half diagonal (the witness is
// somewhere in the voxel) with a direction in its cell; the same bytes on any thread count,
// and shards merge into the single build.
TEST(BuildCapabilityMap, WitnessBitsLieOnThePlanarArmsReachableSetAndAreDeterministic) {
  const test::TempDir dir;
  const Arm arm = planar_arm();
  BuildConfig config;
  config.method = BuildMethod::FkWitness;
  config.voxel_m = 0.05;
  config.directions = 60;
  config.threads = 1;
  BuildStats stats;
  const CapabilityMap map = build_capability_map(arm, config, &stats);
  ASSERT_GT(stats.reached, 100u);
  EXPECT_GE(stats.estimated_recall, config.target_recall);
  EXPECT_EQ(stats.fk_samples % kWitnessRound, 0u);
  const double cell_rad = 1.5 * map.directions().mean_spacing_rad();  // beyond any direction cell's radius
  std::size_t far = 0;
  for (const auto& [voxel, bits] : map.voxels())
    for (int d = 0; d < map.directions().size(); ++d)
      if (map.reachable(voxel, d) &&
          closed_form_distance(map.center_of(voxel), map.directions()[d], cell_rad) > std::sqrt(3.0) * config.voxel_m / 2)
        ++far;
  EXPECT_EQ(far, 0u);
  expect_thread_and_shard_independent(arm, config, dir);
}

// fvx capmap eval on an fk-witness map of the fvx arm: IK finds a pose inside nearly every bit
// drawn, and recall meets the build's own estimate (both with their 95 % intervals).
TEST(EvaluateCapabilityMap, WitnessMapsOfTheFvxArmAreConfirmedAndFindFkPoses) {
  const Arm arm = fvx_arm();
  BuildConfig config = coarse_fvx_arm_build();
  config.method = BuildMethod::FkWitness;
  config.fk_samples = 0;  // until the target recall
  BuildStats stats;
  const CapabilityMap map = build_capability_map(arm, config, &stats);
  EXPECT_EQ(map.header().method, "fk-witness");
  const Evaluation e = evaluate(map, arm, 400, 3);
  std::printf("fvx arm, fk-witness at 15 cm: precision %.3f [%.3f, %.3f], recall %.3f [%.3f, %.3f], %zu samples\n",
              e.precision.value(), e.precision.low(), e.precision.high(), e.recall.value(), e.recall.low(),
              e.recall.high(), stats.fk_samples);
  EXPECT_GE(e.precision.high(), 0.98);
  EXPECT_GE(e.recall.high(), 0.99);
  EXPECT_LE(e.recall.low(), e.recall.value());
}

/// Building through the first joint's turn (one FK per group of witnesses, turned) sets the
/// same bits as one FK per witness: the map decoded from either is the same, byte for byte.
void expect_turned_build_equals_fk_per_witness(const Arm& arm, double voxel_m, const char* name) {
  const test::TempDir dir;
  BuildConfig config;
  config.voxel_m = voxel_m;
  BuildStats turned, each;
  build_capability_map(arm, config, &turned).save(dir / "turned.fcm");
  config.use_first_joint_turn = false;
  build_capability_map(arm, config, &each).save(dir / "each.fcm");
  std::printf("%s, %.0f cm: %zu witnesses from %zu FK (turned) and %zu FK, %zu bits\n", name, voxel_m * 100,
              turned.fk_samples, turned.fk_evaluations, each.fk_evaluations, turned.reached);
  EXPECT_GT(turned.reached, 1000u) << name;
  EXPECT_EQ(turned.fk_samples, each.fk_samples) << name;
  EXPECT_EQ(turned.fk_evaluations * std::size_t(config.turns_per_fk), turned.fk_samples) << name;
  EXPECT_EQ(each.fk_evaluations, each.fk_samples) << name;
  EXPECT_TRUE(bytes_of(dir / "turned.fcm") == bytes_of(dir / "each.fcm")) << name << ": the turned build differs";
}

TEST(BuildCapabilityMap, TheFvxArmsMapBuiltThroughItsFirstJointEqualsOneFkPerWitness) {
  expect_turned_build_equals_fk_per_witness(fvx_arm(), 0.1, "fvx arm");
}

TEST(BuildCapabilityMapRealData, YoubotAndSo101MapsBuiltThroughTheFirstJointEqualOneFkPerWitness) {
  FVX_REAL_DATA_OR_SKIP(youbot, "arms/youbot_arm.urdf");
  FVX_REAL_DATA_OR_SKIP(so101, "arms/so101_arm.urdf");
  expect_turned_build_equals_fk_per_witness(Arm::from_urdf(youbot, {"base_link", "arm_link_5"}), 0.05, "youBot");
  expect_turned_build_equals_fk_per_witness(Arm::from_urdf(so101, {"base_link", "gripper_frame_link"}), 0.05, "SO-101");
}

TEST(EvaluateCapabilityMap, TheFvxArmsWitnessMapHasRecallAtPrecision) { expect_recall_at_precision(fvx_arm(), "fvx arm"); }

TEST(EvaluateCapabilityMapRealData, YoubotAndSo101WitnessMapsHaveRecallAtPrecision) {
  FVX_REAL_DATA_OR_SKIP(youbot, "arms/youbot_arm.urdf");
  FVX_REAL_DATA_OR_SKIP(so101, "arms/so101_arm.urdf");
  expect_recall_at_precision(Arm::from_urdf(youbot, {"base_link", "arm_link_5"}), "youBot");
  expect_recall_at_precision(Arm::from_urdf(so101, {"base_link", "gripper_frame_link"}), "SO-101");
}

}  // namespace
}  // namespace fvx::capmap
