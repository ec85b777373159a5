// fvx simulate — a scene mesh and sensor poses → the scans a Kinect would record there
// (PCD with VIEWPOINT, or depth PNGs with a trajectory), and the scene's voxel ground truth.
#include <filesystem>
#include <optional>

#include "command_table.hpp"
#include "fvx/core/atomic_file.hpp"  // lowercase_extension
#include "common_options.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/io/trajectory.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "analysis_output.hpp"
#include "fvx/report/simulate.hpp"
#include "report.hpp"

namespace fvx::cli {

namespace {
const sim::SensorConfig kSensor;  ///< the defaults --help shows
}  // namespace

const CommandSpec kSimulateSpec = {
    "simulate",
    "SCENE.ply|.obj|.stl|builtin:NAME (--pose P | --look-at E,T | --poses FILE) -o OUT [options]",
    "render the scans a Kinect would record in a scene; voxel ground truth",
    options({{
        {"output", 'o', "PATH", "one pose: the scan file (.pcd, or .png with --depth-png); "
                                "several: a folder (created)", "-"},
        {"pose", 0, "x,y,z,qx,qy,qz,qw", "sensor pose T_world_sensor (metres, quaternion scalar-last)",
         "/results/frames/0/T_world_sensor"},
        {"look-at", 0, "ex,ey,ez,tx,ty,tz", "sensor at eye E looking at target T, world z up",
         "/results/frames/0/T_world_sensor"},
        {"poses", 0, "FILE", "one scan per pose of a TUM or Redwood .log trajectory", "/inputs/poses"},
        {"scene-info", 0, "FILE", "ground-truth sidecar JSON (default: SCENE with .json, if present)",
         "/inputs/scene_info"},
    }, intrinsics_options(true, "/config/intrinsics"), {
        {"depth-min", 0, "M", "nearest measurable depth, metres", "/config/depth_min_m", dflt(kSensor.depth_min_m),
         in(0, 1e3)},
        {"depth-max", 0, "M", "farthest measurable depth, metres", "/config/depth_max_m", dflt(kSensor.depth_max_m),
         above(0, 1e3)},
        {"noise", 0, "MODEL", "depth noise: none (default) or kinect (sigma = 1.4 mm * z^2, z in m)",
         "/config/noise_m_per_m2"},
        {"quantize", 0, nullptr, "round depth to Kinect v1 disparity steps (1/8 pixel, 7.5 cm baseline)",
         "/config/quantize_disparity"},
        {"dropout-deg", 0, "DEG", "drop surfaces seen at more than DEG from their normal",
         "/config/dropout_incidence_deg", dflt(kSensor.dropout_incidence_deg) + ": none", above(0, 90)},
        seed_option("/config/seed", "noise seed", kSensor.seed),
        {"depth-png", 0, nullptr, "write 16-bit depth PNGs (and trajectory.txt, intrinsics.json) "
                                  "instead of PCD", "/config/output_format"},
        {"ground-truth", 0, "FILE.bt", "write the scene's voxel ground truth as a map (solid "
                                       "occupied, empty free)", "/results/ground_truth/file"},
        resolution_option("/results/ground_truth/resolution_m", "ground-truth cell edge, metres", ", the paper's"),
        {"bounds", 0, "x0,y0,z0,x1,y1,z1", "ground-truth region, metres (default: the sidecar's "
                                           "search space, else the mesh bounds)", "/results/ground_truth/region"},
        {"backend", 0, "NAME", "ray casting: embree (default), cgal or brute", "/config/backend"},
        threads_option("/config/threads", "render threads"),
        {"report", 0, "FILE", "write the JSON report to FILE instead of stdout", "-"},
        {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
        {"help", 'h', nullptr, "show this help", "-"},
    }})};

namespace {

std::vector<Eigen::Isometry3d> poses_from(const Args& args) {
  const int given = int(args.has("pose")) + int(args.has("look-at")) + int(args.has("poses"));
  if (given > 1) throw UsageError("fvx simulate: give one of --pose, --look-at, --poses");
  if (args.has("pose")) return {parse_pose(args.get("pose"), "--pose")};
  if (args.has("look-at")) return {parse_look_at(args.get("look-at"), "--look-at")};
  std::vector<Eigen::Isometry3d> poses;
  if (args.has("poses"))
    for (const auto& e : io::read_trajectory(args.get("poses")).entries) poses.push_back(e.T_world_sensor);
  return poses;
}

sim::SensorConfig sensor_from(const Args& args) {
  sim::SensorConfig c;
  if (auto K = parse_intrinsics(args, "simulate")) c.intrinsics = *K;
  args.read("depth-min", c.depth_min_m);
  args.read("depth-max", c.depth_max_m);
  if (!(c.depth_max_m > c.depth_min_m)) throw UsageError("fvx simulate: --depth-max must be greater than --depth-min");
  c.noise_m_per_m2 = parse_depth_noise(args);
  c.quantize_disparity = args.has("quantize");
  args.read("dropout-deg", c.dropout_incidence_deg);
  args.read("seed", c.seed);
  args.read("threads", c.threads);
  FVX_ASSERT(c.validate().empty(), "sensor options were checked above");
  return c;
}

}  // namespace

int run_simulate(const Args& args) {
  if (args.positional.size() != 1)
    throw UsageError("fvx simulate: give one scene (a mesh file or builtin:NAME), got " +
                     std::to_string(args.positional.size()));
  const std::vector<Eigen::Isometry3d> poses = poses_from(args);
  const sim::SensorConfig sensor = sensor_from(args);
  const sim::Backend backend = args.has("backend") ? sim::parse_backend(args.get("backend"), "--backend")
                                                   : sim::Backend::Embree;
  const bool depth_png = args.has("depth-png");
  if (poses.empty() && !args.has("ground-truth"))
    throw UsageError("fvx simulate: nothing to do; give --pose, --look-at or --poses, or --ground-truth");
  if (!poses.empty() && !args.has("output")) throw UsageError("fvx simulate: -o/--output is required with poses");
  const std::string output = args.has("output") ? args.get("output") : "";
  const bool to_folder = args.has("poses");
  if (!poses.empty() && !to_folder) {
    const std::string ext = lowercase_extension(output);
    if (ext != (depth_png ? ".png" : ".pcd"))
      throw UsageError("fvx simulate: --output " + output + ": expected a " + (depth_png ? ".png" : ".pcd") + " file");
  }
  const double resolution_m = parse_resolution(args, kDefaultResolution_m);

  const sim::Scene scene = scene_from(args.positional[0], args);
  const auto caster = sim::make_ray_caster(scene.mesh, backend);

  const sim::FrameFormat format = depth_png ? sim::FrameFormat::DepthPng : sim::FrameFormat::Pcd;
  Json report = new_report("simulate");
  report["config"] = simulate_config_json(sensor, backend, format);
  report["inputs"] = {{"scene", scene.mesh_path},
                      {"poses", args.has("poses") ? Json(args.get("poses")) : Json(nullptr)},
                      {"scene_info", scene.info_path.empty() ? Json(nullptr) : Json(scene.info_path)},
                      {"scene_name", scene.info.name},
                      {"triangles", scene.mesh.triangles.size()},
                      {"vertices", scene.mesh.vertices.size()}};
  std::vector<std::string> warnings;

  std::optional<sim::GroundTruth> gt;  // first: a search space it cannot hold fails before any scan is written
  const auto region = args.has("ground-truth") ? sim::ground_truth_region(scene, parse_bounds(args)) : Eigen::AlignedBox3d();
  if (args.has("ground-truth")) gt.emplace(scene.mesh, *caster, resolution_m, region);
  Progress progress(args.has("progress"));
  const std::vector<sim::RecordedFrame> frames =
      sim::record_frames(*caster, poses, sensor, output, to_folder, format, warnings, [&](std::size_t i) {
        progress.update("fvx simulate: frame " + std::to_string(i + 1) + "/" + std::to_string(poses.size()));
      });
  progress.finish();
  report["results"]["frames"] = frames_json(frames);
  if (gt) {
    gt->to_map().save(args.get("ground-truth"));
    report["results"]["ground_truth"] = ground_truth_json(*gt, args.get("ground-truth"), region, scene);
  }
  report["warnings"] = warnings;
  write_report(report, args.has("report") ? args.get("report") : "");
  return core::end_process(0);
}

}  // namespace fvx::cli
