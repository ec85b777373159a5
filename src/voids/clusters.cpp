#include "fvx/voids/clusters.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "fvx/core/error.hpp"
#include "fvx/map/key_index.hpp"

namespace fvx::voids {

std::vector<std::string> ClusterConfig::validate() const {
  std::vector<std::string> problems;
  if (!(min_fit_score > 0.0 && min_fit_score <= 1.0)) problems.push_back("min_fit_score must be in (0, 1]");
  return problems;
}

std::array<Eigen::Vector3d, 7> VoidCluster::corners() const {
  std::array<Eigen::Vector3d, 7> c;
  c[0] = mean_m;
  for (int j = 0; j < 3; ++j) {
    c[1 + 2 * j] = mean_m + semi_axes_m[j] * axes.col(j);
    c[2 + 2 * j] = mean_m - semi_axes_m[j] * axes.col(j);
  }
  return c;
}

namespace {

/// Running sums of a growing cluster, in a frame near it (for precision). The sums of
/// outer products are symmetric, so only their upper triangle is kept (xx, xy, xz, yy, yz,
/// zz): region growing computes a fit score for every neighbour it tries, and a full 3×3
/// outer product and matrix expression per try were a seventh of `fvx voids` on a real map.
/// The sums, the covariance and so its determinant are those of the full matrices, to the
/// bit: the same products and sums, in the same order.
struct Moments {
  Eigen::Vector3d origin;
  double n = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::array<double, 6> sum_outer{};

  void add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - origin;
    n += 1;
    sum += q;
    sum_outer[0] += q.x() * q.x();
    sum_outer[1] += q.y() * q.x();
    sum_outer[2] += q.z() * q.x();
    sum_outer[3] += q.y() * q.y();
    sum_outer[4] += q.z() * q.y();
    sum_outer[5] += q.z() * q.z();
  }
  /// Σ = Σ q qᵀ / n − mean meanᵀ + cell_variance·I, entry by entry as Eigen evaluates it.
  Eigen::Matrix3d covariance(double cell_variance) const {
    const Eigen::Vector3d mean = sum / n;
    auto at = [&](int upper, int i, int j) {  // off the diagonal cell_variance·0 adds +0.0
      return (sum_outer[std::size_t(upper)] / n - mean[j] * mean[i]) + (i == j ? cell_variance : 0.0);
    };
    const double xx = at(0, 0, 0), xy = at(1, 0, 1), xz = at(2, 0, 2), yy = at(3, 1, 1), yz = at(4, 1, 2), zz = at(5, 2, 2);
    Eigen::Matrix3d c;
    c << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return c;
  }
};

/// Eq. 2 with a_j = sqrt(5 λ_j): a1·a2·a3 = sqrt(125·det Σ).
double fit_score(const Moments& m, double R) {
  const double det = m.covariance(R * R / 12.0).determinant();
  const double abc = std::sqrt(125.0 * std::max(det, 0.0));
  return m.n * R * R * R / (4.0 / 3.0 * M_PI * abc);
}

/// Adds the cell centred at `p` to the cluster of `m` if its fit score (Eq. 2) stays at or
/// above `min_fit_score`; says whether it did.
bool grows(Moments& m, const Eigen::Vector3d& p, double R, double min_fit_score) {
  Moments with = m;
  with.add(p);
  if (fit_score(with, R) < min_fit_score) return false;
  m = with;
  return true;
}

/// Counts the cells clustered and calls ClusterConfig::progress each progress_cells of them.
class Report {
 public:
  Report(const ClusterConfig& config, std::size_t cells)
      : config_(config), cells_(cells), next_(config.progress_cells) {}
  void add(std::size_t clustered) {
    done_ += clustered;
    if (config_.progress && done_ >= next_) {
      config_.progress("clustering void cells", done_, cells_);
      next_ = done_ + config_.progress_cells;
    }
  }

