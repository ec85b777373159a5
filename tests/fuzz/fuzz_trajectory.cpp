// libFuzzer harness: io::read_trajectory (TUM with and without stamps, Redwood .log, KITTI
// rows; the reader tells them apart from the lines) and the same bytes as a folder's one
// per-frame 4x4 pose file (7-Scenes, ScanNet); then io::read_intrinsics, which reads bytes
// that are not JSON as a 3x3 or 4x4 intrinsic matrix.
#include <filesystem>

#include "fuzz_input.hpp"
#include "fvx/io/intrinsics.hpp"
#include "fvx/io/trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "input.txt");
  fvx::fuzz::expect_answer([&] { fvx::io::read_trajectory(path); });
  fvx::fuzz::expect_answer([&] { fvx::io::read_trajectory(path, fvx::io::PoseFormatChoice::Kitti); });
  static const std::filesystem::path poses = [] {
    const auto dir = fvx::fuzz::folder() / "poses";
    std::filesystem::create_directories(dir);
    return dir;
  }();
  fvx::fuzz::expect_answer([&] {
    std::filesystem::copy_file(path, poses / "frame-000000.pose.txt", std::filesystem::copy_options::overwrite_existing);
    fvx::io::read_trajectory(poses.string());
  });
  fvx::fuzz::expect_answer([&] { fvx::io::read_intrinsics(path); });
  return 0;
}
