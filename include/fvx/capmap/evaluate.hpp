#pragma once
/// \file
/// How well a capability map matches its arm, by sampling (fvx capmap eval):
/// - precision: set bits drawn at random that IK confirms. An fk-witness bit (some pose in
///   the voxel, viewing axis in the direction's cell) is confirmed when solve_in_region (IK
///   aimed at the voxel centre, then at each octant's centre, with restarts) passes a pose
///   inside the bit. A centre bit (fk-seeded-ik, exhaustive-ik) is confirmed when IK
///   reaches a point drawn in the voxel with the map's tolerances widened by its quantisation
///   (half the voxel diagonal, half the mean direction spacing).
/// - recall: poses the arm reaches by construction (forward kinematics of configurations
///   drawn uniformly within the joint limits) that the map calls reachable.
/// Each comes with a 95 % Wilson score interval; recall also per height band of voxels, to
/// show where the map misses.
#include <cstdint>
#include <vector>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"

namespace fvx::capmap {

/// A share k/n and its 95 % Wilson score interval.
struct Share {
  int queries = 0, hits = 0;
  double value() const { return queries ? double(hits) / queries : 0.0; }
  double low() const;   ///< 0 without queries
  double high() const;  ///< 1 without queries
};

struct Evaluation {
  Share precision;  ///< set bits drawn; of them, confirmed by IK
  Share recall;     ///< FK poses drawn; of them, reachable in the map
  /// Recall per z-layer of the map's voxels that FK poses fell in (outside the grid: none).
  struct Band {
    double z_min_m = 0, z_max_m = 0;
    Share recall;
  };
  std::vector<Band> recall_by_height;
};

/// `samples` queries for each figure (none for precision when no bit is set), seeded.
Evaluation evaluate(const CapabilityMap& map, const Arm& arm, int samples, std::uint64_t seed);

}  // namespace fvx::capmap
