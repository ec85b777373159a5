#include "fvx/frontier_voids/frontier_voids.hpp"

#include <algorithm>
#include <cstdlib>

#include "fvx/map/key_index.hpp"

#include "fvx/voids/width.hpp"

namespace fvx::frontier_voids {

std::vector<FrontierVoid> pair_frontier_voids(const std::vector<voids::VoidCluster>& voids,
                                              const std::vector<frontiers::Cluster>& frontier_clusters) {
  // From the frontier side: a real map has ten times more void cells than frontier cells.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  for (const auto& v : voids)
    for (const auto& k : v.cells) entries.emplace_back(frontiers::pack(k), std::uint32_t(v.id));
  const map::KeyIndex void_of(entries);
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
            const std::uint32_t id = void_of.find(frontiers::pack({std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)}));
            if (id == map::KeyIndex::kMissing) continue;
            std::vector<int>& ids = out[id].frontier_ids;
            if (ids.empty() || ids.back() != c.id) ids.push_back(c.id);  // clusters come in id order
          }
  return out;
}

Analysis analyse(const map::OccupancyMap& map, const frontiers::FrontierSet& frontier_set,
                 const voids::VoidSet* void_set, const std::optional<Eigen::AlignedBox3d>& bounds_m,
                 const voids::ClusterConfig& config, int min_void_width_cells) {
  Analysis a;
  const map::Stats stats = map.stats();
  if (bounds_m) {
    a.bounds_m = *bounds_m;
  } else if (!stats.empty) {
    a.bounds_m = Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m);
  }
  if (stats.empty) a.warnings.push_back("the map is empty: no frontiers and no voids");
  else if (stats.free_leaves == 0) a.warnings.push_back("the map has no free cells: no frontiers");
  if (void_set && !stats.empty && stats.occupied_leaves == 0)
    a.warnings.push_back("the map has no occupied cells: no hull, no voids");
  else if (void_set && !stats.empty && void_set->hull().empty())
    a.warnings.push_back("the occupied cells span no volume (fewer than four, or flat): no hull, no voids");
  if (bounds_m && !stats.empty && !bounds_m->intersects(Eigen::AlignedBox3d(stats.known_min_m, stats.known_max_m)))
    a.warnings.push_back("the search space holds no known cell");
  a.frontier_cells = frontier_set.cells(map, a.bounds_m);
  a.frontier_clusters = frontiers::cluster(map, a.frontier_cells);
  if (!void_set) return a;
  a.void_cells = void_set->cells(map, a.bounds_m);
  if (min_void_width_cells > 1) {
    const std::size_t all = a.void_cells.size();
    a.void_cells = voids::cells_in_full_cubes(a.void_cells, min_void_width_cells);
    a.thin_void_cells = all - a.void_cells.size();
  }
  a.void_clusters = voids::cluster_voids(map, a.void_cells, config);
  a.frontier_voids = pair_frontier_voids(a.void_clusters, a.frontier_clusters);
  return a;
}

}  // namespace fvx::frontier_voids
