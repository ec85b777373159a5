// Session directories and the closed loop: the manifest round-trips and refuses what it cannot
// read; explore is deterministic, moves the sensor, and stops when no view sees a void.
#include <gtest/gtest.h>

#include <array>

#include <filesystem>
#include <fstream>

#include "fvx/core/error.hpp"
#include "fvx/session/session.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/viewpoints/fov.hpp"
#include "crates_explore.hpp"
#include "test_support.hpp"

namespace fvx::session {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double angle) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  return T;
}

TEST(Session, ManifestRoundTrips) {
  const test::TempDir dir;
  Manifest m;
  m.created_by = "fvx explore test";
  m.scene = "data/scenes/crates.ply";
  m.search_space_m = Eigen::AlignedBox3d(Eigen::Vector3d(0.1, -0.2, 0.0), Eigen::Vector3d(1.0, 0.5, 0.6));
  m.T_world_base = pose(0.2, 0.0, 0.0, 0.4);
  m.arm = "arm.urdf";
  m.capmap = "arm.fcm";
  m.capmap_urdf_hash = "0123abcd";
  m.strategy = "frontier";
  m.seed = 42;
  m.pose_noise_m = 0.02;
  m.pose_noise_deg = 2.0;
  m.registration = true;
  m.near_voids = true;
  m.target_size_m = 0.08;
  for (int i = 0; i < 3; ++i) {
    ManifestView v;
    v.view = i;
    v.scan = "scans/view00" + std::to_string(i) + ".pcd";
    v.map = "maps/view00" + std::to_string(i) + ".ot";
    v.report = "reports/view00" + std::to_string(i) + ".json";
    v.T_world_sensor_prior = pose(0.1 * i, 0.2, 0.9, 0.1 * i);
    if (i) v.T_world_sensor_true = pose(0.1 * i + 0.01, 0.2, 0.9, 0.1 * i);
    v.joints_rad = Eigen::VectorXd::LinSpaced(5, -1.0, 1.0 + i);
    v.stamp_s = i;
    m.views.push_back(v);
  }
  write_manifest(dir.path().string(), m);
  const Manifest r = read_manifest(dir.path().string());
  EXPECT_EQ(r.created_by, m.created_by);
  EXPECT_EQ(r.scene, m.scene);
  EXPECT_TRUE(r.search_space_m->isApprox(*m.search_space_m));
  EXPECT_FALSE(r.view_bounds_m.has_value());
  EXPECT_TRUE(r.T_world_base->isApprox(*m.T_world_base, 1e-12));
  EXPECT_EQ(r.capmap_urdf_hash, m.capmap_urdf_hash);
  EXPECT_EQ(r.strategy, "frontier");
  EXPECT_EQ(r.seed, 42u);
  EXPECT_EQ(r.pose_noise_deg, 2.0);
  EXPECT_TRUE(r.registration);
  EXPECT_TRUE(r.near_voids);
  EXPECT_EQ(r.target_size_m, 0.08);
  ASSERT_EQ(r.views.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(r.views[i].scan, m.views[i].scan);
    EXPECT_TRUE(r.views[i].T_world_sensor_prior.isApprox(m.views[i].T_world_sensor_prior, 1e-12));
    EXPECT_EQ(r.views[i].T_world_sensor_true.has_value(), i > 0);
    EXPECT_TRUE(r.views[i].joints_rad.isApprox(m.views[i].joints_rad));
  }
}

// Sessions written before the strategy had one name in every command call it "planner".
TEST(Session, AnOlderManifestsPlannerIsItsStrategy) {
  const test::TempDir dir;
  Manifest m;
  m.created_by = "test";
  m.strategy = "random";
  write_manifest(dir.path().string(), m);
  const std::string file = (dir.path() / "manifest.json").string();
  std::string text = test::slurp(file);
  const auto key = text.find("\"strategy\":");
  ASSERT_NE(key, std::string::npos);
  std::ofstream(file) << text.replace(key, 11, "\"planner\":");
  EXPECT_EQ(read_manifest(dir.path().string()).strategy, "random");
}

// Sessions searched before --near-unknown existed counted every ray: without the key they
// replay as "ignore"; a value that is none of the four is refused.
TEST(Session, AManifestWithoutNearUnknownWasSearchedIgnoringIt) {
  const test::TempDir dir;
  Manifest m;
  m.created_by = "test";
  m.near_unknown = "void";
  write_manifest(dir.path().string(), m);
  EXPECT_EQ(read_manifest(dir.path().string()).near_unknown, "void");
  const std::string file = (dir.path() / "manifest.json").string();
  const std::string text = test::slurp(file);
  const auto key = text.find("  \"near_unknown\": \"void\",\n");
  ASSERT_NE(key, std::string::npos);
  std::ofstream(file) << std::string(text).erase(key, std::string("  \"near_unknown\": \"void\",\n").size());
  EXPECT_EQ(read_manifest(dir.path().string()).near_unknown, "ignore");
  std::ofstream(file) << std::string(text).replace(text.find("\"void\""), 6, "\"all\"");
  EXPECT_THROW(read_manifest(dir.path().string()), FileError);
}

