#include "fvx/core/capture_stderr.hpp"

#include <unistd.h>

#include <iostream>
#include <mutex>

namespace fvx {

namespace {
/// Recursive: a capture inside a capture on one thread nests (dup2 is undone in reverse).
std::recursive_mutex& capture_lock() {
  static std::recursive_mutex lock;
  return lock;
}
}  // namespace

CaptureStderr::CaptureStderr() {
  capture_lock().lock();
  held_ = true;
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
  if (saved_fd_ >= 0) {
    std::fflush(stderr);
    std::cerr.flush();
    ::dup2(saved_fd_, STDERR_FILENO);
    ::close(saved_fd_);
    saved_fd_ = -1;
  }
  if (held_) {
    held_ = false;
    capture_lock().unlock();
  }
}

}  // namespace fvx
