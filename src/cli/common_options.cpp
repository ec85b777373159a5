#include "common_options.hpp"

#include "fvx/core/error.hpp"
#include "fvx/report/nbv.hpp"
#include "fvx/sim/builtin_scenes.hpp"

namespace fvx::cli {

Json capmap_json(const Args& args, const ArmInputs& in) {
  return arm_json(args.has("capmap") ? args.get("capmap") : "", args.has("arm") ? args.get("arm") : "", in);
}

std::vector<OptionSpec> session_report_options() {
  return {{"timing", 0, nullptr, "add per-stage times (seconds) to the reports (without it they repeat "
                                 "byte for byte)", "-"},
          {"progress", 0, nullptr, "show progress on stderr even when it is not a terminal", "-"},
          {"help", 'h', nullptr, "show this help", "-"}};
}

double parse_depth_noise(const Args& args) {
  const std::string model = args.has("noise") ? args.get("noise") : "none";
  if (model == "kinect") return 1.4e-3;
  if (model != "none") throw UsageError("--noise: '" + model + "' is not a noise model; use none or kinect");
  return 0.0;
}

sim::Scene scene_from(const std::string& source, const Args& args) {
  return sim::scene_from(source, args.has("scene-info") ? args.get("scene-info") : "");
}

nbv::Strategy parse_strategy_option(const Args& args, const std::string& command, nbv::Strategy fallback) {
  if (args.has("strategy") && args.has("planner"))
    throw UsageError("fvx " + command + ": --planner is another name for --strategy: give one");
  if (args.has("strategy")) return nbv::parse_strategy(args.get("strategy"), "--strategy");
  if (args.has("planner")) return nbv::parse_strategy(args.get("planner"), "--planner");
  return fallback;
}

}  // namespace fvx::cli
