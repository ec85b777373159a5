#pragma once
// Private to the map stage: the cells a ray crosses, exactly as OctoMap's
// OcTreeBaseImpl::computeRayKeys (Amanatides & Woo DDA, OctoMap 1.9.7 arithmetic: float
// direction and length, double tMax/tDelta), but handing each key to a visitor instead of
// storing it in a KeyRay. Maps built through it equal OctoMap's bit for bit; a unit test
// compares both on random rays.
#include <octomap/OcTree.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>

namespace fvx::map {

/// Visits the keys of the cells between `origin` and `end`: the origin's cell first, the
/// end's cell excluded. Returns false (visiting nothing) if either point is outside the key
/// space, like computeRayKeys.
template <typename Visit>
bool for_each_ray_key(const octomap::OcTree& tree, const octomap::point3d& origin,
                      const octomap::point3d& end, Visit&& visit) {
  octomap::OcTreeKey key_origin, key_end;
  if (!tree.coordToKeyChecked(origin, key_origin) || !tree.coordToKeyChecked(end, key_end))
    return false;
  if (key_origin == key_end) return true;
  visit(key_origin);

  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;

  const double resolution = tree.getResolution();
  int step[3];
  double t_max[3], t_delta[3];
  octomap::OcTreeKey current = key_origin;
  for (unsigned i = 0; i < 3; ++i) {
    step[i] = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    if (step[i] != 0) {
      double voxel_border = tree.keyToCoord(current[i]);
      voxel_border += float(step[i] * resolution * 0.5);
      t_max[i] = (voxel_border - origin(i)) / direction(i);
      t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }

  while (true) {
    unsigned dim;
    if (t_max[0] < t_max[1])
      dim = t_max[0] < t_max[2] ? 0 : 2;
    else
      dim = t_max[1] < t_max[2] ? 1 : 2;
    current[dim] = octomap::key_type(current[dim] + step[dim]);
    t_max[dim] += t_delta[dim];
    if (current == key_end) return true;
    // Rounding can step past the end's cell; stop once the ray is longer than the segment.
    if (std::min(std::min(t_max[0], t_max[1]), t_max[2]) > length) return true;
    visit(current);
  }
}

/// The same traversal, specialised for marking a flat bitmap: identical arithmetic and tie
/// breaking, but the cell is its bit index alone, stepped by a fixed stride per axis, and the
/// end test compares indices (every cell a ray visits lies in the bitmap's box, where the
/// index is one-to-one: the caller's box holds both ends with a margin for rounding).
/// `mark(bit_index)` gets the index of each visited cell; `index_of(key)` gives a key's.
/// Each step does one compare pair, one add and one length test, whose minimum of the t's
/// the next step's axis choice reuses: a fifth faster per frame than the branch-free form
/// that added to all three t's and kept a packed key beside the index (README, Speed).
template <typename IndexOf, typename Mark>
bool mark_ray_cells(const octomap::OcTree& tree, const octomap::point3d& origin,
                    const octomap::point3d& end, const std::int64_t stride[3], IndexOf&& index_of,
                    Mark&& mark) {
  octomap::OcTreeKey key_origin, key_end;
  if (!tree.coordToKeyChecked(origin, key_origin) || !tree.coordToKeyChecked(end, key_end))
    return false;
  if (key_origin == key_end) return true;
  std::int64_t index = index_of(key_origin);
  const std::int64_t index_end = index_of(key_end);
  mark(index);

  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;

  const double resolution = tree.getResolution();
  std::int64_t index_step[3];
  double t_max[3], t_delta[3];
  for (unsigned i = 0; i < 3; ++i) {
    const int step = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    index_step[i] = step * stride[i];
    if (step != 0) {
      double voxel_border = tree.keyToCoord(key_origin[i]);
      voxel_border += float(step * resolution * 0.5);
      t_max[i] = (voxel_border - origin(i)) / direction(i);
      t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }

  // The t's live in named variables, not an array indexed by the axis (a store and a load on
  // the loop's critical path). dim = t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2), as
  // computeRayKeys: `first` and `smaller` are carried from the previous step's length test.
  double t0 = t_max[0], t1 = t_max[1], t2 = t_max[2];
  const double d0 = t_delta[0], d1 = t_delta[1], d2 = t_delta[2];
  const double length_d = length;
  bool first = t0 < t1;
  double smaller = first ? t0 : t1;
  while (true) {
    const unsigned dim = smaller < t2 ? (first ? 0u : 1u) : 2u;
    index += index_step[dim];
    if (dim == 0)
      t0 += d0;
    else if (dim == 1)
      t1 += d1;
    else
      t2 += d2;
    if (index == index_end) return true;
    first = t0 < t1;
    smaller = first ? t0 : t1;
    // Rounding can step past the end's cell; stop once the ray is longer than the segment
    // (min(t0, t1, t2) > length, as computeRayKeys).
    if ((smaller < t2 ? smaller : t2) > length_d) return true;
    mark(index);
  }
}

}  // namespace fvx::map
