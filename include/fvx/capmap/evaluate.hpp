#pragma once
/// \file
/// How well a capability map matches its arm, by sampling (fvx capmap eval):
/// - precision: set bits drawn at random (a point anywhere in the voxel, the bit's direction)
///   that IK confirms, with the map's tolerances widened by its quantisation (half the voxel
///   diagonal, half the mean direction spacing);
/// - recall: poses the arm reaches by construction (forward kinematics of configurations
///   drawn uniformly within the joint limits) that the map calls reachable.
#include <cstdint>

#include "fvx/capmap/arm.hpp"
#include "fvx/capmap/capability_map.hpp"

namespace fvx::capmap {

struct Evaluation {
  int precision_queries = 0, confirmed = 0;  ///< set bits drawn; of them, reached by IK
  int recall_queries = 0, found = 0;         ///< FK poses drawn; of them, reachable in the map
  double precision() const { return precision_queries ? double(confirmed) / precision_queries : 0.0; }
  double recall() const { return recall_queries ? double(found) / recall_queries : 0.0; }
};

/// `samples` queries for each figure (none for precision when no bit is set), seeded.
Evaluation evaluate(const CapabilityMap& map, const Arm& arm, int samples, std::uint64_t seed);

}  // namespace fvx::capmap
