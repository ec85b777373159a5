// libFuzzer harness: CapabilityMap::load on .fcm.
#include "fuzz_input.hpp"
#include "fvx/capmap/capability_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "input.fcm");
  fvx::fuzz::expect_answer([&] { fvx::capmap::CapabilityMap::load(path); });
  return 0;
}