 private:
  const ClusterConfig& config_;
  std::size_t cells_, done_ = 0, next_;
};

/// 0 … n − 1 in the seeded order in which cells start clusters.
std::vector<std::uint32_t> seeded_order(std::size_t n, std::uint64_t seed) {
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  return order;
}

/// grow() over a key index: for cells that fill little of their box.
std::vector<int> grow_sparse(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                             const ClusterConfig& config) {
  const double R = map.resolution_m();
  const map::KeyIndex index(cells.size(), [&](auto&& visit) {  // cell → its index in `cells`
    for (std::size_t i = 0; i < cells.size(); ++i) visit(map::pack(cells[i]), std::uint32_t(i));
  });
  std::vector<int> owner(cells.size(), -1);  // index → cluster, −1 while unassigned
  const std::vector<std::uint32_t> order = seeded_order(cells.size(), config.seed);
  Report report(config, cells.size());

  int clusters = 0;
  std::vector<std::uint32_t> queue;  // first in, first out: read from `head` on
  for (const std::uint32_t start : order) {
    if (owner[start] >= 0) continue;
    const int id = clusters++;
    Moments m{map.center_of(cells[start])};
    m.add(map.center_of(cells[start]));
    owner[start] = id;
    queue.assign(1, start);
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const map::VoxelKey k = cells[queue[head]];
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
            if ((!dx && !dy && !dz) || x < 0 || y < 0 || z < 0 || x > 0xFFFF || y > 0xFFFF || z > 0xFFFF) continue;
            const map::VoxelKey n{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
            const std::uint32_t j = index.find(map::pack(n));
            if (j == map::KeyIndex::kMissing || owner[j] >= 0) continue;
            if (!grows(m, map.center_of(n), R, config.min_fit_score)) continue;  // stays for a later seed
            owner[j] = id;
            queue.push_back(j);
          }
    }
    report.add(queue.size());
  }
  return owner;
}

/// The cells' box with a margin of one cell, as a dense array of labels: kNone (no cell
/// there), kFree (a cell in no cluster yet) or its cluster. A neighbour is one load at a
/// fixed offset; the margin keeps every neighbour of a cell inside the box.
struct LabelBox {
  static constexpr int kNone = -2, kFree = -1;
  int lo[3] = {0, 0, 0};
  std::int64_t stride[3] = {1, 0, 0};
  std::vector<int> label;

  /// Empty (label.empty()) when the cells fill too little of the box for a dense array
  /// (map::KeyIndex::dense_fits, the key index's own rule).
  explicit LabelBox(const std::vector<map::VoxelKey>& cells) {
    if (cells.empty()) return;  // (the sanitizer job found hi - lo of no cells overflowing)
    int hi[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) lo[a] = INT32_MAX, hi[a] = INT32_MIN;
    for (const map::VoxelKey& k : cells) {
      const int c[3] = {k.x, k.y, k.z};
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a] - 1), hi[a] = std::max(hi[a], c[a] + 1);
    }
    const std::int64_t n[3] = {std::int64_t(hi[0]) - lo[0] + 1, std::int64_t(hi[1]) - lo[1] + 1,
                               std::int64_t(hi[2]) - lo[2] + 1};
    if (!map::KeyIndex::dense_fits(cells.size(), double(n[0]) * double(n[1]) * double(n[2]))) return;
    stride[1] = n[0];
    stride[2] = n[0] * n[1];
    label.assign(std::size_t(stride[2] * n[2]), kNone);
    for (const map::VoxelKey& k : cells) label[at(k)] = kFree;
  }
  std::size_t at(const map::VoxelKey& k) const {
    return std::size_t((k.x - lo[0]) * stride[0] + (k.y - lo[1]) * stride[1] + (k.z - lo[2]) * stride[2]);
  }
};

/// How many seeds ahead grow() fetches a seed's cell, and then its label (which needs the cell).
constexpr std::size_t kPrefetchCell = 32, kPrefetchLabel = 16;

