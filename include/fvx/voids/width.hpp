#pragma once
/// \file
/// Void cells that could hide the target (not in the paper; fvx explore --target-size): a
/// searched object L metres across along each axis wholly covers at least floor(L/R) − 1
/// cells per axis, whatever its alignment to the grid. No ray enters those cells without
/// hitting the object, so while it is unseen they are all unknown: the object lies in a
/// cube of width = floor(L/R) − 1 unknown cells. A void cell in no such cube (a sliver a
/// cell or two thick beside a surface, a pocket in a corner) cannot hide it.
#include <vector>

#include "fvx/map/occupancy_map.hpp"

namespace fvx::voids {

/// The cube width in cells that a target `target_size_m` across (its smallest extent)
/// always fills at resolution `resolution_m`: max(1, floor(L/R) − 1). 1 keeps every cell.
int void_width_for_target(double target_size_m, double resolution_m);

/// The cells of `cells` (key order) that lie in at least one width × width × width cube of
/// cells all in `cells` — a morphological opening by that cube. Key order; width 1 keeps all.
std::vector<map::VoxelKey> cells_in_full_cubes(const std::vector<map::VoxelKey>& cells, int width);

}  // namespace fvx::voids
