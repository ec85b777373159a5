// integrate(): equal to OctoMap's insertPointCloud, change sets against a brute-force oracle,
// and the slambook oracle on real data.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <sstream>

#include "../../../src/map/tree.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "slambook.hpp"
#include "test_support.hpp"

namespace fvx::map {
namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A seeded scan: points on a noisy sphere-ish shell around `origin`, a few far away.
std::vector<Eigen::Vector3f> random_scan(std::mt19937& rng, const Eigen::Vector3f& origin, int n) {
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_real_distribution<float> radius(0.3f, 2.5f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3f d(gauss(rng), gauss(rng), std::abs(gauss(rng)));
    points.push_back(origin + d.normalized() * radius(rng));
  }
  return points;
}

octomap::Pointcloud to_octomap(const std::vector<Eigen::Vector3f>& points) {
  octomap::Pointcloud cloud;
  for (const auto& p : points) cloud.push_back(p.x(), p.y(), p.z());
  return cloud;
}

struct MatchCase {
  const char* name;
  double max_range_m;
  int points_per_scan;  // >= 10000 rays are traced on several threads
  double far_point_m;   // > 0: one point this far away makes the key box too large for a
                        // flat bitmap, so the sparse blocks are used
  double resolution_m;
  bool discretize = false;  // OctoMap's insertPointCloud(…, discretize = true) and --discretize
};

class IntegrateMatchesOctoMap : public ::testing::TestWithParam<MatchCase> {};

TEST_P(IntegrateMatchesOctoMap, SameTreeAfterSeveralScans) {
  const MatchCase c = GetParam();
  const double max_range_m = c.max_range_m;
  const test::TempDir dir;
  std::mt19937 rng(7);
  OccupancyMap map(c.resolution_m);
  octomap::OcTree reference(c.resolution_m);
  for (int s = 0; s < 4; ++s) {
    const Eigen::Vector3f origin(0.3f * s, -0.2f * s, 0.5f);
    auto points = random_scan(rng, origin, c.points_per_scan);
    // 40 m on every axis at 2.5 cm: 1600³ ≈ 4·10⁹ cells, beyond the flat bitmap's 2³⁰.
    const float far = float(c.far_point_m);
    if (far > 0) points.push_back(origin + Eigen::Vector3f(far, far, -far));
    const auto result = map.integrate(points, origin, max_range_m, c.discretize);
    reference.insertPointCloud(to_octomap(points), octomap::point3d(origin.x(), origin.y(), origin.z()),
                               std::isfinite(max_range_m) ? max_range_m : -1.0, false, c.discretize);
    // Discretised, the scan is one ray per distinct cell: fewer than the points.
    if (c.discretize) {
      EXPECT_LT(result.points, points.size());
    }
  }
  // .ot holds the full tree with log-odds: equal bytes mean equal trees.
  map.save(dir / "fvx.ot");
  ASSERT_TRUE(reference.write(dir / "octomap.ot"));
  EXPECT_EQ(file_bytes(dir / "fvx.ot"), file_bytes(dir / "octomap.ot"));
  EXPECT_EQ(map.stats().nodes, reference.size());
}

INSTANTIATE_TEST_SUITE_P(
    Paths, IntegrateMatchesOctoMap,
    ::testing::Values(MatchCase{"no_range_limit", std::numeric_limits<double>::infinity(), 3000, 0, 0.05},
                      MatchCase{"range_limit", 1.5, 3000, 0, 0.05},
                      MatchCase{"threaded", 4.0, 12000, 0, 0.05},
                      MatchCase{"sparse_blocks", std::numeric_limits<double>::infinity(), 2000, 40.0, 0.025},
                      MatchCase{"discretized", std::numeric_limits<double>::infinity(), 6000, 0, 0.1, true},
                      MatchCase{"discretized_range_limit", 1.5, 6000, 0, 0.1, true},
                      MatchCase{"discretized_threaded", 4.0, 30000, 0, 0.1, true},
                      MatchCase{"discretized_sparse_blocks", std::numeric_limits<double>::infinity(), 4000, 40.0, 0.05,
                                true}),
    [](const auto& test_info) { return std::string(test_info.param.name); });

// A map loaded from a file, then integrated: the same tree as OctoMap's from the same file.
// OctoMap's own updates keep every inner node at the max of its children, which lets
// update_cell stop early on the way up; a tree written after lazy updates, or with a stale
// root, does not hold that, and must be updated as OctoMap's recursion does.
TEST(Integrate, ALoadedTreeIsUpdatedAsOctoMapUpdatesIt) {
  enum class Start { Updated, Lazy, StaleRoot };
  for (const Start how : {Start::Updated, Start::Lazy, Start::StaleRoot}) {
    const test::TempDir dir;
    std::mt19937 rng(11);
    octomap::OcTree start(0.05);
    for (int s = 0; s < 2; ++s) {
      const Eigen::Vector3f origin(0.2f * s, 0.1f, 0.5f);
      start.insertPointCloud(to_octomap(random_scan(rng, origin, 2000)),
                             octomap::point3d(origin.x(), origin.y(), origin.z()), -1.0, how == Start::Lazy);
    }
    if (how == Start::StaleRoot) start.getRoot()->setLogOdds(7.0f);  // not the max of its children
    ASSERT_TRUE(start.write(dir / "start.ot"));
    OccupancyMap map = OccupancyMap::load(dir / "start.ot");
    std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read(dir / "start.ot"));
    auto* reference = dynamic_cast<octomap::OcTree*>(read.get());
    ASSERT_NE(reference, nullptr);
    for (int s = 0; s < 3; ++s) {
      const Eigen::Vector3f origin(-0.3f * s, 0.2f, 0.4f);
      const auto points = random_scan(rng, origin, 2000);
      map.integrate(points, origin);
      reference->insertPointCloud(to_octomap(points), octomap::point3d(origin.x(), origin.y(), origin.z()));
    }
    map.save(dir / "fvx.ot");
    ASSERT_TRUE(reference->write(dir / "octomap.ot"));
    EXPECT_EQ(file_bytes(dir / "fvx.ot"), file_bytes(dir / "octomap.ot")) << "start " << int(how);
  }
}

