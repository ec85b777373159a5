// The arm model and the viewing IK: FK against hand computation, the Jacobian against finite
// differences, FK → IK round trips on the project's arm and two real arm models.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>

#include "fvx/capmap/viewing_ik.hpp"
#include "fvx/core/error.hpp"
#include "test_support.hpp"

namespace fvx::capmap {
namespace {

std::string fvx_arm_path() { return std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm.urdf"; }

Arm fvx_arm() { return Arm::from_urdf(fvx_arm_path(), {"base_link", "kinect_optical"}); }

TEST(Arm, TheFvxArmPointsStraightUpAtZero) {
  const Arm arm = fvx_arm();
  ASSERT_EQ(arm.dof(), 5);
  EXPECT_EQ(arm.joint_names().front(), "yaw");
  const Eigen::Isometry3d T = arm.fk(Eigen::VectorXd::Zero(5));
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(0, 0, 1.34), 1e-9));
  EXPECT_TRUE(arm.viewing_direction(Eigen::VectorXd::Zero(5)).isApprox(Eigen::Vector3d::UnitZ(), 1e-9));
  // Shoulder pitched 90° (about +y): the arm points along +x from the shoulder at 0.35 m.
  Eigen::VectorXd q = Eigen::VectorXd::Zero(5);
  q[1] = M_PI / 2;
  EXPECT_TRUE(arm.fk(q).translation().isApprox(Eigen::Vector3d(0.99, 0, 0.35), 1e-9));
  EXPECT_TRUE(arm.viewing_direction(q).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
}

TEST(Arm, JacobianMatchesFiniteDifferencesWithAMount) {
  ArmConfig config{"base_link", "wrist"};
  config.T_tip_sensor.translation() << 0.03, -0.02, 0.15;  // an offset mount
  config.T_tip_sensor.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Arm arm = Arm::from_urdf(fvx_arm_path(), config);
  const Eigen::VectorXd q = (Eigen::VectorXd(4) << 0.3, -0.7, 1.1, 0.4).finished();
  Eigen::Matrix3Xd J_p, J_r;
  arm.jacobian(q, J_p, J_r);
  const double h = 1e-7;
  for (int j = 0; j < arm.dof(); ++j) {
    Eigen::VectorXd qh = q;
    qh[j] += h;
    const Eigen::Isometry3d a = arm.fk(q), b = arm.fk(qh);
    const Eigen::AngleAxisd delta(b.linear() * a.linear().transpose());
    EXPECT_TRUE(((b.translation() - a.translation()) / h).isApprox(J_p.col(j), 1e-5)) << "joint " << j;
    EXPECT_TRUE((delta.angle() * delta.axis() / h).isApprox(J_r.col(j), 1e-5)) << "joint " << j;
  }
}

/// The first joint's axis is the line `point`, `direction` (either way), and every pose is the
/// turn of the pose with that joint at 0: FK(q₀, q₁…) = R(q₀)·FK(0, q₁…), with KDL as oracle.
void expect_first_joint_turns(const Arm& arm, const Eigen::Vector3d& point, const Eigen::Vector3d& direction,
                              const char* name) {
  const auto& axis = arm.first_joint_axis();
  ASSERT_TRUE(axis) << name;
  EXPECT_NEAR(std::abs(axis->direction_base.dot(direction.normalized())), 1.0, 1e-12) << name;
  EXPECT_LT((axis->point_base - point).cross(direction.normalized()).norm(), 1e-9) << name << ": point off the axis";
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 500; ++trial) {
    Eigen::VectorXd q = arm.random_configuration(rng);
    const Eigen::Isometry3d T = arm.fk(q);
    const double q0 = q[0];
    q[0] = 0.0;
    const Eigen::Isometry3d turned = axis->turn(arm.fk(q), q0);
    EXPECT_LT((turned.translation() - T.translation()).norm(), 1e-12) << name << " trial " << trial;
    EXPECT_LT((turned.linear() - T.linear()).norm(), 1e-12) << name << " trial " << trial;
  }
}

TEST(Arm, EveryPoseIsATurnOfTheFirstJoint) {
  expect_first_joint_turns(fvx_arm(), {0, 0, 0.30}, {0, 0, 1}, "fvx arm");
  EXPECT_NEAR(fvx_arm().first_joint_axis()->tilt_from_vertical_rad(), 0.0, 1e-12);
  // A fixed joint before the first one moves and tilts its line: y turned by 90° about x is z.
  const char* tilted = R"(<robot name="t">
    <link name="base"/><link name="mount"/><link name="l1"/><link name="l2"/>
    <joint name="m" type="fixed"><parent link="base"/><child link="mount"/><origin xyz="0.1 0 0.2" rpy="1.5707963267948966 0 0"/></joint>
    <joint name="j1" type="revolute"><parent link="mount"/><child link="l1"/><origin xyz="0 0.05 0"/><axis xyz="0 1 0"/>
      <limit lower="-1" upper="2" effort="1" velocity="1"/></joint>
    <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0.1"/><axis xyz="1 0 0"/></joint>
  </robot>)";
  const Arm arm = Arm::from_urdf_string(tilted, {"base", "l2"}, "tilted");
  expect_first_joint_turns(arm, {0.1, 0, 0.25}, {0, 0, 1}, "mounted arm");
  // A prismatic first joint has no axis to turn about.
  const char* sliding = R"(<robot name="s">
    <link name="base"/><link name="l1"/><link name="l2"/>
    <joint name="j1" type="prismatic"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
      <limit lower="0" upper="1" effort="1" velocity="1"/></joint>
    <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 0 1"/></joint>
  </robot>)";
  EXPECT_FALSE(Arm::from_urdf_string(sliding, {"base", "l2"}, "sliding").first_joint_axis());
}

