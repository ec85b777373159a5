#include "fvx/sim/recording.hpp"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/depth_image.hpp"
#include "fvx/io/intrinsics.hpp"

namespace fvx::sim {

namespace {

RecordedFrame write_frame(const RayCaster& caster, const Eigen::Isometry3d& T, const SensorConfig& sensor,
                          std::size_t i, const std::string& path, FrameFormat format,
                          std::vector<std::string>& warnings) {
  if (inside_solid(caster, T.translation().cast<float>()))
    warnings.push_back("frame " + std::to_string(i) + ": the sensor is inside a solid; it sees only the inside of that object");
  const Frame frame = render(caster, T, sensor, i);
  if (format == FrameFormat::DepthPng)
    io::write_depth_png(path, frame.depth);
  else
    io::write_pcd(path, frame.points_sensor, T, frame.depth.width, frame.depth.height);
  if (frame.valid == 0) warnings.push_back("frame " + std::to_string(i) + ": no pixel has a measurement");
  return {path, T, frame.valid, frame.no_surface, frame.too_near, frame.grazing};
}

}  // namespace

std::vector<RecordedFrame> record_frames(const RayCaster& caster, const std::vector<Eigen::Isometry3d>& poses,
                                         const SensorConfig& sensor, const std::string& output, bool to_folder,
                                         FrameFormat format, std::vector<std::string>& warnings,
                                         const std::function<void(std::size_t)>& progress) {
  const bool png = format == FrameFormat::DepthPng;
  const std::filesystem::path folder = output;
  if (to_folder) create_folder(folder.string());
  std::vector<RecordedFrame> frames;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    progress(i);
    char name[32];
    std::snprintf(name, sizeof name, "%06zu.%s", i, png ? "png" : "pcd");
    frames.push_back(write_frame(caster, poses[i], sensor, i, to_folder ? (folder / name).string() : output, format,
                                 warnings));
  }
  if (!to_folder) return frames;
  write_tum_trajectory((folder / "trajectory.txt").string(), poses);
  if (png)
    write_file_atomically((folder / "intrinsics.json").string(),
                          [&](std::ostream& out) { out << io::intrinsics_json(sensor.intrinsics).dump(2) << "\n"; });
  return frames;
}

void write_tum_trajectory(const std::string& path, const std::vector<Eigen::Isometry3d>& poses) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# timestamp tx ty tz qx qy qz qw (T_world_sensor), written by fvx simulate\n";
    out.precision(9);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Eigen::Quaterniond q(poses[i].rotation());
      const Eigen::Vector3d& t = poses[i].translation();
      out << i << " " << t.x() << " " << t.y() << " " << t.z() << " " << q.x() << " " << q.y() << " " << q.z()
          << " " << q.w() << "\n";
    }
  });
}

Eigen::AlignedBox3d ground_truth_region(const Scene& scene, const std::optional<Eigen::AlignedBox3d>& bounds) {
  if (bounds) return *bounds;
  if (scene.info.search_space) return *scene.info.search_space;
  const Eigen::AlignedBox3f b = scene.mesh.bounds();
  return Eigen::AlignedBox3d(b.min().cast<double>(), b.max().cast<double>());
}

}  // namespace fvx::sim
