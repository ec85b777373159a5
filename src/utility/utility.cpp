#include "fvx/utility/utility.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>

#include "fvx/core/error.hpp"
#include "fvx/core/ray_box.hpp"
#include "fvx/core/threads.hpp"

namespace fvx::utility {

const char* to_string(Accumulation a) { return a == Accumulation::Exact ? "exact" : "sampled"; }

Accumulation parse_accumulation(const std::string& name, const std::string& what) {
  if (name == "exact") return Accumulation::Exact;
  if (name == "sampled") return Accumulation::Sampled;
  throw UsageError(what + " '" + name + "': expected exact or sampled");
}

std::vector<std::string> Config::validate() const {
  std::vector<std::string> problems;
  if (!(sensor_range_m > 0.0) || !std::isfinite(sensor_range_m)) problems.push_back("sensor_range_m must be > 0 m");
  if (!(min_range_m >= 0.0) || !(min_range_m < sensor_range_m))
    problems.push_back("min_range_m must be >= 0 m and below sensor_range_m");
  if (max_vectors < 7) problems.push_back("max_vectors must be >= 7 (one frontier cell's corners)");
  return problems;
}

namespace {

/// The field being accumulated, shared by the threads: utility in cells (u_i / R³ in fixed
/// point, an integer, so that sums do not depend on the order of addition or the number of
/// threads) and, per cell, its kContributors largest contributors (Field::contributors),
/// ordered by rank in `order`. Both are the same whatever order frontier-voids arrive in.
/// A thread adds to the cells of one stripe (Contributors::stripe) at a time under that
/// stripe's lock: with one lock for the whole field, the adds (a quarter of the work on the
/// paper replicas) ran one thread at a time.
struct Shared {
  /// The integer sums, each held in the bytes of the double the field reports (read and
  /// written through memcpy), so that the field takes no second grid-sized array: on a
  /// 17 M-cell grid that is 136 MB of fresh pages less.
  core::LargeVector<double> util_cells;
  Contributors contributors;
  std::vector<std::uint32_t> rank;  ///< per frontier-void: its place in `order`
  std::array<std::mutex, Contributors::kStripes> stripe_locks;
};

/// One thread's scratch for the frontier-void it is tracing: how often its rays passed each
/// cell, and the cells passed, each once. Written to Shared once per frontier-void, not at
/// every cell a ray passes (most passes repeat a cell). The count is a byte per cell that
/// spills 255 passes at a time into `wrapped`: a cell rarely sees that many passes from
/// one frontier-void, and a byte keeps the scratch in the core's cache (a 4-byte count took
/// 1.5 MB per thread on the paper replicas, more than the 1 MB L2 of the machines measured).
struct Worker {
  core::LargeVector<std::uint8_t> passes;  ///< per grid cell, modulo 256
  std::vector<std::size_t> wrapped;        ///< a cell per 255 passes its byte spilled
  std::vector<std::size_t> touched;
  std::size_t vectors = 0;
  std::size_t first_stripe = 0;  ///< where this thread's flushes start, so threads start apart
  /// `touched` and `wrapped` sorted by stripe (counting sort), and where each stripe starts.
  std::vector<std::size_t> by_stripe;
  std::array<std::size_t, Contributors::kStripes + 1> touched_at{}, wrapped_at{};
};

/// Orders `cells` by stripe into `out` (appended); `at[s]` is where stripe s begins in `out`.
void sort_by_stripe(const std::vector<std::size_t>& cells, std::vector<std::size_t>& out,
                    std::array<std::size_t, Contributors::kStripes + 1>& at) {
  at.fill(0);
  for (const std::size_t c : cells) ++at[Contributors::stripe(c) + 1];
  at[0] = out.size();
  for (std::size_t s = 1; s <= Contributors::kStripes; ++s) at[s] += at[s - 1];
  out.resize(at[Contributors::kStripes]);
  std::array<std::size_t, Contributors::kStripes> next;
  std::copy(at.begin(), at.end() - 1, next.begin());
  for (const std::size_t c : cells) out[next[Contributors::stripe(c)]++] = c;
}

/// Adds to `sum` (a cell's fixed-point sum, held in a double's bytes) `add`.
void add_to(double& cell, std::uint64_t add) {
  std::uint64_t sum;
  std::memcpy(&sum, &cell, sizeof sum);
  sum += add;
  std::memcpy(&cell, &sum, sizeof sum);
}

/// Adds the cells of `w`'s frontier-void `fv` in one stripe to the shared field.
void flush_stripe(Worker& w, std::size_t stripe, std::uint64_t weight, std::int32_t fv, Shared& shared) {
  const std::uint32_t rank = shared.rank[std::size_t(fv)];
  for (std::size_t j = w.wrapped_at[stripe]; j < w.wrapped_at[stripe + 1]; ++j)  // integer sums: any order
    add_to(shared.util_cells[w.by_stripe[j]], weight * 255);
  for (std::size_t j = w.touched_at[stripe]; j < w.touched_at[stripe + 1]; ++j) {
    const std::size_t index = w.by_stripe[j];
    add_to(shared.util_cells[index], weight * w.passes[index]);
    w.passes[index] = 0;
    // Frontier-voids arrive about in rank order: most cells already hold four better ones.
    const std::int32_t last = shared.contributors[index].back();
    if (last >= 0 && shared.rank[std::size_t(last)] < rank) continue;
    auto& slots = shared.contributors.make(index);
    std::int32_t carry = fv;  // insert by rank, dropping the last
    for (auto& slot : slots) {
      if (slot >= 0 && shared.rank[std::size_t(slot)] < rank) continue;
      std::swap(slot, carry);
      if (carry < 0) break;
    }
  }
}

/// Adds frontier-void `fv` (its vectors weighing `weight` each) to the shared field at the
/// cells `w` passed, stripe by stripe, and clears `w` for the next one.
void flush(Worker& w, std::uint64_t weight, std::int32_t fv, Shared& shared) {
  w.by_stripe.clear();
  sort_by_stripe(w.touched, w.by_stripe, w.touched_at);
  sort_by_stripe(w.wrapped, w.by_stripe, w.wrapped_at);
  for (std::size_t k = 0; k < Contributors::kStripes; ++k) {
    const std::size_t stripe = (w.first_stripe + k) % Contributors::kStripes;
    if (w.touched_at[stripe] == w.touched_at[stripe + 1] && w.wrapped_at[stripe] == w.wrapped_at[stripe + 1]) continue;
    const std::lock_guard<std::mutex> lock(shared.stripe_locks[stripe]);
    flush_stripe(w, stripe, weight, fv, shared);
  }
  w.touched.clear();
  w.wrapped.clear();
}

/// Interleaves the bits of a key (x lowest): cells close in this order are close in space.
std::uint64_t morton(const map::VoxelKey& k) {
  std::uint64_t code = 0;
  for (int b = 0; b < 16; ++b)
    code |= (std::uint64_t(k.x >> b & 1) << (3 * b)) | (std::uint64_t(k.y >> b & 1) << (3 * b + 1)) |
            (std::uint64_t(k.z >> b & 1) << (3 * b + 2));
  return code;
}

/// Per frontier cluster, its cells inside the grid in Morton order: contiguous strata of
/// this order are compact patches of the frontier surface.
std::vector<std::vector<map::VoxelKey>> starts_per_cluster(const map::DenseGrid& grid,
                                                           const frontier_voids::Analysis& a) {
  std::vector<std::vector<map::VoxelKey>> out(a.frontier_clusters.size());
  for (std::size_t c = 0; c < out.size(); ++c) {
    std::vector<std::pair<std::uint64_t, map::VoxelKey>> coded;
    for (const map::VoxelKey& k : a.frontier_clusters[c].cells)
      if (grid.contains(k)) coded.emplace_back(morton(k), k);
    std::sort(coded.begin(), coded.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
    for (const auto& [code, k] : coded) out[c].push_back(k);
  }
  return out;
}

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Fixed point of the per-cell sums: a vector adds weight·2^kFraction, an integer, so that
/// sums do not depend on the order of addition or the number of threads. Exact vectors
/// weigh u_i/R³ cells, an integer, and lose nothing.
constexpr int kFraction = 8;

/// What one frontier-void traces: S of its N frontier cells, each vector weighing
/// u_i·N/S (in cells, fixed point).
struct Plan {
  std::size_t samples = 0;   ///< S
  std::uint64_t weight = 0;  ///< fixed point
};

/// The frontier cells of fv_index's clusters that the plan draws: one per stratum of
/// `starts` (concatenated in frontier_ids order), at a seeded place within it.
std::vector<map::VoxelKey> draw(const std::vector<const std::vector<map::VoxelKey>*>& lists, std::size_t n,
                                std::size_t samples, std::uint64_t seed, std::int32_t fv_index) {
  std::vector<map::VoxelKey> out;
  out.reserve(samples);
  auto at = [&](std::size_t i) -> const map::VoxelKey& {
    for (const auto* l : lists) {
      if (i < l->size()) return (*l)[i];
      i -= l->size();
    }
    FVX_ASSERT(false, "stratum index beyond the frontier cells");
    return lists.front()->front();
  };
  if (samples >= n) {
    for (const auto* l : lists) out.insert(out.end(), l->begin(), l->end());
    return out;
  }
  std::uint64_t state = seed ^ (std::uint64_t(fv_index) + 1) * 0xD1B54A32D192ED03ull;
  for (std::size_t j = 0; j < samples; ++j) {
    const std::size_t lo = j * n / samples, hi = (j + 1) * n / samples;  // hi > lo as n > samples
    const std::size_t pick = lo + std::size_t((splitmix64(state) >> 11) * 0x1.0p-53 * double(hi - lo));
    out.push_back(at(std::min(pick, hi - 1)));
  }
  return out;
}

/// One pass of the frontier-void's rays through cell `index`.
void count_pass(Worker& w, std::size_t index) {
  const std::uint8_t before = w.passes[index]++;
  if (before == 0) w.touched.push_back(index);
  if (before == 0xFF) {  // 255 passes to `wrapped`; the byte holds this one (never 0: touched once)
    w.wrapped.push_back(index);
    w.passes[index] = 1;
  }
}

/// Whether a ray from `start` along `dir` moves away from `box` (or along its side) on an
/// axis where `start` lies outside it: then ray_box_exit is −1, and it takes no root and no
/// division to know (its slab on that axis lies behind the start, or is never entered).
bool moves_away_from(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& start, const Eigen::Vector3d& dir) {
  for (int a = 0; a < 3; ++a)
    if ((start[a] < box.min()[a] && dir[a] <= 0.0) || (start[a] > box.max()[a] && dir[a] >= 0.0)) return true;
  return false;
}

/// Algorithm 1 for one frontier-void: every corner, from each of `starts`; counts passes in `w`.
/// `read_box`: Config::read_box_m grown by one cell (any point of a cell whose centre lies in
/// the box is within half a cell's diagonal of it), or none.
void trace_frontier_void(const map::DenseGrid& grid, const frontier_voids::Analysis& a, std::int32_t fv_index,
                         const std::vector<map::VoxelKey>& starts, const Config& config,
                         const std::optional<Eigen::AlignedBox3d>& read_box, Worker& w) {
  const auto& fv = a.frontier_voids[std::size_t(fv_index)];
  const auto corners = a.void_clusters[std::size_t(fv.void_id)].corners();
  const double min_range_m = config.min_range_m;
  for (const map::VoxelKey& f : starts) {
    const Eigen::Vector3d start = grid.center_of(f);
    const bool inside = !read_box || read_box->contains(start);
    for (const Eigen::Vector3d& c : corners) {
      const Eigen::Vector3d dir = start - c;
      const double squared = dir.squaredNorm();
      if (squared < 1e-16 && std::sqrt(squared) < 1e-9) continue;  // a corner in the frontier cell: no direction
      ++w.vectors;
      if (!inside && moves_away_from(*read_box, start, dir)) continue;  // no cell it passes is read
      const Eigen::Vector3d d = dir / std::sqrt(squared);  // = dir.normalized(), for the box test and the walk
      const double range_m = read_box ? ray_box_exit(*read_box, start, d, config.sensor_range_m)
                                      : config.sensor_range_m;
      if (range_m < 0.0) continue;  // no cell it passes is read
      bool far_enough = min_range_m <= 0.0;  // cells along a ray only get farther
      grid.walk_unit(grid.states(), f, start, d, range_m, [&](std::size_t index, std::uint8_t s) {
        if (map::VoxelState(s) != map::VoxelState::Free) return false;
        if (!far_enough) {
          far_enough = (grid.center_of(grid.key(index)) - start).squaredNorm() >= min_range_m * min_range_m;
          if (!far_enough) return true;
        }
        count_pass(w, index);
        return true;
      });
    }
  }
}

/// Samples per frontier-void for a budget of `cells` frontier cells in all (7 vectors
/// each), in proportion to u_i·N_i, none above its N_i, none below kMinSamples: water-
/// filling, so that what a small frontier-void cannot use goes to the others.
std::vector<std::size_t> shares(const std::vector<double>& mass, const std::vector<std::size_t>& n, double cells) {
  std::vector<std::size_t> s(n.size(), 0);
  std::vector<bool> fixed(n.size(), false);
  for (bool changed = true; changed;) {
    changed = false;
    double free_mass = 0, free_cells = cells;
    for (std::size_t i = 0; i < n.size(); ++i) (fixed[i] ? free_cells -= double(s[i]) : free_mass += mass[i]);
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (fixed[i]) continue;
      const double share = free_mass > 0 ? std::max(0.0, free_cells) * mass[i] / free_mass : 0.0;
      s[i] = std::clamp<std::size_t>(std::size_t(std::ceil(share)), std::min(n[i], kMinSamples), n[i]);
      if (s[i] == n[i] || s[i] == std::min(n[i], kMinSamples)) {  // bounded: settle it, redistribute the rest
        fixed[i] = true;
        changed = true;
      }
    }
  }
  return s;
}

/// How many frontier cells each frontier-void in `order` traces from, and at what weight.
std::vector<Plan> plan(const frontier_voids::Analysis& a, const std::vector<std::int32_t>& order,
                       const std::vector<std::size_t>& n, double R, const Config& config, std::size_t& exact) {
  exact = 0;
  std::vector<double> mass(order.size());  // u_i·N_i: the frontier-void's share of the exact field
  for (std::size_t i = 0; i < order.size(); ++i) {
    exact += 7 * n[i];
    mass[i] = a.frontier_voids[std::size_t(order[i])].utility_m3 * double(n[i]);
  }
  const bool all = config.accumulation == Accumulation::Exact || exact <= config.max_vectors;
  const std::vector<std::size_t> samples = all ? n : shares(mass, n, double(config.max_vectors) / 7.0);
  std::vector<Plan> plans(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto u_cells = std::uint64_t(std::llround(a.frontier_voids[std::size_t(order[i])].utility_m3 / (R * R * R)));
    plans[i].samples = samples[i];
    plans[i].weight = samples[i] == 0 ? 0
                                      : std::uint64_t(std::llround(double(u_cells) * double(n[i]) /
                                                                   double(samples[i]) * double(1u << kFraction)));
  }
  return plans;
}

/// Runs work(worker, report) on each worker, the first on the calling thread (the one that
/// reports progress); an exception in any thread is rethrown here.
template <typename Work>
void run_threads(std::vector<Worker>& workers, Work& work) {
  std::vector<std::exception_ptr> errors(workers.size());
  auto guarded = [&](std::size_t t) {
    try {
      work(workers[t], t == 0);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers.size(); ++t) pool.emplace_back(guarded, t);
  guarded(0);
  for (auto& t : pool) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// The shared sums in m³, and each cell's contributors.
Field to_field(Shared& shared, double R, const std::vector<Plan>& plans, const std::vector<std::size_t>& frontier_cells,
               std::size_t exact_vectors, const std::vector<Worker>& workers) {
  Field field;
  const double cell_m3 = R * R * R / double(1u << kFraction);
  for (const Worker& w : workers) field.vectors += w.vectors;
  field.exact_vectors = exact_vectors;
  for (std::size_t i = 0; i < plans.size(); ++i) field.sampled |= plans[i].samples < frontier_cells[i];
  field.util_m3 = std::move(shared.util_cells);
  for (double& value : field.util_m3) {
    std::uint64_t sum;
    std::memcpy(&sum, &value, sizeof sum);
    value = double(sum) * cell_m3;
    field.cells += sum > 0;
    field.max_m3 = std::max(field.max_m3, value);
  }
  field.contributors = std::move(shared.contributors);
  return field;
}

}  // namespace

Field accumulate(const map::DenseGrid& grid, const frontier_voids::Analysis& a, const Config& config) {
  throw_if_problems("utility", config.validate());
  // Largest utility first (ties: lower index): a thread that takes frontier-voids in this
  // order meets a cell's largest contributors first, and the merge keeps this order.
  std::vector<std::int32_t> order;
  for (std::size_t i = 0; i < a.frontier_voids.size(); ++i)
    if (!a.frontier_voids[i].enclosed() && a.frontier_voids[i].utility_m3 > 0) order.push_back(std::int32_t(i));
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t l, std::int32_t r) {
    return a.frontier_voids[std::size_t(l)].utility_m3 > a.frontier_voids[std::size_t(r)].utility_m3;
  });

