#include "fvx/map/dense_grid.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include "fvx/core/error.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::map {

DenseGrid::DenseGrid(const OccupancyMap& map, const Eigen::AlignedBox3d& bounds_m) : resolution_m_(map.resolution_m()), inverse_resolution_(1.0 / map.resolution_m()) {
  const double R = resolution_m_;
  if (bounds_m.isEmpty() || !bounds_m.min().allFinite() || !bounds_m.max().allFinite()) return;  // an empty grid
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {  // cells whose centres (k + 0.5)·R lie in the bounds, clamped to the key space
    lo[a] = int(std::max(0.0, std::ceil(bounds_m.min()[a] / R - 0.5) + 32768));
    hi[a] = int(std::min(65535.0, std::floor(bounds_m.max()[a] / R - 0.5) + 32768));
    if (hi[a] < lo[a]) return;  // an empty grid
  }
  min_ = {std::uint16_t(lo[0]), std::uint16_t(lo[1]), std::uint16_t(lo[2])};
  size_ = Eigen::Vector3i(hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1);
  FVX_ASSERT(double(size_.x()) * size_.y() * size_.z() < 4e9, "dense grid too large");
  states_.assign(std::size_t(size_.x()) * size_.y() * size_.z(), std::uint8_t(VoxelState::Unknown));
  const VoxelKey hi_key{std::uint16_t(hi[0]), std::uint16_t(hi[1]), std::uint16_t(hi[2])};
  for (const Leaf& leaf : map.leaves(min_, hi_key)) {
    int from[3], to[3];
    const int k0[3] = {leaf.min_key.x, leaf.min_key.y, leaf.min_key.z};
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      from[a] = std::max(k0[a], lo[a]);
      to[a] = std::min(k0[a] + int(leaf.size_cells) - 1, hi[a]);
      empty |= to[a] < from[a];
    }
    if (empty) continue;
    for (int z = from[2]; z <= to[2]; ++z)
      for (int y = from[1]; y <= to[1]; ++y) {
        const std::size_t row = index({std::uint16_t(from[0]), std::uint16_t(y), std::uint16_t(z)});
        std::fill(states_.begin() + std::ptrdiff_t(row), states_.begin() + std::ptrdiff_t(row) + (to[0] - from[0] + 1),
                  std::uint8_t(leaf.state));
      }
  }
}

