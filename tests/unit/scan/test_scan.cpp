// Scan preprocessing: NaN removal, depth limits, voxel downsampling, back-projection.
#include <gtest/gtest.h>

#include "fvx/io/depth_image.hpp"
#include "fvx/scan/scan.hpp"
#include "test_support.hpp"

namespace fvx::scan {
namespace {

TEST(Filter, RemovesNonFiniteAndAppliesDepthLimitsHalfOpen) {
  Scan s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.points_sensor = {{0, 0, 0.5}, {nan, 0, 1}, {0, 0, 1.0}, {0, 0, 6.999}, {0, 0, 7.0}, {0, 0, 8}};
  FilterConfig config;
  config.depth_min_m = 1.0;
  config.depth_max_m = 7.0;
  const FilterStats stats = filter(s, config);
  EXPECT_EQ(stats.input, 6u);
  EXPECT_EQ(stats.non_finite, 1u);
  EXPECT_EQ(stats.out_of_depth, 3u);  // 0.5, 7.0 (at the limit), 8
  EXPECT_EQ(stats.kept, 2u);
  EXPECT_EQ(s.points_sensor[0].z(), 1.0);
  EXPECT_EQ(s.points_sensor[1].z(), 6.999);
}

TEST(Filter, VoxelDownsampleKeepsCentroidsInFirstSeenOrder) {
  const auto out = voxel_downsample({{0.01, 0.01, 0.01}, {1.01, 0, 0}, {0.03, 0.03, 0.03}, {-0.01, 0, 0}}, 0.1);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_TRUE(out[0].isApprox(Eigen::Vector3d(0.02, 0.02, 0.02)));
  EXPECT_TRUE(out[1].isApprox(Eigen::Vector3d(1.01, 0, 0)));
  EXPECT_TRUE(out[2].isApprox(Eigen::Vector3d(-0.01, 0, 0)));  // negative side is its own voxel
}

TEST(Backproject, PinholeWithNegativeFocalLength) {
  io::DepthImage depth{3, 2, {0, 2000, 0, 0, 0, 5000}};
  io::Intrinsics K{500.0, -500.0, 1.0, 0.5, 1000.0, 3, 2};
  const auto points = backproject(depth, K);
  ASSERT_EQ(points.size(), 6u);
  EXPECT_FALSE(points[0].allFinite());  // d = 0: no measurement
  EXPECT_TRUE(points[1].isApprox(Eigen::Vector3d(0.0, (0 - 0.5) * 2.0 / -500.0, 2.0)));
  EXPECT_GT(points[1].y(), 0.0);        // above the principal point, flipped by fy < 0
  EXPECT_TRUE(points[5].isApprox(Eigen::Vector3d(1 * 5.0 / 500.0, (1 - 0.5) * 5.0 / -500.0, 5.0)));
  K.depth_scale = 5000.0;  // TUM scale: the same raw value is 5x closer
  EXPECT_DOUBLE_EQ(backproject(depth, K)[5].z(), 1.0);
}

TEST(BackprojectRealData, IclNuimScale5000) {
  FVX_REAL_DATA_OR_SKIP(path, "icl-nuim-slambook2-5f/depth/1.png");
  const io::DepthImage depth = io::read_depth_image(path);
  const auto points = backproject(depth, {481.2, -480.0, 319.5, 239.5, 5000.0, 640, 480});
  double z_min = 1e9, z_max = 0;
  for (const auto& p : points) {
    ASSERT_TRUE(p.allFinite());  // 100 % valid (PROVENANCE.md)
    z_min = std::min(z_min, p.z());
    z_max = std::max(z_max, p.z());
  }
  EXPECT_GT(z_min, 0.70);  // 0.71–4.28 m
  EXPECT_LT(z_max, 4.30);
}

}  // namespace
}  // namespace fvx::scan
