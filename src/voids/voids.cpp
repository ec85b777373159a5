#include "fvx/voids/voids.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iterator>

#include "fvx/map/key_index.hpp"
#include "fvx/map/sort_keys.hpp"

namespace fvx::voids {

using map::pack;
using map::unpack;

namespace {

constexpr double kTolerance = 1e-6;  // metres: centres on a hull face count as inside

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

}  // namespace

std::optional<std::pair<double, double>> Hull::z_range(double x, double y) const {
  if (planes.empty()) return std::nullopt;
  double lo = -INFINITY, hi = INFINITY;
  for (const Eigen::Vector4d& p : planes) {
    const double rest = p.x() * x + p.y() * y + p.w() - kTolerance;  // n·(x, y, z) + d <= tol
    if (std::abs(p.z()) < 1e-12) {
      if (rest > 0) return std::nullopt;
    } else if (p.z() > 0) {
      hi = std::min(hi, -rest / p.z());
    } else {
      lo = std::max(lo, -rest / p.z());
    }
  }
  if (lo > hi) return std::nullopt;
  return std::make_pair(lo, hi);
}

bool Hull::contains(const Eigen::Vector3d& p) const {
  const auto range = z_range(p.x(), p.y());
  return range && p.z() >= range->first && p.z() <= range->second;
}

Hull convex_hull(const std::vector<Eigen::Vector3d>& points) {
  Hull hull;
  if (points.size() < 4) return hull;
  // A cloud that spans no volume (one wall, one line) has no interior: check the smallest
  // principal extent before asking CGAL for a 3-D hull.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= double(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : points) covariance += (p - mean) * (p - mean).transpose();
  covariance /= double(points.size());
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues()[0] < 1e-10) return hull;

  std::vector<K::Point_3> cgal_points;
  cgal_points.reserve(points.size());
  for (const auto& p : points) cgal_points.emplace_back(p.x(), p.y(), p.z());
  CGAL::Surface_mesh<K::Point_3> mesh;
  CGAL::convex_hull_3(cgal_points.begin(), cgal_points.end(), mesh);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    hull.vertices.emplace_back(p.x(), p.y(), p.z());
    centroid += hull.vertices.back();
    hull.bounds_m.extend(hull.vertices.back());
  }
  centroid /= double(mesh.number_of_vertices());
  for (const auto f : mesh.faces()) {
    std::vector<Eigen::Vector3d> corner;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      const auto& p = mesh.point(v);
      corner.emplace_back(p.x(), p.y(), p.z());
    }
    Eigen::Vector3d n = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
    if (n.norm() < 1e-15) continue;
    n.normalize();
    double d = -n.dot(corner[0]);
    if (n.dot(centroid) + d > 0) {  // make the normal point outwards
      n = -n;
      d = -d;
    }
    hull.planes.emplace_back(n.x(), n.y(), n.z(), d);
  }
  return hull;
}

struct VoidSet::State {
  std::vector<map::VoxelKey> cells;  ///< in key order
  std::unordered_set<std::uint64_t> occupied;  ///< the cells the hull is built from
  std::unordered_set<std::uint64_t> vertices;  ///< occupied cells on the hull
  Hull hull;
  std::optional<Eigen::AlignedBox3d> hull_box_m;  ///< only occupied cells in it count
};

VoidSet::VoidSet() : state_(std::make_unique<State>()) {}
VoidSet::~VoidSet() = default;
VoidSet::VoidSet(VoidSet&&) noexcept = default;
VoidSet& VoidSet::operator=(VoidSet&&) noexcept = default;

const Hull& VoidSet::hull() const { return state_->hull; }
std::size_t VoidSet::size() const { return state_->cells.size(); }
bool VoidSet::contains(const map::VoxelKey& key) const {
  return std::binary_search(state_->cells.begin(), state_->cells.end(), key);
}

namespace {

/// The hull of the cells `keys` (occupied cell centres), and which of them are its vertices.
Hull hull_of(const map::OccupancyMap& map, const std::vector<std::uint64_t>& keys,
             std::unordered_set<std::uint64_t>& vertices) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(keys.size());
  for (const std::uint64_t p : keys) points.push_back(map.center_of(unpack(p)));
  Hull hull = convex_hull(points);
  vertices.clear();
  for (const Eigen::Vector3d& v : hull.vertices) vertices.insert(pack(*map.key_of(v)));
  return hull;
}

