#include "fvx/utility/utility.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <thread>

#include "fvx/core/error.hpp"

namespace fvx::utility {

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems;
  if (!(sensor_range_m > 0.0) || !std::isfinite(sensor_range_m)) problems.push_back("sensor_range_m must be > 0 m");
  if (!(min_range_m >= 0.0) || !(min_range_m < sensor_range_m))
    problems.push_back("min_range_m must be >= 0 m and below sensor_range_m");
  return problems;
}

namespace {

using Slots = std::array<std::int32_t, kContributors>;

/// One thread's share: utility in cells (u_i / R³, an integer, so that sums do not depend on
/// the order of addition or the number of threads) and contributors per grid cell.
struct Partial {
  std::vector<std::uint64_t> util_cells;
  std::vector<Slots> contributors;
  std::size_t vectors = 0;
  // The cells the current frontier-void reached, each once: its contributor entries are
  // written after its rays, not at every cell a ray passes (most passes repeat a cell).
  std::vector<std::uint64_t> touched_bits;  ///< one bit per cell (fits in cache, unlike an int per cell)
  std::vector<std::size_t> touched;
};

/// Algorithm 1 for one frontier-void: every corner, every frontier cell of its clusters.
void trace_frontier_void(const map::DenseGrid& grid, const frontier_voids::Analysis& a, std::int32_t fv_index,
                         double sensor_range_m, double min_range_m, Partial& out) {
  const auto& fv = a.frontier_voids[std::size_t(fv_index)];
  const double R = grid.resolution_m();
  const auto u = std::uint64_t(std::llround(fv.utility_m3 / (R * R * R)));
  const auto corners = a.void_clusters[std::size_t(fv.void_id)].corners();
  for (const int id : fv.frontier_ids) {
    for (const map::VoxelKey& f : a.frontier_clusters[std::size_t(id)].cells) {
      if (!grid.contains(f)) continue;
      const Eigen::Vector3d start = grid.center_of(f);
      for (const Eigen::Vector3d& c : corners) {
        const Eigen::Vector3d dir = start - c;
        if (dir.norm() < 1e-9) continue;  // a corner in the frontier cell: no direction
        ++out.vectors;
        bool far_enough = min_range_m <= 0.0;  // cells along a ray only get farther
        grid.walk(start, dir, sensor_range_m, [&](std::size_t index, map::VoxelState s) {
          if (s != map::VoxelState::Free) return false;
          if (!far_enough) {
            far_enough = (grid.center_of(grid.key(index)) - start).squaredNorm() >= min_range_m * min_range_m;
            if (!far_enough) return true;
          }
          out.util_cells[index] += u;
          std::uint64_t& word = out.touched_bits[index >> 6];
          const std::uint64_t bit = std::uint64_t(1) << (index & 63);
          if (!(word & bit)) {
            word |= bit;
            out.touched.push_back(index);
          }
          return true;
        });
      }
    }
  }
  // This thread takes frontier-voids in global order: append to each cell's first free slot.
  for (const std::size_t index : out.touched) {
    out.touched_bits[index >> 6] = 0;  // cleared for the next frontier-void
    for (auto& slot : out.contributors[index])
      if (slot < 0) {
        slot = fv_index;
        break;
      }
  }
  out.touched.clear();
}

}  // namespace

Field accumulate(const map::DenseGrid& grid, const frontier_voids::Analysis& a, const Config& config) {
  FVX_ASSERT(config.validate().empty(), "invalid utility::Config");
  // Largest utility first (ties: lower index): a thread that takes frontier-voids in this
  // order meets a cell's largest contributors first, and the merge keeps this order.
  std::vector<std::int32_t> order;
  for (std::size_t i = 0; i < a.frontier_voids.size(); ++i)
    if (!a.frontier_voids[i].enclosed() && a.frontier_voids[i].utility_m3 > 0) order.push_back(std::int32_t(i));
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t l, std::int32_t r) {
    return a.frontier_voids[std::size_t(l)].utility_m3 > a.frontier_voids[std::size_t(r)].utility_m3;
  });
  std::vector<std::size_t> rank(a.frontier_voids.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i) rank[std::size_t(order[i])] = i;

  Slots none;
  none.fill(-1);
  const unsigned threads = std::max(
      1u, std::min<unsigned>(config.threads ? config.threads : std::thread::hardware_concurrency(),
                             unsigned(std::max<std::size_t>(1, order.size()))));
  std::vector<Partial> parts(threads);
  std::atomic<std::size_t> next{0};
  auto work = [&](Partial& part, bool report) {
    part.util_cells.assign(grid.cell_count(), 0);
    part.contributors.assign(grid.cell_count(), none);
    part.touched_bits.assign(grid.cell_count() / 64 + 1, 0);
    for (std::size_t i = next++; i < order.size(); i = next++) {
      if (report && config.progress) config.progress(i, order.size());
      trace_frontier_void(grid, a, order[i], config.sensor_range_m, config.min_range_m, part);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, std::ref(parts[t]), false);
  work(parts[0], true);
  for (auto& t : pool) t.join();

  // Merge: sums of integers, and each cell's contributors from all threads in global order.
  Field field;
  Partial& total = parts[0];
  for (unsigned t = 1; t < threads; ++t) {
    const Partial& p = parts[t];
    total.vectors += p.vectors;
    for (std::size_t i = 0; i < total.util_cells.size(); ++i) {
      if (p.util_cells[i] == 0) continue;
      total.util_cells[i] += p.util_cells[i];
      // Both lists are in global order: merge them, dropping repeats, keep the first slots.
      const Slots& l = total.contributors[i];
      const Slots& r = p.contributors[i];
      Slots merged = none;
      std::size_t li = 0, ri = 0, n = 0;
      auto rank_of = [&](std::int32_t fv) { return fv < 0 ? std::numeric_limits<std::size_t>::max() : rank[std::size_t(fv)]; };
      while (n < std::size_t(kContributors)) {
        const std::int32_t a_fv = li < l.size() ? l[li] : -1, b_fv = ri < r.size() ? r[ri] : -1;
        if (a_fv < 0 && b_fv < 0) break;
        const bool take_left = rank_of(a_fv) <= rank_of(b_fv);
        const std::int32_t fv = take_left ? a_fv : b_fv;
        (take_left ? li : ri)++;
        if (a_fv == b_fv) ++ri;  // one frontier-void is never split between threads; safe anyway
        merged[n++] = fv;
      }
      total.contributors[i] = merged;
    }
  }
  const double R = grid.resolution_m(), cell_m3 = R * R * R;
  field.vectors = total.vectors;
  field.util_m3.resize(total.util_cells.size());
  for (std::size_t i = 0; i < total.util_cells.size(); ++i) {
    field.util_m3[i] = double(total.util_cells[i]) * cell_m3;
    field.cells += total.util_cells[i] > 0;
    field.max_m3 = std::max(field.max_m3, field.util_m3[i]);
  }
  field.contributors = std::move(total.contributors);
  return field;
}

}  // namespace fvx::utility
