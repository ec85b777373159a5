#pragma once
// The results of a next-best-view search as JSON: what `fvx nbv` reports and what `fvx explore`
// writes for each view.
#include <string>
#include <vector>

#include "fvx/nbv/nbv.hpp"
#include "report.hpp"

namespace fvx::cli {

/// bounds, void and frontier counts, the pruning counts, the ranked views (R: the map's cell
/// edge, for dm³; joint names of the arm, or empty) and, with `timing`, the time split.
Json nbv_results_json(const nbv::Result& r, const frontier_voids::Analysis& a, double R,
                      const std::vector<std::string>& joint_names, nbv::Strategy strategy, bool timing);

}  // namespace fvx::cli