TEST(ArmRealData, EveryPoseOfYoubotAndSo101IsATurnOfTheFirstJoint) {
  FVX_REAL_DATA_OR_SKIP(youbot, "arms/youbot_arm.urdf");
  FVX_REAL_DATA_OR_SKIP(so101, "arms/so101_arm.urdf");
  // arm_joint_1 at (0.024, 0, 0.096) about −z; shoulder_pan at (0.0388, 0, 0.0624) about z
  // rolled by the URDF's 3.14159 (not π): tilted 2.65 µrad from the vertical.
  expect_first_joint_turns(Arm::from_urdf(youbot, {"base_link", "arm_link_5"}), {0.024, 0, 0.096}, {0, 0, -1}, "youbot");
  const Arm so101_arm = Arm::from_urdf(so101, {"base_link", "gripper_frame_link"});
  expect_first_joint_turns(so101_arm, {0.0388353, -8.97657e-09, 0.0624}, {0, std::sin(M_PI - 3.14159), -std::cos(M_PI - 3.14159)},
                           "so101");
  EXPECT_NEAR(so101_arm.first_joint_axis()->tilt_from_vertical_rad(), M_PI - 3.14159, 1e-9);
}

/// FK of random configurations → their viewing pose → IK from random starts.
void expect_round_trips(const Arm& arm, const char* name) {
  std::mt19937_64 rng(11);
  const IkConfig config;
  int reached = 0;
  const int trials = 200;
  for (int t = 0; t < trials; ++t) {
    const Eigen::VectorXd q = arm.random_configuration(rng);
    const Eigen::Vector3d p = arm.fk(q).translation(), d = arm.viewing_direction(q);
    const IkResult r = solve_viewing_ik(arm, p, d, config, rng);
    if (!r.reached) continue;
    ++reached;
    // What the solver claims holds when checked with FK.
    EXPECT_LE((arm.fk(r.q).translation() - p).norm(), config.position_tolerance_m) << name;
    EXPECT_LE(std::acos(std::min(1.0, arm.viewing_direction(r.q).dot(d))), config.angle_tolerance_rad + 1e-9) << name;
    EXPECT_TRUE((r.q.array() >= arm.lower_rad().array() - 1e-12).all() && (r.q.array() <= arm.upper_rad().array() + 1e-12).all());
  }
  std::printf("%s: IK reached %d of %d random viewing poses\n", name, reached, trials);
  EXPECT_GE(reached, trials * 95 / 100) << name << ": " << reached << " of " << trials;
}

