#pragma once
// Writing the JSON report (stdout carries only it, design §2) and the progress line.
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <string>

#include "fvx/core/json.hpp"
#include "fvx/core/memory.hpp"
#include "fvx/report/envelope.hpp"

namespace fvx::cli {

using fvx::Json;
/// The library's report forms (include/fvx/report/): the commands only call them.
using namespace fvx::report;

/// Writes report_text(report) to stdout when `path` is empty, otherwise atomically to `path`.
void write_report(const Json& report, const std::string& path);

/// Progress on stderr: only when stderr is a terminal or `--progress` was given.
class Progress {
 public:
  explicit Progress(bool forced);
  void update(const std::string& line);
  void finish();

 private:
  bool enabled_;
  bool tty_;
  bool shown_ = false;
};

}  // namespace fvx::cli
