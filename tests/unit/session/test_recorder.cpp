// The session recorder: each view's scan, map and report are on disk before the manifest
// lists the view, and what it wrote reads back (manifest, organised PCD with the prior as
// VIEWPOINT, the map, the report text as given).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "fvx/io/cloud_file.hpp"
#include "fvx/session/recorder.hpp"
#include "test_support.hpp"

namespace fvx::session {
namespace {

ViewRecord view(int index, const io::DepthCamera& sensor) {
  ViewRecord v;
  v.view = index;
  v.T_world_sensor_true.translation() = Eigen::Vector3d(0.1 * index, 0.0, 1.0);
  v.T_world_sensor_prior = v.T_world_sensor_true;
  v.T_world_sensor_prior.translation().z() += 0.01;
  const int n = sensor.intrinsics.width * sensor.intrinsics.height;
  for (int i = 0; i < n; ++i)
    v.points_sensor.push_back(i % 3 == 0 ? Eigen::Vector3d::Constant(std::nan(""))
                                         : Eigen::Vector3d(0.001 * (i % 640), 0.001 * (i / 640), 1.5));
  return v;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Recorder, AViewsFilesAreWrittenBeforeTheManifestListsIt) {
  const test::TempDir dir;
  io::DepthCamera sensor;
  Manifest manifest;
  manifest.created_by = "test";
  manifest.resolution_m = 0.05;
  Recorder recorder(dir / "session", manifest, sensor);
  EXPECT_TRUE(read_manifest(dir / "session").views.empty());

  map::OccupancyMap map(0.05);
  map.integrate({Eigen::Vector3f(1, 0, 0)}, Eigen::Vector3f::Zero(), 10.0);
  for (int i = 0; i < 2; ++i) {
    const ViewRecord v = view(i, sensor);
    recorder.add(v, map, "{\"view\": " + std::to_string(i) + "}\n");
    const Manifest m = read_manifest(dir / "session");
    ASSERT_EQ(m.views.size(), std::size_t(i + 1));
    const ManifestView& mv = m.views.back();
    EXPECT_EQ(mv.scan, "scans/" + view_file_name(i, ".pcd"));
    EXPECT_TRUE(mv.T_world_sensor_prior.isApprox(v.T_world_sensor_prior, 1e-9));
    ASSERT_TRUE(mv.T_world_sensor_true);
    EXPECT_TRUE(mv.T_world_sensor_true->isApprox(v.T_world_sensor_true, 1e-9));
    const io::CloudFile scan = io::read_cloud(dir / ("session/" + mv.scan));
    EXPECT_EQ(scan.width, sensor.intrinsics.width);
    EXPECT_EQ(scan.height, sensor.intrinsics.height);
    EXPECT_TRUE(scan.viewpoint.translation().isApprox(v.T_world_sensor_prior.translation(), 1e-6));
    EXPECT_EQ(map::OccupancyMap::load(dir / ("session/" + mv.map)).stats().occupied_leaves, 1u);
    EXPECT_EQ(slurp(dir / ("session/" + mv.report)), "{\"view\": " + std::to_string(i) + "}\n");
  }
  EXPECT_EQ(view_file_name(7, ".ot"), "view007.ot");
}

}  // namespace
}  // namespace fvx::session
