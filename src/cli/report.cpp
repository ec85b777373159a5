#include "report.hpp"

#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "fvx/core/atomic_file.hpp"

namespace fvx::cli {

void write_report(const Json& report, const std::string& path) {
  const std::string text = report_text(report);
  if (path.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::fflush(stdout);
    return;
  }
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
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
