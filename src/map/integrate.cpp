// OccupancyMap::integrate — OctoMap's insertPointCloud (exact, or discretised), with the
// change set. Rays follow OctoMap's own arithmetic (ray_keys.hpp), so maps agree bit for bit
// with maps OctoMap builds from the same points. What differs is the bookkeeping: a scan's
// rays visit ~10⁷ cells but only ~10⁵–10⁶ distinct ones, and a bit per cell deduplicates
// them where OctoMap's std::unordered_set spends most of insertPointCloud's time.
#include <algorithm>
#include <cmath>
#include <thread>

#include "key_bitmap.hpp"
#include "ray_keys.hpp"
#include "ray_lanes.hpp"
#include "tree.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::map {
namespace {

struct RayEnd {
  octomap::point3d end;
  bool endpoint_hit;  // false when the ray was cut at max range
  bool in_map;        // the end has a key
};

/// Marks the cells of the rays `t`, `t + threads`, … of `ends` in `cells`: eight or four
/// rays in step where the CPU can (ray_lanes.hpp; 4 096 started rays at a time, so the
/// columns stay in the cache), else one after the other.
void mark_rays(const Tree& tree, const octomap::point3d& origin, const std::vector<RayEnd>& ends, unsigned t,
               unsigned threads, DenseKeyBitmap& cells) {
  const auto index_of = [&](const octomap::OcTreeKey& k) { return std::int64_t(cells.index(k)); };
  // DenseKeyBitmap::set through a pointer held here: marking through the bitmap, the walk's
  // profile showed two loads per cell to reach its words.
  std::uint64_t* const words = cells.words();
  const auto mark = [words](std::int64_t i) { words[std::uint64_t(i) >> 6] |= std::uint64_t(1) << (i & 63); };
  const int lanes = ray_lanes();
  if (lanes == 1) {
    for (std::size_t i = t; i < ends.size(); i += threads)
      if (ends[i].in_map) mark_ray_cells(tree, origin, ends[i].end, cells.strides(), index_of, mark);
    return;
  }
  const auto walk = lanes == 8 ? mark_rays_in_lanes : mark_rays_in_four_lanes;
  constexpr std::size_t kBatch = 4096;
  MarkedRays batch;
  for (std::size_t i = t; i < ends.size(); i += threads) {
    MarkedRay ray;
    bool empty = false;
    if (!ends[i].in_map || !start_marked_ray(tree, origin, ends[i].end, cells.strides(), index_of, ray, empty) ||
        empty)
      continue;
    mark(ray.index);
    batch.push(ray);
    if (batch.size() == kBatch) {
      walk(batch, words);
      batch.clear();
    }
  }
  walk(batch, words);
}

/// Marks the cells of every traceable ray in a flat bitmap, on `threads` threads, each with
/// its own bitmap; their union does not depend on the split, so results are deterministic.
DenseKeyBitmap trace_free_cells(const Tree& tree, const octomap::point3d& origin,
                                const std::vector<RayEnd>& ends, const std::array<int, 3>& key_min,
                                const std::array<int, 3>& key_max, unsigned threads) {
  std::vector<DenseKeyBitmap> cells(threads, DenseKeyBitmap(key_min, key_max));
  auto work = [&](unsigned t) { mark_rays(tree, origin, ends, t, threads, cells[t]); };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();
  for (unsigned t = 1; t < threads; ++t) cells[0].merge(cells[t]);
  return std::move(cells[0]);
}

/// The same for boxes too large for a flat bitmap: one thread, sparse blocks.
KeyBitmap trace_free_cells_sparse(const Tree& tree, const octomap::point3d& origin,
                                  const std::vector<RayEnd>& ends, const std::array<int, 3>& key_min,
                                  const std::array<int, 3>& key_max) {
  KeyBitmap cells(key_min, key_max);
  for (const RayEnd& r : ends)
    if (r.in_map) for_each_ray_key(tree, origin, r.end, [&](const octomap::OcTreeKey& k) { cells.insert(k); });
  return cells;
}

/// Marks the endpoints (occupied), then updates the tree once per distinct cell: occupied
/// wins over free within one scan.
template <typename Bitmap>
void update_tree(Tree& tree, const Bitmap& free_cells, const std::vector<RayEnd>& ends,
                 const std::array<int, 3>& key_min, const std::array<int, 3>& key_max,
                 Integration& result) {
  Bitmap occupied_cells(key_min, key_max);
  octomap::OcTreeKey key;
  for (const RayEnd& r : ends)
    // As OctoMap: the endpoint is marked even when the origin is outside the key space.
    if (r.endpoint_hit && r.in_map && tree.coordToKeyChecked(r.end, key)) occupied_cells.insert(key);

  Tree::UpdatePath last;  // one pass: nothing else changes the tree until it ends
  auto update = [&](const octomap::OcTreeKey& k, bool hit) {
    float log_odds_before = 0.0f;
    const auto [node_before, node_after] = tree.update_cell(k, hit, log_odds_before, last);
    const VoxelState before = node_before ? state_of_log_odds(tree, log_odds_before) : VoxelState::Unknown;
    const VoxelState after = state_of(tree, node_after);
    if (before != after) result.changes.push_back({to_voxel_key(k), before, after});
  };
  free_cells.for_each([&](const octomap::OcTreeKey& k) {
    if (occupied_cells.contains(k)) return;
    ++result.free_updates;
    update(k, false);
  });
  const auto free_end = std::ptrdiff_t(result.changes.size());
  occupied_cells.for_each([&](const octomap::OcTreeKey& k) {
    ++result.occupied_updates;
    update(k, true);
  });
  // A flat bitmap yields keys in (z, y, x) order already: merge its two runs. Sparse blocks
  // come in insertion order and are sorted.
  auto by_key = [](const Change& a, const Change& b) { return a.key < b.key; };
  auto middle = result.changes.begin() + free_end;
  if (std::is_sorted(result.changes.begin(), middle, by_key) &&
      std::is_sorted(middle, result.changes.end(), by_key))
    std::inplace_merge(result.changes.begin(), middle, result.changes.end(), by_key);
  else
    std::sort(result.changes.begin(), result.changes.end(), by_key);
}

/// The distinct keys of `packed` (x | y << 16 | z << 32), in any order: by a bitmap over their
/// box when it has at most 64 cells per key (its scan then costs a word per key at most), else
/// by sorting.
void deduplicate(std::vector<std::uint64_t>& packed) {
  std::array<int, 3> lo{0xFFFF, 0xFFFF, 0xFFFF}, hi{0, 0, 0};
  for (const std::uint64_t k : packed)
    for (int i = 0; i < 3; ++i) {
      lo[std::size_t(i)] = std::min(lo[std::size_t(i)], int((k >> (16 * i)) & 0xFFFF));
      hi[std::size_t(i)] = std::max(hi[std::size_t(i)], int((k >> (16 * i)) & 0xFFFF));
    }
  if (packed.empty() || DenseKeyBitmap::bits_for(lo, hi) > 64 * std::uint64_t(packed.size())) {
    std::sort(packed.begin(), packed.end());
    packed.erase(std::unique(packed.begin(), packed.end()), packed.end());
    return;
  }
  DenseKeyBitmap cells(lo, hi);
  for (const std::uint64_t k : packed)
    cells.insert(octomap::OcTreeKey(std::uint16_t(k), std::uint16_t(k >> 16), std::uint16_t(k >> 32)));
  packed.clear();
  cells.for_each([&](const octomap::OcTreeKey& k) {
    packed.push_back(std::uint64_t(k[0]) | std::uint64_t(k[1]) << 16 | std::uint64_t(k[2]) << 32);
  });
}

/// OctoMap's computeDiscreteUpdate: each distinct cell of the points once, at its centre
/// (keyToCoord, as OctoMap computes it). The order of the centres does not matter: a scan's
/// update is the same for any order of its rays. Keys are deduplicated without a hash set
/// (deduplicate). Non-finite points and points outside the key space are kept as they are
/// (integrate counts them as out of the map).
std::vector<Eigen::Vector3f> discretized(const Tree& tree, const std::vector<Eigen::Vector3f>& points_world) {
  std::vector<std::uint64_t> packed;
  std::vector<Eigen::Vector3f> out;
  packed.reserve(points_world.size());
  octomap::OcTreeKey key;
  for (const auto& p : points_world) {
    if (p.allFinite() && tree.coordToKeyChecked(octomap::point3d(p.x(), p.y(), p.z()), key))
      packed.push_back(std::uint64_t(key[0]) | std::uint64_t(key[1]) << 16 | std::uint64_t(key[2]) << 32);
    else
      out.push_back(p);
  }
  deduplicate(packed);
  for (const std::uint64_t k : packed) {
    const octomap::point3d c = tree.keyToCoord(octomap::OcTreeKey(std::uint16_t(k), std::uint16_t(k >> 16),
                                                                  std::uint16_t(k >> 32)));
    out.emplace_back(c.x(), c.y(), c.z());
  }
  return out;
}

}  // namespace