  const double R = grid.resolution_m();
  const auto starts = starts_per_cluster(grid, a);
  std::vector<std::size_t> frontier_cells(order.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i)
    for (const int id : a.frontier_voids[std::size_t(order[i])].frontier_ids) frontier_cells[i] += starts[std::size_t(id)].size();
  std::size_t exact_vectors = 0;
  const std::vector<Plan> plans = plan(a, order, frontier_cells, R, config, exact_vectors);

  const unsigned threads = core::worker_count(config.threads, order.size());
  Shared shared;
  shared.util_cells.assign(grid.cell_count(), 0.0);  // all bits zero: the sum 0
  shared.contributors = Contributors(grid.cell_count());
  shared.rank.assign(a.frontier_voids.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i) shared.rank[std::size_t(order[i])] = std::uint32_t(i);
  std::optional<Eigen::AlignedBox3d> read_box;
  if (config.read_box_m) {
    const Eigen::Vector3d cell = Eigen::Vector3d::Constant(R);
    read_box = Eigen::AlignedBox3d(config.read_box_m->min() - cell, config.read_box_m->max() + cell);
  }
  std::vector<Worker> workers(threads);
  for (std::size_t t = 0; t < threads; ++t) workers[t].first_stripe = t * Contributors::kStripes / threads;
  std::atomic<std::size_t> next{0};
  auto work = [&](Worker& w, bool report) {
    w.passes.assign(grid.cell_count(), 0);
    for (std::size_t i = next++; i < order.size(); i = next++) {
      if (report && config.progress) config.progress(i, order.size());
      std::vector<const std::vector<map::VoxelKey>*> lists;
      for (const int id : a.frontier_voids[std::size_t(order[i])].frontier_ids) lists.push_back(&starts[std::size_t(id)]);
      const auto drawn = draw(lists, frontier_cells[i], plans[i].samples, config.seed, order[i]);
      trace_frontier_void(grid, a, order[i], drawn, config, read_box, w);
      flush(w, plans[i].weight, order[i], shared);
    }
  };
  run_threads(workers, work);
  return to_field(shared, R, plans, frontier_cells, exact_vectors, workers);
}

}  // namespace fvx::utility
