// The session directory's manifest (man/fvx-session.5).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/pose.hpp"  // version()
#include "fvx/session/session.hpp"

namespace fvx::session {

namespace {

using Json = nlohmann::ordered_json;

Json pose_json(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  return {{"position_m", {T.translation().x(), T.translation().y(), T.translation().z()}},
          {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

Json box_json(const std::optional<Eigen::AlignedBox3d>& b) {
  if (!b) return nullptr;
  return {{"min", {b->min().x(), b->min().y(), b->min().z()}}, {"max", {b->max().x(), b->max().y(), b->max().z()}}};
}

/// Reading: every problem names the manifest and the key.
struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& what) const { throw FileError(file, what); }
  const Json& at(const Json& j, const char* key) const {
    if (!j.is_object() || !j.contains(key)) fail("missing key '" + std::string(key) + "'");
    return j.at(key);
  }
  double number(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (!v.is_number()) fail("'" + std::string(key) + "' must be a number");
    return v.get<double>();
  }
  /// A whole number in [min, max]: a float such as 1e30 is refused, not converted.
  long long integer(const Json& j, const char* key, long long min, long long max) const {
    const double v = number(j, key);
    if (!(v == std::floor(v) && v >= double(min) && v <= double(max)))
      fail("'" + std::string(key) + "' must be a whole number in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    return (long long)v;
  }
  bool flag(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (!v.is_boolean()) fail("'" + std::string(key) + "' must be true or false");
    return v.get<bool>();
  }
  std::string text(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (!v.is_string()) fail("'" + std::string(key) + "' must be a string");
    return v.get<std::string>();
  }
  Eigen::Vector3d vec3(const Json& v, const std::string& what) const {
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail("'" + what + "' must be 3 numbers");
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  }
  Eigen::Isometry3d pose(const Json& j, const std::string& what) const {
    if (!j.is_object()) fail("'" + what + "' must be a pose object");
    const Eigen::Vector3d t = vec3(at(j, "position_m"), what + ".position_m");
    const Json& q = at(j, "quaternion_xyzw");
    if (!q.is_array() || q.size() != 4 || !q[0].is_number() || !q[1].is_number() || !q[2].is_number() ||
        !q[3].is_number())
      fail("'" + what + ".quaternion_xyzw' must be 4 numbers");
    Eigen::Quaterniond quat(q[3].get<double>(), q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
    if (!(std::abs(quat.norm() - 1.0) < 1e-3)) fail("'" + what + ".quaternion_xyzw' is not a unit quaternion");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = quat.normalized().toRotationMatrix();
    T.translation() = t;
    return T;
  }
  std::optional<Eigen::AlignedBox3d> box(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (v.is_null()) return std::nullopt;
    return Eigen::AlignedBox3d(vec3(at(v, "min"), std::string(key) + ".min"), vec3(at(v, "max"), std::string(key) + ".max"));
  }
};

}  // namespace

void write_manifest(const std::string& dir, const Manifest& m) {
  Json j;
  j["schema_version"] = m.schema_version;
  j["created_by"] = m.created_by;
  j["scene"] = m.scene.empty() ? Json(nullptr) : Json(m.scene);
  j["sensor"] = m.sensor;
  j["resolution_m"] = m.resolution_m;
  j["search_space_m"] = box_json(m.search_space_m);
  j["view_bounds_m"] = box_json(m.view_bounds_m);
  j["T_world_base"] = m.T_world_base ? pose_json(*m.T_world_base) : Json(nullptr);
  j["arm"] = m.arm.empty() ? Json(nullptr) : Json(m.arm);
  j["capmap"] = m.capmap.empty() ? Json(nullptr) : Json(m.capmap);
  j["capmap_urdf_hash"] = m.capmap_urdf_hash.empty() ? Json(nullptr) : Json(m.capmap_urdf_hash);
  j["strategy"] = m.strategy;
  j["seed"] = m.seed;
  j["pose_noise"] = {{"sigma_m", m.pose_noise_m}, {"sigma_deg", m.pose_noise_deg}};
  j["registration"] = m.registration;
  j["near_voids"] = m.near_voids;
  j["target_size_m"] = m.target_size_m;
  j["hull_in_bounds"] = m.hull_in_bounds;
  j["unknown_depth_cells"] = m.unknown_depth_cells;
  j["near_unknown"] = m.near_unknown;
  j["clear_beyond_range"] = m.clear_beyond_range;
  j["exterior"] = m.exterior;
  j["discretize"] = m.discretize;
  j["accumulation"] = m.accumulation;
  j["max_utility_vectors"] = m.max_utility_vectors;
  j["coarse_rays"] = {m.coarse_ray_cols, m.coarse_ray_rows};
  Json views = Json::array();
  for (const ManifestView& v : m.views) {
    Json jv = {{"view", v.view}, {"scan", v.scan}, {"map", v.map}, {"report", v.report},
               {"stamp_s", v.stamp_s}, {"T_world_sensor", pose_json(v.T_world_sensor_prior)}};
    jv["T_world_sensor_true"] = v.T_world_sensor_true ? pose_json(*v.T_world_sensor_true) : Json(nullptr);
    jv["joints_rad"] = v.joints_rad.size() ? Json(std::vector<double>(v.joints_rad.data(), v.joints_rad.data() + v.joints_rad.size()))
                                           : Json(nullptr);
    views.push_back(jv);
  }
  j["views"] = views;
  write_file_atomically((std::filesystem::path(dir) / "manifest.json").string(),
                        [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

namespace {

/// The search model's settings, each optional (absent in sessions written before it existed).
void read_search_model(const Json& j, const Reader& r, Manifest& m) {
  const auto flag = [&](const char* key, bool& out) {
    if (j.contains(key)) out = r.flag(j, key);
  };
  flag("near_voids", m.near_voids);
  flag("hull_in_bounds", m.hull_in_bounds);
  flag("clear_beyond_range", m.clear_beyond_range);
  flag("discretize", m.discretize);
  if (j.contains("target_size_m")) {
    m.target_size_m = r.number(j, "target_size_m");
    if (!(m.target_size_m >= 0.0 && m.target_size_m <= 10.0)) r.fail("'target_size_m' must be in [0, 10] metres");
  }
  if (j.contains("unknown_depth_cells")) m.unknown_depth_cells = int(r.integer(j, "unknown_depth_cells", 0, 1000));
  // A mode's name, checked by the parser replay will read it with.
  const auto mode = [&](const char* key, std::string& out, const auto& parse) {
    if (!j.contains(key)) return;
    out = r.text(j, key);
    try {
      parse(out, "'" + std::string(key) + "'");
    } catch (const UsageError& e) {
      r.fail(e.what());
    }
  };
  mode("exterior", m.exterior, nbv::parse_exterior);
  mode("near_unknown", m.near_unknown, viewpoints::parse_near_unknown);
  if (j.contains("accumulation")) {
    m.accumulation = r.text(j, "accumulation");
    if (m.accumulation != "exact" && m.accumulation != "sampled") r.fail("'accumulation' must be exact or sampled");
  }
  if (j.contains("max_utility_vectors")) {
    const Json& v = j["max_utility_vectors"];
    if (!v.is_number_unsigned() || v.get<std::uint64_t>() < 7) r.fail("'max_utility_vectors' must be an integer >= 7");
    m.max_utility_vectors = v.get<std::uint64_t>();
  }
  if (j.contains("coarse_rays")) {
    const Json& v = j["coarse_rays"];
    const auto whole = [](const Json& n) { return n.is_number_unsigned() && n.get<std::uint64_t>() <= 4096; };
    if (!v.is_array() || v.size() != 2 || !whole(v[0]) || !whole(v[1]) || (v[0] == 0) != (v[1] == 0))
      r.fail("'coarse_rays' must be [cols, rows], each in [1, 4096], or [0, 0]");
    m.coarse_ray_cols = v[0].get<int>();
    m.coarse_ray_rows = v[1].get<int>();
  }
}

}  // namespace

namespace {

/// The manifest's keys, each checked for its type and range (Reader names the key).
Manifest manifest_from_json(const Json& j, const Reader& r) {
  Manifest m;
  m.schema_version = int(r.integer(j, "schema_version", 0, 1 << 30));
  if (m.schema_version != kSchemaVersion)
    r.fail("schema_version " + std::to_string(m.schema_version) + " is not one this fvx reads (" +
           std::to_string(kSchemaVersion) + ")");
  m.created_by = r.text(j, "created_by");
  m.scene = r.at(j, "scene").is_null() ? "" : r.text(j, "scene");
  m.sensor = r.text(j, "sensor");
  m.resolution_m = r.number(j, "resolution_m");
  if (!(m.resolution_m > 0)) r.fail("'resolution_m' must be > 0");
  m.search_space_m = r.box(j, "search_space_m");
  m.view_bounds_m = r.box(j, "view_bounds_m");
  if (!r.at(j, "T_world_base").is_null()) m.T_world_base = r.pose(j["T_world_base"], "T_world_base");
  m.arm = r.at(j, "arm").is_null() ? "" : r.text(j, "arm");
  m.capmap = r.at(j, "capmap").is_null() ? "" : r.text(j, "capmap");
  m.capmap_urdf_hash = r.at(j, "capmap_urdf_hash").is_null() ? "" : r.text(j, "capmap_urdf_hash");
  // "planner": its name in sessions written before every command called it the strategy.
  m.strategy = r.text(j, j.contains("strategy") || !j.contains("planner") ? "strategy" : "planner");
  if (!r.at(j, "seed").is_number_unsigned()) r.fail("'seed' must be a whole number >= 0");
  m.seed = j["seed"].get<std::uint64_t>();
  m.pose_noise_m = r.number(r.at(j, "pose_noise"), "sigma_m");
  m.pose_noise_deg = r.number(r.at(j, "pose_noise"), "sigma_deg");
  m.registration = r.flag(j, "registration");
  read_search_model(j, r, m);
  const Json& views = r.at(j, "views");
  if (!views.is_array()) r.fail("'views' must be an array");
  for (const Json& jv : views) {
    ManifestView v;
    v.view = int(r.integer(jv, "view", 0, 1 << 30));
    if (v.view != int(m.views.size()))
      r.fail("view " + std::to_string(v.view) + " is out of order (expected " + std::to_string(m.views.size()) + ")");
    v.scan = r.text(jv, "scan");
    v.map = r.text(jv, "map");
    v.report = r.text(jv, "report");
    v.stamp_s = r.number(jv, "stamp_s");
    v.T_world_sensor_prior = r.pose(r.at(jv, "T_world_sensor"), "T_world_sensor");
    if (!r.at(jv, "T_world_sensor_true").is_null()) v.T_world_sensor_true = r.pose(jv["T_world_sensor_true"], "T_world_sensor_true");
    if (!r.at(jv, "joints_rad").is_null()) {
      const Json& joints = jv["joints_rad"];
      if (!joints.is_array() || !std::all_of(joints.begin(), joints.end(), [](const Json& x) { return x.is_number(); }))
        r.fail("'joints_rad' must be an array of numbers or null");
      const auto q = joints.get<std::vector<double>>();
      v.joints_rad = Eigen::Map<const Eigen::VectorXd>(q.data(), Eigen::Index(q.size()));
    }
    m.views.push_back(std::move(v));
  }
  return m;
}

}  // namespace

Manifest read_manifest(const std::string& dir) {
  const std::string file = (std::filesystem::path(dir) / "manifest.json").string();
  if (std::filesystem::exists(file)) require_readable_file(file);
  std::ifstream in(file);
  if (!in) throw FileError(file, "cannot open the session manifest (is " + dir + " a session directory?)");
  Json j;
  try {
    j = Json::parse(in);
  } catch (const std::exception& e) {
    throw FileError(file, std::string("not valid JSON: ") + e.what());
  }
  const Reader r{file};
  try {
    return manifest_from_json(j, r);
  } catch (const nlohmann::json::exception& e) {  // a type no check above foresaw: still named
    r.fail(std::string("bad manifest: ") + e.what());
  }
}

void write_depth_camera(const std::string& path, const io::DepthCamera& c) {
  const Json j = {{"fx", c.intrinsics.fx},       {"fy", c.intrinsics.fy},         {"cx", c.intrinsics.cx},
                  {"cy", c.intrinsics.cy},       {"depth_scale", c.intrinsics.depth_scale},
                  {"width", c.intrinsics.width}, {"height", c.intrinsics.height}, {"depth_min_m", c.depth_min_m},
                  {"depth_max_m", c.depth_max_m}};
  write_file_atomically(path, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

std::string resolve_path(const std::string& path, const std::string& session_dir) {
  if (path.empty() || std::filesystem::exists(path)) return path;
  const std::filesystem::path beside = std::filesystem::path(session_dir) / path;
  return std::filesystem::exists(beside) ? beside.string() : path;
}

Manifest explore_manifest(const ExploreConfig& config, const std::string& scene, const std::optional<nbv::Reach>& reach,
                          const std::string& capmap_path, const std::string& arm_path) {
  const pipeline::Config& pc = config.pipeline;
  const nbv::Config& nc = pc.nbv;
  Manifest m;
  m.created_by = std::string("fvx explore ") + version();
  m.scene = scene;
  m.resolution_m = pc.resolution_m;
  m.search_space_m = pc.bounds_m;
  m.view_bounds_m = nc.view_bounds_m;
  if (reach) {
    m.T_world_base = reach->T_world_base;
    m.capmap = capmap_path;
    m.capmap_urdf_hash = reach->capmap->header().urdf_hash;
  }
  m.arm = arm_path;
  m.strategy = nbv::to_string(nc.strategy);
  m.seed = config.seed;
  m.pose_noise_m = config.pose_noise_m;
  m.pose_noise_deg = config.pose_noise_deg;
  m.registration = pc.register_scans;
  m.near_voids = nc.count_near_void_cells;
  m.target_size_m = pc.target_size_m;
  m.hull_in_bounds = pc.hull_in_bounds;
  m.unknown_depth_cells = nc.unknown_depth_cells;
  m.near_unknown = viewpoints::to_string(nc.near_unknown);
  m.exterior = nbv::to_string(nc.exterior);
  m.clear_beyond_range = pc.clear_beyond_range;
  m.discretize = pc.discretize;
  m.accumulation = utility::to_string(nc.accumulation);
  m.max_utility_vectors = nc.max_utility_vectors;
  m.coarse_ray_cols = nc.coarse_ray_cols;
  m.coarse_ray_rows = nc.coarse_ray_rows;
  return m;
}

}  // namespace fvx::session