/// Seeded region growing (§IV-B): from each cell not yet in a cluster, in a seeded random
/// order, breadth first over 26-neighbours, adding a neighbour while the fit score (Eq. 2)
/// stays at or above the threshold. Returns each cell's cluster, clusters in growing order.
/// Void cells fill much of their box: labels in a dense box (LabelBox); a sparse set of
/// cells goes through a key index.
std::vector<int> grow(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                      const ClusterConfig& config) {
  LabelBox box(cells);
  if (box.label.empty()) return grow_sparse(map, cells, config);
  const double R = map.resolution_m();
  const std::vector<std::uint32_t> order = seeded_order(cells.size(), config.seed);
  Report report(config, cells.size());

  int clusters = 0;
  std::vector<std::pair<map::VoxelKey, std::size_t>> queue;  // (cell, its label); read from `head` on
  for (std::size_t s = 0; s < order.size(); ++s) {
    // Seeds come in random order, so nearly every seed's cell and label miss the cache, and
    // most seeds are taken already: fetch both a few seeds ahead (the order is known).
    if (s + kPrefetchCell < order.size()) __builtin_prefetch(&cells[order[s + kPrefetchCell]]);
    if (s + kPrefetchLabel < order.size()) __builtin_prefetch(&box.label[box.at(cells[order[s + kPrefetchLabel]])]);
    const std::uint32_t start = order[s];
    const std::size_t at = box.at(cells[start]);
    if (box.label[at] != LabelBox::kFree) continue;
    const int id = clusters++;
    Moments m{map.center_of(cells[start])};
    m.add(map.center_of(cells[start]));
    box.label[at] = id;
    queue.assign(1, {cells[start], at});
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const auto [k, k_at] = queue[head];
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const std::size_t n_at = std::size_t(std::int64_t(k_at) + dz * box.stride[2] + dy * box.stride[1] + dx);
            if (box.label[n_at] != LabelBox::kFree) continue;  // no void cell, in a cluster, or k itself
            const map::VoxelKey n{std::uint16_t(k.x + dx), std::uint16_t(k.y + dy), std::uint16_t(k.z + dz)};
            if (!grows(m, map.center_of(n), R, config.min_fit_score)) continue;  // stays for a later seed
            box.label[n_at] = id;
            queue.emplace_back(n, n_at);
          }
    }
    report.add(queue.size());
  }
  std::vector<int> owner(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) owner[i] = box.label[box.at(cells[i])];
  return owner;
}

/// μ, the axes, λ, a, N·R³ and S of a cluster's cells (key order).
VoidCluster describe(std::vector<map::VoxelKey> cells, const map::OccupancyMap& map) {
  const double R = map.resolution_m();
  VoidCluster c;
  Moments m{map.center_of(cells.front())};
  for (const auto& k : cells) m.add(map.center_of(k));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(m.covariance(R * R / 12.0));
  c.mean_m = m.origin + m.sum / m.n;
  c.axes = eigen.eigenvectors();
  c.variances_m2 = eigen.eigenvalues();
  c.semi_axes_m = (5.0 * c.variances_m2.array().max(0.0)).sqrt();
  c.volume_m3 = double(cells.size()) * R * R * R;
  c.fit_score = fit_score(m, R);
  c.cells = std::move(cells);
  return c;
}

/// The clusters of `owner` (each cell's cluster, numbered in growing order).
std::vector<VoidCluster> number_and_describe(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                             const std::vector<int>& owner) {
  // Number clusters by their smallest key: `cells` is in key order, so in order of first
  // appearance; and each cluster's cells come out in key order too.
  std::vector<int> id_of(owner.empty() ? 0 : std::size_t(*std::max_element(owner.begin(), owner.end())) + 1, -1);
  std::vector<std::vector<map::VoxelKey>> members;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    int& id = id_of[std::size_t(owner[i])];
    if (id < 0) {
      id = int(members.size());
      members.emplace_back();
    }
    members[std::size_t(id)].push_back(cells[i]);
  }
  std::vector<VoidCluster> clusters;
  clusters.reserve(members.size());
  for (auto& cluster_cells : members) {
    clusters.push_back(describe(std::move(cluster_cells), map));
    clusters.back().id = int(clusters.size()) - 1;
  }
  return clusters;
}

}  // namespace

std::vector<VoidCluster> cluster_voids(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                       const ClusterConfig& config) {
  throw_if_problems("void clusters", config.validate());
  return number_and_describe(map, cells, grow(map, cells, config));
}

std::vector<VoidCluster> cluster_voids_indexed(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                               const ClusterConfig& config) {
  throw_if_problems("void clusters", config.validate());
  return number_and_describe(map, cells, grow_sparse(map, cells, config));
}

}  // namespace fvx::voids

namespace fvx::voids {

Json config_json(const ClusterConfig& c) { return {{"min_fit_score", c.min_fit_score}, {"seed", c.seed}}; }

}  // namespace fvx::voids