Integration OccupancyMap::integrate(const std::vector<Eigen::Vector3f>& points_in,
                                    const Eigen::Vector3f& origin_world, double max_range_m, bool discretize) {
  FVX_ASSERT(max_range_m > 0.0, "max range " + std::to_string(max_range_m));
  auto& tree = impl_->tree;
  const std::vector<Eigen::Vector3f> centres = discretize ? discretized(tree, points_in) : std::vector<Eigen::Vector3f>();
  const std::vector<Eigen::Vector3f>& points_world = discretize ? centres : points_in;
  Integration result;
  result.points = points_world.size();
  const bool limited = std::isfinite(max_range_m);
  const octomap::point3d origin(origin_world.x(), origin_world.y(), origin_world.z());

  // Ray ends (cut at max range exactly as OctoMap's computeUpdate does) and their key box.
  std::vector<RayEnd> ends;
  ends.reserve(points_world.size());
  std::array<int, 3> key_min{0xFFFF, 0xFFFF, 0xFFFF}, key_max{0, 0, 0};
  auto extend = [&](const octomap::OcTreeKey& k) {
    for (int i = 0; i < 3; ++i) {
      key_min[i] = std::min(key_min[i], int(k[i]));
      key_max[i] = std::max(key_max[i], int(k[i]));
    }
  };
  octomap::OcTreeKey key;
  const bool origin_in_map = tree.coordToKeyChecked(origin, key);
  if (origin_in_map) extend(key);
  for (const auto& p : points_world) {
    if (!p.allFinite()) {
      ++result.points_out_of_map;
      continue;
    }
    const octomap::point3d pt(p.x(), p.y(), p.z());
    if (!limited || (pt - origin).norm() <= max_range_m) {
      ends.push_back({pt, true, false});
    } else {
      const octomap::point3d direction = (pt - origin).normalized();
      ends.push_back({origin + direction * float(max_range_m), false, false});
      ++result.points_beyond_range;
    }
    ends.back().in_map = tree.coordToKeyChecked(ends.back().end, key);
    if (ends.back().in_map) extend(key);
  }
  if (key_min[0] > key_max[0]) {  // nothing inside the key space
    result.points_out_of_map = result.points;
    return result;
  }
  // DDA rounding can step one cell past the ends' box; two cells of margin keep it inside.
  for (int i = 0; i < 3; ++i) {
    key_min[i] = std::max(0, key_min[i] - 2);
    key_max[i] = std::min(0xFFFF, key_max[i] + 2);
  }

  for (const RayEnd& r : ends) result.points_out_of_map += !(origin_in_map && r.in_map);
  const std::vector<RayEnd> no_rays;
  const std::vector<RayEnd>& rays = origin_in_map ? ends : no_rays;  // no free space without an origin
  const std::uint64_t bits = DenseKeyBitmap::bits_for(key_min, key_max);
  if (bits <= DenseKeyBitmap::kMaxBits) {
    // Threads pay off from ~10⁴ rays; each needs its own bitmap, so large boxes use fewer.
    const unsigned threads = ends.size() < 10000 || bits > (std::uint64_t(1) << 28) ? 1u : core::worker_count(0, 8);
    update_tree(tree, trace_free_cells(tree, origin, rays, key_min, key_max, threads), ends, key_min,
                key_max, result);
  } else {
    update_tree(tree, trace_free_cells_sparse(tree, origin, rays, key_min, key_max), ends, key_min,
                key_max, result);
  }
  return result;
}

}  // namespace fvx::map
