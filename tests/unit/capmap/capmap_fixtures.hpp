#pragma once
// What the capability-map tests share: a planar arm with a closed-form reachable set, the
// fvx arm, byte comparisons of builds across threads and shards, and the issue's
// recall-at-precision bar.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "fvx/capmap/build.hpp"
#include "fvx/capmap/evaluate.hpp"
#include "test_support.hpp"

namespace fvx::capmap::fixtures {

// Two links in the x–z plane (joints about y, full circles), the sensor looking along the
// second link: p = s + L1·u + L2·d with s = (0, 0, 0.2), L1 = 0.3, L2 = 0.2.
inline const char* kPlanarArm = R"(<robot name="planar">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="sensor"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/></joint>
  <joint name="mount" type="fixed"><parent link="l2"/><child link="sensor"/><origin xyz="0 0 0.2"/></joint>
</robot>)";

inline Arm planar_arm() { return Arm::from_urdf_string(kPlanarArm, {"base", "sensor"}, "planar arm"); }

/// The distance from voxel centre c to the nearest sensor position that looks along some
/// in-plane d within `angle` of d_i: the circle of radius L1 around s + L2·d. In-plane
/// d(θ) = (sin θ, 0, cos θ) has d·d_i = r·cos(θ − θ0) with r = sqrt(1 − d_i,y²), so the valid
/// θ form the interval |θ − θ0| ≤ acos(cos(angle) / r), sampled densely.
inline double closed_form_distance(const Eigen::Vector3d& c, const Eigen::Vector3d& d_i, double angle) {
  const Eigen::Vector3d s(0, 0, 0.2);
  const double r = std::hypot(d_i.x(), d_i.z());
  if (r < 1e-12 || std::cos(angle) > r) return INFINITY;  // no in-plane direction close enough
  const double theta0 = std::atan2(d_i.x(), d_i.z()), half_width = std::acos(std::cos(angle) / r);
  double best = INFINITY;
  for (int k = -1000; k <= 1000; ++k) {
    const double theta = theta0 + half_width * k / 1000.0;
    const Eigen::Vector3d m = s + 0.2 * Eigen::Vector3d(std::sin(theta), 0, std::cos(theta));
    const double in_plane = std::hypot(c.x() - m.x(), c.z() - m.z()) - 0.3;
    best = std::min(best, std::hypot(in_plane, c.y()));
  }
  return best;
}

inline std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// Builds `config` (threads = 1) into dir/one.fcm, then checks that 3 threads write the same
/// bytes and that its 3 shards merge into them.
inline void expect_thread_and_shard_independent(const Arm& arm, BuildConfig config, const test::TempDir& dir) {
  config.threads = 1;
  build_capability_map(arm, config).save(dir / "one.fcm");
  config.threads = 3;
  build_capability_map(arm, config).save(dir / "three.fcm");
  EXPECT_TRUE(bytes_of(dir / "one.fcm") == bytes_of(dir / "three.fcm")) << "1 and 3 threads differ";
  std::vector<CapabilityMap> shards;
  for (std::uint32_t i = 0; i < 3; ++i) {
    config.shard_index = i;
    config.shard_count = 3;
    shards.push_back(build_capability_map(arm, config));
  }
  CapabilityMap::merge(shards).save(dir / "merged.fcm");
  EXPECT_TRUE(bytes_of(dir / "merged.fcm") == bytes_of(dir / "one.fcm")) << "merged shards differ";
}

inline Arm fvx_arm() {
  return Arm::from_urdf(std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm.urdf",
                        {"base_link", "kinect_optical"});
}

/// The issue's bar for an fk-witness build (5 cm, 200 directions, seed 1): recall ≥ 0.9 at
/// precision ≥ 0.99, each measured by `fvx capmap eval` with 4000 queries (a 95 % interval
/// within ±0.01 at these shares; checked, not assumed).
inline void expect_recall_at_precision(const Arm& arm, const char* name, MapLayout layout = MapLayout::Grid) {
  BuildConfig config;
  config.method = BuildMethod::FkWitness;
  config.layout = layout;
  const CapabilityMap map = build_capability_map(arm, config);
  EXPECT_EQ(map.header().method, "fk-witness");
  const Evaluation e = evaluate(map, arm, 4000, 11);
  std::printf("%s, 5 cm: precision %.4f [%.4f, %.4f], recall %.4f [%.4f, %.4f]\n", name, e.precision.value(),
              e.precision.low(), e.precision.high(), e.recall.value(), e.recall.low(), e.recall.high());
  EXPECT_GE(e.precision.value(), 0.99) << name;
  EXPECT_GE(e.recall.value(), 0.9) << name;
  for (const Share& s : {e.precision, e.recall}) {
    EXPECT_LT(s.high() - s.value(), 0.01) << name;
    EXPECT_LT(s.value() - s.low(), 0.01) << name;
  }
}

}  // namespace fvx::capmap::fixtures
