#pragma once
/// \file
/// What every fvx fuzz harness shares. fvx's readers take paths (PCL, OpenCV and OctoMap
/// open files themselves), so each input is written to a file in a private folder under
/// /dev/shm (or $TMPDIR) and read from there. A reader may refuse an input only with
/// fvx::Error on one line; anything else - a crash, a sanitizer report, another exception,
/// a message over several lines, an allocation over libFuzzer's -malloc_limit_mb or a run
/// over -timeout - is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fvx/core/error.hpp"

namespace fvx::fuzz {

/// The harness's folder, made once and removed at exit.
inline const std::filesystem::path& folder() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    const std::filesystem::path root = std::filesystem::exists("/dev/shm") ? "/dev/shm" : (tmp ? tmp : "/tmp");
    auto d = root / ("fvx-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] { std::error_code ec; std::filesystem::remove_all(folder(), ec); });
    return d;
  }();
  return dir;
}

/// Writes the input to <folder>/<name> and returns its path.
inline std::string write_input(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::string path = (folder() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) std::abort();  // the fuzzer's own disk, not fvx: stop loudly
  return path;
}

/// Runs one reader: fvx::Error on one line is an answer, anything else propagates.
template <class Read>
void expect_answer(Read&& read) {
  try {
    read();
  } catch (const fvx::Error& e) {
    const std::string message = e.what();
    if (message.empty() || message.find('\n') != std::string::npos) {
      std::fprintf(stderr, "fvx error message is not one line: [%s]\n", message.c_str());
      std::abort();
    }
  }
}

}  // namespace fvx::fuzz