TEST(ViewingIk, RoundTripsOnTheFvxArm) { expect_round_trips(fvx_arm(), "fvx-arm"); }

TEST(ViewingIkRealData, RoundTripsOnYoubotAndSo101) {
  FVX_REAL_DATA_OR_SKIP(youbot, "arms/youbot_arm.urdf");
  FVX_REAL_DATA_OR_SKIP(so101, "arms/so101_arm.urdf");
  expect_round_trips(Arm::from_urdf(youbot, {"base_link", "arm_link_5"}), "youbot");
  expect_round_trips(Arm::from_urdf(so101, {"base_link", "gripper_frame_link"}), "so101");
}

// An fk-witness bit's region (the IK's goal in solve_in_region): from any pose outside it,
// one step along its errors lands inside the bit, in its voxel with the axis in its
// direction's cell, wherever the pose starts (up to two voxels off, any direction).
TEST(ViewingIk, OneStepAlongABitRegionsErrorsLandsInTheBit) {
  CapabilityHeader h;
  h.voxel_m = 0.1;
  h.origin_m = Eigen::Vector3d::Constant(-0.5);
  h.dims = {{10, 10, 10}};
  h.directions = 200;
  const CapabilityMap map(h);
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> inner(2, 7), direction(0, h.directions - 1);
  std::uniform_real_distribution<double> offset(-2.5, 2.5);
  std::normal_distribution<double> g(0, 1);
  int outside = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const std::int64_t voxel = inner(rng) + 10 * (inner(rng) + 10 * inner(rng));
    const int i = direction(rng);
    const Eigen::Vector3d p = map.center_of(voxel) + h.voxel_m * Eigen::Vector3d(offset(rng), offset(rng), offset(rng));
    const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    Eigen::Vector3d e_p = Eigen::Vector3d::Zero(), e_r = Eigen::Vector3d::Zero();
    if (bit_region(map, voxel, i)(p, d, e_p, e_r)) {
      EXPECT_TRUE(in_bit(map, voxel, i, p, d));
      continue;
    }
    ++outside;
    const Eigen::Vector3d turned =
        e_r.norm() > 0 ? Eigen::Vector3d(Eigen::AngleAxisd(e_r.norm(), e_r.normalized()) * d) : d;
    EXPECT_TRUE(in_bit(map, voxel, i, p + e_p, turned)) << "trial " << trial;
  }
  EXPECT_GT(outside, 2900);
}

/// FNV-1a 64 of `text` from `basis`, hex: the rule fvx-capmap(5) names.
std::string fnv1a(const std::string& text, std::uint64_t basis) {
  for (unsigned char c : text) basis = (basis ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(basis));
  return out;
}

TEST(Arm, TheUrdfHashIsFnv1aWithTheStandardBasisAndTheOldOneStillMatches) {
  const Arm arm = fvx_arm();
  const std::string text = test::slurp(fvx_arm_path());
  EXPECT_EQ(arm.urdf_hash(), fnv1a(text, 14695981039346656037ull));
  EXPECT_TRUE(arm.is_urdf_hash(arm.urdf_hash()));
  EXPECT_TRUE(arm.is_urdf_hash(fnv1a(text, 1469598103934665603ull)));  // maps written before
  EXPECT_FALSE(arm.is_urdf_hash(fnv1a(text + " ", 14695981039346656037ull)));
}

TEST(Arm, BadModelsAreRefused) {
  const test::TempDir dir;
  std::ofstream(dir / "broken.urdf") << "<robot name='x'><link name='a'/><joint name='j'";
  EXPECT_THROW(Arm::from_urdf(dir / "broken.urdf", {"a", "b"}), FileError);
  EXPECT_THROW(Arm::from_urdf(dir / "missing.urdf", {"a", "b"}), FileError);
  EXPECT_THROW(Arm::from_urdf(fvx_arm_path(), {"base_link", "no_such_link"}), UsageError);
  EXPECT_THROW(Arm::from_urdf(fvx_arm_path(), {"forearm", "turret"}), UsageError);  // tip above base
  try {
    Arm::from_urdf(fvx_arm_path(), {"base_link", "no_such_link"});
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_link"), std::string::npos);
  }
}

}  // namespace
}  // namespace fvx::capmap
