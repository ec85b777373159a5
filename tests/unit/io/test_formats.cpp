// The io helpers that the fvx binary has without fvx-heavy.so.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "fvx/io/visual.hpp"

namespace fvx::test {
namespace {

// The oracle: the OpenCV conversion that cluster_color used before it left OpenCV behind,
// so that pictures and coloured clouds keep their colours.
io::Rgb opencv_cluster_color(int id) {
  const double hue = std::fmod(id * 137.508, 360.0);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue / 2.0, 200, 230)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return {c[2], c[1], c[0]};
}

TEST(ClusterColor, IsOpenCvsHsvConversionForEveryId) {
  for (int id = -10; id < 20000; ++id) ASSERT_EQ(io::cluster_color(id), opencv_cluster_color(id)) << id;
}

}  // namespace
}  // namespace fvx::test
