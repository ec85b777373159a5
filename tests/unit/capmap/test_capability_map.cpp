// The direction set, the capability map's queries, its file (round trip, determinism,
// corruption) and the merge of shards.
#include <gtest/gtest.h>

#include <fstream>

#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/error.hpp"
#include "test_support.hpp"

namespace fvx::capmap {
namespace {

TEST(DirectionSet, UnitSpiralWithNearestLookup) {
  const DirectionSet set(200);
  ASSERT_EQ(set.size(), 200);
  double closest = M_PI;
  for (int i = 0; i < 200; ++i) {
    EXPECT_NEAR(set[i].norm(), 1.0, 1e-12);
    EXPECT_EQ(set.nearest(set[i]), i);
    for (int j = i + 1; j < 200; ++j) closest = std::min(closest, std::acos(std::min(1.0, set[i].dot(set[j]))));
  }
  EXPECT_NEAR(set.mean_spacing_rad(), 0.2507, 1e-3);
  EXPECT_GT(closest, 0.5 * set.mean_spacing_rad());  // evenly spread: no two crowd together
  EXPECT_EQ(set.nearest((set[17] + 0.05 * set[17].unitOrthogonal()).normalized()), 17);
}

CapabilityHeader small_header() {
  CapabilityHeader h;
  h.base_link = "base_link";
  h.tip_link = "kinect_optical";
  h.urdf_hash = "0123456789abcdef";
  h.voxel_m = 0.1;
  h.origin_m = Eigen::Vector3d(-1, -1, 0);
  h.dims = {20, 20, 15};
  h.method = "test";
  h.fvx_version = "test";
  return h;
}

CapabilityMap small_map(std::uint32_t shard_index = 0, std::uint32_t shard_count = 1) {
  CapabilityHeader h = small_header();
  h.shard_index = shard_index;
  h.shard_count = shard_count;
  CapabilityMap map(h);
  for (std::int64_t v = 0; v < 6000; v += 37)
    if (shard_count == 1 || std::uint32_t(v / 400) % shard_count == shard_index)  // z-slabs
      for (int d = int(v % 7); d < 200; d += 13) map.set(v, d);
  return map;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST(CapabilityMap, QueriesFindTheVoxelAndTheNearestDirection) {
  CapabilityMap map(small_header());
  const Eigen::Vector3d p(0.33, -0.47, 0.81);
  const std::int64_t v = map.voxel_of(p);
  ASSERT_GE(v, 0);
  EXPECT_EQ(map.voxel_of(map.center_of(v)), v);
  EXPECT_LE((map.center_of(v) - p).cwiseAbs().maxCoeff(), 0.05 + 1e-12);
  map.set(v, 42);
  const Eigen::Vector3d d = map.directions()[42];
  EXPECT_TRUE(map.reachable(p, (d + 0.05 * d.unitOrthogonal()).normalized()));
  EXPECT_FALSE(map.reachable(p, map.directions()[43]));
  EXPECT_DOUBLE_EQ(map.reachability_index(p), 0.5);  // 1 of 200
  EXPECT_EQ(map.voxel_of({5, 0, 0}), -1);
  EXPECT_FALSE(map.reachable(Eigen::Vector3d(5, 0, 0), d));
}

TEST(CapabilityMap, WorldFrameQueriesGoThroughTheBasePose) {
  CapabilityMap map(small_header());
  const Eigen::Vector3d p_base(0.33, -0.47, 0.81);
  map.set(map.voxel_of(p_base), 42);
  Eigen::Isometry3d T_world_base(Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.2, -0.3, 1).normalized()));
  T_world_base.translation() << 2.0, -1.0, 0.3;
  const Eigen::Vector3d d_base = map.directions()[42];
  EXPECT_TRUE(map.reachable(T_world_base, T_world_base * p_base, T_world_base.linear() * d_base));
  EXPECT_FALSE(map.reachable(T_world_base, p_base, d_base));  // the base-frame point, taken as world
  const auto dirs = map.reachable_directions(T_world_base, T_world_base * p_base);
  ASSERT_EQ(dirs.size(), 1u);
  EXPECT_TRUE(dirs[0].isApprox(T_world_base.linear() * d_base));
}

TEST(CapabilityMap, FileRoundTripIsExactAndDeterministic) {
  const test::TempDir dir;
  const CapabilityMap map = small_map();
  map.save(dir / "a.fcm");
  const CapabilityMap back = CapabilityMap::load(dir / "a.fcm");
  EXPECT_EQ(back.voxels(), map.voxels());
  EXPECT_EQ(back.header().urdf_hash, "0123456789abcdef");
  EXPECT_EQ(back.header().dims, map.header().dims);
  back.save(dir / "b.fcm");
  EXPECT_TRUE(bytes_of(dir / "a.fcm") == bytes_of(dir / "b.fcm"));
}

TEST(CapabilityMap, ShardsMergeIntoTheSingleRunFile) {
  const test::TempDir dir;
  small_map().save(dir / "single.fcm");
  std::vector<CapabilityMap> shards;
  for (std::uint32_t i = 0; i < 3; ++i) {
    small_map(i, 3).save(dir / ("part" + std::to_string(i) + ".fcm"));
    shards.push_back(CapabilityMap::load(dir / ("part" + std::to_string(i) + ".fcm")));
  }
  CapabilityMap::merge(shards).save(dir / "merged.fcm");
  EXPECT_TRUE(bytes_of(dir / "merged.fcm") == bytes_of(dir / "single.fcm"));
  shards.pop_back();
  EXPECT_THROW(CapabilityMap::merge(shards), Error);  // a missing shard
}

TEST(CapabilityMap, CorruptFilesAreRefused) {
  const test::TempDir dir;
  small_map().save(dir / "good.fcm");
  const std::string good = bytes_of(dir / "good.fcm");
  std::string flipped = good;
  flipped[good.size() / 2] = char(flipped[good.size() / 2] ^ 0x10);
  std::ofstream(dir / "flipped.fcm", std::ios::binary) << flipped;
  std::ofstream(dir / "truncated.fcm", std::ios::binary) << good.substr(0, good.size() - 100);
  std::ofstream(dir / "short.fcm", std::ios::binary) << good.substr(0, 12);
  std::ofstream(dir / "text.fcm") << "hello\n";
  for (const char* name : {"flipped.fcm", "truncated.fcm", "short.fcm", "text.fcm", "missing.fcm"}) {
    try {
      CapabilityMap::load(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(small_map().save(dir / "map.bin"), FileError);
}

}  // namespace
}  // namespace fvx::capmap
