#pragma once
/// \file
/// Stage `capmap`, part 3: building a capability map from an arm.
///
/// The method `fk-witness` (man fvx-capmap.5): a bit says that some configuration
/// puts the sensor inside the voxel with its viewing axis in the direction's cell (the
/// directions nearer to it than to any other). Forward kinematics of configurations drawn
/// uniformly within the joint limits are the witnesses: each sets the bit it lands in, so no
/// bit is set without one. Sampling runs in rounds of kWitnessRound configurations; the
/// share of a round that lands on bits already set is an unbiased estimate of the recall of
/// the map before it (recall as `fvx capmap eval` measures it), and the build stops once it
/// reaches `target_recall` (or after `fk_samples`). Each round's configurations come from
/// generators seeded by (seed, round, chunk): the map depends neither on the thread count
/// nor on sharding (every shard samples the whole workspace and keeps its z-slab).
/// An arm whose first movable joint is revolute (Arm::first_joint_axis) is sampled in groups:
/// one draw of all joints, then `turns_per_fk` − 1 more draws of the first joint. With
/// `use_first_joint_turn` the group costs one forward kinematics at q₀ = 0, turned about the
/// joint's axis for each witness (RM4D's symmetry); without it, one per witness. Both set the
/// same bits.
///
/// The turn layout (fk-witness only) draws configurations the same way, takes each with the
/// first joint at 0 (one FK each) and keeps per reduced cell the first witness drawn
/// (turn_layout.hpp); the estimate is the share landing in cells that hold one. A shard keeps
/// the cells whose height cell is ≡ its index mod the count.
///
/// The IK methods (`fk-seeded-ik`, `exhaustive-ik`) decide a bit by IK at the voxel centre:
/// 1. Workspace: the grid covers the sensor positions of `workspace_samples` random
///    configurations, one voxel of margin around them; voxel centres lie on the lattice k·v
///    through the base origin.
/// 2. Candidates: `fk_samples` random configurations each propose the bits (voxel of the
///    sensor, every direction within the angle tolerance of its viewing direction) and a
///    seed configuration for them (a forward-kinematics pre-pass: cheap, and the IK starts
///    close to a solution).
/// 3. The IK check decides every candidate: the sensor at the voxel centre looking along the
///    direction, within the tolerances. Each bit's restarts draw from a generator seeded by
///    (seed, voxel, direction), so the map depends neither on the thread count nor on sharding.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/capmap/viewing_ik.hpp"

