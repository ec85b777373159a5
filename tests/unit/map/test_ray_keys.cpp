// The ray traversal used by integrate() visits exactly the cells of OctoMap's computeRayKeys.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <random>

#include "../../../src/map/ray_keys.hpp"

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

}  // namespace
}  // namespace fvx::map
