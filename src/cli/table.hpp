#pragma once
// --format of the session commands; the tables themselves are fvx/report/table.hpp.
#include "fvx/report/table.hpp"
#include "options.hpp"

namespace fvx::cli {

using report::fixed;
using report::Format;

/// --format markdown (default) | csv | json; UsageError otherwise.
inline Format parse_format(const Args& args) {
  return report::parse_format(args.has("format") ? args.get("format") : "markdown");
}

}  // namespace fvx::cli
