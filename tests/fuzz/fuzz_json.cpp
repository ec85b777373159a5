// libFuzzer harness: the JSON readers - intrinsics, sensor, scene sidecar and session
// manifest - each on the same bytes (they share the parser and differ in keys and limits).
#include "fuzz_input.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/session/session.hpp"
#include "fvx/sim/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "manifest.json");
  fvx::fuzz::expect_answer([&] { fvx::io::read_intrinsics(path); });
  fvx::fuzz::expect_answer([&] { fvx::io::read_depth_camera(path); });
  fvx::fuzz::expect_answer([&] { fvx::sim::read_scene_info(path); });
  fvx::fuzz::expect_answer([&] { fvx::session::read_manifest(fvx::fuzz::folder().string()); });
  return 0;
}
