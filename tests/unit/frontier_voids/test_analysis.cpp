// The whole §IV-A/B analysis on real maps and on a simulated scene with known ground truth.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "fvx/frontier_voids/frontier_voids.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "test_support.hpp"

namespace fvx::frontier_voids {
namespace {

Analysis analyse_with_sets(const map::OccupancyMap& map, voids::VoidSet& void_set,
                     const std::optional<Eigen::AlignedBox3d>& bounds = std::nullopt) {
  frontiers::FrontierSet frontier_set;
  frontier_set.rebuild(map);
  void_set.rebuild(map);
  return analyse(map, frontier_set, &void_set, bounds, voids::ClusterConfig{});
}

void expect_invariants(const map::OccupancyMap& map, const voids::VoidSet& void_set, const Analysis& a) {
  for (const auto& k : a.frontier_cells) ASSERT_TRUE(frontiers::is_frontier(map, k));
  for (const auto& k : a.void_cells) {
    ASSERT_EQ(map.state(k), map::VoxelState::Unknown);
    ASSERT_TRUE(void_set.hull().contains(map.center_of(k)));
    ASSERT_TRUE(a.bounds_m.contains(map.center_of(k)));
  }
  std::size_t clustered = 0;
  for (const auto& c : a.void_clusters) clustered += c.cells.size();
  EXPECT_EQ(clustered, a.void_cells.size()) << "every void cell in exactly one cluster";
  std::size_t frontier_clustered = 0;
  for (const auto& c : a.frontier_clusters) frontier_clustered += c.cells.size();
  EXPECT_EQ(frontier_clustered, a.frontier_cells.size());
  ASSERT_EQ(a.frontier_voids.size(), a.void_clusters.size());
  const double R = map.resolution_m();
  for (const auto& fv : a.frontier_voids)
    EXPECT_DOUBLE_EQ(to_dm3(fv.utility_m3), double(a.void_clusters[std::size_t(fv.void_id)].cells.size()) * R * R * R * 1000.0);
}

/// The one-shot dense path against the incremental sets rebuilt from scratch, its oracle.
void expect_same(const Analysis& dense, const Analysis& sets, const std::string& what) {
  EXPECT_EQ(dense.warnings, sets.warnings) << what;
  EXPECT_EQ(dense.hull_faces, sets.hull_faces) << what;
  EXPECT_EQ(dense.thin_void_cells, sets.thin_void_cells) << what;
  ASSERT_EQ(dense.frontier_cells, sets.frontier_cells) << what;
  ASSERT_EQ(dense.void_cells, sets.void_cells) << what;
  ASSERT_EQ(dense.frontier_clusters.size(), sets.frontier_clusters.size()) << what;
  for (std::size_t i = 0; i < dense.frontier_clusters.size(); ++i)
    ASSERT_EQ(dense.frontier_clusters[i].cells, sets.frontier_clusters[i].cells) << what;
  ASSERT_EQ(dense.void_clusters.size(), sets.void_clusters.size()) << what;
  for (std::size_t i = 0; i < dense.void_clusters.size(); ++i)
    ASSERT_EQ(dense.void_clusters[i].cells, sets.void_clusters[i].cells) << what;
  ASSERT_EQ(dense.frontier_voids.size(), sets.frontier_voids.size()) << what;
  for (std::size_t i = 0; i < dense.frontier_voids.size(); ++i)
    ASSERT_EQ(dense.frontier_voids[i].frontier_ids, sets.frontier_voids[i].frontier_ids) << what;
}

void expect_same_as_sets(const map::OccupancyMap& map, const std::optional<Eigen::AlignedBox3d>& bounds,
                         int min_void_width_cells, const std::string& what) {
  frontiers::FrontierSet frontier_set;
  frontier_set.rebuild(map);
  voids::VoidSet void_set;
  void_set.rebuild(map);
  const voids::ClusterConfig config;
  expect_same(analyse_map(map, bounds, config, min_void_width_cells),
              analyse(map, frontier_set, &void_set, bounds, config, min_void_width_cells), what);
  expect_same(analyse_map(map, bounds, config, 1, false), analyse(map, frontier_set, nullptr, bounds, config),
              what + ", frontiers only");
  if (!bounds) return;
  voids::VoidSet in_bounds;  // the hull of the occupied cells in S only (--void-hull search-space)
  in_bounds.rebuild(map, bounds);
  expect_same(analyse_map(map, bounds, config, min_void_width_cells, true, true),
              analyse(map, frontier_set, &in_bounds, bounds, config, min_void_width_cells), what + ", hull in bounds");
}

/// Random blocks of free and occupied cells (pruned leaves among them) over unknown space.
map::OccupancyMap random_blocks(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> corner(-20, 20), extent(1, 9), state(0, 3);
  map::OccupancyMap map(0.1);
  for (int b = 0; b < 60; ++b) {
    const int x0 = corner(rng), y0 = corner(rng), z0 = corner(rng) / 2;
    const int ex = extent(rng), ey = extent(rng), ez = extent(rng);
    const map::VoxelState s = state(rng) == 0 ? map::VoxelState::Occupied : map::VoxelState::Free;
    for (int z = z0; z < z0 + ez; ++z)
      for (int y = y0; y < y0 + ey; ++y)
        for (int x = x0; x < x0 + ex; ++x)
          map.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), std::uint16_t(32768 + z)}, s);
  }
  return map;
}

