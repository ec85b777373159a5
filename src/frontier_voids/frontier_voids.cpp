#include "fvx/frontier_voids/frontier_voids.hpp"

#include <algorithm>
#include <cstdlib>
#include <future>

#include "fvx/core/memory.hpp"
#include "fvx/map/key_index.hpp"

#include "fvx/voids/width.hpp"

namespace fvx::frontier_voids {

std::vector<FrontierVoid> pair_frontier_voids(const std::vector<voids::VoidCluster>& voids,
                                              const std::vector<frontiers::Cluster>& frontier_clusters) {
  // From the frontier side: a real map has ten times more void cells than frontier cells.
  std::size_t void_cells = 0;
  for (const auto& v : voids) void_cells += v.cells.size();
  const map::KeyIndex void_of(void_cells, [&](auto&& visit) {
    for (const auto& v : voids)
      for (const auto& k : v.cells) visit(map::pack(k), std::uint32_t(v.id));
  });
  std::vector<FrontierVoid> out(voids.size());
  for (const auto& v : voids) {
    out[std::size_t(v.id)].void_id = v.id;
    out[std::size_t(v.id)].utility_m3 = v.volume_m3;
  }
  for (const auto& c : frontier_clusters)
    for (const auto& k : c.cells)
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int moved = std::abs(dx) + std::abs(dy) + std::abs(dz);
            if (moved == 0 || moved == 3) continue;  // faces and edges, not corners
            const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
            if (x < 0 || y < 0 || z < 0 || x > 0xFFFF || y > 0xFFFF || z > 0xFFFF) continue;
            const std::uint32_t id = void_of.find(map::pack({std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)}));
            if (id == map::KeyIndex::kMissing) continue;
            std::vector<int>& ids = out[id].frontier_ids;
            if (ids.empty() || ids.back() != c.id) ids.push_back(c.id);  // clusters come in id order
          }
  return out;
}

namespace {

/// The one-shot path's dense grid takes about 10 bytes per cell of the known box (states,
/// marks, column extremes); above this many cells the sets are used instead.
constexpr std::size_t kMaxDenseCells = std::size_t(1) << 28;

/// S (default: the box of the known cells) and the warnings that say why a result is empty.
Analysis start(const map::Stats& stats, const std::optional<Eigen::AlignedBox3d>& bounds_m, bool with_voids,
               bool hull_empty) {
  Analysis a;
  if (bounds_m) {
    a.bounds_m = *bounds_m;
  } else if (!stats.empty) {
    a.bounds_m = Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m);
  }
  if (stats.empty) a.warnings.push_back("the map is empty: no frontiers and no voids");
  else if (stats.free_leaves == 0) a.warnings.push_back("the map has no free cells: no frontiers");
  if (with_voids && !stats.empty && stats.occupied_leaves == 0)
    a.warnings.push_back("the map has no occupied cells: no hull, no voids");
  else if (with_voids && !stats.empty && hull_empty)
    a.warnings.push_back("the occupied cells span no volume (fewer than four, or flat): no hull, no voids");
  if (bounds_m && !stats.empty && !bounds_m->intersects(Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m)))
    a.warnings.push_back("the search space holds no known cell");
  return a;
}

/// The box of the one-shot path's grid: the known cells' box, within S grown by two cells
/// when S is given (a cell in S has its face-neighbours in the grid, or they lie beyond the
/// known cells and are unknown), so that a small S on a large map reads a small grid.
Eigen::AlignedBox3d grid_box(const Eigen::AlignedBox3d& known, const std::optional<Eigen::AlignedBox3d>& bounds_m,
                             double R) {
  if (!bounds_m || known.isEmpty()) return known;
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(2 * R);
  const Eigen::AlignedBox3d around(bounds_m->min() - margin, bounds_m->max() + margin);
  return around.contains(known) ? known : around.intersection(known);
}

/// Peak bytes per cell of the box the one-shot analysis reads, a search over it included:
/// `fvx nbv` took 39–40 B per cell on maps whose voids fill 42 % and 100 % of the box, and
/// `fvx frontiers` 9 B (README, "Maps larger than the machine"); rounded up, so that a run
/// refused would not have fitted.
constexpr double kPeakBytesPerCell = 48, kPeakBytesPerCellFrontiers = 12;

/// The box of the occupied cells (each leaf whole), which holds their hull and every void.
Eigen::AlignedBox3d occupied_box_m(const map::OccupancyMap& map) {
  Eigen::AlignedBox3d box;
  const double R = map.resolution_m();
  for (const map::Leaf& leaf : map.leaves())
    if (leaf.state == map::VoxelState::Occupied) {
      const Eigen::Vector3d lo = map.center_of(leaf.min_key) - Eigen::Vector3d::Constant(R / 2);
      box.extend(lo).extend(lo + Eigen::Vector3d::Constant(R * leaf.size_cells));
    }
  return box;
}