namespace fvx::capmap {

/// How bits are decided (CapabilityHeader::method names it in the file).
enum class BuildMethod {
  FkWitness,   ///< some pose in the voxel and direction cell, from FK samples (default)
  FkSeededIk,  ///< IK at the voxel centre for the bits FK samples propose
  ExhaustiveIk,  ///< IK at the voxel centre for every bit (a slow baseline)
};
const char* to_string(BuildMethod method);
/// "fk-witness", "fk-seeded-ik" or "exhaustive-ik"; UsageError naming `what` otherwise.
BuildMethod parse_build_method(const std::string& name, const std::string& what);

/// How the file stores the map (CapabilityHeader::layout).
enum class MapLayout {
  Grid,  ///< bits per voxel (default)
  Turn,  ///< fk-witness, revolute first joint: one witness per cell of the turn's coordinates
};
const char* to_string(MapLayout layout);
/// "grid" or "turn"; UsageError naming `what` otherwise.
MapLayout parse_map_layout(const std::string& name, const std::string& what);

/// How shards divide a build: Slab (each shard keeps its z-slab's bits; an fk-witness shard
/// still draws every witness, since its stop rule needs all of them) or Samples (fk-witness,
/// grid layout, a budget `fk_samples`: shard I of N draws the chunks g ≡ I−1 mod N of the
/// budget, and the merge applies the stop rule; CapabilityMap::merge).
enum class ShardSplit { Slab, Samples };
const char* to_string(ShardSplit split);
/// "slab" or "samples"; UsageError naming `what` otherwise.
ShardSplit parse_shard_split(const std::string& name, const std::string& what);

/// Configurations per round of the fk-witness build.
constexpr std::size_t kWitnessRound = std::size_t(1) << 18;

struct BuildConfig {
  /// fk-witness: `fvx capmap eval` finds recall ≥ 0.99 at precision ≥ 0.99 on the youBot,
  /// the SO-101 and the fvx arm at 5 cm, where the IK methods reach 0.50–0.74 recall.
  BuildMethod method = BuildMethod::FkWitness;
  double voxel_m = 0.05;              ///< grid edge, metres
  int directions = 200;               ///< directions per voxel (golden-angle spiral)
  double position_tolerance_m = 0.005;
  /// Angle tolerance, radians; 0 (default): half the mean spacing of the direction set.
  double angle_tolerance_rad = 0.0;
  int ik_restarts = 8;                ///< IK methods: random restarts after the FK seed
  std::uint64_t seed = 1;
  std::size_t workspace_samples = 20000;
  /// fk-witness: at most this many configurations (0: 2^27); fk-seeded-ik: the proposals
  /// (0: 400 000).
  std::size_t fk_samples = 0;
  /// fk-witness: stop when a round's estimate of the recall reaches this.
  double target_recall = 0.995;
  /// fk-witness, revolute first joint: witnesses per draw of the other joints. 8: FK is no
  /// longer most of a witness's cost (youBot 5 cm: 0.85 s at 1, 0.35 s at 8, 0.28 s at 16),
  /// and precision and recall stay within their intervals (youBot, fvx arm, 1 to 32).
  int turns_per_fk = 8;
  /// fk-witness, revolute first joint: one FK per group, turned, instead of one per witness.
  bool use_first_joint_turn = true;
  /// Grid (default): the youBot, SO-101 and fvx arm at 5 cm build faster, load in
  /// milliseconds and recall 0.3–0.7 % more than Turn; Turn pays off at fine voxels (README).
  MapLayout layout = MapLayout::Grid;
  unsigned threads = 0;               ///< 0: all cores
  std::uint32_t shard_index = 0, shard_count = 1;  ///< build only this shard
  ShardSplit shard_split = ShardSplit::Slab;

  std::vector<std::string> validate() const;
};

/// Sets the shard of `config` from "I/N" (1-based, N ≤ 100 000); UsageError naming `what`.
void parse_shard(const std::string& text, const std::string& what, BuildConfig& config);

struct BuildStats {
  std::size_t candidates = 0;  ///< bits the IK checked (IK methods)
  std::size_t reached = 0;     ///< bits set (in this shard)
  std::size_t ik_iterations = 0;
  std::size_t fk_samples = 0;          ///< fk-witness: configurations drawn (witnesses)
  std::size_t fk_evaluations = 0;      ///< fk-witness: forward kinematics computed
  double estimated_recall = 0.0;       ///< fk-witness: the last round's estimate
};

/// The seed of a generator for (a, b), mixed (SplitMix64's finaliser): rounds, chunks and bits
/// draw streams that do not depend on the thread count.
std::uint64_t seed_mix(std::uint64_t a, std::uint64_t b);

/// The fk-witness build in the turn layout (build_capability_map with MapLayout::Turn).
void build_turn_witnesses(const Arm& arm, const BuildConfig& config, CapabilityMap& map, BuildStats& stats,
                          const std::function<void(std::size_t, std::size_t)>& progress,
                          const std::atomic<bool>* cancel);

/// Builds the map (or the configured shard). `progress(done, total)` is called now and then
/// from the calling thread; `cancel` stops the build early (the map is then incomplete and
/// must not be saved).
CapabilityMap build_capability_map(const Arm& arm, const BuildConfig& config, BuildStats* stats = nullptr,
                                   const std::function<void(std::size_t, std::size_t)>& progress = {},
                                   const std::atomic<bool>* cancel = nullptr);

}  // namespace fvx::capmap
