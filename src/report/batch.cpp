#include "fvx/report/batch.hpp"

#include <nlohmann/json.hpp>

namespace fvx::report {

Json batch_plan_json(const batch::Plan& plan) {
  return {{"folder", plan.folder}, {"tasks", plan.tasks.size()}, {"result", plan.result}, {"merge", plan.merge_command}};
}

Json sweep_json(const batch::Sweep& sweep) {
  Json planners = Json::array();
  for (const batch::Planner& p : sweep.planners)
    planners.push_back({{"label", p.label}, {"strategy", p.strategy}, {"flags", p.flags}});
  return {{"scenes", sweep.scenes}, {"planners", planners}, {"seeds", sweep.seeds}, {"max_views", sweep.max_views},
          {"explore_options", sweep.options}};
}

Json batch_status_json(const batch::Status& s) {
  return {{"done", s.done.size()},           {"failed", s.failed.size()},
          {"remaining", s.remaining.size()}, {"failed_tasks", s.failed},
          {"failed_exit_status", s.exit_status}, {"job_log_read", s.job_log},
          {"merged", s.merged}};
}

std::string batch_status_line(const batch::Status& s) {
  return std::to_string(s.done.size()) + " done, " + std::to_string(s.failed.size()) + " failed, " +
         std::to_string(s.remaining.size()) + " remaining; " + (s.merged ? "merged" : "not merged");
}

}  // namespace fvx::report
