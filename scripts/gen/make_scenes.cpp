// Writes the built-in scenes (fvx::sim::builtin_scene) as PLY meshes with JSON sidecars, so
// that users can open, edit and pass them to `fvx simulate` like any other scene.
//
//   make_scenes OUT_DIR [NAME...]     (default: every named built-in scene; suite/N → suite-N.ply)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "fvx/core/error.hpp"
#include "fvx/sim/builtin_scenes.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_scenes OUT_DIR [NAME...]\n");
    return 2;
  }
  const std::filesystem::path out = argv[1];
  try {
    std::filesystem::create_directories(out);
    std::vector<std::string> names(argv + 2, argv + argc);
    if (names.empty()) names = fvx::sim::builtin_scene_names();
    for (const std::string& builtin : names) {
      const fvx::sim::Scene scene = fvx::sim::builtin_scene(builtin);
      std::string name = builtin;
      std::replace(name.begin(), name.end(), '/', '-');
      fvx::sim::write_mesh_ply((out / (name + ".ply")).string(), scene.mesh);
      fvx::sim::write_scene_info((out / (name + ".json")).string(), scene.info);
      std::printf("%s: %zu triangles\n", (out / (name + ".ply")).c_str(), scene.mesh.triangles.size());
    }
  } catch (const fvx::Error& e) {
    std::fprintf(stderr, "make_scenes: %s\n", e.what());
    return 1;
  }
  return 0;
}
