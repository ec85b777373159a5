#include "fvx/report/envelope.hpp"

#include <nlohmann/json.hpp>

#include "fvx/core/pose.hpp"  // version()

namespace fvx::report {

constexpr int kSchemaVersion = 1;

Json new_report(const std::string& command) {
  Json report;
  report["schema_version"] = kSchemaVersion;
  report["fvx_version"] = version();
  report["command"] = command;
  report["config"] = Json::object();
  report["inputs"] = Json::object();
  report["results"] = Json::object();
  report["warnings"] = Json::array();
  return report;
}

std::string report_text(const Json& report) { return report.dump(2) + "\n"; }

}  // namespace fvx::report
