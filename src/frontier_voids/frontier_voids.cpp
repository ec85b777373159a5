#include "fvx/frontier_voids/frontier_voids.hpp"

#include <algorithm>
#include <cstdlib>
#include <unordered_map>

namespace fvx::frontier_voids {

std::vector<FrontierVoid> pair_frontier_voids(const std::vector<voids::VoidCluster>& voids,
                                              const std::vector<frontiers::Cluster>& frontier_clusters) {
  std::unordered_map<std::uint64_t, int> frontier_of;
  for (const auto& c : frontier_clusters)
    for (const auto& k : c.cells) frontier_of.emplace(frontiers::pack(k), c.id);
  std::vector<FrontierVoid> out;
  out.reserve(voids.size());
  for (const auto& v : voids) {
    FrontierVoid fv;
    fv.void_id = v.id;
    fv.utility_m3 = v.volume_m3;
    for (const auto& k : v.cells)
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int moved = std::abs(dx) + std::abs(dy) + std::abs(dz);
            if (moved == 0 || moved == 3) continue;  // faces and edges, not corners
            const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
            if (x < 0 || y < 0 || z < 0 || x > 0xFFFF || y > 0xFFFF || z > 0xFFFF) continue;
            const auto it = frontier_of.find(
                frontiers::pack({std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)}));
            if (it != frontier_of.end()) fv.frontier_ids.push_back(it->second);
          }
    std::sort(fv.frontier_ids.begin(), fv.frontier_ids.end());
    fv.frontier_ids.erase(std::unique(fv.frontier_ids.begin(), fv.frontier_ids.end()), fv.frontier_ids.end());
    out.push_back(std::move(fv));
  }
  return out;
}

}  // namespace fvx::frontier_voids
