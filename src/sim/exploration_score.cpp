#include "fvx/sim/exploration_score.hpp"

#include <algorithm>
#include <atomic>
#include <deque>
#include <thread>

#include "fvx/core/ray_box.hpp"
#include "fvx/map/dense_grid.hpp"
#include "fvx/voids/voids.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::sim {
namespace {

/// The convex hull of the solid cells' centres in S: per column only the lowest and highest
/// (the others lie between them, as voids::void_cells builds it).
voids::Hull hull_of_surfaces(const GroundTruth& gt, const Eigen::AlignedBox3d& S) {
  const Eigen::Vector3i n = gt.size();
  std::vector<Eigen::Vector3d> extremes;
  for (int y = 0; y < n.y(); ++y)
    for (int x = 0; x < n.x(); ++x) {
      std::optional<Eigen::Vector3d> lowest, highest;
      for (int z = 0; z < n.z(); ++z) {
        const Eigen::Vector3i cell = gt.first_cell() + Eigen::Vector3i(x, y, z);
        const Eigen::Vector3d p = gt.center_of(cell);
        if (!gt.solid(cell) || !S.contains(p)) continue;
        if (!lowest) lowest = p;
        highest = p;
      }
      if (!lowest) continue;
      extremes.push_back(*lowest);
      if (*highest != *lowest) extremes.push_back(*highest);
    }
  return voids::convex_hull(extremes);
}

/// The grid's states with bit 2 set on the cells of `centres_m`, in `cells`; returns the box
/// of those cells and of `target_m`, one cell wider on every side.
Eigen::AlignedBox3d flag_cells(const map::OccupancyMap& truth, const map::DenseGrid& grid,
                               const std::vector<Eigen::Vector3d>& centres_m,
                               const std::optional<Eigen::AlignedBox3d>& target_m, std::vector<std::uint8_t>& cells) {
  Eigen::AlignedBox3d box_m;
  cells.assign(grid.states(), grid.states() + grid.cell_count());
  for (const Eigen::Vector3d& p : centres_m) {
    box_m.extend(p);
    if (const auto key = truth.key_of(p); key && grid.contains(*key)) cells[grid.index(*key)] |= 4;
  }
  if (target_m) box_m.extend(*target_m);
  box_m.min().array() -= grid.resolution_m();
  box_m.max().array() += grid.resolution_m();
  return box_m;
}

}  // namespace

ExplorationScore::ExplorationScore(const GroundTruth& gt, const Eigen::AlignedBox3d& search_space_m,
                                   std::optional<Eigen::AlignedBox3d> target_m)
    : target_m_(std::move(target_m)) {
  const Eigen::Vector3i n = gt.size();
  auto index = [&](const Eigen::Vector3i& c) { return (std::size_t(c.z()) * n.y() + c.y()) * n.x() + c.x(); };
  std::vector<std::uint8_t> reached(std::size_t(n.x()) * n.y() * n.z(), 0);
  std::deque<Eigen::Vector3i> queue;
  // Seeds: the empty cells on the region's border.
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const bool border = x == 0 || y == 0 || z == 0 || x == n.x() - 1 || y == n.y() - 1 || z == n.z() - 1;
        const Eigen::Vector3i c(x, y, z);
        if (border && !gt.solid(gt.first_cell() + c)) {
          reached[index(c)] = 1;
          queue.push_back(c);
        }
      }
  while (!queue.empty()) {
    const Eigen::Vector3i c = queue.front();
    queue.pop_front();
    for (int a = 0; a < 3; ++a)
      for (int step : {-1, 1}) {
        Eigen::Vector3i m = c;
        m[a] += step;
        if (m[a] < 0 || m[a] >= n[a] || reached[index(m)] || gt.solid(gt.first_cell() + m)) continue;
        reached[index(m)] = 1;
        queue.push_back(m);
      }
  }
  const voids::Hull hull = hull_of_surfaces(gt, search_space_m);
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const Eigen::Vector3d p = gt.center_of(gt.first_cell() + Eigen::Vector3i(x, y, z));
        if (!reached[index({x, y, z})] || !search_space_m.contains(p)) continue;
        observable_.push_back(p);
        in_hull_.push_back(!hull.empty() && hull.contains(p));
      }
}

std::size_t ExplorationScore::observable_void_cells() const {
  return std::size_t(std::count(in_hull_.begin(), in_hull_.end(), true));
}