namespace {

/// One pass of the 1-D squared distance transform (lower envelope of parabolas): f holds
/// the input along a line, d receives min_q (p − q)² + f(q).
void distance_1d(const std::vector<float>& f, std::vector<float>& d, std::vector<int>& v, std::vector<float>& z) {
  const int n = int(f.size());
  int k = 0;
  int first = 0;
  while (first < n && std::isinf(f[std::size_t(first)])) ++first;
  if (first == n) {  // nothing along this line
    std::fill(d.begin(), d.end(), INFINITY);
    return;
  }
  v[0] = first;
  z[0] = -INFINITY;
  z[1] = INFINITY;
  for (int q = first + 1; q < n; ++q) {
    if (std::isinf(f[std::size_t(q)])) continue;
    float s;
    while (true) {
      const int p = v[std::size_t(k)];
      s = ((f[std::size_t(q)] + float(q) * float(q)) - (f[std::size_t(p)] + float(p) * float(p))) / (2.0f * float(q - p));
      if (s <= z[std::size_t(k)] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[std::size_t(k)] = q;
    z[std::size_t(k)] = s;
    z[std::size_t(k) + 1] = INFINITY;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[std::size_t(k) + 1] < float(q)) ++k;
    const int p = v[std::size_t(k)];
    d[std::size_t(q)] = float(q - p) * float(q - p) + f[std::size_t(p)];
  }
}

/// A squared distance above `max_sq` as +infinity: it can only grow in later passes.
float capped(float d_sq, float max_sq) { return d_sq > max_sq ? INFINITY : d_sq; }

/// Runs part(from, to) over [0, count) split into at most `threads` parts, the first here.
template <typename Part>
void in_parts(int count, unsigned threads, Part& part) {
  const int parts = int(std::min<unsigned>(threads, unsigned(std::max(1, count))));
  std::vector<std::thread> pool;
  for (int t = 1; t < parts; ++t) pool.emplace_back(part, count * t / parts, count * (t + 1) / parts);
  part(0, count / parts);
  for (auto& t : pool) t.join();
}

/// Lines along x run in `threads` parts of the y range, one line at a time (each line is
/// contiguous).
void transform_x(core::LargeVector<float>& dist, const Eigen::Vector3i& n, unsigned threads, float max_sq) {
  auto lines = [&](int y_from, int y_to) {
    std::vector<float> f(static_cast<std::size_t>(n.x())), d(f.size()), z(f.size() + 1);
    std::vector<int> v(f.size());
    for (int zc = 0; zc < n.z(); ++zc)
      for (int y = y_from; y < y_to; ++y) {
        float* line = dist.data() + (std::size_t(zc) * std::size_t(n.y()) + std::size_t(y)) * std::size_t(n.x());
        std::copy(line, line + n.x(), f.begin());
        distance_1d(f, d, v, z);
        for (int i = 0; i < n.x(); ++i) line[i] = capped(d[std::size_t(i)], max_sq);
      }
  };
  in_parts(n.y(), threads, lines);
}

/// Lines along y (axis 1) or z (axis 2), kTile neighbouring x at a time: a row of the tile
/// is one read of contiguous memory, where one line at a time read a cache line per cell.
/// The parts split the third axis. Each line's transform is the one of transform_x.
void transform_tiled(core::LargeVector<float>& dist, const Eigen::Vector3i& n, int axis, unsigned threads,
                     float max_sq) {
  constexpr int kTile = 16;
  const int other = 3 - axis;  // the axis that is neither x nor `axis`
  const std::size_t stride[3] = {1, std::size_t(n.x()), std::size_t(n.x()) * std::size_t(n.y())};
  const int len = n[axis];
  auto tiles = [&](int o_from, int o_to) {
    std::vector<float> tile(std::size_t(len) * kTile), f(static_cast<std::size_t>(len)), d(f.size()), z(f.size() + 1);
    std::vector<int> v(f.size());
    for (int o = o_from; o < o_to; ++o)
      for (int x0 = 0; x0 < n.x(); x0 += kTile) {
        const int width = std::min(kTile, n.x() - x0);
        float* base = dist.data() + std::size_t(o) * stride[other] + std::size_t(x0);
        for (int i = 0; i < len; ++i)
          std::copy_n(base + std::size_t(i) * stride[axis], width, &tile[std::size_t(i) * kTile]);
        for (int w = 0; w < width; ++w) {
          for (int i = 0; i < len; ++i) f[std::size_t(i)] = tile[std::size_t(i) * kTile + std::size_t(w)];
          distance_1d(f, d, v, z);
          for (int i = 0; i < len; ++i)
            tile[std::size_t(i) * kTile + std::size_t(w)] = capped(d[std::size_t(i)], max_sq);
        }
        for (int i = 0; i < len; ++i)
          std::copy_n(&tile[std::size_t(i) * kTile], width, base + std::size_t(i) * stride[axis]);
      }
  };
  in_parts(n[other], threads, tiles);
}

}  // namespace

core::LargeVector<float> squared_distance_to(const DenseGrid& grid, VoxelState state, unsigned threads, float max_sq) {
  const Eigen::Vector3i n = grid.size();
  core::LargeVector<float> dist(grid.cell_count());
  for (std::size_t i = 0; i < dist.size(); ++i) dist[i] = grid.state_at(i) == state ? 0.0f : INFINITY;
  threads = core::worker_count(threads);
  if (dist.empty()) return dist;
  transform_x(dist, n, threads, max_sq);
  transform_tiled(dist, n, 1, threads, max_sq);
  transform_tiled(dist, n, 2, threads, max_sq);
  return dist;
}

}  // namespace fvx::map
