// Void clusters: Eq. 2 on shapes with known scores; every cell in exactly one cluster;
// determinism; frontier-void pairing and utility.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <random>
#include <set>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/voids/clusters.hpp"

namespace fvx::voids {
namespace {

std::vector<map::VoxelKey> box_cells(int x0, int y0, int z0, int nx, int ny, int nz) {
  std::vector<map::VoxelKey> cells;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        cells.push_back({std::uint16_t(32768 + x0 + x), std::uint16_t(32768 + y0 + y), std::uint16_t(32768 + z0 + z)});
  return cells;
}

TEST(VoidClusters, AFilledBoxIsOneClusterWithTheBoxScore) {
  const map::OccupancyMap map(0.05);
  auto cells = box_cells(0, 0, 0, 12, 8, 5);
  std::sort(cells.begin(), cells.end());
  const auto clusters = cluster_voids(map, cells, ClusterConfig{});
  ASSERT_EQ(clusters.size(), 1u);
  const VoidCluster& c = clusters[0];
  EXPECT_EQ(c.cells.size(), 480u);
  EXPECT_NEAR(c.fit_score, 1.0 / (4.0 / 3.0 * M_PI * std::pow(5.0 / 12.0, 1.5)), 1e-9);  // 0.887 for any box
  EXPECT_NEAR(c.volume_m3, 480 * 0.05 * 0.05 * 0.05, 1e-12);
  EXPECT_TRUE(c.mean_m.isApprox(Eigen::Vector3d(0.3, 0.2, 0.125), 1e-9));
  // The longest axis is x: a = sqrt(5 · L²/12) with L = 0.6 m.
  EXPECT_NEAR(c.semi_axes_m.maxCoeff(), std::sqrt(5.0 * 0.36 / 12.0), 1e-9);
  for (const auto& corner : c.corners()) EXPECT_TRUE(corner.allFinite());
}

// The dense path (labels in the cells' box) against the key-index path, its oracle: the same
// clusters, cell for cell and bit for bit, on random blobs of void cells (many clusters, cells
// at the edge of the key space) over several seeds and thresholds.
TEST(VoidClusters, TheDensePathEqualsTheIndexedOne) {
  const map::OccupancyMap map(0.05);
  std::mt19937 rng(11);
  std::size_t compared = 0;
  for (const int origin : {32700, 0, 65535 - 30}) {
    std::set<map::VoxelKey> unique;
    std::uniform_int_distribution<int> u(0, 29);
    for (int blob = 0; blob < 6; ++blob) {
      const int cx = u(rng), cy = u(rng), cz = u(rng), r = 2 + u(rng) % 5;
      for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
          for (int x = -r; x <= r; ++x) {
            const int k[3] = {std::clamp(origin + cx + x, 0, 65535), std::clamp(origin + cy + y, 0, 65535),
                              std::clamp(origin + cz + z, 0, 65535)};
            if (x * x + y * y + 2 * z * z <= r * r) unique.insert({std::uint16_t(k[0]), std::uint16_t(k[1]), std::uint16_t(k[2])});
          }
    }
    const std::vector<map::VoxelKey> cells(unique.begin(), unique.end());  // key order
    for (const double threshold : {0.5, 0.7, 0.9})
      for (std::uint64_t seed : {1u, 2u}) {
        ClusterConfig config;
        config.seed = seed;
        config.min_fit_score = threshold;
        const auto dense = cluster_voids(map, cells, config), indexed = cluster_voids_indexed(map, cells, config);
        ASSERT_EQ(dense.size(), indexed.size());
        for (std::size_t i = 0; i < dense.size(); ++i) {
          ASSERT_EQ(dense[i].cells, indexed[i].cells) << "cluster " << i;
          ASSERT_EQ(dense[i].mean_m, indexed[i].mean_m);
          ASSERT_EQ(dense[i].fit_score, indexed[i].fit_score);
        }
        compared += dense.size();
      }
  }
  EXPECT_GT(compared, 100u) << "the blobs should split into many clusters";
}

// Eq. 2 as the paper writes it, with full 3×3 matrices and Eigen's determinant, as the oracle
// of the clusters' fit scores and variances (region growing keeps the sums' upper triangle
// only): equal to the bit, on random blobs over several thresholds and seeds.
TEST(VoidClusters, FitScoresEqualTheFullMatrixFormulaToTheBit) {
  const map::OccupancyMap map(0.05);
  const double R = map.resolution_m();
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> u(0, 29);
  std::set<map::VoxelKey> unique;
  for (int blob = 0; blob < 8; ++blob) {
    const int cx = u(rng), cy = u(rng), cz = u(rng), r = 2 + u(rng) % 6;
    for (int z = -r; z <= r; ++z)
      for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x)
          if (2 * x * x + y * y + 3 * z * z <= 2 * r * r)
            unique.insert({std::uint16_t(32700 + cx + x), std::uint16_t(32700 + cy + y), std::uint16_t(32700 + cz + z)});
  }
  const std::vector<map::VoxelKey> cells(unique.begin(), unique.end());
  std::size_t compared = 0;
  for (const double threshold : {0.5, 0.7, 0.9})
    for (std::uint64_t seed : {1u, 2u}) {
      ClusterConfig config;
      config.seed = seed;
      config.min_fit_score = threshold;
      for (const VoidCluster& c : cluster_voids(map, cells, config)) {
        const Eigen::Vector3d origin = map.center_of(c.cells.front());
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
        for (const auto& k : c.cells) {
          const Eigen::Vector3d q = map.center_of(k) - origin;
          sum += q;
          outer += q * q.transpose();
        }
        const double n = double(c.cells.size());
        const Eigen::Vector3d mean = sum / n;
        const Eigen::Matrix3d covariance = outer / n - mean * mean.transpose() + R * R / 12.0 * Eigen::Matrix3d::Identity();
        const double abc = std::sqrt(125.0 * std::max(covariance.determinant(), 0.0));
        ASSERT_EQ(c.fit_score, n * R * R * R / (4.0 / 3.0 * M_PI * abc)) << "cluster of " << c.cells.size();
        ASSERT_EQ(c.variances_m2, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues());
        ++compared;
      }
    }
  EXPECT_GT(compared, 30u);
}

// Progress on both paths: counts that only grow, never past the cells, each at least the
// step beyond the one before; and the same clusters as without it.
TEST(VoidClusters, ProgressCountsTheCellsClusteredAndChangesNothing) {
  const map::OccupancyMap map(0.05);
  std::vector<map::VoxelKey> cells;  // twelve boxes apart, 125 cells each: a cluster each
  for (int b = 0; b < 12; ++b) {
    const auto box = box_cells(10 * b, 0, 0, 5, 5, 5);
    cells.insert(cells.end(), box.begin(), box.end());
  }
  std::sort(cells.begin(), cells.end());
  for (const bool indexed : {false, true}) {
    ClusterConfig quiet, counted;
    std::vector<std::pair<std::size_t, std::size_t>> calls;
    counted.progress = [&](const std::string&, std::size_t done, std::size_t total) { calls.emplace_back(done, total); };
    counted.progress_cells = 200;
    const auto a = indexed ? cluster_voids_indexed(map, cells, quiet) : cluster_voids(map, cells, quiet);
    const auto b = indexed ? cluster_voids_indexed(map, cells, counted) : cluster_voids(map, cells, counted);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].cells, b[i].cells);
    ASSERT_GE(calls.size(), 5u) << "indexed " << indexed;
    EXPECT_GE(calls.front().first, 200u);
    for (std::size_t i = 0; i < calls.size(); ++i) {
      EXPECT_EQ(calls[i].second, cells.size());
      EXPECT_LE(calls[i].first, cells.size());
      if (i > 0) {
        EXPECT_GE(calls[i].first, calls[i - 1].first + 200);
      }
    }
  }
}

