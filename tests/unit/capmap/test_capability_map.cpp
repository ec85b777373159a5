// The direction set, the capability map's queries, its file (round trip, determinism,
// corruption) and the merge of shards.
#include <gtest/gtest.h>

#include <cstring>

#include <fstream>

#include "capmap_fixtures.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/error.hpp"
#include "test_support.hpp"

namespace fvx::capmap {
namespace {

using fixtures::bytes_of;

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
  h.method = "fk-seeded-ik";
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

// The reachable box bounds the voxels with a reachable direction, as cubes, and no more:
// every query outside it has index 0, and each face of it touches such a voxel.
TEST(CapabilityMap, TheReachableBoxHoldsEveryReachableVoxelTightly) {
  CapabilityMap map(small_header());
  EXPECT_TRUE(map.reachable_box_base().isEmpty());
  const std::vector<Eigen::Vector3d> reached = {{0.33, -0.47, 0.81}, {-0.62, 0.15, 0.05}, {0.71, 0.88, 1.32}};
  for (const auto& p : reached) map.set(map.voxel_of(p), 7);
  const Eigen::AlignedBox3d box = map.reachable_box_base();
  for (const auto& p : reached) {
    EXPECT_TRUE(box.contains(map.center_of(map.voxel_of(p))));
    EXPECT_GT(map.reachability_index(p), 0.0);
  }
  EXPECT_NEAR(box.min().x(), map.center_of(map.voxel_of(reached[1])).x() - 0.05, 1e-12);
  EXPECT_NEAR(box.max().z(), map.center_of(map.voxel_of(reached[2])).z() + 0.05, 1e-12);
  for (double x = -1.0; x < 1.0; x += 0.03)
    for (double z = 0.0; z < 1.5; z += 0.03) {
      const Eigen::Vector3d p(x, 0.15, z);
      if (!box.contains(p)) {
        EXPECT_EQ(map.reachability_index(p), 0.0) << p.transpose();
      }
    }
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

// A bit past the last direction (here in the last voxel's last word, with a valid checksum)
// would make counts and lists of directions disagree: the file is refused.
TEST(CapabilityMap, BitsBeyondTheLastDirectionAreRefused) {
  const test::TempDir dir;
  small_map().save(dir / "good.fcm");
  std::string bytes = bytes_of(dir / "good.fcm");
  std::string body = bytes.substr(0, bytes.size() - 8);
  body[body.size() - 1] = char(body[body.size() - 1] | 0x80);  // bit 63 of the last word (200 directions)
  std::uint64_t hash = 14695981039346656037ull;  // the file's checksum (FNV-1a 64, format version 2)
  for (const char c : body) hash = (hash ^ std::uint8_t(c)) * 1099511628211ull;
  for (int i = 0; i < 8; ++i) body.push_back(char(hash >> (8 * i) & 0xff));
  std::ofstream(dir / "bits.fcm", std::ios::binary) << body;
  try {
    CapabilityMap::load(dir / "bits.fcm");
    ADD_FAILURE() << "accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond its 200 directions"), std::string::npos) << e.what();
  }
}

/// `body` (a file without its checksum) with its version set and FNV-1a 64 from `basis` appended.
std::string with_version(std::string body, std::uint32_t version, std::uint64_t basis) {
  std::memcpy(body.data() + 8, &version, sizeof version);
  std::uint64_t hash = basis;
  for (const char c : body) hash = (hash ^ std::uint8_t(c)) * 1099511628211ull;
  for (int i = 0; i < 8; ++i) body.push_back(char(hash >> (8 * i) & 0xff));
  return body;
}

// Format version 2 (this fvx's) checksums with FNV-1a's own offset basis; version 1 files
// (the old basis, centre bits) still load with the same bits; other versions are refused.
TEST(CapabilityMap, VersionOneFilesStillLoadAndUnknownVersionsAreRefused) {
  const test::TempDir dir;
  small_map().save(dir / "v2.fcm");
  const std::string bytes = bytes_of(dir / "v2.fcm");
  const std::string body = bytes.substr(0, bytes.size() - 8);
  std::ofstream(dir / "v1.fcm", std::ios::binary) << with_version(body, 1, 1469598103934665603ull);
  std::ofstream(dir / "v3.fcm", std::ios::binary) << with_version(body, 3, 14695981039346656037ull);
  const CapabilityMap v1 = CapabilityMap::load(dir / "v1.fcm");
  EXPECT_EQ(v1.voxels(), small_map().voxels());
  try {
    CapabilityMap::load(dir / "v3.fcm");
    ADD_FAILURE() << "version 3 accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("version 3"), std::string::npos) << e.what();
  }
}

/// The file at `path` with `from` replaced by `to` in its header JSON, a valid checksum and
/// header length: a header that lies, as a fuzzer or another writer makes it.
std::string with_header_edit(const std::string& path, const std::string& from, const std::string& to) {
  const std::string bytes = bytes_of(path);  // magic (8), version (4), header length (4), header, voxels, checksum (8)
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  std::string header = bytes.substr(16, length);
  const std::string voxels = bytes.substr(16 + length, bytes.size() - 8 - 16 - length);
  const auto at = header.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  header.replace(at, from.size(), to);
  length = std::uint32_t(header.size());
  const std::string body = bytes.substr(0, 12) + std::string(reinterpret_cast<const char*>(&length), 4) + header + voxels;
  return with_version(body, 2, 14695981039346656037ull);
}

// Header numbers beyond what fvx builds are refused before anything is sized by them: 2e9
// directions allocated gigabytes, dims whose product overflowed int64 loaded with exit 0.
TEST(CapabilityMap, HeadersThatLieAboutTheirSizesAreRefusedBeforeAllocating) {
  const test::TempDir dir;
  small_map().save(dir / "good.fcm");
  const std::string good = bytes_of(dir / "good.fcm");
  const std::string dims = good.substr(good.find("\"dims\":"), good.find("]", good.find("\"dims\":")) - good.find("\"dims\":") + 1);
  const std::vector<std::pair<std::string, std::string>> lies = {
      {"\"directions\":200", "\"directions\":2000000000"},
      {dims, "\"dims\":[4000000000,4000000000,4000000000]"},
      {dims, "\"dims\":[1048576,1048576,1048576]"},
      {"\"voxel_m\":", "\"voxel_m\":-"},
  };
  for (const auto& [from, to] : lies) {
    std::ofstream(dir / "lie.fcm", std::ios::binary) << with_header_edit(dir / "good.fcm", from, to);
    try {
      CapabilityMap::load(dir / "lie.fcm");
      ADD_FAILURE() << to << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("bad capability-map header"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace fvx::capmap
