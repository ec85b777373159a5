// The fine pass's nearest-neighbour search: a search started from a hint (the partner of the
// iteration before) finds what the plain search finds, whatever the hint.
#include <gtest/gtest.h>

#include <random>

#include "point_to_plane.hpp"

namespace fvx::test {
namespace {

using registration::Cloud;
using registration::TargetSurface;

/// Random points in a 1 m box, plus points on a 2 cm lattice (many equally near ones for a
/// query on the lattice's planes) and exact duplicates.
Cloud::Ptr target_cloud(std::mt19937& rng) {
  auto cloud = std::make_shared<Cloud>();
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 3000; ++i) cloud->push_back({u(rng), u(rng), u(rng)});
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 12; ++y)
      for (int z = 0; z < 4; ++z) cloud->push_back({0.3f + 0.02f * float(x), 0.3f + 0.02f * float(y), 0.5f + 0.02f * float(z)});
  for (int i = 0; i < 200; ++i) cloud->push_back((*cloud)[std::size_t(i) * 7]);
  return cloud;
}

// Oracle: TargetSurface::nearest without a hint. Hints: none, the answer itself, a random
// point, a far point, and the answer for a nearby query (what the fine pass passes).
TEST(TargetSurface, AHintedSearchFindsWhatThePlainSearchFinds) {
  std::mt19937 rng(11);
  const Cloud::Ptr cloud = target_cloud(rng);
  const TargetSurface surface(cloud);
  std::uniform_real_distribution<float> u(-0.1f, 1.1f), jitter(-0.01f, 0.01f);
  std::uniform_int_distribution<int> any(0, int(cloud->size()) - 1);
  std::size_t found = 0, pairs = 0;
  for (int n = 0; n < 4000; ++n) {
    Eigen::Vector3f q(u(rng), u(rng), u(rng));
    if (n % 4 == 0) q = Eigen::Vector3f(0.31f, 0.33f + 0.02f * float(n % 5), 0.51f);  // between lattice points
    for (const float limit : {0.01f, 0.05f, 0.1f, 2.0f}) {
      float expected_sq = -1, near_sq = -1;
      const int expected = surface.nearest(q, limit * limit, expected_sq);
      float moved_sq = 0;
      const int nearby = surface.nearest(q + Eigen::Vector3f(jitter(rng), jitter(rng), jitter(rng)), limit * limit, moved_sq);
      for (const int hint : {-1, expected, any(rng), 0, nearby}) {
        const int got = surface.nearest_near(q, limit * limit, hint, near_sq);
        ASSERT_EQ(got, expected) << "query " << q.transpose() << " limit " << limit << " hint " << hint;
        if (expected >= 0) {
          EXPECT_EQ(near_sq, expected_sq);
        }
      }
      found += expected >= 0;
      ++pairs;
    }
  }
  EXPECT_GT(found, pairs / 4);  // queries with and without a partner within the limit both occur
  EXPECT_LT(found, pairs - pairs / 10);
}

}  // namespace
}  // namespace fvx::test