TEST(VoidClusters, TwoBoxesJoinedByALineSplitAndEveryCellIsInOneCluster) {
  const map::OccupancyMap map(0.05);
  auto cells = box_cells(0, 0, 0, 6, 6, 6);
  const auto second = box_cells(20, 0, 0, 6, 6, 6);
  cells.insert(cells.end(), second.begin(), second.end());
  for (int x = 6; x < 20; ++x) cells.push_back({std::uint16_t(32768 + x), 32768 + 2, 32768 + 2});  // a thin bridge
  std::sort(cells.begin(), cells.end());
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    ClusterConfig config;
    config.seed = seed;
    const auto clusters = cluster_voids(map, cells, config);
    EXPECT_GE(clusters.size(), 2u) << "a dumbbell is not one ellipsoid";
    std::set<std::tuple<int, int, int>> seen;
    std::size_t total = 0;
    for (const auto& c : clusters) {
      EXPECT_GE(c.fit_score, config.min_fit_score);
      for (const auto& k : c.cells) seen.insert({k.x, k.y, k.z});
      total += c.cells.size();
    }
    EXPECT_EQ(total, cells.size()) << "no cell twice";
    EXPECT_EQ(seen.size(), cells.size()) << "every cell once";
    const auto again = cluster_voids(map, cells, config);
    ASSERT_EQ(again.size(), clusters.size());
    for (std::size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].cells, clusters[i].cells);
  }
}

TEST(FrontierVoids, PairingByFaceOrEdgeAdjacencyAndUtility) {
  const map::OccupancyMap map(0.025);
  auto cells = box_cells(0, 0, 0, 4, 4, 4);
  std::sort(cells.begin(), cells.end());
  const auto voids = cluster_voids(map, cells, ClusterConfig{});
  ASSERT_EQ(voids.size(), 1u);
  frontiers::Cluster face, edge, corner;
  face.id = 0;
  face.cells = {{32768 + 4, 32768 + 1, 32768 + 1}};  // touches the x+ face
  edge.id = 1;
  edge.cells = {{32768 - 1, 32768 - 1, 32768 + 2}};  // touches an edge
  corner.id = 2;
  corner.cells = {{32768 + 4, 32768 + 4, 32768 + 4}};  // only a corner: not paired
  const auto pairs = frontier_voids::pair_frontier_voids(voids, {face, edge, corner});
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].frontier_ids, (std::vector<int>{0, 1}));
  EXPECT_FALSE(pairs[0].enclosed());
  // Utility in dm³ = cells × R³ × 1000: 64 cells at 2.5 cm = 1.0 dm³ (the paper's 1245 → 19.45).
  EXPECT_DOUBLE_EQ(frontier_voids::to_dm3(pairs[0].utility_m3), 64 * 0.025 * 0.025 * 0.025 * 1000);
  EXPECT_TRUE(frontier_voids::pair_frontier_voids(voids, {corner})[0].enclosed());
}

}  // namespace
}  // namespace fvx::voids
