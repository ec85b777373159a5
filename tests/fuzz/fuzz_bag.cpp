// libFuzzer harness: io::index_bag and io::read_bag_scan (ROS 1 bags through librosbag_storage
// and tf2) on topic /depth, fixed frame odom, with the default intrinsics given (so an Image
// topic needs no CameraInfo), reading at most the first two messages.
#include <algorithm>

#include "fuzz_input.hpp"
#include "fvx/io/rosbag.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fvx::fuzz::write_input(data, size, "input.bag");
  const fvx::io::BagQuery query{path, "/depth", "odom", "", fvx::io::Intrinsics{}};
  fvx::fuzz::expect_answer([&] {
    const std::vector<fvx::io::BagMessage> messages = fvx::io::index_bag(query);
    for (std::size_t i = 0; i < std::min<std::size_t>(2, messages.size()); ++i) fvx::io::read_bag_scan(query, messages[i]);
  });
  return 0;
}
