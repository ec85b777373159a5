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
/// breaking, but the axis is chosen without branches, the key lives packed in one integer
/// (x | y << 16 | z << 32) so the end test is one comparison, and the bit index steps by a
/// fixed stride per axis. `mark(bit_index)` gets the index of each visited cell;
/// `index_of(key)` gives the index of a key. Keys stay inside [0, 0xFFFF] (they are between
/// two keys of the key space), so the packed additions never carry across fields.
template <typename IndexOf, typename Mark>
bool mark_ray_cells(const octomap::OcTree& tree, const octomap::point3d& origin,
                    const octomap::point3d& end, const std::int64_t stride[3], IndexOf&& index_of,
                    Mark&& mark) {
  octomap::OcTreeKey key_origin, key_end;
  if (!tree.coordToKeyChecked(origin, key_origin) || !tree.coordToKeyChecked(end, key_end))
    return false;
  if (key_origin == key_end) return true;
  std::int64_t index = index_of(key_origin);
  mark(index);

  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;

  auto pack = [](const octomap::OcTreeKey& k) {
    return std::int64_t(k[0]) | std::int64_t(k[1]) << 16 | std::int64_t(k[2]) << 32;
  };
  const std::int64_t packed_end = pack(key_end);
  std::int64_t packed = pack(key_origin);
  const double resolution = tree.getResolution();
  std::int64_t packed_step[3], index_step[3];
  double t_max[3], t_delta[3];
  for (unsigned i = 0; i < 3; ++i) {
    const int step = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    packed_step[i] = std::int64_t(step) * (std::int64_t(1) << (16 * i));  // step < 0: no left shift of a negative (UB in C++17)
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

  // The t's live in registers: indexing an array by the chosen axis would put a store and a
  // load on the loop's critical path. Adding 0.0 to the axes not chosen is exact.
  double t0 = t_max[0], t1 = t_max[1], t2 = t_max[2];
  const double d0 = t_delta[0], d1 = t_delta[1], d2 = t_delta[2];
  const double length_d = length;
  while (true) {
    // dim = t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2), without branches.
    const bool first = t0 < t1;
    const double smaller = first ? t0 : t1;
    const unsigned dim = smaller < t2 ? (first ? 0u : 1u) : 2u;
    packed += packed_step[dim];
    index += index_step[dim];
    t0 += dim == 0 ? d0 : 0.0;
    t1 += dim == 1 ? d1 : 0.0;
    t2 += dim == 2 ? d2 : 0.0;
    if (packed == packed_end) return true;
    if (std::min(std::min(t0, t1), t2) > length_d) return true;
    mark(index);
  }
}

}  // namespace fvx::map
