// libFuzzer harness: OccupancyMap::load on .bt and .ot. The name follows the first line, so
// a mutation of either kind reaches its own reader (a wrong first line is refused early).
#include <cstring>

#include "fuzz_input.hpp"
#include "fvx/map/occupancy_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char kBinary[] = "# Octomap OcTree binary file";
  const bool binary = size >= sizeof kBinary - 1 && std::memcmp(data, kBinary, sizeof kBinary - 1) == 0;
  const std::string path = fvx::fuzz::write_input(data, size, binary ? "input.bt" : "input.ot");
  fvx::fuzz::expect_answer([&] { fvx::map::OccupancyMap::load(path); });
  return 0;
}
