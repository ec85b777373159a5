// The virtual depth sensor against analytic truth: a plane at a known distance and angle,
// a cube's silhouette, range limits, seeded noise with the model's σ.
#include <gtest/gtest.h>

#include <cmath>

#include "fvx/core/error.hpp"
#include "fvx/sim/depth_sensor.hpp"

namespace fvx::sim {
namespace {

/// A large square plane (two triangles) through `center` with unit normal `n`.
Mesh plane(const Eigen::Vector3f& center, const Eigen::Vector3f& n, float half_size) {
  const Eigen::Vector3f u = n.unitOrthogonal() * half_size, w = n.cross(n.unitOrthogonal()) * half_size;
  Mesh m;
  m.vertices = {center - u - w, center + u - w, center + u + w, center - u + w};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

/// Looking along +z from the origin: the optical frame is the world frame.
const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

TEST(DepthSensor, TiltedPlaneGivesTheExactDepthAtEveryPixel) {
  // Plane through (0, 0, 2) tilted 30° about x: points with n·(p − c) = 0.
  const Eigen::Vector3f n = Eigen::AngleAxisf(float(M_PI / 6), Eigen::Vector3f::UnitX()) * Eigen::Vector3f(0, 0, -1);
  const Mesh mesh = plane({0, 0, 2}, n, 20.0f);
  SensorConfig config;
  config.depth_max_m = 10.0;
  for (Backend backend : {Backend::Embree, Backend::CgalAabb, Backend::BruteForce}) {
    const auto caster = make_ray_caster(mesh, backend);
    config.intrinsics.width = 64;  // small image: the brute-force back end is slow
    config.intrinsics.height = 48;
    config.intrinsics.cx = 31.5;
    config.intrinsics.cy = 23.5;
    config.intrinsics.fx = config.intrinsics.fy = 52.5;
    const Frame frame = render(*caster, kIdentity, config);
    ASSERT_EQ(frame.valid, 64u * 48u) << to_string(backend);
    double worst = 0;
    for (int v = 0; v < 48; ++v) {
      for (int u = 0; u < 64; ++u) {
        const Eigen::Vector3d ray((u - 31.5) / 52.5, (v - 23.5) / 52.5, 1.0);
        // n·(z·ray − c) = 0  →  z = n·c / n·ray
        const double z = n.cast<double>().dot(Eigen::Vector3d(0, 0, 2)) / n.cast<double>().dot(ray);
        const Eigen::Vector3f p = frame.points_sensor[std::size_t(v) * 64 + u];
        worst = std::max(worst, std::abs(p.z() - z));
        EXPECT_LE(std::abs(frame.depth.at(v, u) / 1000.0 - z), 0.0005 + 1e-6);  // mm encoding
      }
    }
    EXPECT_LT(worst, 2e-6 * 4) << to_string(backend) << ": float error at up to 4 m";
  }
}

TEST(DepthSensor, CubeSeenFaceOnHasTheRightSilhouette) {
  Mesh mesh;
  mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-0.25f, -0.25f, 2.0f), Eigen::Vector3f(0.25f, 0.25f, 2.5f)));
  const auto caster = make_ray_caster(mesh);
  SensorConfig config;  // Kinect v1: 640×480, f = 525
  const Frame frame = render(*caster, kIdentity, config);
  std::size_t mismatches = 0, inside = 0;
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) {
      // The front face spans x, y ∈ [−0.25, 0.25] at z = 2: |u − cx| < 525·0.25/2 = 65.6.
      const double x = (u - 319.5) / 525.0 * 2.0, y = (v - 239.5) / 525.0 * 2.0;
      const bool expected = std::abs(x) < 0.25 && std::abs(y) < 0.25;
      const bool seen = frame.depth.at(v, u) != 0;
      inside += expected;
      if (expected != seen) ++mismatches;
      if (seen) {
        EXPECT_EQ(frame.depth.at(v, u), 2000);
      }
    }
  }
  EXPECT_EQ(inside, 17424u);  // 132 × 132 pixels
  EXPECT_EQ(mismatches, 0u);
}

TEST(DepthSensor, RangeLimitsDropPointsButStillOcclude) {
  Mesh mesh = plane({0, 0, 5}, {0, 0, -1}, 50.0f);
  Mesh near_plate;
  near_plate.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-0.1f, -0.1f, 0.3f), Eigen::Vector3f(0.1f, 0.1f, 0.31f)));
  mesh.append(near_plate);
  const auto caster = make_ray_caster(mesh);
  SensorConfig config;
  config.depth_max_m = 4.0;
  Frame frame = render(*caster, kIdentity, config);
  EXPECT_EQ(frame.valid, 0u);  // the wall at 5 m is beyond range, the plate nearer than 0.5 m
  EXPECT_GT(frame.too_near, 0u);
  EXPECT_EQ(frame.too_near + frame.no_surface, 640u * 480u);
  config.depth_max_m = 6.0;
  frame = render(*caster, kIdentity, config);
  EXPECT_EQ(frame.valid + frame.too_near, 640u * 480u);  // the plate hides the wall behind it
}

