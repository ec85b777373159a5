// The ray traversal used by integrate() visits exactly the cells of OctoMap's computeRayKeys.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <random>

#include "../../../src/map/ray_keys.hpp"
#include "../../../src/map/key_bitmap.hpp"
#include "../../../src/map/ray_lanes.hpp"

namespace fvx::map {
namespace {

/// One KeyRay for every ray: its constructor fills 100 000 keys, which under ASan took most
/// of these tests' 30 s.
octomap::KeyRay& reused_key_ray() {
  static octomap::KeyRay ray;
  return ray;
}

void expect_same_keys(const octomap::OcTree& tree, const octomap::point3d& a, const octomap::point3d& b) {
  octomap::KeyRay& reference = reused_key_ray();
  const bool ok_reference = tree.computeRayKeys(a, b, reference);
  std::vector<octomap::OcTreeKey> mine;
  const bool ok_mine = for_each_ray_key(tree, a, b, [&](const octomap::OcTreeKey& k) { mine.push_back(k); });
  ASSERT_EQ(ok_mine, ok_reference);
  ASSERT_EQ(mine.size(), reference.size()) << a << " -> " << b;
  std::size_t i = 0;
  for (const auto& k : reference) ASSERT_EQ(mine[i++], k) << a << " -> " << b << " step " << i;
}

TEST(RayKeys, EqualToOctoMapOnRandomRays) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coord(-4.0f, 4.0f);
  for (double resolution : {0.025, 0.05, 0.1}) {
    const octomap::OcTree tree(resolution);
    for (int i = 0; i < 20000; ++i)
      expect_same_keys(tree, {coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)});
  }
}

// The bitmap walk (integrate's hot loop) marks computeRayKeys's cells, in its order, in a
// box holding both ends with integrate's margin of two cells.
void expect_same_marks(const octomap::OcTree& tree, const octomap::point3d& a, const octomap::point3d& b) {
  octomap::KeyRay& reference = reused_key_ray();
  const bool ok_reference = tree.computeRayKeys(a, b, reference);
  octomap::OcTreeKey ka, kb;
  if (!tree.coordToKeyChecked(a, ka) || !tree.coordToKeyChecked(b, kb)) {
    EXPECT_FALSE(ok_reference);
    return;
  }
  int lo[3], n[3];
  for (int i = 0; i < 3; ++i) {
    lo[i] = std::min(ka[i], kb[i]) - 2;
    n[i] = std::max(ka[i], kb[i]) + 2 - lo[i] + 1;
  }
  const std::int64_t stride[3] = {1, n[0], std::int64_t(n[0]) * n[1]};
  const auto index_of = [&](const octomap::OcTreeKey& k) {
    return (std::int64_t(k[2] - lo[2]) * n[1] + (k[1] - lo[1])) * n[0] + (k[0] - lo[0]);
  };
  std::vector<std::int64_t> marks;
  ASSERT_EQ(mark_ray_cells(tree, a, b, stride, index_of, [&](std::int64_t i) { marks.push_back(i); }), ok_reference);
  ASSERT_EQ(marks.size(), reference.size()) << a << " -> " << b;
  std::size_t i = 0;
  for (const auto& k : reference) ASSERT_EQ(marks[i++], index_of(k)) << a << " -> " << b << " step " << i;
}

TEST(RayKeys, TheBitmapWalkMarksOctoMapsCells) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> coord(-4.0f, 4.0f);
  for (double resolution : {0.025, 0.05, 0.1}) {
    const octomap::OcTree tree(resolution);
    for (int i = 0; i < 20000; ++i)
      expect_same_marks(tree, {coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)});
  }
  const octomap::OcTree tree(0.05);
  const float border = 0.05f * 7;  // exactly on a cell border
  expect_same_marks(tree, {0.01f, 0.01f, 0.01f}, {2.01f, 0.01f, 0.01f});
  expect_same_marks(tree, {border, border, border}, {-border, 3 * border, 0.0f});
  expect_same_marks(tree, {0, 0, 0}, {1, 1, 1});  // through cell corners
  expect_same_marks(tree, {0.01f, 0.01f, 0.01f}, {0.02f, 0.02f, 0.02f});  // same cell
}

