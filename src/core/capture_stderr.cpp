#include "fvx/core/capture_stderr.hpp"

#include <unistd.h>

#include <iostream>

namespace fvx {

CaptureStderr::CaptureStderr() {
  std::fflush(stderr);
  std::cerr.flush();
  file_ = std::tmpfile();
  saved_fd_ = file_ ? ::dup(STDERR_FILENO) : -1;
  if (saved_fd_ >= 0) ::dup2(::fileno(file_), STDERR_FILENO);
}

CaptureStderr::~CaptureStderr() {
  restore();
  if (file_) std::fclose(file_);
}

std::string CaptureStderr::text() {
  restore();
  if (!file_) return "";
  std::string t;
  std::rewind(file_);
  for (int c; (c = std::fgetc(file_)) != EOF;) t += c == '\n' ? ' ' : char(c);
  while (!t.empty() && t.back() == ' ') t.pop_back();
  while (!t.empty() && t.front() == ' ') t.erase(0, 1);
  return t;
}

void CaptureStderr::restore() {
  if (saved_fd_ < 0) return;
  std::fflush(stderr);
  std::cerr.flush();
  ::dup2(saved_fd_, STDERR_FILENO);
  ::close(saved_fd_);
  saved_fd_ = -1;
}

}  // namespace fvx
