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

/// A ray of the bitmap walk (mark_ray_cells) after its set-up: the bit index of the cell it
/// is in and of its end's cell, the index step per axis, computeRayKeys's t's and their
/// steps, and the segment's length (float, as computeRayKeys's test reads it).
struct MarkedRay {
  std::int64_t index = 0, index_end = 0, index_step[3] = {0, 0, 0};
  double t_max[3] = {0, 0, 0}, t_delta[3] = {0, 0, 0}, length = 0;
};

/// mark_ray_cells's set-up. Returns false if either end is outside the key space; sets
/// `empty` when both ends share a cell (the ray marks nothing, not even its first cell).
template <typename IndexOf>
bool start_marked_ray(const octomap::OcTree& tree, const octomap::point3d& origin, const octomap::point3d& end,
                      const std::int64_t stride[3], IndexOf&& index_of, MarkedRay& ray, bool& empty) {
  octomap::OcTreeKey key_origin, key_end;
  if (!tree.coordToKeyChecked(origin, key_origin) || !tree.coordToKeyChecked(end, key_end)) return false;
  empty = key_origin == key_end;
  if (empty) return true;
  ray.index = index_of(key_origin);
  ray.index_end = index_of(key_end);

  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;
  ray.length = length;

  const double resolution = tree.getResolution();
  for (unsigned i = 0; i < 3; ++i) {
    const int step = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    ray.index_step[i] = step * stride[i];
    if (step != 0) {
      double voxel_border = tree.keyToCoord(key_origin[i]);
      voxel_border += float(step * resolution * 0.5);
      ray.t_max[i] = (voxel_border - origin(i)) / direction(i);
      ray.t_delta[i] = resolution / std::fabs(direction(i));
    } else {
      ray.t_max[i] = std::numeric_limits<double>::max();
      ray.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  return true;
}

/// The cells of a started ray after its first, each given to `mark(bit_index)`: identical
/// arithmetic and tie breaking to computeRayKeys, but the cell is its bit index alone,
/// stepped by a fixed stride per axis, and the end test compares indices (every cell a ray
/// visits lies in the bitmap's box, where the index is one-to-one: the caller's box holds
/// both ends with a margin for rounding). Each step does one compare pair, one add and one
/// length test, whose minimum of the t's the next step's axis choice reuses: a fifth faster
/// per frame than the branch-free form that added to all three t's and kept a packed key
/// beside the index (README, Speed).
template <typename Mark>
void walk_marked_ray(const MarkedRay& ray, Mark&& mark) {
  // The t's live in named variables, not an array indexed by the axis (a store and a load on
  // the loop's critical path). dim = t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2), as
  // computeRayKeys: `first` and `smaller` are carried from the previous step's length test.
  // Locals, not the struct's fields: `mark` writes 64-bit words, which may alias them.
  std::int64_t index = ray.index;
  const std::int64_t index_end = ray.index_end;
  const std::int64_t index_step[3] = {ray.index_step[0], ray.index_step[1], ray.index_step[2]};
  const double length = ray.length;
  double t0 = ray.t_max[0], t1 = ray.t_max[1], t2 = ray.t_max[2];
  const double d0 = ray.t_delta[0], d1 = ray.t_delta[1], d2 = ray.t_delta[2];
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
    if (index == index_end) return;
    first = t0 < t1;
    smaller = first ? t0 : t1;
    // Rounding can step past the end's cell; stop once the ray is longer than the segment
    // (min(t0, t1, t2) > length, as computeRayKeys).
    if ((smaller < t2 ? smaller : t2) > length) return;
    mark(index);
  }
}

/// The same traversal, specialised for marking a flat bitmap: start_marked_ray, the first
/// cell, then walk_marked_ray. `index_of(key)` gives a key's bit index.
template <typename IndexOf, typename Mark>
bool mark_ray_cells(const octomap::OcTree& tree, const octomap::point3d& origin,
                    const octomap::point3d& end, const std::int64_t stride[3], IndexOf&& index_of,
                    Mark&& mark) {
  MarkedRay ray;
  bool empty = false;
  if (!start_marked_ray(tree, origin, end, stride, index_of, ray, empty)) return false;
  if (empty) return true;
  mark(ray.index);
  walk_marked_ray(ray, mark);
  return true;
}

}  // namespace fvx::map
