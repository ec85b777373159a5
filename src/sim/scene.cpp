#include "fvx/sim/scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::sim {
namespace {

using nlohmann::json;

void only_keys(const json& j, const std::set<std::string>& known, const std::string& path,
               const std::string& where) {
  if (!j.is_object()) throw FileError(path, where + " must be a JSON object");
  for (const auto& item : j.items())
    if (!known.count(item.key())) throw FileError(path, "unknown key '" + item.key() + "' in " + where);
}

/// Scenes are rooms, not continents: ±10 km keeps every box inside what a map and a ray
/// caster can hold (1e6 m aborted the ground truth, 1e308 Embree).
constexpr double kSceneLimitM = 1e4;

Eigen::Vector3d vec3(const json& j, const std::string& path, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw FileError(path, where + " must be [x, y, z] in metres");
  const Eigen::Vector3d v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  if (!(v.array().abs() <= kSceneLimitM).all()) throw FileError(path, where + " must lie within ±10000 m");
  return v;
}

Eigen::AlignedBox3d box_of(const json& j, const std::string& path, const std::string& where) {
  if (!j.contains("min") || !j.contains("max")) throw FileError(path, where + " needs 'min' and 'max'");
  const Eigen::Vector3d lo = vec3(j.at("min"), path, where + ".min"), hi = vec3(j.at("max"), path, where + ".max");
  if (!(lo.array() < hi.array()).all()) throw FileError(path, where + ": min must be below max on every axis");
  return {lo, hi};
}

NamedBox named_box(const json& j, const std::string& path, const std::string& where) {
  only_keys(j, {"name", "min", "max"}, path, where);
  NamedBox b;
  if (j.contains("name")) {
    if (!j.at("name").is_string()) throw FileError(path, where + ".name must be a string");
    b.name = j.at("name").get<std::string>();
  }
  b.box = box_of(j, path, where);
  return b;
}

/// Metres rounded to micrometres: scene coordinates built in float read back as written.
double um(double v) { return std::round(v * 1e6) / 1e6; }

nlohmann::ordered_json box_json(const Eigen::AlignedBox3d& b) {
  return {{"min", {um(b.min().x()), um(b.min().y()), um(b.min().z())}},
          {"max", {um(b.max().x()), um(b.max().y()), um(b.max().z())}}};
}

}  // namespace

SceneInfo read_scene_info(const std::string& path) {
  require_readable_file(path);
  std::ifstream in(path);
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw FileError(path, std::string("not valid JSON: ") + e.what());
  }
  only_keys(j, {"name", "search_space", "target", "containers", "bases"}, path, "the scene file");
  SceneInfo info;
  if (j.contains("name")) info.name = j.at("name").is_string() ? j.at("name").get<std::string>() : "";
  if (j.contains("search_space")) {
    only_keys(j.at("search_space"), {"min", "max"}, path, "search_space");
    info.search_space = box_of(j.at("search_space"), path, "search_space");
  }
  if (j.contains("target")) info.target = named_box(j.at("target"), path, "target");
  if (j.contains("containers")) {
    if (!j.at("containers").is_array()) throw FileError(path, "containers must be a list");
    for (std::size_t i = 0; i < j.at("containers").size(); ++i)
      info.containers.push_back(named_box(j.at("containers")[i], path, "containers[" + std::to_string(i) + "]"));
  }
  if (j.contains("bases")) {
    if (!j.at("bases").is_array()) throw FileError(path, "bases must be a list");
    for (const json& b : j.at("bases")) {
      std::array<double, 6> pose{};
      if (!b.is_array() || b.size() != 6) throw FileError(path, "each of bases must be [x, y, z, roll, pitch, yaw]");
      for (std::size_t i = 0; i < 6; ++i) {
        if (!b[i].is_number() || !std::isfinite(b[i].get<double>()))
          throw FileError(path, "each of bases must be [x, y, z, roll, pitch, yaw]: finite numbers");
        pose[i] = b[i].get<double>();
      }
      info.bases.push_back(pose);
    }
  }
  return info;
}

void write_scene_info(const std::string& path, const SceneInfo& info) {
  using ordered = nlohmann::ordered_json;
  auto named = [](const NamedBox& b) {
    ordered j = {{"name", b.name}};
    j.update(box_json(b.box));
    return j;
  };
  ordered j;
  j["name"] = info.name;
  if (info.search_space) j["search_space"] = box_json(*info.search_space);
  if (info.target) j["target"] = named(*info.target);
  j["containers"] = ordered::array();
  for (const auto& c : info.containers) j["containers"].push_back(named(c));
  if (!info.bases.empty()) {
    j["bases"] = ordered::array();
    for (const auto& b : info.bases) j["bases"].push_back({um(b[0]), um(b[1]), um(b[2]), b[3], b[4], b[5]});
  }
  write_file_atomically(path, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

Scene load_scene(const std::string& mesh_path, const std::string& info_path) {
  Scene scene;
  scene.mesh_path = mesh_path;
  scene.mesh = read_mesh(mesh_path);
  std::string sidecar = info_path;
  if (sidecar.empty()) {
    const std::string candidate = std::filesystem::path(mesh_path).replace_extension(".json").string();
    if (std::filesystem::exists(candidate)) sidecar = candidate;
  }
  if (!sidecar.empty()) {
    scene.info = read_scene_info(sidecar);
    scene.info_path = sidecar;
  }
  return scene;
}

}  // namespace fvx::sim