TEST(Session, ABadManifestNamesTheProblem) {
  const test::TempDir dir;
  EXPECT_THROW(read_manifest(dir.path().string()), FileError);
  Manifest m;
  m.created_by = "test";
  write_manifest(dir.path().string(), m);
  const std::string file = (dir.path() / "manifest.json").string();
  std::string text = test::slurp(file);
  const auto version = text.find("\"schema_version\": 1");
  ASSERT_NE(version, std::string::npos);
  std::ofstream(file) << std::string(text).replace(version, 19, "\"schema_version\": 7");
  try {
    read_manifest(dir.path().string());
    FAIL() << "schema 7 was read";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("schema_version 7"), std::string::npos) << e.what();
  }
  std::ofstream(file) << "{\"schema_version\": 1";
  EXPECT_THROW(read_manifest(dir.path().string()), FileError);
}

// Wrong JSON types and numbers no int holds are named with their key, never "unexpected
// error: [json.exception.type_error.302]" or a schema_version of -2147483648.
TEST(Session, WrongTypesAndHugeNumbersInAManifestNameTheirKey) {
  const test::TempDir dir;
  Manifest m;
  m.created_by = "test";
  ManifestView v;
  v.joints_rad = Eigen::VectorXd::Zero(2);
  m.views.push_back(v);
  write_manifest(dir.path().string(), m);
  const std::string file = (dir.path() / "manifest.json").string();
  const std::string good = test::slurp(file);
  const std::vector<std::array<std::string, 3>> cases = {
      {"\"schema_version\": 1", "\"schema_version\": 1e30", "'schema_version' must be a whole number"},
      {"\"seed\": 1", "\"seed\": \"one\"", "'seed' must be a whole number >= 0"},
      {"\"registration\": false", "\"registration\": 0", "'registration' must be true or false"},
      {"\"view\": 0", "\"view\": 2.5", "'view' must be a whole number"},
      {"\"joints_rad\": [", "\"joints_rad\": [\"a\", ", "'joints_rad' must be an array of numbers"},
      {"\"quaternion_xyzw\": [", "\"quaternion_xyzw\": [\"x\", ", "quaternion_xyzw' must be 4 numbers"},
  };
  for (const auto& [from, to, words] : cases) {
    std::string text = good;
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    std::ofstream(file) << text.replace(at, from.size(), to);
    try {
      read_manifest(dir.path().string());
      ADD_FAILURE() << to << " was read";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("manifest.json"), std::string::npos) << e.what();
    }
  }
}

// A free-flying Kinect in the crates scene: the loop moves, reveals, and gives the same views
// on a second run.
TEST(Explore, TheLoopMovesRevealsAndRepeatsItself) {
  const sim::Scene scene = sim::builtin_scene("crates");
  const auto caster = sim::make_ray_caster(scene.mesh);
  const Sensor kinect = test::kinect_on(*caster);
  const ExploreConfig config = test::crates_explore(scene, 4);
  auto run = [&] {
    std::vector<ViewRecord> records;
    const ExploreResult r = explore(kinect, std::nullopt, config, [&](const ViewRecord& v, const pipeline::State& s) {
      EXPECT_EQ(s.steps, v.view + 1);
      records.push_back(v);
      records.back().points_sensor.clear();
    });
    EXPECT_EQ(r.views, int(records.size()));
    return records;
  };
  const std::vector<ViewRecord> a = run(), b = run();
  ASSERT_GE(a.size(), 2u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a[i].T_world_sensor_true.isApprox(b[i].T_world_sensor_true)) << "view " << i;
    EXPECT_EQ(a[i].step.analysis.void_cells, b[i].step.analysis.void_cells);
    // Without noise the prior is the truth and the sensor went where the search said.
    EXPECT_TRUE(a[i].T_world_sensor_prior.isApprox(a[i].T_world_sensor_true));
    if (i > 0) {
      const nbv::View& chosen = a[i - 1].step.nbv.views[*a[i - 1].chosen];
      EXPECT_TRUE(a[i].T_world_sensor_true.isApprox(chosen.T_world_sensor));
      EXPECT_EQ(a[i].previous_prediction, chosen.void_cells_seen);
      EXPECT_GT(a[i].revealed_void_cells, 0u) << "view " << i;
    }
  }
}

TEST(Explore, AStartOutOfReachIsRefused) {
  const capmap::CapabilityMap cm = capmap::CapabilityMap::load(test::source("data/arms/fvx-arm.fcm"));
  nbv::Reach reach{&cm, Eigen::Isometry3d::Identity(), nullptr, {}};
  ExploreConfig config;
  config.T_world_sensor_start.translation() = Eigen::Vector3d(30.0, 0.0, 1.0);
  int calls = 0;
  const Sensor none = [&](const Eigen::Isometry3d&, int) {
    ++calls;
    return std::vector<Eigen::Vector3d>{};
  };
  try {
    explore(none, reach, config, [](const ViewRecord&, const pipeline::State&) {});
    FAIL() << "a start 30 m away was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out of the arm's reach"), std::string::npos) << e.what();
  }
  EXPECT_EQ(calls, 0);
  config.max_views = 0;
  EXPECT_THROW(explore(none, std::nullopt, config, [](const ViewRecord&, const pipeline::State&) {}), UsageError);
}

}  // namespace
}  // namespace fvx::session
