// Reading and writing maps: round trips, OctoMap's own files, bad files.
#include <gtest/gtest.h>
#include <octomap/AbstractOcTree.h>
#include <octomap/ColorOcTree.h>

#include <fstream>
#include <memory>
#include <random>

#include "fvx/core/error.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "test_support.hpp"

namespace fvx::map {
namespace {

OccupancyMap small_map() {
  OccupancyMap map(0.1);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 20; ++i) points.emplace_back(1.0f + 0.05f * i, -0.5f + 0.05f * i, 0.3f);
  map.integrate(points, Eigen::Vector3f(0, 0, 0));
  return map;
}

TEST(MapIo, OtRoundTripKeepsProbabilities) {
  const test::TempDir dir;
  const OccupancyMap map = small_map();
  map.save(dir / "m.ot");
  const OccupancyMap back = OccupancyMap::load(dir / "m.ot");
  EXPECT_EQ(back.resolution_m(), 0.1);
  EXPECT_EQ(back.stats().nodes, map.stats().nodes);
  const auto key = *map.key_of({1.0, -0.5, 0.3});
  ASSERT_TRUE(back.probability(key).has_value());
  EXPECT_DOUBLE_EQ(*back.probability(key), *map.probability(key));
}

// fvx reads an OcTree .ot into its own tree instead of OctoMap's reader and a copy: the same
// tree, node for node (written back, the bytes OctoMap's reader and writer give), also for
// an empty map (size 0, no data).
TEST(MapIo, AnOcTreeOtLoadsAsOctoMapsOwnReaderReadsIt) {
  const test::TempDir dir;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  OccupancyMap map(0.05);
  for (int scan = 0; scan < 3; ++scan) {
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i < 2000; ++i) points.emplace_back(2.0f + u(rng), u(rng), 0.5f * u(rng));
    map.integrate(points, Eigen::Vector3f(0.0f, 0.3f * float(scan), 0.2f));
  }
  const OccupancyMap empty(0.05);
  for (const OccupancyMap* m : {static_cast<const OccupancyMap*>(&map), &empty}) {
    m->save(dir / "m.ot");
    const OccupancyMap loaded = OccupancyMap::load(dir / "m.ot");
    loaded.save(dir / "fvx.ot");
    std::ifstream in(dir / "m.ot", std::ios::binary);
    const std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(in));
    ASSERT_TRUE(tree);
    ASSERT_TRUE(tree->write(dir / "octomap.ot"));
    EXPECT_EQ(test::slurp(dir / "fvx.ot"), test::slurp(dir / "octomap.ot"));
    EXPECT_EQ(loaded.stats().nodes, tree->size());
    EXPECT_EQ(loaded.resolution_m(), tree->getResolution());
  }
  EXPECT_GT(map.stats().nodes, 1000u);
}

TEST(MapIo, BtRoundTripKeepsStatesAndLeavesTheMapIntact) {
  const test::TempDir dir;
  const OccupancyMap map = small_map();
  const auto key = *map.key_of({0.5, -0.25, 0.15});
  const double p_before = *map.probability(key);
  map.save(dir / "m.bt");
  EXPECT_DOUBLE_EQ(*map.probability(key), p_before);  // saving .bt did not threshold the map
  const OccupancyMap back = OccupancyMap::load(dir / "m.bt");
  EXPECT_EQ(back.stats().occupied_leaves, map.stats().occupied_leaves);
  EXPECT_EQ(back.state(key), VoxelState::Free);
}

TEST(MapIo, ColorOcTreeIsReadAsOccupancy) {
  const test::TempDir dir;
  octomap::ColorOcTree color(0.1);
  color.updateNode(octomap::point3d(0.05f, 0.05f, 0.05f), true);
  color.updateNode(octomap::point3d(0.25f, 0.05f, 0.05f), false);
  ASSERT_TRUE(color.write(dir / "c.ot"));
  const OccupancyMap map = OccupancyMap::load(dir / "c.ot");
  EXPECT_EQ(map.state(*map.key_of({0.05, 0.05, 0.05})), VoxelState::Occupied);
  EXPECT_EQ(map.state(*map.key_of({0.25, 0.05, 0.05})), VoxelState::Free);
  EXPECT_EQ(map.state(*map.key_of({0.45, 0.05, 0.05})), VoxelState::Unknown);
}

TEST(MapIo, RealColorOcTreeAndLaserMapLoad) {
  FVX_REAL_DATA_OR_SKIP(color_path, "octomap-maps/octomap_tutor/map.ot");
  FVX_REAL_DATA_OR_SKIP(geb_path, "octomap-maps/octomap-share-data/geb079.bt");
  const Stats color = OccupancyMap::load(color_path).stats();
  EXPECT_EQ(color.resolution_m, 0.05);
  EXPECT_GT(color.occupied_leaves, 0u);
  const Stats geb = OccupancyMap::load(geb_path).stats();
  EXPECT_EQ(geb.resolution_m, 0.08);
  EXPECT_EQ(geb.occupied_leaves, 143729u);  // PROVENANCE.md
  EXPECT_EQ(geb.free_leaves, 284415u);
}

TEST(MapIo, BadFilesAreRefusedWithTheirName) {
  const test::TempDir dir;
  small_map().save(dir / "good.bt");
  std::ifstream in(dir / "good.bt", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(dir / "truncated.bt", std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
  std::ofstream(dir / "text.ot") << "hello, I am not a map\n";
  std::ofstream(dir / "text.bt") << "hello, I am not a map\n";
  std::ofstream(dir / "map.xyz") << "x";
  for (const char* name : {"truncated.bt", "text.ot", "text.bt", "missing.bt", "map.xyz"}) {
    try {
      OccupancyMap::load(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

TEST(MapIo, AFailedSaveLeavesTheExistingFileUntouched) {
  const test::TempDir dir;
  small_map().save(dir / "m.bt");
  std::ifstream in(dir / "m.bt", std::ios::binary);
  const std::string before((std::istreambuf_iterator<char>(in)), {});
  EXPECT_THROW(small_map().save(dir / "m.txt"), Error);
  EXPECT_THROW(small_map().save(dir / "no-such-folder/m.bt"), Error);
  std::ifstream again(dir / "m.bt", std::ios::binary);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), {}), before);
  // No temporary files are left behind.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) files += entry.is_regular_file();
  EXPECT_EQ(files, 1u);
}

}  // namespace
}  // namespace fvx::map
