#include "fvx/frontiers/frontiers.hpp"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "fvx/map/key_index.hpp"

namespace fvx::frontiers {
namespace {

constexpr int kFaces[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

/// The neighbour of `k` one cell along (dx, dy, dz), or empty at the edge of the key space.
std::optional<map::VoxelKey> neighbour(const map::VoxelKey& k, int dx, int dy, int dz) {
  const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
  if (x < 0 || y < 0 || z < 0 || x > 0xFFFF || y > 0xFFFF || z > 0xFFFF) return std::nullopt;
  return map::VoxelKey{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
}

bool has_unknown_face_neighbour(const map::OccupancyMap& map, const map::VoxelKey& key) {
  for (const auto& d : kFaces) {
    const auto n = neighbour(key, d[0], d[1], d[2]);
    if (n && map.state(*n) == map::VoxelState::Unknown) return true;
  }
  return false;
}

}  // namespace

bool is_frontier(const map::OccupancyMap& map, const map::VoxelKey& key) {
  return map.state(key) == map::VoxelState::Free && has_unknown_face_neighbour(map, key);
}

std::vector<map::VoxelKey> frontier_cells(const map::DenseGrid& grid) {
  const Eigen::Vector3i n = grid.size();
  const int lo[3] = {grid.min_key().x, grid.min_key().y, grid.min_key().z};
  const std::ptrdiff_t stride[3] = {1, n.x(), std::ptrdiff_t(n.x()) * n.y()};
  // A face-neighbour beyond the grid is unknown, unless it is beyond the key space too.
  auto unknown = [&](std::size_t i, const int (&c)[3], int a, int step) {
    const int m = c[a] + step;
    if (m < 0 || m >= n[a]) return lo[a] + m >= 0 && lo[a] + m <= 0xFFFF;
    return grid.state_at(std::size_t(std::ptrdiff_t(i) + step * stride[a])) == map::VoxelState::Unknown;
  };
  std::vector<map::VoxelKey> out;
  std::size_t i = 0;  // index order is key order (z, then y, then x)
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x, ++i) {
        if (grid.state_at(i) != map::VoxelState::Free) continue;
        const int c[3] = {x, y, z};
        bool frontier = false;
        for (int a = 0; a < 3 && !frontier; ++a) frontier = unknown(i, c, a, -1) || unknown(i, c, a, +1);
        if (frontier) out.push_back(grid.key(i));
      }
  return out;
}

void FrontierSet::rebuild(const map::OccupancyMap& map) {
  cells_.clear();
  for (const map::Leaf& leaf : map.leaves()) {
    if (leaf.state != map::VoxelState::Free) continue;
    const int n = int(leaf.size_cells);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const bool surface = x == 0 || y == 0 || z == 0 || x == n - 1 || y == n - 1 || z == n - 1;
          if (!surface) {  // jump over the interior of this row
            x = n - 2;
            continue;
          }
          const map::VoxelKey key{std::uint16_t(leaf.min_key.x + x), std::uint16_t(leaf.min_key.y + y),
                                  std::uint16_t(leaf.min_key.z + z)};
          if (has_unknown_face_neighbour(map, key)) cells_.insert(pack(key));
        }
  }
}

void FrontierSet::update(const map::OccupancyMap& map, const std::vector<map::Change>& changes) {
  std::unordered_set<std::uint64_t> candidates;
  candidates.reserve(changes.size() * 4);
  for (const map::Change& c : changes) {
    candidates.insert(pack(c.key));
    for (const auto& d : kFaces)
      if (const auto n = neighbour(c.key, d[0], d[1], d[2])) candidates.insert(pack(*n));
  }
  for (const std::uint64_t p : candidates) {
    if (is_frontier(map, unpack(p)))
      cells_.insert(p);
    else
      cells_.erase(p);
  }
}

std::vector<map::VoxelKey> FrontierSet::cells(const map::OccupancyMap& map,
                                              const std::optional<Eigen::AlignedBox3d>& bounds_m) const {
  std::vector<map::VoxelKey> out;
  out.reserve(cells_.size());
  for (const std::uint64_t p : cells_) {
    const map::VoxelKey k = unpack(p);
    if (!bounds_m || bounds_m->contains(map.center_of(k))) out.push_back(k);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Cluster> cluster(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells) {
  // Union-find over the cells' indices; neighbours are found through a key → index table.
  const map::KeyIndex index(cells.size(), [&](auto&& visit) {
    for (std::size_t i = 0; i < cells.size(); ++i) visit(pack(cells[i]), std::uint32_t(i));
  });
  std::vector<std::size_t> parent(cells.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t i = 0; i < cells.size(); ++i) {
    // The 13 neighbours after the cell in key order: each pair of neighbours is joined once.
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dz == 0 && (dy < 0 || (dy == 0 && dx <= 0))) continue;
          const auto n = neighbour(cells[i], dx, dy, dz);
          if (!n) continue;
          const std::uint32_t j = index.find(pack(*n));
          if (j == map::KeyIndex::kMissing) continue;
          const std::size_t a = find(i), b = find(j);
          if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the smallest index
        }
  }
  // Cells are in key order and every root is its cluster's smallest index, so numbering roots
  // in index order numbers clusters by their smallest key.
  std::vector<int> id_of_root(cells.size(), -1);
  std::vector<Cluster> clusters;
  const double R = map.resolution_m();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t root = find(i);
    if (id_of_root[root] < 0) {
      id_of_root[root] = int(clusters.size());
      clusters.emplace_back();
      clusters.back().id = id_of_root[root];
    }
    Cluster& c = clusters[std::size_t(id_of_root[root])];
    const Eigen::Vector3d center = map.center_of(cells[i]);
    c.cells.push_back(cells[i]);
    c.centroid_m += center;
    c.bounds_m.extend(center - Eigen::Vector3d::Constant(R / 2));
    c.bounds_m.extend(center + Eigen::Vector3d::Constant(R / 2));
  }
  for (Cluster& c : clusters) c.centroid_m /= double(c.cells.size());
  return clusters;
}

}  // namespace fvx::frontiers
