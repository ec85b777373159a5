#include "fvx/session/recorder.hpp"

#include <cstdio>
#include <filesystem>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/io/cloud_file.hpp"

namespace fvx::session {

std::string view_file_name(int view, const char* extension) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "view%03d%s", view, extension);
  return buf;
}

Recorder::Recorder(std::string dir, Manifest manifest, const io::DepthCamera& sensor)
    : dir_(std::move(dir)), manifest_(std::move(manifest)), sensor_(sensor) {
  FVX_ASSERT(manifest_.views.empty(), "Recorder: a new session has no views");
  const std::filesystem::path root(dir_);
  for (const char* sub : {"scans", "maps", "reports"}) create_folder((root / sub).string());
  write_depth_camera((root / manifest_.sensor).string(), sensor_);
  write_manifest(dir_, manifest_);
}

Recorder::Recorder(std::string dir) : dir_(std::move(dir)) {}

void Recorder::save_map(int view, const map::OccupancyMap& map) const {
  create_folder((std::filesystem::path(dir_) / "maps").string());
  map.save((std::filesystem::path(dir_) / "maps" / view_file_name(view, ".ot")).string());
}

void Recorder::save_report(int view, const std::string& report_text) const {
  create_folder((std::filesystem::path(dir_) / "reports").string());
  write_file_atomically((std::filesystem::path(dir_) / "reports" / view_file_name(view, ".json")).string(),
                        [&](std::ostream& out) { out << report_text; });
}

ManifestView Recorder::files_of(const ViewRecord& v) const {
  ManifestView mv;
  mv.view = v.view;
  mv.scan = "scans/" + view_file_name(v.view, ".pcd");
  mv.map = "maps/" + view_file_name(v.view, ".ot");
  mv.report = "reports/" + view_file_name(v.view, ".json");
  mv.T_world_sensor_prior = v.T_world_sensor_prior;
  mv.T_world_sensor_true = v.T_world_sensor_true;
  mv.joints_rad = v.joints_rad;
  mv.stamp_s = double(v.view);  // simulated: one second per view
  return mv;
}

void Recorder::add(const ViewRecord& v, const map::OccupancyMap& map, const std::string& report_text) {
  const ManifestView mv = files_of(v);
  const std::filesystem::path root(dir_);
  std::vector<Eigen::Vector3f> organised;
  organised.reserve(v.points_sensor.size());
  for (const auto& p : v.points_sensor) organised.push_back(p.cast<float>());
  io::write_pcd((root / mv.scan).string(), organised, v.T_world_sensor_prior, sensor_.intrinsics.width,
                sensor_.intrinsics.height);
  save_map(v.view, map);  // mv.map
  save_report(v.view, report_text);  // mv.report
  manifest_.views.push_back(mv);
  write_manifest(dir_, manifest_);
}

}  // namespace fvx::session
