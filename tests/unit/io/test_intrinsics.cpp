#include <gtest/gtest.h>

#include <fstream>

#include "fvx/core/error.hpp"
#include "fvx/io/intrinsics.hpp"
#include "test_support.hpp"

namespace fvx::io {
namespace {

TEST(IntrinsicsRealData, Open3dColumnMajorLayout) {
  FVX_REAL_DATA_OR_SKIP(path, "open3d-redwood-testdata/camera_primesense.json");
  const Intrinsics K = read_intrinsics(path);
  EXPECT_EQ(K.fx, 525.0);
  EXPECT_EQ(K.fy, 525.0);
  EXPECT_EQ(K.cx, 319.5);
  EXPECT_EQ(K.cy, 239.5);
  EXPECT_EQ(K.width, 640);
}

TEST(Intrinsics, FvxLayoutWithNegativeFocalLengthAndTumScale) {
  const test::TempDir dir;
  std::ofstream(dir / "k.json") << R"({"fx": 481.2, "fy": -480, "cx": 319.5, "cy": 239.5, "depth_scale": 5000})";
  const Intrinsics K = read_intrinsics(dir / "k.json");
  EXPECT_EQ(K.fy, -480.0);
  EXPECT_EQ(K.depth_scale, 5000.0);
}

TEST(Intrinsics, TyposAndNonsenseAreRefused) {
  const test::TempDir dir;
  std::ofstream(dir / "typo.json") << R"({"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "depth_scal": 5000})";
  std::ofstream(dir / "zero.json") << R"({"fx": 0, "fy": 525, "cx": 319.5, "cy": 239.5})";
  std::ofstream(dir / "missing.json") << R"({"fx": 525, "cx": 319.5, "cy": 239.5})";
  std::ofstream(dir / "broken.json") << R"({"fx": 525,)";
  std::ofstream(dir / "scale.json") << R"({"fx": 525, "fy": 525, "cx": 1, "cy": 1, "depth_scale": -1})";
  for (const char* name : {"typo.json", "zero.json", "missing.json", "broken.json", "scale.json"}) {
    try {
      read_intrinsics(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace fvx::io
