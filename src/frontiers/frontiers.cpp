#include "fvx/frontiers/frontiers.hpp"

#include <algorithm>
#include <numeric>

#include "fvx/core/error.hpp"
#include "fvx/map/sort_keys.hpp"

namespace fvx::frontiers {
namespace {

// Below, cells go as packed keys (map::pack: x | y << 16 | z << 32), whose numeric order is
// the key order (z, then y, then x).

/// The packed key of offset s of the cell packed as `c` (s = 0: the cell itself; 1-6: its
/// face-neighbours at +x, -x, +y, -y, +z, -z), or false at the edge of the key space. Adding
/// a constant to every key of a key-ordered list keeps it in key order.
inline bool shifted(std::uint64_t c, int s, std::uint64_t& out) {
  if (s == 0) return out = c, true;
  const int shift = 16 * ((s - 1) / 2);  // x, x, y, y, z, z
  const unsigned v = unsigned(c >> shift) & 0xFFFF;
  const bool up = s % 2 == 1;
  if (v == (up ? 0xFFFFu : 0u)) return false;
  out = up ? c + (std::uint64_t(1) << shift) : c - (std::uint64_t(1) << shift);
  return true;
}

/// `read`: OccupancyMap::state or a map::StateReader.
template <typename Read>
bool has_unknown_face_neighbour(Read& read, const map::VoxelKey& key) {
  std::uint64_t n;
  for (int s = 1; s < 7; ++s)
    if (shifted(pack(key), s, n) && read(unpack(n)) == map::VoxelState::Unknown) return true;
  return false;
}

/// The changed cells and their face neighbours, each once, in key order. The change set is
/// in key order, and so is each of its shifts by one face offset, so their union is one merge
/// of seven lists: sorting the 7·n keys instead took longer than integrating the scan itself
/// on a first Kinect frame (269 000 changes; bench_integrate's step).
std::vector<std::uint64_t> changed_and_neighbours(const std::vector<std::uint64_t>& changed) {
  constexpr std::uint64_t kEnd = ~std::uint64_t(0);  // above every packed key
  std::size_t at[7] = {};
  std::uint64_t head[7];
  const auto advance = [&](int s) {  // to the stream's next key inside the key space
    for (; at[s] < changed.size(); ++at[s])
      if (shifted(changed[at[s]], s, head[s])) return;
    head[s] = kEnd;
  };
  for (int s = 0; s < 7; ++s) advance(s);
  std::vector<std::uint64_t> out;
  out.reserve(changed.size() * 3);
  for (std::uint64_t m = *std::min_element(head, head + 7); m != kEnd; m = *std::min_element(head, head + 7)) {
    out.push_back(m);
    for (int s = 0; s < 7; ++s)
      if (head[s] == m) ++at[s], advance(s);
  }
  return out;
}

/// The map's state at the cells a key-ordered walk asks about: a changed cell's state is its
/// change's `after` (no octree look-up), any other cell's is read from the map. Inside the
/// volume a scan changed, a candidate and its neighbours are all changed cells, so most of
/// the update reads no octree (on a first Kinect frame the reads were most of its time).
class ChangedStates {
 public:
  ChangedStates(const std::vector<std::uint64_t>& changed, const std::vector<map::Change>& changes,
                map::StateReader& read)
      : changed_(changed), changes_(changes), read_(read) {}
  /// The state at the cell packed as `c`; cells asked in key order.
  map::VoxelState operator()(std::uint64_t c) {
    while (at_ < changed_.size() && changed_[at_] < c) ++at_;
    if (at_ < changed_.size() && changed_[at_] == c) return changes_[at_].after;
    return read_(unpack(c));
  }

 private:
  const std::vector<std::uint64_t>& changed_;
  const std::vector<map::Change>& changes_;
  map::StateReader& read_;
  std::size_t at_ = 0;
};

}  // namespace

bool is_frontier(const map::OccupancyMap& map, const map::VoxelKey& key) {
  auto read = [&](const map::VoxelKey& k) { return map.state(k); };
  return map.state(key) == map::VoxelState::Free && has_unknown_face_neighbour(read, key);
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
  map::StateReader read(map);
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
          if (has_unknown_face_neighbour(read, key)) cells_.push_back(key);
        }
  }
  map::sort_keys(cells_);  // leaves do not overlap: no key twice
}