/// Stops before the analysis allocates when `box_m` (what it reads) would need more memory
/// than the machine has available: a map of a building at a fine resolution, searched whole.
void check_memory(const Eigen::AlignedBox3d& box_m, double R, double bytes_per_cell) {
  core::require_memory_for_box(box_m, R, bytes_per_cell, "the search space",
                               "give --bounds x0,y0,z0,x1,y1,z1 to search part of the map");
}

/// Clusters and pairs the frontier and void cells already in `a`.
void cluster_and_pair(const map::OccupancyMap& map, Analysis& a, bool with_voids, const voids::ClusterConfig& config,
                      int min_void_width_cells) {
  // Neither clustering reads the other's cells: the frontier clusters are found on another
  // core while the voids are clustered here (each result as on one core).
  std::future<std::vector<frontiers::Cluster>> frontier_clusters =
      std::async(std::launch::async, [&] { return frontiers::cluster(map, a.frontier_cells); });
  if (with_voids) {
    if (min_void_width_cells > 1) {
      const std::size_t all = a.void_cells.size();
      a.void_cells = voids::cells_in_full_cubes(a.void_cells, min_void_width_cells);
      a.thin_void_cells = all - a.void_cells.size();
    }
    a.void_clusters = voids::cluster_voids(map, a.void_cells, config);
  }
  a.frontier_clusters = frontier_clusters.get();
  if (with_voids) a.frontier_voids = pair_frontier_voids(a.void_clusters, a.frontier_clusters);
}

}  // namespace

Analysis analyse(const map::OccupancyMap& map, const frontiers::FrontierSet& frontier_set,
                 const voids::VoidSet* void_set, const std::optional<Eigen::AlignedBox3d>& bounds_m,
                 const voids::ClusterConfig& config, int min_void_width_cells) {
  Analysis a = start(map.stats(), bounds_m, void_set != nullptr, void_set && void_set->hull().empty());
  a.frontier_cells = frontier_set.cells(map, a.bounds_m);
  if (void_set) {
    a.void_cells = void_set->cells(map, a.bounds_m);
    a.hull_faces = void_set->hull().planes.size();
    a.hull = void_set->hull();
  }
  cluster_and_pair(map, a, void_set != nullptr, config, min_void_width_cells);
  return a;
}

Analysis analyse_map(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& bounds_m,
                     const voids::ClusterConfig& config, int min_void_width_cells, bool with_voids,
                     bool hull_in_bounds) {
  const std::optional<Eigen::AlignedBox3d> hull_box_m = hull_in_bounds ? bounds_m : std::nullopt;
  const map::Stats stats = map.stats();
  const Eigen::AlignedBox3d known = stats.empty ? Eigen::AlignedBox3d() : Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m);
  const Eigen::AlignedBox3d box = grid_box(known, bounds_m, map.resolution_m());
  if (!box.isEmpty() && (box.sizes() / map.resolution_m()).prod() > double(kMaxDenseCells)) {
    // A few cells far apart: the sets hold only them, and the voids lie between the occupied ones.
    if (with_voids)
      check_memory(occupied_box_m(map).intersection(bounds_m ? *bounds_m : box), map.resolution_m(), kPeakBytesPerCell);
    frontiers::FrontierSet frontier_set;
    frontier_set.rebuild(map);
    voids::VoidSet void_set;
    if (with_voids) void_set.rebuild(map, hull_box_m);
    return analyse(map, frontier_set, with_voids ? &void_set : nullptr, bounds_m, config, min_void_width_cells);
  }
  check_memory(box, map.resolution_m(), with_voids ? kPeakBytesPerCell : kPeakBytesPerCellFrontiers);
  const map::DenseGrid grid(map, box);
  std::future<std::vector<map::VoxelKey>> frontier_cells =  // on another core, beside the voids
      std::async(std::launch::async, [&] { return frontiers::frontier_cells(grid); });
  voids::Hull hull;
  std::vector<map::VoxelKey> void_cells;
  const bool whole = box.min() == known.min() && box.max() == known.max();
  if (with_voids && whole) {
    void_cells = voids::void_cells(grid, hull, hull_box_m);
  } else if (with_voids) {  // the grid holds part of the map: the hull comes from all of it
    hull = voids::hull_of_map(map, hull_box_m);
    void_cells = voids::void_cells_in(grid, hull);
  }
  Analysis a = start(stats, bounds_m, with_voids, hull.empty());
  a.frontier_cells = map::keys_within(map, frontier_cells.get(), a.bounds_m);
  a.void_cells = map::keys_within(map, std::move(void_cells), a.bounds_m);
  a.hull_faces = hull.planes.size();
  a.hull = std::move(hull);
  cluster_and_pair(map, a, with_voids, config, min_void_width_cells);
  return a;
}

}  // namespace fvx::frontier_voids