TEST(Analysis, FromScratchEqualsTheSetsOnRandomMaps) {
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    const map::OccupancyMap map = random_blocks(seed);
    const std::string what = "seed " + std::to_string(seed);
    expect_same_as_sets(map, std::nullopt, 1, what);
    expect_same_as_sets(map, Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1.5, -0.5), Eigen::Vector3d(1.2, 0.8, 0.9)), 2,
                        what + ", bounds and width 2");
    // Search spaces smaller than the map read a grid over them alone, the hull from all of it.
    expect_same_as_sets(map, Eigen::AlignedBox3d(Eigen::Vector3d(-3, 0.05, -3), Eigen::Vector3d(0.3, 5, 0.42)), 1,
                        what + ", bounds across the map's edge");
    expect_same_as_sets(map, Eigen::AlignedBox3d(Eigen::Vector3d(0.05, -0.35, 0.1), Eigen::Vector3d(0.15, 0.35, 0.2)), 1,
                        what + ", bounds one cell thick");
  }
}

TEST(Analysis, FromScratchEqualsTheSetsOnDegenerateMaps) {
  map::OccupancyMap free_only(0.1), flat(0.1), edge(0.5);
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y) {
      free_only.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), 32768}, map::VoxelState::Free);
      flat.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), 32768}, map::VoxelState::Occupied);
    }
  for (const std::uint16_t k : {std::uint16_t(0), std::uint16_t(1), std::uint16_t(0xFFFF)})
    edge.set_state({k, std::uint16_t(k ^ 1), 7}, map::VoxelState::Free);  // free cells at the key space's edge
  expect_same_as_sets(free_only, std::nullopt, 1, "free only");
  expect_same_as_sets(flat, std::nullopt, 1, "flat");
  expect_same_as_sets(edge, std::nullopt, 1, "key space edge");
  expect_same_as_sets(map::OccupancyMap(0.1), std::nullopt, 1, "empty");
  expect_same_as_sets(free_only, Eigen::AlignedBox3d(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6)), 1,
                      "bounds without known cells");
}

TEST(AnalysisRealData, FromScratchEqualsTheSetsOnRealMaps) {
  for (const char* name : {"octomap-maps/slambook_ch13/octomap.bt", "octomap-maps/octomap-share-data/geb079.bt"}) {
    FVX_REAL_DATA_OR_SKIP(path, name);
    const map::OccupancyMap map = map::OccupancyMap::load(path);
    expect_same_as_sets(map, std::nullopt, 1, name);
    const map::Stats st = map.stats();  // a search space of a quarter of the map, off its centre
    const Eigen::Vector3d lo = st.known_min_m + 0.2 * (st.known_max_m - st.known_min_m);
    expect_same_as_sets(map, Eigen::AlignedBox3d(lo, lo + 0.5 * (st.known_max_m - st.known_min_m)), 1,
                        std::string(name) + ", bounds");
  }
}

TEST(AnalysisRealData, InvariantsHoldOnRealMaps) {
  for (const char* name : {"octomap-maps/slambook_ch13/octomap.bt", "octomap-maps/octomap-share-data/geb079.bt"}) {
    FVX_REAL_DATA_OR_SKIP(path, name);
    const map::OccupancyMap map = map::OccupancyMap::load(path);
    voids::VoidSet void_set;
    const Analysis a = analyse_with_sets(map, void_set);
    EXPECT_GT(a.frontier_cells.size(), 1000u) << name;
    EXPECT_GT(a.void_cells.size(), 1000u) << name;
    EXPECT_TRUE(a.warnings.empty()) << name;
    expect_invariants(map, void_set, a);
  }
}

