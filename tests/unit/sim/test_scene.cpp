// Scenes: mesh formats, sidecars, bad files, voxel ground truth, and what a scan of a closed
// box with one opening reveals.
#include <gtest/gtest.h>

#include <fstream>

#include "fvx/core/error.hpp"
#include "fvx/map/occupancy_map.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "test_support.hpp"

namespace fvx::sim {
namespace {

TEST(Mesh, PlyObjStlRoundTrip) {
  const test::TempDir dir;
  Mesh cube;
  cube.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 2, 3)));
  write_mesh_ply(dir / "cube.ply", cube);
  const Mesh back = read_mesh(dir / "cube.ply");
  EXPECT_EQ(back.triangles.size(), 12u);
  EXPECT_TRUE(back.bounds().isApprox(cube.bounds()));
  std::ofstream(dir / "quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  EXPECT_EQ(read_mesh(dir / "quad.obj").triangles.size(), 2u);  // a quad becomes a fan
  std::ofstream(dir / "tri.stl") << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                    "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  EXPECT_EQ(read_mesh(dir / "tri.stl").triangles.size(), 1u);
}

TEST(Mesh, BadMeshesAreRefusedWithTheirName) {
  const test::TempDir dir;
  std::ofstream(dir / "garbage.ply") << "ply\nformat ascii 1.0\nelement vertex two\nend_header\n";
  std::ofstream(dir / "points.obj") << "v 0 0 0\nv 1 0 0\n";
  std::ofstream(dir / "text.stl") << "this is not a mesh";
  std::ofstream(dir / "mesh.dae") << "<collada/>";
  std::ofstream(dir / "nofaces.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                        "property float y\nproperty float z\nelement face 0\n"
                                        "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  for (const char* name : {"garbage.ply", "points.obj", "text.stl", "mesh.dae", "missing.ply", "nofaces.ply"}) {
    try {
      read_mesh(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

TEST(Scene, SidecarRoundTripAndStrictKeys) {
  const test::TempDir dir;
  const Scene scene = builtin_scene("crates");
  write_mesh_ply(dir / "crates.ply", scene.mesh);
  write_scene_info(dir / "crates.json", scene.info);
  const Scene back = load_scene(dir / "crates.ply");  // finds crates.json beside it
  EXPECT_EQ(back.info.name, scene.info.name);
  ASSERT_TRUE(back.info.target.has_value());
  EXPECT_TRUE(back.info.target->box.isApprox(scene.info.target->box, 1e-5));  // written in µm
  EXPECT_EQ(back.info.containers.size(), 3u);
  std::ofstream(dir / "typo.json") << R"({"search_spac": {"min": [0,0,0], "max": [1,1,1]}})";
  std::ofstream(dir / "flat.json") << R"({"search_space": {"min": [0,0,0], "max": [1,1,0]}})";
  EXPECT_THROW(read_scene_info(dir / "typo.json"), FileError);
  EXPECT_THROW(read_scene_info(dir / "flat.json"), FileError);
}

TEST(GroundTruth, ClosedBoxInteriorVolumeAndWalls) {
  const Scene scene = builtin_scene("closed-box");
  const auto caster = make_ray_caster(scene.mesh);
  const double R = 0.02;
  const GroundTruth gt(scene.mesh, *caster, R, *scene.info.search_space);
  // The interior is 0.46 × 0.46 × 0.36 m; cells whose centres fall inside it are free
  // unless a wall passes through them.
  const Eigen::AlignedBox3d inside = scene.info.containers[0].box;
  const double analytic_m3 = inside.volume();
  EXPECT_NEAR(gt.free_volume_m3(inside), analytic_m3, analytic_m3 * 0.12);
  // Wall cells and floor cells are solid, the air above is free.
  EXPECT_TRUE(gt.solid(gt.cell_of({0.53, 0.0, 0.2})));    // the x− wall, 2 cm thick
  EXPECT_TRUE(gt.solid(gt.cell_of({0.77, -0.02, 0.01})));  // the box's floor
  EXPECT_FALSE(gt.solid(gt.cell_of({0.77, -0.02, 0.2})));  // its middle
  EXPECT_FALSE(gt.solid(gt.cell_of({0.77, -0.02, 0.39})));  // the opening in the lid
  EXPECT_TRUE(gt.solid(gt.cell_of({0.6, -0.2, 0.39})));    // the lid beside it
  EXPECT_FALSE(gt.solid(gt.cell_of({0.45, 0.0, 0.3})));    // air outside
}

/// Segment origin → p crosses the lid plane inside the opening grown by `margin_m`.
bool through_opening(const Eigen::Vector3d& origin, const Eigen::Vector3d& p, double margin_m) {
  const double lid_z = 0.39;  // middle of the 2 cm lid (0.38..0.40)
  const double s = (lid_z - origin.z()) / (p.z() - origin.z());
  const Eigen::Vector3d q = origin + s * (p - origin);
  const Eigen::Vector2d hole_center(0.77, -0.02);
  return (q.head<2>() - hole_center).cwiseAbs().maxCoeff() <= 0.08 + margin_m;
}

// A scan of the closed box with one opening, integrated, leaves the interior unknown except
// what is visible through the opening.
TEST(GroundTruth, ScanOfTheClosedBoxRevealsOnlyWhatTheOpeningShows) {
  const Scene scene = builtin_scene("closed-box");
  const auto caster = make_ray_caster(scene.mesh);
  const double R = 0.02;
  const GroundTruth gt(scene.mesh, *caster, R, *scene.info.search_space);
  // Sensor 0.7 m above the opening, looking straight down (optical z = world −z).
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  T_world_sensor.linear() << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  T_world_sensor.translation() << 0.77, -0.02, 1.1;
  const Frame frame = render(*caster, T_world_sensor, SensorConfig{});
  ASSERT_GT(frame.valid, 100000u);

  map::OccupancyMap map(R);
  std::vector<Eigen::Vector3f> points_world;
  for (const auto& p : frame.points_sensor)
    if (p.allFinite()) points_world.push_back((T_world_sensor * p.cast<double>()).cast<float>());
  map.integrate(points_world, T_world_sensor.translation().cast<float>());

  const Eigen::AlignedBox3d inside = scene.info.containers[0].box;
  std::size_t interior = 0, known = 0, outside_the_cone = 0, seen_free_but_solid = 0;
  for (int z = 0; z < gt.size().z(); ++z)
    for (int y = 0; y < gt.size().y(); ++y)
      for (int x = 0; x < gt.size().x(); ++x) {
        const Eigen::Vector3i cell = gt.first_cell() + Eigen::Vector3i(x, y, z);
        const Eigen::Vector3d c = gt.center_of(cell);
        const map::VoxelState state = map.state(*map.key_of(c));
        if (state == map::VoxelState::Free && gt.solid(cell)) ++seen_free_but_solid;
        if (!inside.contains(c) || gt.solid(cell)) continue;
        ++interior;
        if (state == map::VoxelState::Unknown) continue;
        ++known;
        // A known interior cell must be on a line of sight through the opening (one cell of
        // slack for rays that graze the rim).
        if (!through_opening(T_world_sensor.translation(), c, R * std::sqrt(3.0))) ++outside_the_cone;
      }
  EXPECT_GT(interior, 5000u);
  EXPECT_GT(known, 200u) << "the opening shows part of the interior";
  EXPECT_LT(known, interior / 3) << "most of the interior stays hidden";
  EXPECT_EQ(outside_the_cone, 0u);
  // A wall that fills only part of a cell (here the outer 1 cm of 2 cm cells) is carved free
  // by rays passing down its empty part: inherent to voxel maps (50 of ~3800 solid cells
  // here, all on the outer faces of the box's walls).
  EXPECT_LT(seen_free_but_solid, gt.solid_cells() / 50);
}

TEST(BuiltinScenes, AllBuildWithTheirTargetsInsideContainers) {
  for (const std::string& name : builtin_scene_names()) {
    const Scene s = builtin_scene(name);
    EXPECT_GT(s.mesh.triangles.size(), 12u) << name;
    ASSERT_TRUE(s.info.search_space.has_value()) << name;
    EXPECT_FALSE(s.info.containers.empty()) << name;
    if (s.info.target) {
      bool held = false;
      for (const auto& c : s.info.containers) held |= c.box.contains(s.info.target->box);
      EXPECT_TRUE(held) << name << ": the target is inside a container";
    }
  }
  EXPECT_THROW(builtin_scene("nope"), UsageError);
}

}  // namespace
}  // namespace fvx::sim
