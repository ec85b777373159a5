// libFuzzer harness: io::read_cloud on a .pcd (ascii, binary, binary_compressed).
#include "fuzz_input.hpp"
#include "fvx/io/cloud_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "input.pcd");
  fvx::fuzz::expect_answer([&] { fvx::io::read_cloud(path); });
  return 0;
}