/// Cell indices (key − 32768) whose centres (k + 0.5)·R lie in [lo, hi].
std::pair<int, int> cell_range(double lo, double hi, double R) {
  return {int(std::ceil(lo / R - 0.5)), int(std::floor(hi / R - 0.5))};
}

/// The unknown cells inside `now` but not `before` (`added`) and the cells inside `before`
/// but not `now` (`removed`), column by column, each in key order.
void rescan(const map::OccupancyMap& map, const Hull& before, const Hull& now, std::vector<map::VoxelKey>& added,
            std::vector<map::VoxelKey>& removed) {
  Eigen::AlignedBox3d box = now.bounds_m;
  if (!before.empty()) box.extend(before.bounds_m);
  if (box.isEmpty()) return;
  const double R = map.resolution_m();
  const auto [x0, x1] = cell_range(box.min().x(), box.max().x(), R);
  const auto [y0, y1] = cell_range(box.min().y(), box.max().y(), R);
  map::StateReader read(map);  // up a column, each look-up near the last
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double cx = (x + 0.5) * R, cy = (y + 0.5) * R;
      const auto r_now = now.z_range(cx, cy), r_before = before.z_range(cx, cy);
      std::pair<int, int> in_now{1, 0}, in_before{1, 0};
      if (r_now) in_now = cell_range(r_now->first, r_now->second, R);
      if (r_before) in_before = cell_range(r_before->first, r_before->second, R);
      auto key = [&](int z) {
        return map::VoxelKey{std::uint16_t(x + 32768), std::uint16_t(y + 32768), std::uint16_t(z + 32768)};
      };
      for (int z = in_now.first; z <= in_now.second; ++z) {
        if (z >= in_before.first && z <= in_before.second) continue;
        if (read(key(z)) == map::VoxelState::Unknown) added.push_back(key(z));
      }
      for (int z = in_before.first; z <= in_before.second; ++z)
        if (z < in_now.first || z > in_now.second) removed.push_back(key(z));
    }
  }
  map::sort_keys(added);
  map::sort_keys(removed);
}

/// (cells ∪ added) \ removed, all three in key order.
std::vector<map::VoxelKey> merge(const std::vector<map::VoxelKey>& cells, const std::vector<map::VoxelKey>& added,
                                 const std::vector<map::VoxelKey>& removed) {
  std::vector<map::VoxelKey> both, out;
  if (!added.empty()) {
    both.reserve(cells.size() + added.size());
    std::set_union(cells.begin(), cells.end(), added.begin(), added.end(), std::back_inserter(both));
  }
  const std::vector<map::VoxelKey>& all = added.empty() ? cells : both;
  out.reserve(all.size());
  std::set_difference(all.begin(), all.end(), removed.begin(), removed.end(), std::back_inserter(out));
  return out;
}

/// Per column (x, y) of the grid, the centres of its lowest and highest occupied cells (in
/// `box_m` when given).
std::vector<Eigen::Vector3d> column_extremes(const map::DenseGrid& grid, const std::optional<Eigen::AlignedBox3d>& box_m) {
  const Eigen::Vector3i n = grid.size();
  const std::size_t columns = std::size_t(n.x()) * std::size_t(n.y());
  std::vector<int> low(columns, -1), high(columns, -1);
  std::size_t i = 0;
  for (int z = 0; z < n.z(); ++z)
    for (std::size_t c = 0; c < columns; ++c, ++i)
      if (grid.state_at(i) == map::VoxelState::Occupied &&
          (!box_m || box_m->contains(grid.center_of(grid.key(i))))) {
        if (low[c] < 0) low[c] = z;
        high[c] = z;
      }
  std::vector<Eigen::Vector3d> points;
  for (std::size_t c = 0; c < columns; ++c) {
    if (low[c] < 0) continue;
    for (const int z : {low[c], high[c]}) {
      points.push_back(grid.center_of(grid.key(std::size_t(z) * columns + c)));
      if (low[c] == high[c]) break;
    }
  }
  return points;
}

