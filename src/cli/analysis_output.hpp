#pragma once
// The search-space option of the commands that analyse a map; their outputs are
// fvx/report/analysis.hpp.
#include <optional>

#include "fvx/pipeline/options.hpp"
#include "fvx/report/analysis.hpp"
#include "options.hpp"
#include "report.hpp"

namespace fvx::cli {

using pipeline::parse_bounds;

}  // namespace fvx::cli
