// fvx simulate — a scene mesh and sensor poses → the scans a Kinect would record there
// (PCD with VIEWPOINT, or depth PNGs with a trajectory), and the scene's voxel ground truth.
#include <cmath>
#include <filesystem>
#include <fstream>

#include "command_table.hpp"
#include "common_options.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"
#include "fvx/core/pose.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/trajectory.hpp"
#include "fvx/sim/builtin_scenes.hpp"
#include "fvx/sim/depth_sensor.hpp"
#include "fvx/sim/ground_truth.hpp"
#include "report.hpp"

namespace fvx::cli {

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
        {"depth-min", 0, "M", "nearest measurable depth, metres (default 0.5)", "/config/depth_min_m"},
        {"depth-max", 0, "M", "farthest measurable depth, metres (default 4)", "/config/depth_max_m"},
        {"noise", 0, "MODEL", "depth noise: none (default) or kinect (sigma = 1.4 mm * z^2, z in m)",
         "/config/noise_m_per_m2"},
        {"quantize", 0, nullptr, "round depth to Kinect v1 disparity steps (1/8 pixel, 7.5 cm baseline)",
         "/config/quantize_disparity"},
        {"dropout-deg", 0, "DEG", "drop surfaces seen at more than DEG from their normal (default 90: none)",
         "/config/dropout_incidence_deg"},
        {"seed", 0, "N", "noise seed (default 1)", "/config/seed"},
        {"depth-png", 0, nullptr, "write 16-bit depth PNGs (and trajectory.txt, intrinsics.json) "
                                  "instead of PCD", "/config/output_format"},
        {"ground-truth", 0, "FILE.bt", "write the scene's voxel ground truth as a map (solid "
                                       "occupied, empty free)", "/results/ground_truth/file"},
        {"resolution", 'r', "M", "ground-truth cell edge, metres (default 0.025, the paper's)",
         "/results/ground_truth/resolution_m"},
        {"bounds", 0, "x0,y0,z0,x1,y1,z1", "ground-truth region, metres (default: the sidecar's "
                                           "search space, else the mesh bounds)", "/results/ground_truth/region"},
        {"backend", 0, "NAME", "ray casting: embree (default), cgal or brute", "/config/backend"},
        {"threads", 0, "N", "render threads (default 0: all cores)", "/config/threads"},
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
  c.depth_min_m = args.number("depth-min", c.depth_min_m, 0.0, 1e3);
  c.depth_max_m = args.number("depth-max", c.depth_max_m, 0.0, 1e3, true);
  if (!(c.depth_max_m > c.depth_min_m)) throw UsageError("fvx simulate: --depth-max must be greater than --depth-min");
  c.noise_m_per_m2 = parse_depth_noise(args);
  c.quantize_disparity = args.has("quantize");
  c.dropout_incidence_deg = args.number("dropout-deg", c.dropout_incidence_deg, 0.0, 90.0, true);
  c.seed = std::uint64_t(args.integer("seed", 1, 0, std::numeric_limits<long long>::max()));
  c.threads = unsigned(args.integer("threads", 0, 0, 256));
  FVX_ASSERT(c.validate().empty(), "sensor options were checked above");
  return c;
}

Json box_json(const Eigen::AlignedBox3d& b) { return {{"min", vec_json(b.min())}, {"max", vec_json(b.max())}}; }

/// TUM trajectory with stamp i for frame i, so that `fvx integrate` matches <i>.png by stamp.
void write_tum(const std::string& path, const std::vector<Eigen::Isometry3d>& poses) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# timestamp tx ty tz qx qy qz qw (T_world_sensor), written by fvx simulate\n";
    out.precision(9);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Eigen::Quaterniond q(poses[i].rotation());
      const Eigen::Vector3d& t = poses[i].translation();
      out << i << " " << t.x() << " " << t.y() << " " << t.z() << " " << q.x() << " " << q.y() << " "
          << q.z() << " " << q.w() << "\n";
    }
  });
}