/// column_extremes of a grid over every known cell of `map`, from its occupied leaves: each
/// leaf's lowest and highest cell per column (in `box_m` when given), sorted by (y, x, z), so
/// that each column's first and last are its extremes and the columns come in grid order.
std::vector<Eigen::Vector3d> column_extremes(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& box_m) {
  std::vector<std::uint64_t> ends;  // y << 32 | x << 16 | z
  for (const map::Leaf& leaf : map.leaves()) {
    if (leaf.state != map::VoxelState::Occupied) continue;
    const std::uint32_t n = leaf.size_cells;
    for (std::uint32_t y = 0; y < n; ++y)
      for (std::uint32_t x = 0; x < n; ++x) {
        const std::uint64_t column = std::uint64_t(leaf.min_key.y + y) << 32 | std::uint64_t(leaf.min_key.x + x) << 16;
        std::int64_t low = -1, high = -1;
        for (std::uint32_t z = 0; z < n; ++z) {
          const map::VoxelKey k{std::uint16_t(leaf.min_key.x + x), std::uint16_t(leaf.min_key.y + y),
                                std::uint16_t(leaf.min_key.z + z)};
          if (box_m && !box_m->contains(map.center_of(k))) continue;
          if (low < 0) low = k.z;
          high = k.z;
        }
        if (low < 0) continue;
        ends.push_back(column | std::uint64_t(low));
        if (high != low) ends.push_back(column | std::uint64_t(high));
      }
  }
  std::sort(ends.begin(), ends.end());
  std::vector<Eigen::Vector3d> points;
  auto center = [&](std::uint64_t e) {
    return map.center_of({std::uint16_t(e >> 16 & 0xFFFF), std::uint16_t(e >> 32), std::uint16_t(e & 0xFFFF)});
  };
  for (std::size_t i = 0; i < ends.size();) {
    std::size_t j = i;
    while (j + 1 < ends.size() && ends[j + 1] >> 16 == ends[i] >> 16) ++j;
    points.push_back(center(ends[i]));
    if (ends[j] != ends[i]) points.push_back(center(ends[j]));
    i = j + 1;
  }
  return points;
}

}  // namespace

std::vector<map::VoxelKey> void_cells(const map::DenseGrid& grid, Hull& hull,
                                      const std::optional<Eigen::AlignedBox3d>& hull_box_m) {
  hull = convex_hull(column_extremes(grid, hull_box_m));
  return void_cells_in(grid, hull);
}

Hull hull_of_map(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& hull_box_m) {
  return convex_hull(column_extremes(map, hull_box_m));
}

std::vector<map::VoxelKey> void_cells_in(const map::DenseGrid& grid, const Hull& hull) {
  if (hull.empty()) return {};
  const core::LargeVector<std::uint8_t> inside = inside_hull(grid, hull);
  std::vector<map::VoxelKey> out;
  for (std::size_t i = 0; i < inside.size(); ++i)
    if (inside[i] && grid.state_at(i) == map::VoxelState::Unknown) out.push_back(grid.key(i));
  return out;
}

core::LargeVector<std::uint8_t> inside_hull(const map::DenseGrid& grid, const Hull& hull) {
  core::LargeVector<std::uint8_t> inside(grid.cell_count(), 0);
  if (hull.empty()) return inside;
  const Eigen::Vector3i n = grid.size();
  const int lo[3] = {grid.min_key().x - 32768, grid.min_key().y - 32768, grid.min_key().z - 32768};
  const double R = grid.resolution_m();
  const auto [x0, x1] = cell_range(hull.bounds_m.min().x(), hull.bounds_m.max().x(), R);
  const auto [y0, y1] = cell_range(hull.bounds_m.min().y(), hull.bounds_m.max().y(), R);
  for (int y = std::max(y0, lo[1]); y <= std::min(y1, lo[1] + n.y() - 1); ++y)
    for (int x = std::max(x0, lo[0]); x <= std::min(x1, lo[0] + n.x() - 1); ++x) {
      const auto range = hull.z_range((x + 0.5) * R, (y + 0.5) * R);
      if (!range) continue;
      const auto [z0, z1] = cell_range(range->first, range->second, R);
      // The hull lies within the occupied cells' box, inside the grid; clamp all the same.
      for (int z = std::max(z0, lo[2]); z <= std::min(z1, lo[2] + n.z() - 1); ++z) {
        const std::size_t i = (std::size_t(z - lo[2]) * std::size_t(n.y()) + std::size_t(y - lo[1])) * std::size_t(n.x()) +
                              std::size_t(x - lo[0]);
        inside[i] = 1;
      }
    }
  return inside;
}

