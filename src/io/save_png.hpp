#pragma once
/// \file
/// OpenCV's PNG writer with its failures as one-line FileErrors: libpng prints "libpng
/// error: Write Error" on stderr itself when a disk fills up, and cv::imwrite only returns
/// false.
#include <cerrno>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/capture_stderr.hpp"
#include "fvx/core/error.hpp"

namespace fvx::io {

/// Writes `image` to `temp` (a write_path_atomically temporary) as PNG; a failure is a
/// FileError naming `path` and why (the system's reason, else what OpenCV or libpng said).
inline void save_png(const std::string& temp, const cv::Mat& image, const std::string& path) {
  bool ok = false;
  int error = 0;
  std::string said;
  {
    CaptureStderr capture;
    errno = 0;
    try {
      ok = cv::imwrite(temp, image);
    } catch (const cv::Exception& e) {
      said = e.what();
    }
    error = errno;
    const std::string printed = capture.text();
    if (said.empty()) said = printed;
  }
  if (ok) return;
  std::string why = write_failure(error);
  if (why.empty() && !said.empty()) why = " (" + said + ")";
  throw FileError(path, "cannot write the PNG" + why);
}

}  // namespace fvx::io
