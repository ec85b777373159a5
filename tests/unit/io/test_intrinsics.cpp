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

TEST(Intrinsics, ThreeByThreeAndScanNetFourByFourText) {
  const test::TempDir dir;
  std::ofstream(dir / "camera-intrinsics.txt") << "585 0 320\n0 585.5 240\n0 0 1\n";
  std::ofstream(dir / "intrinsic_depth.txt")
      << "577.590698 0.000000 318.905426 0.000000\n0.000000 578.729797 242.683609 0.000000\n"
         "0.000000 0.000000 1.000000 0.000000\n0.000000 0.000000 0.000000 1.000000\n";
  const Intrinsics a = read_intrinsics(dir / "camera-intrinsics.txt");
  EXPECT_EQ(a.fx, 585.0);
  EXPECT_EQ(a.fy, 585.5);
  EXPECT_EQ(a.cx, 320.0);
  EXPECT_EQ(a.cy, 240.0);
  EXPECT_EQ(a.depth_scale, 1000.0);  // 3DMatch, 7-Scenes and ScanNet depth are millimetres
  EXPECT_FALSE(a.size_stated);
  const Intrinsics b = read_intrinsics(dir / "intrinsic_depth.txt");
  EXPECT_EQ(b.fx, 577.590698);
  EXPECT_EQ(b.cy, 242.683609);
}

TEST(Intrinsics, TextMatricesThatAreNoPinholeAreRefused) {
  const test::TempDir dir;
  std::ofstream(dir / "skew.txt") << "585 1 320\n0 585 240\n0 0 1\n";
  std::ofstream(dir / "eight.txt") << "585 0 320 0 585 240 0 0\n";
  std::ofstream(dir / "words.txt") << "fx = 585\n";
  std::ofstream(dir / "zero.txt") << "0 0 320\n0 585 240\n0 0 1\n";
  std::ofstream(dir / "long.txt") << std::string(5000, '1') << "\n";
  for (const char* name : {"skew.txt", "eight.txt", "words.txt", "zero.txt", "long.txt"}) {
    try {
      read_intrinsics(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace fvx::io
