#pragma once
/// \file
/// Voxel keys into key order (z, then y, then x), as the change sets, the frontier and void
/// sets and the reports keep them. A set of a few million keys read out of a hash set is
/// sorted in three stable counting passes (x, then y, then z) over each axis's range of
/// values, instead of a comparison sort: one pass over the keys each, not log n.
#include <vector>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::map {

/// Sorts `keys` by operator< (z, then y, then x); equal keys stay (the sort is stable).
void sort_keys(std::vector<VoxelKey>& keys);

}  // namespace fvx::map