void VoidSet::rebuild(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& hull_box_m) {
  State& s = *state_;
  s = State{};
  s.hull_box_m = hull_box_m;
  for (const map::Leaf& leaf : map.leaves()) {
    if (leaf.state != map::VoxelState::Occupied) continue;
    for (std::uint32_t z = 0; z < leaf.size_cells; ++z)
      for (std::uint32_t y = 0; y < leaf.size_cells; ++y)
        for (std::uint32_t x = 0; x < leaf.size_cells; ++x) {
          const map::VoxelKey k{std::uint16_t(leaf.min_key.x + x), std::uint16_t(leaf.min_key.y + y),
                                std::uint16_t(leaf.min_key.z + z)};
          if (!hull_box_m || hull_box_m->contains(map.center_of(k))) s.occupied.insert(pack(k));
        }
  }
  s.hull = hull_of(map, std::vector<std::uint64_t>(s.occupied.begin(), s.occupied.end()), s.vertices);
  std::vector<map::VoxelKey> removed;
  rescan(map, Hull{}, s.hull, s.cells, removed);
}

void VoidSet::update(const map::OccupancyMap& map, const std::vector<map::Change>& changes) {
  State& s = *state_;
  std::vector<std::uint64_t> outside;  // new occupied cells beyond the hull
  std::vector<map::VoxelKey> known;    // cells now known: no longer void
  bool vertex_lost = false;
  for (const map::Change& c : changes) {
    const std::uint64_t p = pack(c.key);
    if (c.after != map::VoxelState::Unknown) known.push_back(c.key);
    if (s.hull_box_m && !s.hull_box_m->contains(map.center_of(c.key))) continue;  // not a hull cell
    if (c.after == map::VoxelState::Occupied && c.before != map::VoxelState::Occupied) {
      s.occupied.insert(p);
      if (!s.hull.contains(map.center_of(c.key))) outside.push_back(p);
    } else if (c.before == map::VoxelState::Occupied && c.after != map::VoxelState::Occupied) {
      s.occupied.erase(p);
      vertex_lost |= s.vertices.count(p) != 0;  // a vertex left: the hull may shrink
    }
  }
  // integrate()'s change sets are in key order; a change set made otherwise need not be.
  if (!std::is_sorted(known.begin(), known.end())) map::sort_keys(known);
  if (outside.empty() && !vertex_lost) {
    s.cells = merge(s.cells, {}, known);
    return;
  }
  const Hull before = s.hull;
  if (vertex_lost) {
    s.hull = hull_of(map, std::vector<std::uint64_t>(s.occupied.begin(), s.occupied.end()), s.vertices);
  } else {
    // Growth only: the hull of the old vertices and the new outside points is the hull of all.
    outside.insert(outside.end(), s.vertices.begin(), s.vertices.end());
    s.hull = hull_of(map, outside, s.vertices);
  }
  // A cell the scan made known is never added again (rescan adds only unknown cells).
  std::vector<map::VoxelKey> added, removed;
  rescan(map, before, s.hull, added, removed);
  std::vector<map::VoxelKey> gone;
  std::set_union(known.begin(), known.end(), removed.begin(), removed.end(), std::back_inserter(gone));
  s.cells = merge(s.cells, added, gone);
}

std::vector<map::VoxelKey> VoidSet::cells(const map::OccupancyMap& map,
                                          const std::optional<Eigen::AlignedBox3d>& bounds_m) const {
  return bounds_m ? map::keys_within(map, state_->cells, *bounds_m) : state_->cells;
}

}  // namespace fvx::voids
