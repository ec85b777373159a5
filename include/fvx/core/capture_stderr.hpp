#pragma once
/// \file
/// Libraries that print their problems (OctoMap, libpng, OpenCV) would put stray lines
/// before fvx's own one-line error. While a CaptureStderr lives, file descriptor 2 goes to a
/// temporary file; what was printed can then become part of fvx's message. Captures are
/// taken one at a time across threads (a replay saves its map on one thread while pictures
/// are written on another): two interleaved dup2 pairs would leave stderr pointing at a
/// closed temporary. Lines other threads print meanwhile go into the capture.
#include <cstdio>
#include <string>

namespace fvx {

class CaptureStderr {
 public:
  CaptureStderr();
  ~CaptureStderr();
  CaptureStderr(const CaptureStderr&) = delete;
  CaptureStderr& operator=(const CaptureStderr&) = delete;

  /// Restores stderr and returns what was printed on one line (newlines as spaces, trimmed),
  /// or "" when nothing was.
  std::string text();

 private:
  void restore();
  std::FILE* file_ = nullptr;
  int saved_fd_ = -1;
  bool held_ = false;  ///< the process-wide capture lock, until restore()
};

}  // namespace fvx
