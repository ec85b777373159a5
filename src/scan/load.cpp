#include "fvx/scan/load.hpp"

#include <glob.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fvx/core/atomic_file.hpp"
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
    case PoseMatch::ByFrameName: return "frame-name";
    case PoseMatch::ByTf: return "tf";
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

void match_by_frame_name(ScanPlan& plan, const io::Trajectory& trajectory, const std::string& dir) {
  plan.match = PoseMatch::ByFrameName;
  for (auto& scan : plan.scans) {
    const std::string name = io::frame_name(scan.path);
    const auto it = std::find_if(trajectory.entries.begin(), trajectory.entries.end(),
                                 [&](const io::TrajectoryEntry& e) { return e.frame_name == name; });
    if (it == trajectory.entries.end())
      throw Error(dir + ": no pose file for frame '" + name + "' (scan " + scan.path + ")");
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

UsageError needs_intrinsics(const std::string& path) {
  return UsageError(path + ": a depth image needs intrinsics (--intrinsics FILE or --fx/--fy/--cx/--cy)");
}

FileError no_pose(const std::string& path) {
  return FileError(path, std::string("no pose: ") +
                             (io::is_depth_image_path(path) ? "a depth image states none"
                                                            : "the file states none (no PCD VIEWPOINT, no PLY camera element)") +
                             "; give --trajectory, or --pose (0,0,0,0,0,0,1: the sensor frame)");
}

}  // namespace

ScanPlan plan_scans(const std::vector<std::string>& paths, const LoadConfig& config) {
  ScanPlan plan;
  for (const auto& p : paths) plan.scans.push_back({p, std::nullopt, PoseSource::Identity, std::nullopt});
  if (!config.trajectory_path.empty()) {
    const io::Trajectory trajectory = io::read_trajectory(config.trajectory_path, config.pose_format);
    const auto& tp = config.trajectory_path;
    const bool integral_stems =
        all_stems(paths, [](double v) { return v >= 0 && v == std::floor(v); });
    const bool by_id = trajectory.format == io::TrajectoryFormat::RedwoodLog || trajectory.format == io::TrajectoryFormat::Kitti;
    if (trajectory.format == io::TrajectoryFormat::PoseFiles)
      match_by_frame_name(plan, trajectory, tp);
    else if (by_id && integral_stems)
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
  } else {
    // A depth image never states its pose: say so before the first scan is integrated.
    for (const auto& p : paths) {
      if (!io::is_depth_image_path(p)) continue;
      if (!config.intrinsics) throw needs_intrinsics(p);  // the first thing to fix
      throw no_pose(p);
    }
  }
  return plan;
}

ScanPlan plan_bag(const io::BagQuery& query) {
  ScanPlan plan;
  plan.match = PoseMatch::ByTf;
  for (const io::BagMessage& m : io::index_bag(query))
    plan.scans.push_back({io::bag_message_name(query, m), m.T_fixed_sensor, PoseSource::Tf, std::pair{query, m}});
  return plan;
}

namespace {

/// The image's points, unless the intrinsics state another size: they are then another
/// camera's (or resolution's), and back-projecting with them would misplace every point.
std::vector<Eigen::Vector3d> backproject_checked(const std::string& path, const io::DepthImage& depth,
                                                 const io::Intrinsics& K) {
  if (K.size_stated && (depth.width != K.width || depth.height != K.height))
    throw FileError(path, "the image is " + std::to_string(depth.width) + "x" + std::to_string(depth.height) +
                              " but the intrinsics say " + std::to_string(K.width) + "x" + std::to_string(K.height));
  return backproject(depth, K);
}

/// A bag message's points in its frame: a cloud's, or its depth image back-projected.
Scan load_bag_scan(const ScanSource& source) {
  const auto& [query, message] = *source.bag;
  io::BagScan data = io::read_bag_scan(query, message);
  Scan scan;
  scan.source = source.path;
  scan.points_sensor = data.depth ? backproject_checked(source.path, *data.depth, data.intrinsics) : std::move(data.points);
  scan.T_world_sensor = message.T_fixed_sensor;
  scan.pose_source = PoseSource::Tf;
  return scan;
}

}  // namespace

Scan load_scan(const ScanSource& source, const LoadConfig& config,
               std::vector<std::string>& warnings) {
  if (source.bag) return load_bag_scan(source);
  Scan scan;
  scan.source = source.path;
  std::optional<Eigen::Isometry3d> viewpoint;  // the pose the file states
  const bool cloud = !io::is_depth_image_path(source.path);
  if (!cloud) {
    if (!config.intrinsics) throw needs_intrinsics(source.path);
    scan.points_sensor = backproject_checked(source.path, io::read_depth_image(source.path), *config.intrinsics);
  } else {
    io::CloudFile file = io::read_cloud(source.path);
    scan.points_sensor = std::move(file.points);
    if (file.viewpoint_stated) viewpoint = file.viewpoint;
    if (config.use_viewpoint && !source.T_world_sensor && io::is_legacy_openni_viewpoint(file.viewpoint))
      warnings.push_back(source.path + ": VIEWPOINT is the legacy OpenNI 180° rotation about x; "
                         "if the points are already in the optical frame, pass --ignore-viewpoint");
  }
  // The pose rule: a trajectory (or --pose), else the scan's own pose, else an error.
  if (source.T_world_sensor) {
    scan.T_world_sensor = *source.T_world_sensor;
    scan.pose_source = source.pose_source;
  } else if (cloud && !config.use_viewpoint) {
    scan.pose_source = PoseSource::Identity;  // --ignore-viewpoint: the points are in the world frame
  } else if (viewpoint) {
    scan.T_world_sensor = *viewpoint;
    scan.pose_source = PoseSource::Viewpoint;
  } else {
    throw no_pose(source.path);
  }
  return scan;
}

std::vector<std::string> expand_glob(const std::string& pattern, const std::string& what) {
  glob_t g{};
  const int rc = ::glob(pattern.c_str(), 0, nullptr, &g);
  std::vector<std::string> paths;
  if (rc == 0)
    for (std::size_t i = 0; i < g.gl_pathc; ++i) paths.emplace_back(g.gl_pathv[i]);
  globfree(&g);
  if (paths.empty()) throw UsageError(what + " '" + pattern + "' matches no file");
  std::sort(paths.begin(), paths.end());
  return paths;
}

namespace {

/// Per line of a TUM associations file, the depth image it names (relative to the folder).
std::vector<std::string> associated_depth_images(const std::string& associations) {
  require_readable_file(associations);
  std::ifstream in(associations);
  if (!in) throw FileError(associations, "cannot open the associations file");
  std::vector<std::string> names;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string w; fields >> w;) f.push_back(w);
    std::string depth;
    for (const auto& w : f)
      if (w.rfind("depth/", 0) == 0) depth = w;
    if (depth.empty() && f.size() >= 2) depth = f[1];
    if (depth.empty())
      throw FileError(associations + ":" + std::to_string(number),
                      "expected 'stamp depth/FILE' or 'stamp rgb/FILE stamp depth/FILE'");
    names.push_back(depth);
  }
  return names;
}

}  // namespace

std::vector<std::string> tum_depth_images(const std::string& dir, const std::string& associations) {
  const std::filesystem::path root(dir);
  std::vector<std::string> paths;
  if (!associations.empty()) {
    for (const std::string& name : associated_depth_images(associations)) paths.push_back((root / name).string());
  } else {
    if (!std::filesystem::is_directory(root / "depth")) throw FileError(dir, "not a TUM RGB-D folder: no depth/ inside");
    for (const auto& e : std::filesystem::directory_iterator(root / "depth"))
      if (e.is_regular_file()) paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
  }
  if (paths.empty()) throw FileError(dir, "no depth image to replay");
  return paths;
}

std::vector<std::string> tum_recording(const std::string& dir, const std::string& associations, LoadConfig& load) {
  std::vector<std::string> paths = tum_depth_images(dir, associations);
  if (load.trajectory_path.empty()) load.trajectory_path = (std::filesystem::path(dir) / "groundtruth.txt").string();
  if (!std::filesystem::exists(load.trajectory_path))
    throw FileError(load.trajectory_path, "no trajectory: a TUM folder holds groundtruth.txt (or give --trajectory)");
  return paths;
}

}  // namespace fvx::scan