// A ray with no surface within range comes back as the point at no_return_depth_m along it
// when asked (a laser's max-range return), never in the depth image; too near or hit: as before.
TEST(DepthSensor, RaysWithoutASurfaceBecomeFarPointsWhenAsked) {
  Mesh mesh;
  mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-0.25f, -0.25f, 2.0f), Eigen::Vector3f(0.25f, 0.25f, 2.5f)));
  Mesh near_plate;  // covers the image's top-left corner, nearer than the minimum depth
  near_plate.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-1.0f, -1.0f, 0.3f), Eigen::Vector3f(-0.05f, -0.05f, 0.31f)));
  mesh.append(near_plate);
  const auto caster = make_ray_caster(mesh);
  SensorConfig config;
  const Frame kinect = render(*caster, kIdentity, config);
  config.no_return_depth_m = 8.0;
  const Frame laser = render(*caster, kIdentity, config);
  EXPECT_EQ(laser.valid, kinect.valid);
  EXPECT_EQ(laser.no_surface, kinect.no_surface);
  EXPECT_GT(kinect.too_near, 0u);
  EXPECT_EQ(laser.depth.raw, kinect.depth.raw);
  std::size_t far = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const std::size_t i = std::size_t(v) * 640 + u;
      const Eigen::Vector3f& k = kinect.points_sensor[i];
      const Eigen::Vector3f& l = laser.points_sensor[i];
      if (k.allFinite()) {
        EXPECT_EQ(l, k);
      } else if (l.allFinite()) {
        ++far;
        EXPECT_FLOAT_EQ(l.z(), 8.0f);
        EXPECT_NEAR(l.x(), float((u - 319.5) / 525.0 * 8.0), 1e-5);
      }
    }
  EXPECT_EQ(far, kinect.no_surface);  // too-near pixels stay without a point
  config.no_return_depth_m = 3.0;     // not beyond depth_max_m (4 m)
  EXPECT_THROW(render(*caster, kIdentity, config), Error);
}

TEST(DepthSensor, SameSeedSameNoiseAndTheModelSigma) {
  SensorConfig config;
  config.noise_m_per_m2 = 1.4e-3;
  config.depth_max_m = 5.0;
  config.intrinsics.depth_scale = 1e4;  // 0.1 mm steps: encoding does not hide the noise
  for (double distance : {1.0, 2.0, 3.0}) {
    const Mesh mesh = plane({0, 0, float(distance)}, {0, 0, -1}, 50.0f);
    const auto caster = make_ray_caster(mesh);
    config.seed = 7;
    const Frame a = render(*caster, kIdentity, config, 3);
    const Frame b = render(*caster, kIdentity, config, 3);
    EXPECT_EQ(a.depth.raw, b.depth.raw);
    config.seed = 8;
    EXPECT_NE(render(*caster, kIdentity, config, 3).depth.raw, a.depth.raw);
    double sum = 0, sum_sq = 0;
    for (const auto& p : a.points_sensor) {
      sum += p.z() - distance;
      sum_sq += (p.z() - distance) * (p.z() - distance);
    }
    const double n = double(a.points_sensor.size());
    const double sigma = std::sqrt(sum_sq / n - (sum / n) * (sum / n));
    const double model = 1.4e-3 * distance * distance;
    EXPECT_NEAR(sigma / model, 1.0, 0.10) << distance << " m";
    EXPECT_NEAR(sum / n, 0.0, model * 0.02) << "the noise is unbiased";
  }
}

TEST(DepthSensor, NoiseDoesNotDependOnTheThreadCount) {
  const Mesh mesh = plane({0, 0, 2}, {0, 0, -1}, 50.0f);
  const auto caster = make_ray_caster(mesh);
  SensorConfig config;
  config.noise_m_per_m2 = 1.4e-3;
  config.quantize_disparity = true;
  config.threads = 1;
  const Frame one = render(*caster, kIdentity, config);
  config.threads = 3;
  EXPECT_EQ(render(*caster, kIdentity, config).depth.raw, one.depth.raw);
}

TEST(DepthSensor, DisparityQuantisationStepsGrowWithDepthSquared) {
  SensorConfig config;
  config.quantize_disparity = true;
  config.intrinsics.depth_scale = 1e4;
  const double fb = 525.0 * 0.075;
  for (double distance : {1.03, 2.97}) {
    const Mesh mesh = plane({0, 0, float(distance)}, {0, 0, -1}, 50.0f);
    const Frame frame = render(*make_ray_caster(mesh), kIdentity, config);
    const double z = frame.points_sensor[240 * 640 + 320].z();
    const double step = distance * distance / (8.0 * fb);  // Δz for 1/8 disparity
    EXPECT_LE(std::abs(z - distance), step / 2 + 1e-6);
    EXPECT_NEAR(std::fmod(8.0 * fb / z + 0.5, 1.0), 0.5, 1e-3);  // an exact 1/8 step
  }
}

TEST(DepthSensor, GrazingSurfacesDropOut) {
  // A floor 1 m below the sensor, seen at grazing angles towards the horizon.
  const Mesh mesh = plane({0, 1, 0}, {0, -1, 0}, 50.0f);
  const auto caster = make_ray_caster(mesh);
  SensorConfig config;
  config.depth_max_m = 20.0;
  const Frame all = render(*caster, kIdentity, config);
  config.dropout_incidence_deg = 75.0;
  const Frame dropped = render(*caster, kIdentity, config);
  EXPECT_GT(dropped.grazing, 0u);
  EXPECT_EQ(dropped.valid + dropped.grazing, all.valid);
  for (int v = 0; v < 480; ++v) {
    const double angle_deg = std::atan2(1.0, (v - 239.5) / 525.0) * 180.0 / M_PI;  // from the normal
    if (v > 240 && all.depth.at(v, 320) != 0 && std::abs(angle_deg - 75.0) > 0.5) {
      EXPECT_EQ(dropped.depth.at(v, 320) != 0, angle_deg < 75.0) << "row " << v;
    }
  }
}

}  // namespace
}  // namespace fvx::sim
