#pragma once
/// \file
/// Where a ray leaves a box: the walks of Algorithm 1 and of the field-of-view scorer stop
/// there when nothing beyond it is read.
#include <Eigen/Geometry>
#include <algorithm>
#include <utility>

namespace fvx {

/// The distance along the ray from `start` (unit direction `d`) at which it leaves `box`,
/// at most `range_m`; −1 when no point of the ray within [0, range_m] lies in the box
/// (a slab test; an empty box is missed by every ray).
inline double ray_box_exit(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& start, const Eigen::Vector3d& d,
                           double range_m) {
  double t0 = 0.0, t1 = range_m;
  for (int a = 0; a < 3; ++a) {
    const double lo = box.min()[a], hi = box.max()[a];
    if (d[a] == 0.0) {
      if (!(start[a] >= lo && start[a] <= hi)) return -1.0;
      continue;
    }
    double near = (lo - start[a]) / d[a], far = (hi - start[a]) / d[a];
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
  }
  return t0 <= t1 ? t1 : -1.0;
}

}  // namespace fvx
