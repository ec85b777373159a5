// Depth images: 16-bit PNG/PGM/TIFF; back-projection equals the organised PCD of the same frame.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "fvx/core/error.hpp"
#include "fvx/io/cloud_file.hpp"
#include "fvx/io/depth_image.hpp"
#include "fvx/scan/scan.hpp"
#include "test_support.hpp"

namespace fvx::io {
namespace {

TEST(DepthImage, SixteenBitFormatsRoundTrip) {
  const test::TempDir dir;
  cv::Mat image(4, 5, CV_16UC1);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 5; ++c) image.at<std::uint16_t>(r, c) = std::uint16_t(1000 * r + 300 * c + 7);
  for (const char* name : {"d.png", "d.pgm", "d.tiff"}) {
    ASSERT_TRUE(cv::imwrite(dir / name, image));
    const DepthImage depth = read_depth_image(dir / name);
    ASSERT_EQ(depth.width, 5);
    ASSERT_EQ(depth.height, 4);
    EXPECT_EQ(depth.at(3, 4), 1000 * 3 + 300 * 4 + 7) << name;  // big-endian PGM swapped
  }
}

TEST(DepthImage, EightBitAndColourImagesAreRefused) {
  const test::TempDir dir;
  cv::imwrite(dir / "gray8.png", cv::Mat(4, 4, CV_8UC1, cv::Scalar(3)));
  cv::imwrite(dir / "color.png", cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3)));
  std::ofstream(dir / "text.png") << "not an image";
  for (const char* name : {"gray8.png", "color.png", "text.png", "missing.png"})
    EXPECT_THROW(read_depth_image(dir / name), FileError) << name;
}

// The header is read before OpenCV decodes (image_header.cpp) and must give the size OpenCV
// decodes: images written by OpenCV (libtiff puts a big image's directory after its pixels,
// far past the first 4 KB), and PGMs with comments or in ascii.
TEST(DepthImage, TheHeaderSizeIsTheDecodedSizeForEveryWriter) {
  const test::TempDir dir;
  for (const auto& [rows, cols] : {std::pair{1, 1}, {480, 640}, {1500, 2000}, {3, 16384}}) {
    const cv::Mat image(rows, cols, CV_16UC1, cv::Scalar(1234));
    for (const char* name : {"d.png", "d.pgm", "d.tiff"}) {
      ASSERT_TRUE(cv::imwrite(dir / name, image));
      const DepthImage depth = read_depth_image(dir / name);
      EXPECT_EQ(depth.width, cols) << name;
      EXPECT_EQ(depth.height, rows) << name;
    }
  }
  std::ofstream(dir / "c.pgm", std::ios::binary) << "P5\n# made by hand\n# two comments\n2 1\n65535\n"
                                                 << std::string("\x03\xe8\x07\xd0", 4);
  const DepthImage commented = read_depth_image(dir / "c.pgm");
  EXPECT_EQ(commented.width, 2);
  EXPECT_EQ(commented.at(0, 1), 2000);
  std::ofstream(dir / "a.pgm") << "P2\n3 2\n65535\n1 2 3\n4 5 60000\n";
  EXPECT_EQ(read_depth_image(dir / "a.pgm").at(1, 2), 60000);
}

TEST(DepthImage, SizesBeyondTheLimitsAreRefusedBeforeDecoding) {
  const test::TempDir dir;
  for (const auto& [header, words] : {std::pair{"P5\n16385 1\n65535\n", "PGM width 16385 is not 1 to 16384 pixels"},
                                      {"P5\n0 10\n65535\n", "PGM width 0 is not 1 to 16384 pixels"},
                                      {"P5\n9000 9000\n65535\n", "PGM of 9000x9000 pixels is larger than 2^26 pixels"},
                                      {"P5\n# only a comment\n", "PGM header without a width and a height"}}) {
    std::ofstream(dir / "big.pgm", std::ios::binary) << header;
    try {
      read_depth_image(dir / "big.pgm");
      ADD_FAILURE() << header;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  }
}

TEST(DepthImageRealData, TiffBackProjectsToTheOrganisedPcdWithinOneMillimetre) {
  const std::string stem = "pcl-kinect-sequences/pcl_grabber_sequences/";
  FVX_REAL_DATA_OR_SKIP(tiff, stem + "tiff/frame_20121214T142255.814212_depth.tiff");
  FVX_REAL_DATA_OR_SKIP(pcd, stem + "pcd/frame_20121214T142255.814212.pcd");
  const DepthImage depth = read_depth_image(tiff);
  const CloudFile cloud = read_cloud(pcd);
  // Intrinsics from the frame's XML (PROVENANCE.md): fx = fy = 525, cx = 320, cy = 240, mm.
  const Intrinsics K{525.0, 525.0, 320.0, 240.0, 1000.0, 640, 480};
  const auto points = scan::backproject(depth, K);
  ASSERT_EQ(points.size(), cloud.points.size());
  std::size_t compared = 0, both_invalid = 0;
  double worst_m = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool a = points[i].allFinite(), b = cloud.points[i].allFinite();
    ASSERT_EQ(a, b) << "pixel " << i << " valid in one and not the other";
    if (!a) {
      ++both_invalid;
      continue;
    }
    worst_m = std::max(worst_m, (points[i] - cloud.points[i]).norm());
    ++compared;
  }
  EXPECT_GT(compared, 250000u);
  EXPECT_LT(worst_m, 1e-3) << "largest per-pixel distance";
}

}  // namespace
}  // namespace fvx::io
