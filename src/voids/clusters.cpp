#include "fvx/voids/clusters.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <deque>
#include <random>

#include "fvx/core/error.hpp"
#include "fvx/map/key_index.hpp"
#include "fvx/frontiers/frontiers.hpp"  // pack

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

/// Running sums of a growing cluster, in a frame near it (for precision).
struct Moments {
  Eigen::Vector3d origin;
  double n = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_outer = Eigen::Matrix3d::Zero();

  void add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - origin;
    n += 1;
    sum += q;
    sum_outer += q * q.transpose();
  }
  Eigen::Matrix3d covariance(double cell_variance) const {
    const Eigen::Vector3d mean = sum / n;
    return sum_outer / n - mean * mean.transpose() + cell_variance * Eigen::Matrix3d::Identity();
  }
};

/// Eq. 2 with a_j = sqrt(5 λ_j): a1·a2·a3 = sqrt(125·det Σ).
double fit_score(const Moments& m, double R) {
  const double det = m.covariance(R * R / 12.0).determinant();
  const double abc = std::sqrt(125.0 * std::max(det, 0.0));
  return m.n * R * R * R / (4.0 / 3.0 * M_PI * abc);
}

}  // namespace

std::vector<VoidCluster> cluster_voids(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                       const ClusterConfig& config) {
  FVX_ASSERT(config.validate().empty(), "invalid ClusterConfig");
  const double R = map.resolution_m();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) entries[i] = {frontiers::pack(cells[i]), std::uint32_t(i)};
  const map::KeyIndex index(entries);         // cell → its index in `cells`
  std::vector<int> owner(cells.size(), -1);  // index → cluster, −1 while unassigned

  std::vector<std::size_t> order(cells.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937_64 rng(config.seed);
  std::shuffle(order.begin(), order.end(), rng);

  std::vector<std::vector<map::VoxelKey>> grown;
  for (const std::size_t start : order) {
    if (owner[start] >= 0) continue;
    const int id = int(grown.size());
    grown.emplace_back();
    Moments m{map.center_of(cells[start])};
    std::deque<map::VoxelKey> queue{cells[start]};
    owner[start] = id;
    m.add(map.center_of(cells[start]));
    while (!queue.empty()) {
      const map::VoxelKey k = queue.front();
      queue.pop_front();
      grown.back().push_back(k);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
            if ((!dx && !dy && !dz) || x < 0 || y < 0 || z < 0 || x > 0xFFFF || y > 0xFFFF || z > 0xFFFF) continue;
            const map::VoxelKey n{std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)};
            const std::uint32_t j = index.find(frontiers::pack(n));
            if (j == map::KeyIndex::kMissing || owner[j] >= 0) continue;
            Moments with = m;
            with.add(map.center_of(n));
            if (fit_score(with, R) < config.min_fit_score) continue;  // stays for a later seed
            m = with;
            owner[j] = id;
            queue.push_back(n);
          }
    }
  }

  // Number clusters by their smallest key; describe each.
  for (auto& g : grown) std::sort(g.begin(), g.end());
  std::sort(grown.begin(), grown.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  std::vector<VoidCluster> clusters;
  clusters.reserve(grown.size());
  for (auto& g : grown) {
    VoidCluster c;
    c.id = int(clusters.size());
    Moments m{map.center_of(g.front())};
    for (const auto& k : g) m.add(map.center_of(k));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(m.covariance(R * R / 12.0));
    c.mean_m = m.origin + m.sum / m.n;
    c.axes = eigen.eigenvectors();
    c.variances_m2 = eigen.eigenvalues();
    c.semi_axes_m = (5.0 * c.variances_m2.array().max(0.0)).sqrt();
    c.volume_m3 = double(g.size()) * R * R * R;
    c.fit_score = fit_score(m, R);
    c.cells = std::move(g);
    clusters.push_back(std::move(c));
  }
  return clusters;
}

}  // namespace fvx::voids