std::vector<Eigen::Vector3d> ExplorationScore::observable_void_centres_m() const {
  std::vector<Eigen::Vector3d> centres;
  for (std::size_t c = 0; c < observable_.size(); ++c)
    if (in_hull_[c]) centres.push_back(observable_[c]);
  return centres;
}

void ExplorationScore::restrict_to_views(const GroundTruth& gt, const std::vector<Eigen::Isometry3d>& T_world_sensor,
                                         const std::vector<Eigen::Vector3d>& rays_sensor, double depth_min_m,
                                         double depth_max_m, unsigned threads) {
  const map::OccupancyMap truth = gt.to_map();
  const double R = gt.resolution_m();
  const Eigen::Vector3d lo = gt.center_of(gt.first_cell()) - Eigen::Vector3d::Constant(R / 2);
  const map::DenseGrid grid(truth, Eigen::AlignedBox3d(lo, lo + gt.size().cast<double>() * R));
  const unsigned n = core::worker_count(threads);
  std::vector<std::vector<std::uint8_t>> revealed(n, std::vector<std::uint8_t>(grid.cell_count(), 0));
  // Only the observable cells and the target's cells are read below. A ray that passes none
  // of their cubes cannot change the result and is not walked (on the suite's scenes three
  // rays in four of the arm's poses look past the search space); a walked ray keeps only the
  // observable cells it crosses, flagged beside the state (bit 2) so that a cell is one load.
  std::vector<std::uint8_t> cells;
  const Eigen::AlignedBox3d read_box_m = flag_cells(truth, grid, observable_, target_m_, cells);
  std::atomic<std::size_t> next{0};
  auto work = [&](unsigned t) {
    std::vector<std::size_t> crossed;
    for (std::size_t p = next++; p < T_world_sensor.size(); p = next++) {
      const Eigen::Isometry3d& T = T_world_sensor[p];
      for (const Eigen::Vector3d& ray : rays_sensor) {
        const Eigen::Vector3d d_world = T.linear() * ray;
        if (ray_box_exit(read_box_m, T.translation(), d_world.normalized(), depth_max_m * ray.norm()) < 0) continue;
        crossed.clear();
        std::size_t hit = std::size_t(-1);
        grid.walk_cells(cells.data(), T.translation(), d_world, depth_max_m * ray.norm(),
                        [&](std::size_t i, std::uint8_t cell) {
                          if (map::VoxelState(cell & 3) == map::VoxelState::Occupied) {
                            hit = i;
                            return false;
                          }
                          if (cell & 4) crossed.push_back(i);
                          return true;
                        });
        if (hit == std::size_t(-1)) continue;  // no surface within range: no measurement
        const double depth = (grid.center_of(grid.key(hit)) - T.translation()).dot(T.linear().col(2));
        if (depth < depth_min_m || depth > depth_max_m) continue;
        for (const std::size_t i : crossed) revealed[t][i] = 1;
        revealed[t][hit] |= 2;  // a measured surface
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& t : pool) t.join();
  std::vector<Eigen::Vector3d> kept;
  std::vector<bool> kept_in_hull;
  for (std::size_t c = 0; c < observable_.size(); ++c) {
    const auto key = truth.key_of(observable_[c]);
    if (!key || !grid.contains(*key)) continue;
    const std::size_t i = grid.index(*key);
    if (std::any_of(revealed.begin(), revealed.end(), [&](const auto& r) { return (r[i] & 1) != 0; })) {
      kept.push_back(observable_[c]);
      kept_in_hull.push_back(in_hull_[c]);
    }
  }
  observable_ = std::move(kept);
  in_hull_ = std::move(kept_in_hull);
  if (target_m_) {
    observable_target_cells_ = 0;
    Eigen::AlignedBox3d above_floor = *target_m_;
    above_floor.min().z() += R;
    for (std::size_t i = 0; i < grid.cell_count(); ++i)
      if (above_floor.contains(grid.center_of(grid.key(i))) &&
          std::any_of(revealed.begin(), revealed.end(), [&](const auto& r) { return (r[i] & 2) != 0; }))
        ++*observable_target_cells_;
  }
}

void ExplorationScore::restrict_target_to_views(const RayCaster& caster,
                                                const std::vector<Eigen::Isometry3d>& T_world_sensor,
                                                const io::Intrinsics& K, double depth_min_m, double depth_max_m,
                                                double resolution_m, unsigned threads) {
  if (!target_m_) return;
  const double R = resolution_m;
  Eigen::AlignedBox3d above_floor = *target_m_;
  above_floor.min().z() += R;
  // The cells a measurement can mark: those whose centres lie in the box, by key.
  const Eigen::Vector3i first = (above_floor.min().array() / R).floor().cast<int>();
  const Eigen::Vector3i size = (above_floor.max().array() / R).floor().cast<int>() - first.array() + 1;
  auto slot = [&](const Eigen::Vector3i& k) { return (std::size_t(k.z()) * size.y() + k.y()) * size.x() + k.x(); };
  const unsigned n = core::worker_count(threads);
  std::vector<std::vector<std::uint8_t>> measured(n, std::vector<std::uint8_t>(std::size_t(size.prod()), 0));
  std::atomic<std::size_t> next{0};
  auto work = [&](unsigned t) {
    for (std::size_t p = next++; p < T_world_sensor.size(); p = next++) {
      const Eigen::Isometry3d& T = T_world_sensor[p];
      const Eigen::Isometry3d T_sensor_world = T.inverse();
      // The pixel rectangle the target box covers (all of the image when it reaches behind).
      double u0 = 0, u1 = K.width - 1, v0 = 0, v1 = K.height - 1;
      bool in_front = true, behind = true;
      Eigen::AlignedBox2d rect;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d q = T_sensor_world * target_m_->corner(Eigen::AlignedBox3d::CornerType(c));
        in_front = in_front && q.z() > 1e-6;
        behind = behind && q.z() <= 1e-6;
        if (q.z() > 1e-6) rect.extend(Eigen::Vector2d(K.fx * q.x() / q.z() + K.cx, K.fy * q.y() / q.z() + K.cy));
      }
      if (behind) continue;
      if (in_front) {
        u0 = std::max(u0, std::floor(rect.min().x())), u1 = std::min(u1, std::ceil(rect.max().x()));
        v0 = std::max(v0, std::floor(rect.min().y())), v1 = std::min(v1, std::ceil(rect.max().y()));
      }
      if (u0 > u1 || v0 > v1) continue;
      const double du = std::max(1.0, (u1 - u0) / 15.0), dv = std::max(1.0, (v1 - v0) / 15.0);
      for (double v = v0; v <= v1; v += dv)
        for (double u = u0; u <= u1; u += du) {
          // The renderer's rule (sim::render): the first surface, at a depth within the limits,
          // marks the cell that holds the measured point, as the map's integration does.
          const Eigen::Vector3d ray = T.linear() * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
          const Hit hit = caster.cast(T.translation().cast<float>(), ray.cast<float>(), 0.0f, float(depth_max_m));
          if (!hit.hit() || hit.distance < depth_min_m) continue;
          const Eigen::Vector3d point = T.translation() + double(hit.distance) * ray;
          const Eigen::Vector3i key = (point.array() / R).floor().cast<int>();
          const Eigen::Vector3d centre = (key.cast<double>().array() + 0.5) * R;
          if (above_floor.contains(centre)) measured[t][slot(key - first)] = 1;
        }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& t : pool) t.join();
  std::size_t cells = 0;
  for (std::size_t i = 0; i < measured[0].size(); ++i)
    cells += std::any_of(measured.begin(), measured.end(), [&](const auto& m) { return m[i] != 0; });
  observable_target_cells_ = std::max(observable_target_cells_.value_or(0), cells);
}

double ExplorationScore::known_fraction(const map::OccupancyMap& map) const {
  if (observable_.empty()) return 1.0;
  std::size_t known = 0;
  map::StateReader read(map);
  for (const Eigen::Vector3d& p : observable_) {
    const auto key = map.key_of(p);
    known += key && read(*key) != map::VoxelState::Unknown;
  }
  return double(known) / double(observable_.size());
}

double ExplorationScore::void_known_fraction(const map::OccupancyMap& map) const {
  std::size_t all = 0, known = 0;
  map::StateReader read(map);
  for (std::size_t c = 0; c < observable_.size(); ++c) {
    if (!in_hull_[c]) continue;
    ++all;
    const auto key = map.key_of(observable_[c]);
    known += key && read(*key) != map::VoxelState::Unknown;
  }
  return all ? double(known) / double(all) : 1.0;
}

std::size_t ExplorationScore::target_cells_seen(const map::OccupancyMap& map) const {
  if (!target_m_) return 0;
  const double R = map.resolution_m();
  Eigen::AlignedBox3d above_floor = *target_m_;
  above_floor.min().z() += R;
  std::size_t seen = 0;
  for (const Eigen::Vector3f& c : map.occupied_centers()) seen += above_floor.contains(c.cast<double>());
  return seen;
}

}  // namespace fvx::sim
