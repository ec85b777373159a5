// Observability of a correction on synthetic geometry with known weak directions.
#include <gtest/gtest.h>

#include "fvx/core/pose.hpp"
#include "fvx/registration/observability.hpp"

namespace fvx::registration {
namespace {

/// A grid of points on the plane through `origin` with unit normal `n`.
void add_plane(std::vector<PlaneConstraint>& out, const Eigen::Vector3d& origin, const Eigen::Vector3d& n) {
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) out.push_back({origin + 0.1 * i * u + 0.1 * j * w, n});
}

Eigen::Isometry3d small_correction() {
  Eigen::Isometry3d T(Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.3, -0.5, 1).normalized()));
  T.translation() << 0.03, -0.02, 0.01;
  return T;
}

TEST(Observability, BoxCornerConstrainsEverything) {
  std::vector<PlaneConstraint> c;
  add_plane(c, {0, 0, -1}, {0, 0, 1});
  add_plane(c, {2, 0, 0}, {-1, 0, 0});
  add_plane(c, {0, 2, 0}, {0, -1, 0});
  const Observability o = analyse_observability(c, 2.0, 0.01);
  EXPECT_EQ(o.weak_count, 0);
  const Eigen::Isometry3d prior = Eigen::Isometry3d::Identity();
  EXPECT_TRUE(constrain_correction(prior, small_correction(), o).isApprox(small_correction(), 1e-9));
}

TEST(Observability, CorridorLeavesItsAxisFree) {
  std::vector<PlaneConstraint> c;
  // Floor and two walls, all long along x (a corridor): nothing constrains translation in x.
  for (int k = -20; k <= 20; ++k) {
    for (int i = -5; i <= 5; ++i) {
      c.push_back({{0.2 * k, 0.1 * i, -1.0}, {0, 0, 1}});
      c.push_back({{0.2 * k, -1.0, 0.1 * i}, {0, 1, 0}});
      c.push_back({{0.2 * k, 1.0, 0.1 * i}, {0, -1, 0}});
    }
  }
  const Observability o = analyse_observability(c, 2.0, 0.01);
  ASSERT_EQ(o.weak_count, 1);
  EXPECT_NEAR(std::abs(o.directions.col(0)[0]), 1.0, 1e-9);  // pure translation along x
  EXPECT_EQ(describe_direction(o, 0).rfind("translation along", 0), 0u);

  const Eigen::Isometry3d prior(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Eigen::Isometry3d refined = small_correction() * prior;
  const Eigen::Isometry3d kept = constrain_correction(prior, refined, o);
  EXPECT_NEAR(kept.translation().x(), prior.translation().x(), 1e-9);  // x stays at the prior
  EXPECT_NEAR(kept.translation().y(), refined.translation().y(), 1e-9);
  EXPECT_NEAR(kept.translation().z(), refined.translation().z(), 1e-9);
  EXPECT_NEAR(rotation_angle_deg(kept * refined.inverse()), 0.0, 1e-6);  // rotation kept
}

TEST(Observability, SinglePlaneLeavesThreeDirectionsFree) {
  std::vector<PlaneConstraint> c;
  add_plane(c, {0, 0, 2}, {0, 0, -1});
  const Observability o = analyse_observability(c, 2.0, 0.01);
  EXPECT_EQ(o.weak_count, 3);  // in-plane translation and rotation about the normal
  EXPECT_EQ(analyse_observability({}, 2.0, 0.01).weak_count, 6);
}

}  // namespace
}  // namespace fvx::registration
