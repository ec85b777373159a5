// libFuzzer harness: capmap::Arm::from_urdf_string. The input's first line names the base
// and the tip link ("base_link camera"), the rest is the URDF: the corpus's arms keep their
// own chain ends, and mutations of the names reach the "unknown link" paths.
#include "fuzz_input.hpp"
#include "fvx/capmap/arm.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t eol = text.find('\n');
  if (eol == std::string::npos) return 0;
  const std::string names = text.substr(0, eol);
  const std::size_t space = names.find(' ');
  if (space == std::string::npos) return 0;
  fvx::capmap::ArmConfig config;
  config.base_link = names.substr(0, space);
  config.tip_link = names.substr(space + 1);
  fvx::fuzz::expect_answer([&] {
    const auto arm = fvx::capmap::Arm::from_urdf_string(text.substr(eol + 1), config, "input.urdf");
    (void)arm.first_joint_axis();
  });
  return 0;
}
