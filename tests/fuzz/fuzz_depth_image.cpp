// libFuzzer harness: io::read_depth_image (OpenCV decides PNG, PGM or TIFF from the bytes,
// not the name).
#include "fuzz_input.hpp"
#include "fvx/io/depth_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "input.png");
  fvx::fuzz::expect_answer([&] { fvx::io::read_depth_image(path); });
  return 0;
}
