#include "report.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::cli {

void write_report(const Json& report, const std::string& path) {
  const std::string text = report_text(report);
  if (path.empty() || path == "-") {  // "-": standard output, as the shell's tools read it
    // A report that does not reach standard output (a full disk, a closed pipe) is a failure.
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
      throw Error(std::string("cannot write the report to standard output: ") + std::strerror(errno));
    return;
  }
  write_text_atomically(path, text);
}

Progress::Progress(bool forced) : tty_(::isatty(STDERR_FILENO) != 0) { enabled_ = forced || tty_; }

void Progress::update(const std::string& line) {
  if (!enabled_) return;
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
  else
    std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void Progress::finish() {
  if (enabled_ && tty_ && shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

}  // namespace fvx::cli