TEST(Analysis, DegenerateMapsGiveEmptyResultsWithAWarning) {
  map::OccupancyMap free_only(0.1), flat(0.1);
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y) {
      free_only.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), 32768}, map::VoxelState::Free);
      flat.set_state({std::uint16_t(32768 + x), std::uint16_t(32768 + y), 32768}, map::VoxelState::Occupied);
    }
  for (const map::OccupancyMap* map : {&free_only, &flat}) {
    voids::VoidSet void_set;
    const Analysis a = analyse_with_sets(*map, void_set);
    EXPECT_TRUE(a.void_cells.empty());
    EXPECT_FALSE(a.warnings.empty());
  }
  voids::VoidSet void_set;
  const Analysis outside =
      analyse_with_sets(free_only, void_set, Eigen::AlignedBox3d(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6)));
  EXPECT_TRUE(outside.frontier_cells.empty());
  EXPECT_NE(outside.warnings.back().find("no known cell"), std::string::npos);
  const map::OccupancyMap empty(0.1);
  EXPECT_FALSE(analyse_with_sets(empty, void_set).warnings.empty());
}

// The closed box with one opening, scanned through the opening: the interior is a void,
// paired with the frontier at the opening, and its utility is its unknown volume.
TEST(Analysis, ClosedBoxInteriorIsAVoidPairedWithTheOpening) {
  const sim::Scene scene = sim::builtin_scene("closed-box");
  const auto caster = sim::make_ray_caster(scene.mesh);
  const double R = 0.02;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  // 0.7 m above the opening, looking down
  T.linear() << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  T.translation() << 0.77, -0.02, 1.1;
  const sim::Frame frame = sim::render(*caster, T, sim::SensorConfig{});
  map::OccupancyMap map(R);
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : frame.points_sensor)
    if (p.allFinite()) points.push_back((T * p.cast<double>()).cast<float>());
  map.integrate(points, T.translation().cast<float>());

  // Search space: the box's interior.
  const Eigen::AlignedBox3d interior = scene.info.containers[0].box;
  voids::VoidSet void_set;
  const Analysis a = analyse_with_sets(map, void_set, interior);
  expect_invariants(map, void_set, a);
  ASSERT_FALSE(a.void_clusters.empty());
  // The interior's unknown cells (centres inside the interior): the voids are exactly those
  // inside the hull, which spans the box whose walls are occupied — all but a layer of cells.
  std::size_t unknown_inside = 0;
  const sim::GroundTruth gt(scene.mesh, *caster, R, interior);
  for (int z = 0; z < gt.size().z(); ++z)
    for (int y = 0; y < gt.size().y(); ++y)
      for (int x = 0; x < gt.size().x(); ++x) {
        const Eigen::Vector3d c = gt.center_of(gt.first_cell() + Eigen::Vector3i(x, y, z));
        unknown_inside += map.state(*map.key_of(c)) == map::VoxelState::Unknown;
      }
  double utility_m3 = 0;
  for (const auto& fv : a.frontier_voids) utility_m3 += fv.utility_m3;
  const Eigen::Vector3d size = interior.sizes() / R;
  const double one_layer_cells = 2 * (size.x() * size.y() + size.y() * size.z() + size.x() * size.z());
  EXPECT_NEAR(utility_m3 / (R * R * R), double(unknown_inside), one_layer_cells);
  EXPECT_GT(unknown_inside, 5000u);
  // The largest void is paired with the frontier cluster at the opening: the surface of the
  // cone of free cells seen through it, centred under the opening.
  const auto largest = std::max_element(a.void_clusters.begin(), a.void_clusters.end(),
                                        [](const auto& p, const auto& q) { return p.cells.size() < q.cells.size(); });
  const FrontierVoid& fv = a.frontier_voids[std::size_t(largest->id)];
  ASSERT_FALSE(fv.enclosed());
  bool at_opening = false;
  for (int id : fv.frontier_ids) {
    const Eigen::Vector3d c = a.frontier_clusters[std::size_t(id)].centroid_m;
    at_opening |= std::abs(c.x() - 0.77) < 0.08 && std::abs(c.y() + 0.02) < 0.08;
  }
  EXPECT_TRUE(at_opening);
}

}  // namespace
}  // namespace fvx::frontier_voids
