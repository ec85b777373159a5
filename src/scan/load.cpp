#include "fvx/scan/load.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "fvx/core/error.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/depth_image.hpp"

namespace fvx::scan {

const char* to_string(PoseMatch match) {
  switch (match) {
    case PoseMatch::None: return "none";
    case PoseMatch::ByOrder: return "order";
    case PoseMatch::ByTimestamp: return "timestamp";
    case PoseMatch::ByFrameId: return "frame-id";
  }
  return "?";
}

namespace {

std::optional<double> stem_number(const std::string& path) {
  const std::string stem = std::filesystem::path(path).stem().string();
  if (stem.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(stem.c_str(), &end);
  if (*end != '\0' || !std::isfinite(value)) return std::nullopt;
  return value;
}

template <typename Predicate>
bool all_stems(const std::vector<std::string>& paths, Predicate predicate) {
  for (const auto& p : paths) {
    const auto n = stem_number(p);
    if (!n || !predicate(*n)) return false;
  }
  return true;
}

void match_by_order(ScanPlan& plan, const io::Trajectory& trajectory, const std::string& path) {
  plan.match = PoseMatch::ByOrder;
  if (trajectory.entries.size() < plan.scans.size())
    throw Error(path + ": the trajectory has " + std::to_string(trajectory.entries.size()) +
                " poses for " + std::to_string(plan.scans.size()) +
                " scans (matched by order); give a trajectory with a pose for every scan");
  if (trajectory.entries.size() > plan.scans.size())
    plan.warnings.push_back(path + ": " + std::to_string(trajectory.entries.size()) +
                            " poses for " + std::to_string(plan.scans.size()) +
                            " scans; matched by order, the first poses are used");
  for (std::size_t i = 0; i < plan.scans.size(); ++i)
    plan.scans[i].T_world_sensor = trajectory.entries[i].T_world_sensor;
}

void match_by_frame_id(ScanPlan& plan, const io::Trajectory& trajectory, const std::string& path) {
  plan.match = PoseMatch::ByFrameId;
  for (auto& scan : plan.scans) {
    const long id = std::lround(*stem_number(scan.path));
    const auto it = std::find_if(trajectory.entries.begin(), trajectory.entries.end(),
                                 [&](const io::TrajectoryEntry& e) { return e.frame_id == id; });
    if (it == trajectory.entries.end())
      throw Error(path + ": no pose with frame id " + std::to_string(id) + " for scan " + scan.path);
    scan.T_world_sensor = it->T_world_sensor;
  }
}

void match_by_stamp(ScanPlan& plan, const io::Trajectory& trajectory, const std::string& path,
                    double max_time_diff_s) {
  plan.match = PoseMatch::ByTimestamp;
  for (auto& scan : plan.scans) {
    const double stamp = *stem_number(scan.path);
    const io::TrajectoryEntry* best = nullptr;
    for (const auto& e : trajectory.entries)
      if (!best || std::abs(*e.stamp_s - stamp) < std::abs(*best->stamp_s - stamp)) best = &e;
    if (std::abs(*best->stamp_s - stamp) > max_time_diff_s)
      throw Error(path + ": no pose within " + std::to_string(max_time_diff_s) +
                  " s of the stamp of scan " + scan.path + " (nearest is " +
                  std::to_string(std::abs(*best->stamp_s - stamp)) + " s away)");
    scan.T_world_sensor = best->T_world_sensor;
  }
}

}  // namespace

ScanPlan plan_scans(const std::vector<std::string>& paths, const LoadConfig& config) {
  ScanPlan plan;
  for (const auto& p : paths) plan.scans.push_back({p, std::nullopt, PoseSource::Identity});
  if (!config.trajectory_path.empty()) {
    const io::Trajectory trajectory = io::read_trajectory(config.trajectory_path);
    const auto& tp = config.trajectory_path;
    const bool integral_stems =
        all_stems(paths, [](double v) { return v >= 0 && v == std::floor(v); });
    if (trajectory.format == io::TrajectoryFormat::RedwoodLog && integral_stems)
      match_by_frame_id(plan, trajectory, tp);
    else if (trajectory.format == io::TrajectoryFormat::Tum && all_stems(paths, [](double) { return true; }))
      match_by_stamp(plan, trajectory, tp, config.max_time_diff_s);
    else
      match_by_order(plan, trajectory, tp);
    for (auto& s : plan.scans) s.pose_source = PoseSource::Trajectory;
  } else if (config.pose) {
    for (auto& s : plan.scans) {
      s.T_world_sensor = *config.pose;
      s.pose_source = PoseSource::Flag;
    }
  }
  return plan;
}

Scan load_scan(const ScanSource& source, const LoadConfig& config,
               std::vector<std::string>& warnings) {
  Scan scan;
  scan.source = source.path;
  std::optional<Eigen::Isometry3d> viewpoint;
  if (io::is_depth_image_path(source.path)) {
    if (!config.intrinsics)
      throw UsageError(source.path + ": a depth image needs intrinsics (--intrinsics FILE or --fx/--fy/--cx/--cy)");
    const io::DepthImage depth = io::read_depth_image(source.path);
    const io::Intrinsics& K = *config.intrinsics;
    if (depth.width != K.width || depth.height != K.height)
      warnings.push_back(source.path + ": image is " + std::to_string(depth.width) + "x" +
                         std::to_string(depth.height) + " but the intrinsics say " +
                         std::to_string(K.width) + "x" + std::to_string(K.height));
    scan.points_sensor = backproject(depth, K);
  } else {
    io::CloudFile cloud = io::read_cloud(source.path);
    scan.points_sensor = std::move(cloud.points);
    viewpoint = cloud.viewpoint;
    if (config.use_viewpoint && !source.T_world_sensor && io::is_legacy_openni_viewpoint(cloud.viewpoint))
      warnings.push_back(source.path + ": VIEWPOINT is the legacy OpenNI 180° rotation about x; "
                         "if the points are already in the optical frame, pass --ignore-viewpoint");
  }
  if (source.T_world_sensor) {
    scan.T_world_sensor = *source.T_world_sensor;
    scan.pose_source = source.pose_source;
  } else if (viewpoint && config.use_viewpoint) {
    scan.T_world_sensor = *viewpoint;
    scan.pose_source = PoseSource::Viewpoint;
  } else {
    scan.pose_source = PoseSource::Identity;
    if (!viewpoint) warnings.push_back(source.path + ": no pose given; using the identity");
  }
  return scan;
}

}  // namespace fvx::scan
