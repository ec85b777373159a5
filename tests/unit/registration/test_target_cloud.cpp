// The registration target: one point per world cell, the mean of what fell in it.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "fvx/registration/target_cloud.hpp"

namespace fvx::test {
namespace {

using registration::TargetCloud;

TEST(TargetCloud, WithoutACellEveryFinitePointIsKeptInOrder) {
  TargetCloud target(0.0);
  target.add({{1, 2, 3}, {NAN, 0, 0}, {1, 2, 3}, {-4, 5, 6}});
  ASSERT_EQ(target.points().size(), 3u);
  EXPECT_EQ(target.points()[2], Eigen::Vector3f(-4, 5, 6));
}

// Oracle: group by floor(p / cell) in a std::map and average, on random points in a small box
// (many per cell, negative coordinates included), added in three batches.
TEST(TargetCloud, EachCellHoldsTheMeanOfItsPoints) {
  const double cell = 0.025;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  std::vector<Eigen::Vector3f> all;
  TargetCloud target(cell);
  for (int batch = 0; batch < 3; ++batch) {
    std::vector<Eigen::Vector3f> points(2000);
    for (auto& p : points) p = {u(rng), u(rng), u(rng)};
    target.add(points);
    all.insert(all.end(), points.begin(), points.end());
  }
  std::map<std::tuple<int, int, int>, std::pair<Eigen::Vector3d, int>> oracle;
  for (const auto& p : all) {
    const Eigen::Vector3d d = p.cast<double>();
    auto& [sum, n] = oracle[{int(std::floor(d.x() / cell)), int(std::floor(d.y() / cell)), int(std::floor(d.z() / cell))}];
    if (n == 0) sum.setZero();
    sum += d;
    ++n;
  }
  ASSERT_EQ(target.points().size(), oracle.size());
  for (const auto& p : target.points()) {
    const Eigen::Vector3d d = p.cast<double>();
    const auto it = oracle.find({int(std::floor(d.x() / cell)), int(std::floor(d.y() / cell)), int(std::floor(d.z() / cell))});
    ASSERT_NE(it, oracle.end());
    EXPECT_LT((d - it->second.first / it->second.second).norm(), 1e-6);
  }
}

TEST(TargetCloud, ScanPointsArePlacedByTheirPose) {
  Eigen::Isometry3d T = Eigen::Isometry3d(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  T.translation() << 1.0, -2.0, 0.5;
  const std::vector<Eigen::Vector3d> sensor = {{0.1, 0.2, 2.0}, {-0.3, 0.0, 1.5}, {NAN, 0, 1}};
  TargetCloud a(0.05), b(0.05);
  a.add(T, sensor);
  b.add(std::vector<Eigen::Vector3f>{(T * sensor[0]).cast<float>(), (T * sensor[1]).cast<float>()});
  ASSERT_EQ(a.points().size(), 2u);
  EXPECT_LT((a.points()[0] - b.points()[0]).norm(), 1e-6);
  EXPECT_LT((a.points()[1] - b.points()[1]).norm(), 1e-6);
}

}  // namespace
}  // namespace fvx::test
