#pragma once
/// \file
/// What `fvx batch` shows of a plan and of its progress.
#include <string>

#include "fvx/batch/plan.hpp"
#include "fvx/batch/sweep.hpp"
#include "fvx/core/json.hpp"

namespace fvx::report {

/// The plan's folder, number of tasks, result and merge command.
Json batch_plan_json(const batch::Plan& plan);
/// A sweep's scenes, planners (label, strategy, flags), seeds, max_views and the options
/// every run takes.
Json sweep_json(const batch::Sweep& sweep);
/// Done, failed and remaining counts, the failed tasks (0-based) and their exit status,
/// whether a job log was read, and whether the result exists.
Json batch_status_json(const batch::Status& s);
/// "3 done, 1 failed, 0 remaining; not merged".
std::string batch_status_line(const batch::Status& s);

}  // namespace fvx::report
