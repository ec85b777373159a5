#pragma once
// The JSON report every command writes: stdout carries only this (ARCHITECTURE.md §2).
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "fvx/core/json.hpp"
#include <string>

namespace fvx::cli {

using fvx::Json;

/// {"schema_version", "fvx_version", "command", "config": {}, "inputs": {}, "results": {},
///  "warnings": []} — the fields every report has, in that order.
Json new_report(const std::string& command);

/// The report as written: two-space indented, newline-terminated.
std::string report_text(const Json& report);

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
