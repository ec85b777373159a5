#include "fvx/voids/clusters.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
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

namespace {

/// Seeded region growing (§IV-B): from each cell not yet in a cluster, in a seeded random
/// order, breadth first over 26-neighbours, adding a neighbour while the fit score (Eq. 2)
/// stays at or above the threshold. Returns each cell's cluster, clusters in growing order.
std::vector<int> grow(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                      const ClusterConfig& config) {
  const double R = map.resolution_m();
  const map::KeyIndex index(cells.size(), [&](auto&& visit) {  // cell → its index in `cells`
    for (std::size_t i = 0; i < cells.size(); ++i) visit(map::pack(cells[i]), std::uint32_t(i));
  });
  std::vector<int> owner(cells.size(), -1);  // index → cluster, −1 while unassigned
  std::vector<std::uint32_t> order(cells.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::uint32_t(i);
  std::mt19937_64 rng(config.seed);
  std::shuffle(order.begin(), order.end(), rng);

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
            Moments with = m;
            with.add(map.center_of(n));
            if (fit_score(with, R) < config.min_fit_score) continue;  // stays for a later seed
            m = with;
            owner[j] = id;
            queue.push_back(j);
          }
    }
  }
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

}  // namespace

std::vector<VoidCluster> cluster_voids(const map::OccupancyMap& map, const std::vector<map::VoxelKey>& cells,
                                       const ClusterConfig& config) {
  throw_if_problems("void clusters", config.validate());
  const std::vector<int> owner = grow(map, cells, config);
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

}  // namespace fvx::voids

namespace fvx::voids {

Json config_json(const ClusterConfig& c) { return {{"min_fit_score", c.min_fit_score}, {"seed", c.seed}}; }

}  // namespace fvx::voids
