// The scene family builtin:suite/N. Oracles: a second generation of the same scene (bit for
// bit), the voxel ground truth (the target and the container walls are solid, the interiors
// free), and hand-made layouts that break each rule the check enforces.
#include <gtest/gtest.h>

#include <set>

#include "fvx/core/error.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "fvx/sim/scene_suite.hpp"

namespace fvx::sim {
namespace {

bool same_mesh(const Mesh& a, const Mesh& b) {
  if (a.vertices.size() != b.vertices.size() || a.triangles != b.triangles) return false;
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    if (a.vertices[i] != b.vertices[i]) return false;
  return true;
}

TEST(SceneSuite, EachSceneIsTheSameEveryTimeAndScenesDiffer) {
  for (int n = 1; n <= kSuiteScenes; ++n) {
    const Scene a = suite_scene(n), b = builtin_scene("suite/" + std::to_string(n));
    EXPECT_TRUE(same_mesh(a.mesh, b.mesh)) << n;
    EXPECT_EQ(b.mesh_path, "builtin:suite/" + std::to_string(n));
    EXPECT_EQ(a.info.name, b.info.name);
    if (n > 1) {
      EXPECT_FALSE(same_mesh(a.mesh, suite_scene(n - 1).mesh)) << n;
    }
  }
  EXPECT_THROW(builtin_scene("suite/0"), UsageError);
  EXPECT_THROW(builtin_scene("suite/x"), UsageError);
  EXPECT_THROW(builtin_scene("suite/"), UsageError);
}

TEST(SceneSuite, EveryDefaultSceneIsValidAndTheSuiteHoldsEveryKind) {
  std::set<std::string> kinds;
  int targets = 0, walls = 0;
  for (int n = 1; n <= kSuiteScenes; ++n) {
    const Scene s = suite_scene(n);
    const auto problems = check_scene_layout(s);
    EXPECT_TRUE(problems.empty()) << "suite/" << n << ": " << (problems.empty() ? "" : problems.front());
    ASSERT_TRUE(s.info.search_space);
    ASSERT_EQ(s.info.bases.size(), 1u);
    EXPECT_FALSE(s.info.search_space->contains(Eigen::Vector3d(s.info.bases[0][0], s.info.bases[0][1], 0.1)));
    targets += bool(s.info.target);
    walls += s.info.name.find("walls") != std::string::npos;
    for (const NamedBox& c : s.info.containers)
      for (const char* kind : {"crate", "shelf", "stack"})
        if (c.name.rfind(kind, 0) == 0) kinds.insert(kind);
    for (const NamedBox& c : s.info.containers)
      for (const char* side : {"towards the base", "away from the base", "open top", "closed"})
        if (c.name.find(side) != std::string::npos) kinds.insert(side);
  }
  EXPECT_EQ(kinds.size(), 7u);
  EXPECT_GE(targets, 18);
  EXPECT_LT(targets, kSuiteScenes);  // some scenes hide nothing
  EXPECT_GT(walls, 0);
  EXPECT_LT(walls, kSuiteScenes);
}

// The ground truth sees what the sidecar says: the target solid, each container's interior
// empty except for what stands in it, its walls solid.
TEST(SceneSuite, GroundTruthAgreesWithTheSidecar) {
  for (const int n : {1, 2, 3, 4, 7}) {
    const Scene s = suite_scene(n);
    const auto caster = make_ray_caster(s.mesh);
    const double R = 0.025;
    const GroundTruth gt(s.mesh, *caster, R, *s.info.search_space);
    auto solid_at = [&](const Eigen::Vector3d& p) { return gt.solid(gt.cell_of(p)); };
    if (s.info.target) {
      EXPECT_TRUE(solid_at(s.info.target->box.center())) << n;
    }
    for (const NamedBox& c : s.info.containers) {
      const Eigen::Vector3d probe = c.box.center();  // 6 cm or more from every wall
      Eigen::AlignedBox3d near_target;
      if (s.info.target) near_target = Eigen::AlignedBox3d(s.info.target->box.min().array() - R, s.info.target->box.max().array() + R);
      if (!near_target.contains(probe)) {
        EXPECT_FALSE(solid_at(probe)) << n << " " << c.name;
      }
      if (c.box.min().z() > R) continue;  // a floor of its own only when the container stands on the ground
      const Eigen::Vector3d below(c.box.center().x(), c.box.center().y(), c.box.min().z() - 0.004);
      EXPECT_TRUE(solid_at(below)) << n << " " << c.name << ": its floor";
    }
  }
}

TEST(SceneSuite, TheCheckNamesOverlapsAndAStrayTarget) {
  Scene s = suite_scene(1);
  ASSERT_TRUE(check_scene_layout(s).empty());
  Scene overlapping = s;
  overlapping.mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(0.0f, 0.0f, -0.02f), Eigen::Vector3f(0.1f, 0.1f, 0.02f)));
  const auto p1 = check_scene_layout(overlapping);
  ASSERT_EQ(p1.size(), 1u);
  EXPECT_NE(p1[0].find("overlap"), std::string::npos);
  Scene touching = s;  // a block standing on the floor touches it: allowed
  touching.mesh.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(0.0f, 0.0f, 0.0f), Eigen::Vector3f(0.1f, 0.1f, 0.02f)));
  EXPECT_TRUE(check_scene_layout(touching).empty());
  Scene stray = s;
  ASSERT_TRUE(stray.info.target);
  stray.info.target->box.translate(Eigen::Vector3d(0.0, 0.0, 0.5));
  const auto p2 = check_scene_layout(stray);
  EXPECT_FALSE(p2.empty());
  Scene no_base = s;
  no_base.info.bases.clear();
  EXPECT_EQ(check_scene_layout(no_base).size(), 1u);
}

