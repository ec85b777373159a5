// libFuzzer harness: io::read_trajectory (TUM with and without stamps, Redwood .log; the
// reader tells them apart from the lines).
#include "fuzz_input.hpp"
#include "fvx/io/trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "input.txt");
  fvx::fuzz::expect_answer([&] { fvx::io::read_trajectory(path); });
  return 0;
}