// update_cell starts each descent from the path of the cell before it; pruning deletes nodes
// of that path. The same scan again and again clamps the free cells, which prunes them into
// coarser leaves within a pass, and scans from other origins then expand those leaves: the
// tree still equals OctoMap's, byte for byte, and pruned leaves exist in it.
TEST(Integrate, ScansThatPruneAndExpandTheTreeGiveOctoMapsTree) {
  const test::TempDir dir;
  std::mt19937 rng(5);
  OccupancyMap map(0.05);
  octomap::OcTree reference(0.05);
  const Eigen::Vector3f first(0.0f, 0.0f, 0.5f);
  const auto same = random_scan(rng, first, 4000);
  for (int s = 0; s < 14; ++s) {
    const Eigen::Vector3f origin = s < 10 ? first : Eigen::Vector3f(0.35f * float(s - 9), -0.1f, 0.4f);
    const auto points = s < 10 ? same : random_scan(rng, origin, 4000);
    map.integrate(points, origin);
    reference.insertPointCloud(to_octomap(points), octomap::point3d(origin.x(), origin.y(), origin.z()));
  }
  std::size_t pruned_leaves = 0;
  for (auto it = reference.begin_leafs(); it != reference.end_leafs(); ++it) pruned_leaves += it.getDepth() < 16;
  EXPECT_GT(pruned_leaves, 100u);
  map.save(dir / "fvx.ot");
  ASSERT_TRUE(reference.write(dir / "octomap.ot"));
  EXPECT_EQ(file_bytes(dir / "fvx.ot"), file_bytes(dir / "octomap.ot"));
}

// What update_cell's early stop relies on, checked on trees OctoMap itself updated.
TEST(Integrate, TheInnerNodeCheckTellsUpdatedTreesFromStaleOnes) {
  std::mt19937 rng(3);
  const auto points = to_octomap(random_scan(rng, Eigen::Vector3f(0, 0, 0.5f), 2000));
  Tree updated(0.05), lazy(0.05);
  updated.insertPointCloud(points, octomap::point3d(0, 0, 0.5f));
  lazy.insertPointCloud(points, octomap::point3d(0, 0, 0.5f), -1.0, true);
  updated.check_inner_nodes();
  lazy.check_inner_nodes();
  EXPECT_TRUE(updated.inner_nodes_hold_max());
  EXPECT_FALSE(lazy.inner_nodes_hold_max());
  lazy.updateInnerOccupancy();
  lazy.check_inner_nodes();
  EXPECT_TRUE(lazy.inner_nodes_hold_max());
  updated.getRoot()->setLogOdds(7.0f);
  updated.check_inner_nodes();
  EXPECT_FALSE(updated.inner_nodes_hold_max());
}

