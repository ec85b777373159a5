// The replay plan and the merge of plans (plan.hpp).
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fvx/batch/plan.hpp"
#include "fvx/batch/sweep.hpp"
#include "fvx/capmap/capability_map.hpp"
#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::batch {

namespace fs = std::filesystem;

Plan replay_plan(const std::string& fvx, const std::string& list, const std::vector<std::string>& options,
                 const std::string& folder, const std::string& result) {
  require_readable_file(list);
  const std::string here = fs::absolute(list).parent_path().lexically_normal().string();
  const std::string plan_folder = absolute_path(folder);
  const std::string binary = shell_quote(fs::absolute(fvx).lexically_normal().string());
  Plan plan{"replay", plan_folder, {}, binary + " batch merge " + shell_quote(plan_folder),
            result.empty() ? plan_folder + "/tables.csv" : fs::absolute(result).lexically_normal().string()};
  std::string passed;
  for (const std::string& word : options) passed += " " + shell_quote(word);
  std::ifstream in(list);
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::string part = plan_folder + "/parts/replay-" + std::to_string(plan.tasks.size() + 1);
    const std::string temp = shell_quote(part + ".tmp"), table = shell_quote(part + ".csv");
    plan.tasks.push_back({"cd " + shell_quote(here) + " && rm -rf " + temp + " && " + binary + " replay " + line + passed +
                              " --format csv -o " + temp + " > " + table + " && mv " + table + " " + temp +
                              "/table.csv && rm -rf " + shell_quote(part) + " && mv " + temp + " " + shell_quote(part),
                          part});
  }
  if (plan.tasks.empty()) throw FileError(list, "lists no sequence (one replay's inputs per line)");
  return plan;
}

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {  // fvx's tables quote nothing
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  return fields;
}

/// The tables of every part, in task order, as one CSV without the seconds columns.
std::string merged_tables(const Plan& plan) {
  std::string out, header;
  std::vector<bool> keep;
  for (std::size_t i = 0; i < plan.tasks.size(); ++i) {
    const std::string path = plan.tasks[i].output + "/table.csv";
    if (!fs::is_regular_file(path)) throw FileError(plan.tasks[i].output, "this part of the batch is missing (task " + std::to_string(i + 1) + ")");
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line) || line.rfind("view,", 0) != 0) throw FileError(path, "not a replay table (its first line names view, ...)");
    if (header.empty()) {
      header = line;
      for (const std::string& name : split_csv_line(line)) keep.push_back(name.size() < 2 || name.substr(name.size() - 2) != "_s");
      out = "sequence";
      for (std::size_t c = 0; c < keep.size(); ++c) out += keep[c] ? "," + split_csv_line(line)[c] : "";
      out += "\n";
    } else if (line != header) {
      throw FileError(path, "its table has other columns than the first part's");
    }
    while (std::getline(in, line)) {
      const std::vector<std::string> fields = split_csv_line(line);
      if (fields.size() != keep.size()) throw FileError(path, "a row has " + std::to_string(fields.size()) + " fields, the header " + std::to_string(keep.size()));
      out += std::to_string(i + 1);
      for (std::size_t c = 0; c < keep.size(); ++c) out += keep[c] ? "," + fields[c] : "";
      out += "\n";
    }
  }
  return out;
}

}  // namespace

void merge_plan(const Plan& plan) {
  if (plan.job == "sweep") return merge_sweep(plan);
  if (plan.job == "replay") {
    const std::string table = merged_tables(plan);
    write_text_atomically(plan.result, table);
    return;
  }
  std::vector<capmap::CapabilityMap> shards;
  for (const Task& t : plan.tasks) shards.push_back(capmap::CapabilityMap::load(t.output));
  capmap::CapabilityMap::merge(shards).save(plan.result);
}

}  // namespace fvx::batch
