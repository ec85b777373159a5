#pragma once
/// \file
/// Stage `capmap`, part 3: building a capability map from an arm.
///
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

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/capmap/viewing_ik.hpp"

namespace fvx::capmap {

struct BuildConfig {
  double voxel_m = 0.05;              ///< grid edge, metres
  int directions = 200;               ///< directions per voxel (golden-angle spiral)
  double position_tolerance_m = 0.005;
  /// Angle tolerance, radians; 0 (default): half the mean spacing of the direction set.
  double angle_tolerance_rad = 0.0;
  int ik_restarts = 8;                ///< random restarts after the FK seed
  std::uint64_t seed = 1;
  std::size_t workspace_samples = 20000;
  std::size_t fk_samples = 400000;
  unsigned threads = 0;               ///< 0: all cores
  std::uint32_t shard_index = 0, shard_count = 1;  ///< build only this z-slab of the grid
  bool exhaustive = false;            ///< baseline: IK for every voxel and direction

  std::vector<std::string> validate() const;
};

struct BuildStats {
  std::size_t candidates = 0;  ///< bits the IK checked
  std::size_t reached = 0;     ///< bits set
  std::size_t ik_iterations = 0;
};

/// Builds the map (or the configured shard). `progress(done, total)` is called now and then
/// from the calling thread; `cancel` stops the build early (the map is then incomplete and
/// must not be saved).
CapabilityMap build_capability_map(const Arm& arm, const BuildConfig& config, BuildStats* stats = nullptr,
                                   const std::function<void(std::size_t, std::size_t)>& progress = {},
                                   const std::atomic<bool>* cancel = nullptr);

}  // namespace fvx::capmap
