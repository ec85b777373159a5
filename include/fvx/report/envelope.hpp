#pragma once
/// \file
/// The JSON report every command writes (design §2): the envelope and its text form.
#include <string>

#include "fvx/core/json.hpp"

namespace fvx::report {

/// {"schema_version", "fvx_version", "command", "config": {}, "inputs": {}, "results": {},
///  "warnings": []} — the fields every report has, in that order.
Json new_report(const std::string& command);

/// The report as written: two-space indented, newline-terminated.
std::string report_text(const Json& report);

}  // namespace fvx::report