TEST(Integrate, ChangeSetEqualsBruteForceDifference) {
  const double resolution_m = 0.1;
  OccupancyMap map(resolution_m);
  std::mt19937 rng(11);
  // Every ray stays inside [-3, 3]³: compare the states of all cells there.
  const auto k0 = *map.key_of({-3, -3, -3});
  const auto k1 = *map.key_of({3, 3, 3});
  auto snapshot = [&] {
    std::map<std::tuple<int, int, int>, VoxelState> states;
    for (int z = k0.z; z <= k1.z; ++z)
      for (int y = k0.y; y <= k1.y; ++y)
        for (int x = k0.x; x <= k1.x; ++x)
          states[{x, y, z}] = map.state({std::uint16_t(x), std::uint16_t(y), std::uint16_t(z)});
    return states;
  };
  auto before = snapshot();
  std::size_t total_changes = 0;
  for (int s = 0; s < 5; ++s) {
    const Eigen::Vector3f origin(0.2f * s - 0.4f, 0.1f * s, 0.0f);
    const Integration result = map.integrate(random_scan(rng, origin, 400), origin, 2.0);
    const auto after = snapshot();
    std::vector<Change> expected;
    for (const auto& [k, state] : after) {
      const VoxelState old = before.at(k);
      if (old != state)
        expected.push_back({{std::uint16_t(std::get<0>(k)), std::uint16_t(std::get<1>(k)),
                             std::uint16_t(std::get<2>(k))}, old, state});
    }
    std::sort(expected.begin(), expected.end(), [](const Change& a, const Change& b) { return a.key < b.key; });
    ASSERT_EQ(result.changes.size(), expected.size()) << "scan " << s;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(result.changes[i].key, expected[i].key);
      EXPECT_EQ(result.changes[i].before, expected[i].before);
      EXPECT_EQ(result.changes[i].after, expected[i].after);
    }
    total_changes += expected.size();
    before = after;
  }
  EXPECT_GT(total_changes, 1000u);  // the scans did change the map
}

TEST(Integrate, OccupiedWinsOverFreeWithinOneScan) {
  OccupancyMap map(0.25);
  // The second ray passes through the first point's cell.
  const Integration r = map.integrate({Eigen::Vector3f(1.1f, 0.1f, 0.1f), Eigen::Vector3f(2.1f, 0.1f, 0.1f)},
                                      Eigen::Vector3f(0.1f, 0.1f, 0.1f));
  EXPECT_EQ(map.state(*map.key_of({1.1, 0.1, 0.1})), VoxelState::Occupied);
  EXPECT_EQ(map.state(*map.key_of({1.6, 0.1, 0.1})), VoxelState::Free);
  EXPECT_EQ(map.state(*map.key_of({2.1, 0.1, 0.1})), VoxelState::Occupied);
  EXPECT_EQ(r.occupied_updates, 2u);
  EXPECT_EQ(r.free_updates, 7u);  // cells 0..7 less the occupied cell 4; cell 8 is the end
}

TEST(Integrate, MaxRangeCutsRaysAndMarksNoEndpoint) {
  OccupancyMap map(0.25);
  const Integration r = map.integrate({Eigen::Vector3f(3.1f, 0.1f, 0.1f)}, Eigen::Vector3f(0.1f, 0.1f, 0.1f), 1.0);
  EXPECT_EQ(r.points_beyond_range, 1u);
  EXPECT_EQ(r.occupied_updates, 0u);
  EXPECT_EQ(map.state(*map.key_of({0.9, 0.1, 0.1})), VoxelState::Free);
  EXPECT_EQ(map.state(*map.key_of({3.1, 0.1, 0.1})), VoxelState::Unknown);
}

TEST(Integrate, NonFiniteAndOutOfMapPointsAreCountedNotInserted) {
  OccupancyMap map(0.05);
  const Integration r = map.integrate({Eigen::Vector3f(NAN, 0, 0), Eigen::Vector3f(1e6f, 0, 0),
                                       Eigen::Vector3f(1, 0, 0)},
                                      Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(r.points_out_of_map, 2u);
  EXPECT_EQ(r.occupied_updates, 1u);
}

// The oracle of ARCHITECTURE/PROVENANCE: slambook's octomap_mapping over the 5 frames.
TEST(IntegrateRealData, SlambookReproducesTheReferenceOctree) {
  FVX_REAL_DATA_OR_SKIP(frames, "slambook-joinmap-5kf");
  FVX_REAL_DATA_OR_SKIP(reference_path, "octomap-maps/slambook_ch13/octomap.bt");
  OccupancyMap map(0.05);
  test::for_each_slambook_frame(frames, [&](const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& origin,
                                            const std::string&) { map.integrate(points, origin); });
  const test::TempDir dir;
  map.save(dir / "slambook.bt");
  // Byte-identical, and therefore the same free and occupied leaf sets...
  EXPECT_EQ(file_bytes(dir / "slambook.bt"), file_bytes(reference_path));
  // ...which is also checked leaf by leaf, so that a failure says what differs.
  octomap::OcTree mine(0.05), reference(0.05);
  ASSERT_TRUE(mine.readBinary(dir / "slambook.bt"));
  ASSERT_TRUE(reference.readBinary(reference_path));
  auto leaves = [](const octomap::OcTree& t) {
    std::map<std::tuple<int, int, int, unsigned>, bool> set;
    for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it)
      set[{it.getKey()[0], it.getKey()[1], it.getKey()[2], it.getDepth()}] = t.isNodeOccupied(*it);
    return set;
  };
  const auto a = leaves(mine), b = leaves(reference);
  std::size_t occupied = 0;
  for (const auto& [k, occ] : b) occupied += occ;
  EXPECT_EQ(occupied, 37811u);
  EXPECT_EQ(b.size() - occupied, 80783u);
  EXPECT_TRUE(a == b);
}

}  // namespace
}  // namespace fvx::map
