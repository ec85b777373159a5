#pragma once
/// \file
/// A simulated scene: a mesh plus an optional ground-truth sidecar (JSON beside the mesh,
/// same name with .json):
///
///     {"name": "closed box",
///      "search_space": {"min": [x, y, z], "max": [x, y, z]},
///      "target": {"name": "victim", "min": [...], "max": [...]},
///      "containers": [{"name": "box A", "min": [...], "max": [...]}],
///      "bases": [[x, y, z, roll, pitch, yaw], ...]}
///
/// All keys are optional; boxes are axis-aligned, metres, world frame. `containers` are the
/// interiors of boxes whose free volume ground truth reports. `bases` are where an arm's base
/// may stand (T_world_base, metres and degrees, as --base takes it); the first is the one
/// `fvx explore` uses when --base is not given.
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "fvx/sim/mesh.hpp"

namespace fvx::sim {

struct NamedBox {
  std::string name;
  Eigen::AlignedBox3d box;
};

struct SceneInfo {
  std::string name;
  std::optional<Eigen::AlignedBox3d> search_space;
  std::optional<NamedBox> target;
  std::vector<NamedBox> containers;
  std::vector<std::array<double, 6>> bases;  ///< x, y, z (m), roll, pitch, yaw (degrees)
};

struct Scene {
  std::string mesh_path;
  std::string info_path;  ///< empty when the scene has no sidecar
  Mesh mesh;
  SceneInfo info;
};

/// Reads a sidecar; unknown keys and malformed boxes are refused with FileError.
SceneInfo read_scene_info(const std::string& path);
void write_scene_info(const std::string& path, const SceneInfo& info);

/// Reads the mesh and its sidecar: `info_path` if given, else <mesh without extension>.json
/// when that file exists.
Scene load_scene(const std::string& mesh_path, const std::string& info_path = "");

}  // namespace fvx::sim
