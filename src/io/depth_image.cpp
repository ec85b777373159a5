#include "fvx/io/depth_image.hpp"

#include <algorithm>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/capture_stderr.hpp"
#include "fvx/core/error.hpp"
#include "fvx/io/image_header.hpp"
#include "save_png.hpp"

namespace fvx::io {

DepthImage read_depth_image(const std::string& path) {
  require_readable_file(path);
  const ImageHeader header = check_image_header(path);  // before OpenCV sizes the image
  cv::Mat image;
  CaptureStderr capture;  // libpng and OpenCV print their complaints; they go into ours
  try {
    // IMREAD_ANYDEPTH keeps 16 bits; PGM is big-endian on disk and OpenCV swaps it.
    image = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception& e) {
    std::string what = e.what();  // OpenCV's messages span lines
    std::replace(what.begin(), what.end(), '\n', ' ');
    throw FileError(path, "unreadable " + header.format + ": " + what);
  }
  const std::string said = capture.text();
  if (image.empty() || image.cols != header.width || image.rows != header.height)
    throw FileError(path, "unreadable " + header.format + " (corrupt or cut short)" +
                              (said.empty() ? "" : ": " + said));
  if (image.channels() != 1)
    throw FileError(path, "has " + std::to_string(image.channels()) +
                              " channels; a depth image has one (is this the colour image?)");
  if (image.depth() != CV_16U)
    throw FileError(path, "is not a 16-bit image; depth must be stored as 16-bit integers");
  DepthImage depth;
  depth.width = image.cols;
  depth.height = image.rows;
  depth.raw.resize(std::size_t(image.rows) * image.cols);
  for (int r = 0; r < image.rows; ++r) {
    const auto* row = image.ptr<std::uint16_t>(r);
    std::copy(row, row + image.cols, depth.raw.begin() + std::ptrdiff_t(r) * image.cols);
  }
  return depth;
}

void write_depth_png(const std::string& path, const DepthImage& depth) {
  FVX_ASSERT(depth.raw.size() == std::size_t(depth.width) * depth.height, "depth image size");
  const cv::Mat image(depth.height, depth.width, CV_16UC1, const_cast<std::uint16_t*>(depth.raw.data()));
  write_path_atomically(path, [&](const std::string& temp) { save_png(temp, image, path); });
}

}  // namespace fvx::io