TEST(RayKeys, EqualToOctoMapOnAxisAlignedAndBorderRays) {
  const octomap::OcTree tree(0.05);
  const float border = 0.05f * 7;  // exactly on a cell border
  expect_same_keys(tree, {0.01f, 0.01f, 0.01f}, {2.01f, 0.01f, 0.01f});
  expect_same_keys(tree, {0.01f, 0.01f, 0.01f}, {0.01f, -2.01f, 0.01f});
  expect_same_keys(tree, {border, border, border}, {-border, 3 * border, 0.0f});
  expect_same_keys(tree, {0, 0, 0}, {1, 1, 1});  // through cell corners
  expect_same_keys(tree, {0.01f, 0.01f, 0.01f}, {0.02f, 0.02f, 0.02f});  // same cell
  expect_same_keys(tree, {0, 0, 0}, {5000.0f, 0, 0});                   // end outside the key space
}

// The eight-lane walk (integrate's hot loop where the CPU has AVX-512) and the four-lane one
// (AVX2) set exactly the bits the one-ray walk marks: 30 000 rays from one origin (as a scan's) and 10 000 from anywhere,
// in batches whose sizes are not multiples of eight, including axis-parallel rays and rays
// through cell corners or along two axes at once, whose t's tie. A CPU without the
// instructions cannot run a walk at all: its test skips, and the RayLanes ctest entries
// (tests/CMakeLists.txt) run the OctoMap oracles with the walks it has.
void expect_lanes_set_the_one_ray_walks_bits(void (*walk_in_lanes)(const MarkedRays&, std::uint64_t*)) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coord(-2.0f, 2.0f);
  const octomap::OcTree tree(0.05);
  const std::array<int, 3> lo{32768 - 100, 32768 - 100, 32768 - 100}, hi{32768 + 100, 32768 + 100, 32768 + 100};
  DenseKeyBitmap lanes(lo, hi), one(lo, hi);
  const auto index_of = [&](const octomap::OcTreeKey& k) { return std::int64_t(one.index(k)); };
  std::uint64_t* const one_words = one.words();
  const auto mark = [&](std::int64_t i) { one_words[std::uint64_t(i) >> 6] |= std::uint64_t(1) << (i & 63); };
  MarkedRays batch;
  std::size_t rays = 0;
  auto add = [&](const octomap::point3d& a, const octomap::point3d& b) {
    MarkedRay ray;
    bool empty = false;
    if (!start_marked_ray(tree, a, b, one.strides(), index_of, ray, empty) || empty) return;
    walk_marked_ray(ray, mark);
    batch.push(ray);
    ++rays;
    if (batch.size() == 997) {
      walk_in_lanes(batch, lanes.words());
      batch.clear();
    }
  };
  const octomap::point3d origin(0.013f, -0.021f, 0.037f);
  for (int i = 0; i < 30000; ++i) add(origin, {coord(rng), coord(rng), coord(rng)});
  for (int i = 0; i < 10000; ++i) add({coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)});
  for (float f : {-1.5f, -0.35f, 0.35f, 1.5f}) {
    add({0.01f, 0.01f, 0.01f}, {f, 0.01f, 0.01f});
    add({0.01f, 0.01f, 0.01f}, {0.01f, f, 0.01f});
    add({0.01f, 0.01f, 0.01f}, {0.01f, 0.01f, f});
    add({0, 0, 0}, {f, f, f});
    add({0.35f, 0.35f, 0.35f}, {-f, 3 * f, 0.0f});
    // Two axes tie at every crossing (equal offsets and slopes), the third does not.
    add({0.01f, 0.01f, 0.013f}, {0.01f + f, 0.01f + f, 0.013f + 0.3f * f});
    add({0.01f, 0.013f, 0.01f}, {0.01f + f, 0.013f - 0.3f * f, 0.01f + f});
    add({0.013f, 0.01f, 0.01f}, {0.013f + 0.3f * f, 0.01f - f, 0.01f - f});
  }
  walk_in_lanes(batch, lanes.words());
  ASSERT_GT(rays, 39000u);
  std::size_t bits = 0, differ = 0;
  one.for_each([&](const octomap::OcTreeKey& k) {
    ++bits;
    differ += !lanes.contains(k);
  });
  lanes.for_each([&](const octomap::OcTreeKey& k) { differ += !one.contains(k); });
  EXPECT_GT(bits, 100000u);
  EXPECT_EQ(differ, 0u);
}

TEST(RayKeys, TheEightLaneWalkSetsTheOneRayWalksBits) {
  if (!ray_lanes_available()) GTEST_SKIP() << "this CPU has no AVX-512 (F, DQ)";
  expect_lanes_set_the_one_ray_walks_bits(mark_rays_in_lanes);
}

TEST(RayKeys, TheFourLaneWalkSetsTheOneRayWalksBits) {
  if (!four_ray_lanes_available()) GTEST_SKIP() << "this CPU has no AVX2";
  expect_lanes_set_the_one_ray_walks_bits(mark_rays_in_four_lanes);
}

}  // namespace
}  // namespace fvx::map