/// The scene's ground truth over --bounds (default: the scene's search space, else its
/// bounds) as a map at `path`, and what the report says of it.
Json write_ground_truth(const Args& args, const sim::Scene& scene, const sim::RayCaster& caster, double resolution_m) {
  Eigen::AlignedBox3d region;
  if (args.has("bounds")) {
    const auto b = parse_double_list(args.get("bounds"), "--bounds (x0,y0,z0,x1,y1,z1)", 6);
    region = Eigen::AlignedBox3d(Eigen::Vector3d(b[0], b[1], b[2]), Eigen::Vector3d(b[3], b[4], b[5]));
    if (!(region.min().array() < region.max().array()).all())
      throw UsageError("--bounds: the minimum must be below the maximum on every axis");
  } else if (scene.info.search_space) {
    region = *scene.info.search_space;
  } else {
    const Eigen::AlignedBox3f b = scene.mesh.bounds();
    region = Eigen::AlignedBox3d(b.min().cast<double>(), b.max().cast<double>());
  }
  const sim::GroundTruth gt(scene.mesh, caster, resolution_m, region);
  const std::string path = args.get("ground-truth");
  gt.to_map().save(path);
  const double cell_m3 = std::pow(resolution_m, 3);
  Json containers = Json::array();
  for (const auto& c : scene.info.containers)
    containers.push_back({{"name", c.name}, {"box", box_json(c.box)},
                          {"free_volume_dm3", gt.free_volume_m3(c.box) * 1e3}});
  Json result = {{"file", path},
                 {"resolution_m", resolution_m},
                 {"region", box_json(region)},
                 {"solid_cells", gt.solid_cells()},
                 {"free_cells", gt.free_cells()},
                 {"solid_volume_m3", double(gt.solid_cells()) * cell_m3},
                 {"free_volume_m3", double(gt.free_cells()) * cell_m3},
                 {"containers", containers}};
  if (scene.info.target)
    result["target"] = {{"name", scene.info.target->name}, {"box", box_json(scene.info.target->box)}};
  return result;
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

  Json report = new_report("simulate");
  report["config"] = {{"intrinsics", io::intrinsics_json(sensor.intrinsics)},
                      {"depth_min_m", sensor.depth_min_m},
                      {"depth_max_m", sensor.depth_max_m},
                      {"noise_m_per_m2", sensor.noise_m_per_m2},
                      {"quantize_disparity", sensor.quantize_disparity},
                      {"dropout_incidence_deg", sensor.dropout_incidence_deg},
                      {"seed", sensor.seed},
                      {"backend", sim::to_string(backend)},
                      {"threads", sensor.threads},
                      {"output_format", depth_png ? "png" : "pcd"}};
  report["inputs"] = {{"scene", scene.mesh_path},
                      {"poses", args.has("poses") ? Json(args.get("poses")) : Json(nullptr)},
                      {"scene_info", scene.info_path.empty() ? Json(nullptr) : Json(scene.info_path)},
                      {"scene_name", scene.info.name},
                      {"triangles", scene.mesh.triangles.size()},
                      {"vertices", scene.mesh.vertices.size()}};
  std::vector<std::string> warnings;

  if (to_folder) std::filesystem::create_directories(output);
  Progress progress(args.has("progress"));
  Json frames = Json::array();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    progress.update("fvx simulate: frame " + std::to_string(i + 1) + "/" + std::to_string(poses.size()));
    const Eigen::Isometry3d& T = poses[i];
    if (sim::inside_solid(*caster, T.translation().cast<float>()))
      warnings.push_back("frame " + std::to_string(i) + ": the sensor is inside a solid; it sees only the inside of that object");
    const sim::Frame frame = sim::render(*caster, T, sensor, i);
    char name[32];
    std::snprintf(name, sizeof name, "%06zu.%s", i, depth_png ? "png" : "pcd");
    const std::string path = to_folder ? (std::filesystem::path(output) / name).string() : output;
    if (depth_png)
      io::write_depth_png(path, frame.depth);
    else
      io::write_pcd(path, frame.points_sensor, T, frame.depth.width, frame.depth.height);
    if (frame.valid == 0) warnings.push_back("frame " + std::to_string(i) + ": no pixel has a measurement");
    frames.push_back({{"index", i}, {"file", path}, {"T_world_sensor", pose_json(T)},
                      {"pixels", {{"valid", frame.valid}, {"no_surface", frame.no_surface},
                                  {"too_near", frame.too_near}, {"grazing", frame.grazing}}}});
  }
  progress.finish();
  if (to_folder) {
    write_tum((std::filesystem::path(output) / "trajectory.txt").string(), poses);
    if (depth_png) {
      const std::string path = (std::filesystem::path(output) / "intrinsics.json").string();
      write_file_atomically(path, [&](std::ostream& out) { out << io::intrinsics_json(sensor.intrinsics).dump(2) << "\n"; });
    }
  }
  report["results"]["frames"] = frames;

  if (args.has("ground-truth"))
    report["results"]["ground_truth"] = write_ground_truth(args, scene, *caster, resolution_m);
  report["warnings"] = warnings;
  write_report(report, args.has("report") ? args.get("report") : "");
  return 0;
}

}  // namespace fvx::cli
