#include "fvx/viewpoints/fov.hpp"

#include <algorithm>
#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/core/ray_box.hpp"

namespace fvx::viewpoints {

const char* to_string(NearUnknown mode) {
  switch (mode) {
    case NearUnknown::Ignore: return "ignore";
    case NearUnknown::Void: return "void";
    case NearUnknown::Any: return "any";
    case NearUnknown::Hidden: return "hidden";
  }
  return "?";
}

NearUnknown parse_near_unknown(const std::string& name, const std::string& what) {
  for (const NearUnknown m : {NearUnknown::Ignore, NearUnknown::Void, NearUnknown::Any, NearUnknown::Hidden})
    if (name == to_string(m)) return m;
  throw UsageError(what + " '" + name + "': expected ignore, void, any or hidden");
}

std::vector<Eigen::Vector3d> ray_fan(const io::Intrinsics& K, int cols, int rows) {
  FVX_ASSERT(cols > 0 && rows > 0 && K.validate().empty(), "ray_fan: bad grid or intrinsics");
  std::vector<Eigen::Vector3d> rays;
  rays.reserve(std::size_t(cols) * std::size_t(rows));
  for (int r = 0; r < rows; ++r) {
    // Centres of `rows` equal bands of the image's pixel extent [−0.5, height − 0.5].
    const double v = (r + 0.5) * K.height / rows - 0.5;
    for (int c = 0; c < cols; ++c) {
      const double u = (c + 0.5) * K.width / cols - 0.5;
      rays.emplace_back((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
    }
  }
  return rays;
}

double ray_area_at_1m(const io::Intrinsics& K, int cols, int rows) {
  return (double(K.width) / cols / std::abs(K.fx)) * (double(K.height) / rows / std::abs(K.fy));
}

double CoarseFan::full_hits_per_hit(double depth_m, double shadow_factor) const {
  const double cube_shadow_m2 = shadow_factor * cell_m * cell_m;
  const double z2 = std::max(depth_m * depth_m, 1e-12);
  const double p_coarse = std::min(1.0, cube_shadow_m2 / (z2 * ray_area_at_1m2));
  const double p_full = std::min(1.0, cube_shadow_m2 / (z2 * full_ray_area_at_1m2));
  return p_full / p_coarse;
}

CoarseFan coarse_fan(const io::Intrinsics& K, int cols, int rows, int full_cols, int full_rows, double cell_m) {
  FVX_ASSERT(cell_m > 0.0, "coarse_fan: the cell size must be > 0");
  return {ray_fan(K, cols, rows), ray_area_at_1m(K, cols, rows), ray_area_at_1m(K, full_cols, full_rows), cell_m};
}

Eigen::Matrix3d look_along(const Eigen::Vector3d& direction_world, double roll_rad) {
  const Eigen::Vector3d z = direction_world.normalized();
  // Image x (right) = z × up, so that image −y (up) = the part of world up across z.
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = z.cross(Eigen::Vector3d::UnitX());
  x.normalize();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return R * Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ());
}

FovScorer::FovScorer(const map::DenseGrid& grid, core::LargeVector<std::uint8_t> target,
                     std::vector<Eigen::Vector3d> rays_sensor, double depth_max_m, double depth_min_m,
                     bool near_targets_count)
    : grid_(grid),
      cells_(std::move(target)),
      rays_sensor_(std::move(rays_sensor)),
      depth_max_m_(depth_max_m),
      depth_min_m_(depth_min_m),
      count_from_m_(near_targets_count ? 0.0 : depth_min_m),
      diagonal_m_(std::sqrt(3.0) * grid.resolution_m()) {
  FVX_ASSERT(cells_.size() == grid_.cell_count(), "FovScorer: one target flag per grid cell");
  const std::uint8_t* states = grid_.states();
  // The targets' extent in cells, by the loop's own coordinates: key(i) divides, and real
  // maps have millions of void cells.
  const Eigen::Vector3i n = grid_.size();
  Eigen::Vector3i lo = n, hi = Eigen::Vector3i::Constant(-1);
  std::size_t i = 0;
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x, ++i) {
        if (cells_[i]) {
          lo = lo.cwiseMin(Eigen::Vector3i(x, y, z));
          hi = hi.cwiseMax(Eigen::Vector3i(x, y, z));
        }
        cells_[i] = std::uint8_t(states[i] | (cells_[i] ? kTarget : 0));
      }
  if (hi.x() >= 0) {
    auto key_at = [&](const Eigen::Vector3i& c) {
      const map::VoxelKey& m = grid_.min_key();
      return map::VoxelKey{std::uint16_t(m.x + c.x()), std::uint16_t(m.y + c.y()), std::uint16_t(m.z + c.z())};
    };
    const Eigen::Vector3d margin = Eigen::Vector3d::Constant(grid_.resolution_m());
    target_box_m_ = Eigen::AlignedBox3d(grid_.center_of(key_at(lo)) - margin, grid_.center_of(key_at(hi)) + margin);
  }
  FVX_ASSERT(depth_max_m_ > 0.0, "FovScorer: depth_max_m must be > 0");
}

void FovScorer::set_blocking(const std::vector<std::size_t>& cells) {
  for (const std::size_t i : cells) {
    FVX_ASSERT(i < cells_.size(), "FovScorer::set_blocking: a cell beyond the grid");
    cells_[i] |= kBlocking;
  }
}

void FovScorer::ascending(const Workspace& ws, std::vector<std::size_t>& seen) {
  seen.clear();
  seen.reserve(ws.counted.size());
  // A view of a real map sees 10^5 cells and more: reading them off the bits in order takes
  // a pass over the words, where sorting took a tenth of a replay's time. Few cells: sort.
  if (ws.counted.size() * 16 < ws.counted_bits.size()) {
    seen.assign(ws.counted.begin(), ws.counted.end());
    std::sort(seen.begin(), seen.end());
    return;
  }
  for (std::size_t w = 0; w < ws.counted_bits.size(); ++w)
    for (std::uint64_t bits = ws.counted_bits[w]; bits != 0; bits &= bits - 1)
      seen.push_back(w * 64 + std::size_t(__builtin_ctzll(bits)));
}

FovScorer::Score FovScorer::score(const Eigen::Isometry3d& T_world_sensor, Workspace& ws,
                                  std::vector<std::size_t>* seen, const CoarseFan* coarse) const {
  const std::size_t words = (grid_.cell_count() + 63) / 64;
  if (ws.counted_bits.size() != words) ws.counted_bits.assign(words, 0);
  auto counted = [&ws](std::size_t i) { return (ws.counted_bits[i >> 6] >> (i & 63)) & 1; };
  Score s;
  const Eigen::Vector3d origin = T_world_sensor.translation();
  const Eigen::Matrix3d R = T_world_sensor.linear();
  const Eigen::Vector3d axis = R.col(2);
  const std::optional<map::VoxelKey> origin_cell = grid_.cell_of(origin);
  if (!origin_cell) {  // outside the grid: every walk ends where it starts
    if (seen) seen->clear();
    return s;
  }
  for (const Eigen::Vector3d& ray : coarse ? coarse->rays : rays_sensor_) {
    // The depth limit is along z: the ray (x, y, 1) reaches depth_max at length depth_max·|ray|.
    ws.ray_targets.clear();
    const double length = ray.norm();  // per metre of depth
    const Eigen::Vector3d d = (R * ray).normalized();  // the box test and the walk take it unit
    const double exit_m = ray_box_exit(target_box_m_, origin, d, depth_max_m_ * length);
    if (exit_m < 0.0) continue;  // it crosses no target
    const double range_m = std::max(exit_m, std::min(depth_min_m_, depth_max_m_) * length);
    std::size_t hit = std::size_t(-1);
    int unknown = 0;
    // An unknown cell nearer than the minimum depth (its centre's) may hide the ray's end
    // (NearUnknown). Centres' depths along a ray fall back by up to a cell's diagonal, so the
    // check ends at the first such cell whose centre lies that far beyond the minimum depth.
    // Like the occupied-cell rule below, it sees the cells the walk enters before it stops.
    const std::uint8_t blocking = near_unknown_ == NearUnknown::Void     ? kTarget
                                  : near_unknown_ == NearUnknown::Hidden ? kBlocking
                                                                         : 0;
    bool near = near_unknown_ != NearUnknown::Ignore, blocked = false;
    grid_.walk_unit(cells_.data(), *origin_cell, origin, d, range_m, [&](std::size_t i, std::uint8_t cell) {
      ++s.cells_visited;
      if (near && map::VoxelState(cell & 3) == map::VoxelState::Unknown && (cell & blocking) == blocking) {
        const double depth_m = (grid_.center_of(grid_.key(i)) - origin).dot(axis);
        blocked = depth_m < depth_min_m_;
        if (blocked) return false;  // the ray counts nothing
        near = depth_m < depth_min_m_ + diagonal_m_;
      }
      if (map::VoxelState(cell & 3) == map::VoxelState::Occupied ||
          (unknown_depth_ > 0 && map::VoxelState(cell & 3) == map::VoxelState::Unknown && ++unknown > unknown_depth_)) {
        hit = i;  // a surface, or the first unknown cell the ray is not trusted beyond
        return false;
      }
      // The sensor measures nothing nearer than the minimum depth, so it cannot promise
      // to reveal a target there (its cell centre's depth).
      if ((cell & kTarget) && !counted(i) &&
          (count_from_m_ <= 0.0 || (grid_.center_of(grid_.key(i)) - origin).dot(axis) >= count_from_m_))
        ws.ray_targets.push_back(i);
      return true;
    });
    // A surface nearer than the minimum depth (its cell centre's depth) gives no measurement.
    if (hit != std::size_t(-1) && depth_min_m_ > 0.0 &&
        (grid_.center_of(grid_.key(hit)) - origin).dot(axis) < depth_min_m_)
      continue;
    if (blocked) continue;
    const double shadow_factor = d.cwiseAbs().sum();  // CoarseFan::full_hits_per_hit
    for (const std::size_t i : ws.ray_targets) {
      if (counted(i)) continue;  // a ray may cross a cell twice only by rounding; count once
      ws.counted_bits[i >> 6] |= std::uint64_t(1) << (i & 63);
      ws.counted.push_back(i);
      if (coarse)  // in ray order: the same sum on any thread
        s.full_fan_estimate +=
            coarse->full_hits_per_hit((grid_.center_of(grid_.key(i)) - origin).dot(axis), shadow_factor);
    }
  }
  s.targets_seen = ws.counted.size();
  if (!coarse) s.full_fan_estimate = double(s.targets_seen);
  if (seen) ascending(ws, *seen);
  for (const std::size_t i : ws.counted) ws.counted_bits[i >> 6] = 0;  // clean for the next pose
  ws.counted.clear();
  return s;
}

}  // namespace fvx::viewpoints