// Inside or outside, where solids touch: a floor slab against a wall (their faces at x = 2
// coincide, one hit for the caster, so a ray along +x from inside the floor counted two
// crossings and called the point outside), a hollow crate standing on the floor. Oracle: the
// boxes' own extents.
TEST(InsideSolid, HoldsWhereSolidsTouch) {
  Mesh m;
  m.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(-0.6f, -1.6f, -0.05f), Eigen::Vector3f(2.0f, 1.6f, 0.0f)));
  m.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(2.0f, -1.6f, -0.05f), Eigen::Vector3f(2.05f, 1.6f, 2.0f)));
  m.append(hollow_box(Eigen::AlignedBox3f(Eigen::Vector3f(0.5f, -0.2f, 0.0f), Eigen::Vector3f(0.9f, 0.2f, 0.3f)), 0.02f,
                      {{}, {}, {}, {}, {}, {Face::Open}}));
  for (const Backend backend : {Backend::Embree, Backend::BruteForce}) {
    const auto caster = make_ray_caster(m, backend);
    SCOPED_TRACE(to_string(backend));
    EXPECT_TRUE(inside_solid(*caster, Eigen::Vector3f(-0.299f, 0.0006f, -0.004f)));  // in the floor
    EXPECT_TRUE(inside_solid(*caster, Eigen::Vector3f(1.5f, 0.3f, -0.03f)));
    EXPECT_TRUE(inside_solid(*caster, Eigen::Vector3f(2.02f, 0.0f, -0.02f)));  // in the wall, below the floor's top
    EXPECT_TRUE(inside_solid(*caster, Eigen::Vector3f(2.02f, 0.0f, 1.0f)));
    EXPECT_TRUE(inside_solid(*caster, Eigen::Vector3f(0.51f, 0.0f, 0.15f)));  // in the crate's wall
    EXPECT_TRUE(inside_solid(*caster, Eigen::Vector3f(0.7f, 0.0f, 0.01f)));   // in its bottom
    EXPECT_FALSE(inside_solid(*caster, Eigen::Vector3f(0.7f, 0.0f, 0.15f)));  // the air in the crate
    EXPECT_FALSE(inside_solid(*caster, Eigen::Vector3f(-0.3f, 0.0f, 0.004f)));  // just above the floor
    EXPECT_FALSE(inside_solid(*caster, Eigen::Vector3f(1.9f, 0.0f, 0.5f)));
  }
}

}  // namespace
}  // namespace fvx::sim