void FrontierSet::update(const map::OccupancyMap& map, const std::vector<map::Change>& changes) {
  std::vector<std::uint64_t> changed(changes.size());
  for (std::size_t i = 0; i < changes.size(); ++i) changed[i] = pack(changes[i].key);
  FVX_ASSERT(std::is_sorted(changed.begin(), changed.end()), "FrontierSet::update: changes not in key order");
  // The candidates in key order: so are the cells at one offset from each, which one
  // ChangedStates per offset walks, and each octree look-up is near the one before it
  // (StateReader). Then one merge: a candidate's new status replaces its old one, every
  // other cell keeps its own.
  map::StateReader read(map);
  std::vector<ChangedStates> state(7, ChangedStates(changed, changes, read));
  std::vector<map::VoxelKey> merged;
  merged.reserve(cells_.size() + changes.size() / 2);
  auto old = cells_.begin();
  for (const std::uint64_t c : changed_and_neighbours(changed)) {
    const map::VoxelKey k = unpack(c);
    for (; old != cells_.end() && *old < k; ++old) merged.push_back(*old);
    if (old != cells_.end() && *old == k) ++old;
    if (state[0](c) != map::VoxelState::Free) continue;
    std::uint64_t n;
    for (int s = 1; s < 7; ++s)
      if (shifted(c, s, n) && state[std::size_t(s)](n) == map::VoxelState::Unknown) {
        merged.push_back(k);
        break;
      }
  }
  merged.insert(merged.end(), old, cells_.end());
  cells_ = std::move(merged);
}

bool FrontierSet::contains(const map::VoxelKey& key) const {
  return std::binary_search(cells_.begin(), cells_.end(), key);
}

std::vector<map::VoxelKey> FrontierSet::cells(const map::OccupancyMap& map,
                                              const std::optional<Eigen::AlignedBox3d>& bounds_m) const {
  return bounds_m ? map::keys_within(map, cells_, *bounds_m) : cells_;
}

namespace {

/// One row (z, y) of a key-ordered cell list: the cells at indices [begin, end), x ascending.
struct Row {
  int z = 0, y = 0;
  std::size_t begin = 0, end = 0;
  bool before(int z_other, int y_other) const { return z < z_other || (z == z_other && y < y_other); }
};

std::vector<Row> rows_of(const std::vector<map::VoxelKey>& cells) {
  std::vector<Row> rows;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (rows.empty() || rows.back().z != cells[i].z || rows.back().y != cells[i].y)
      rows.push_back({cells[i].z, cells[i].y, i, i});
    rows.back().end = i + 1;
  }
  return rows;
}

/// Union-find over cell indices; every root is the smallest index of its set.
struct Forest {
  std::vector<std::size_t> parent;
  explicit Forest(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(std::size_t i, std::size_t j) {
    const std::size_t a = find(i), b = find(j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// Joins each cell of row `a` with the cells of row `b` whose x lies within one of its own:
/// both rows are sorted by x, so one pass over each.
void join_rows(const std::vector<map::VoxelKey>& cells, const Row& a, const Row& b, Forest& forest) {
  std::size_t lo = b.begin;
  for (std::size_t i = a.begin; i < a.end; ++i) {
    const int x = cells[i].x;
    while (lo < b.end && int(cells[lo].x) + 1 < x) ++lo;
    for (std::size_t j = lo; j < b.end && int(cells[j].x) <= x + 1; ++j) forest.join(i, j);
  }
}

/// 26-connectivity over key-ordered cells, without a key look-up: each cell meets the 13
/// neighbours after it in key order in its own row (x + 1) and in the four rows after it,
/// (z, y + 1) and (z + 1, y − 1 … y + 1), which are found by walking the rows in order.
Forest connect(const std::vector<map::VoxelKey>& cells) {
  Forest forest(cells.size());
  const std::vector<Row> rows = rows_of(cells);
  constexpr int kNext[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};  // (dz, dy) of the rows after
  std::size_t next[4] = {0, 0, 0, 0};  // per offset: the first row not before its target
  for (const Row& row : rows) {
    for (std::size_t i = row.begin; i + 1 < row.end; ++i)
      if (cells[i + 1].x == cells[i].x + 1) forest.join(i, i + 1);
    for (int k = 0; k < 4; ++k) {
      const int z = row.z + kNext[k][0], y = row.y + kNext[k][1];
      while (next[k] < rows.size() && rows[next[k]].before(z, y)) ++next[k];
      if (next[k] < rows.size() && rows[next[k]].z == z && rows[next[k]].y == y)
        join_rows(cells, row, rows[next[k]], forest);
    }
  }
  return forest;
}

}  // namespace

std::vector<Cluster> cluster(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells) {
  Forest forest = connect(cells);
  // Cells are in key order and every root is its cluster's smallest index, so numbering roots
  // in index order numbers clusters by their smallest key.
  std::vector<int> id_of_root(cells.size(), -1);
  std::vector<Cluster> clusters;
  const double R = map.resolution_m();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t root = forest.find(i);
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
