#pragma once
// The search-space option of the commands that analyse a map; their outputs are
// fvx/report/analysis.hpp.
#include <optional>

#include "fvx/report/analysis.hpp"
#include "options.hpp"
#include "report.hpp"

namespace fvx::cli {

/// --bounds x0,y0,z0,x1,y1,z1 (metres; or another option of that form), or empty.
std::optional<Eigen::AlignedBox3d> parse_bounds(const Args& args, const std::string& name = "bounds");

}  // namespace fvx::cli
