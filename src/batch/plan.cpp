#include "fvx/batch/plan.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"

namespace fvx::batch {

namespace fs = std::filesystem;

std::string fvx_binary() {
  char path[4096];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) throw Error("cannot find the fvx binary (/proc/self/exe)");
  return std::string(path, std::size_t(n));
}

std::string shell_quote(const std::string& word) {
  std::string out = "'";
  for (const char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string absolute_path(const std::string& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (!p.has_filename() && p != p.root_path()) p = p.parent_path();
  return p.string();
}

namespace {

/// "shard-007-of-064.fcm": names that sort in task order.
std::string shard_name(int i, int n) {
  const int width = int(std::to_string(n).size());
  std::ostringstream name;
  name << "shard-" << std::string(std::size_t(width) - std::to_string(i).size(), '0') << i << "-of-" << n << ".fcm";
  return name.str();
}

}  // namespace

Plan capmap_plan(const std::string& fvx, const std::string& urdf,
                 const std::vector<std::pair<std::string, std::string>>& options, int shards,
                 const std::string& folder, const std::string& result) {
  if (shards < 1 || shards > 100000) throw UsageError("--shards " + std::to_string(shards) + ": expected 1 to 100000");
  Plan plan{"capmap", absolute_path(folder), {}, "", result.empty() ? absolute_path(folder) + "/map.fcm" : absolute_path(result)};
  std::string build = shell_quote(absolute_path(fvx)) + " capmap build " + shell_quote(absolute_path(urdf));
  for (const auto& [name, value] : options) build += " --" + name + (value.empty() ? "" : " " + shell_quote(value));
  std::string merge = shell_quote(absolute_path(fvx)) + " capmap merge";
  for (int i = 1; i <= shards; ++i) {
    const std::string output = plan.folder + "/parts/" + shard_name(i, shards);
    const std::string report = output.substr(0, output.size() - 4) + ".json";  // the shard's report, beside it
    plan.tasks.push_back({build + " --shard " + std::to_string(i) + "/" + std::to_string(shards) + " -o " +
                              shell_quote(output) + " > " + shell_quote(report),
                          output});
    merge += " " + shell_quote(output);
  }
  plan.merge_command = merge + " -o " + shell_quote(plan.result);
  return plan;
}

namespace {

nlohmann::ordered_json plan_json(const Plan& plan) {
  nlohmann::ordered_json tasks = nlohmann::ordered_json::array();
  for (const Task& t : plan.tasks) tasks.push_back({{"command", t.command}, {"output", t.output}});
  return {{"job", plan.job}, {"folder", plan.folder}, {"tasks", tasks}, {"merge", plan.merge_command},
          {"result", plan.result}};
}

std::string slurm_script(const Plan& plan) {
  const std::string self = shell_quote(plan.folder + "/slurm.sbatch"), n = std::to_string(plan.tasks.size());
  return "#!/bin/sh\n"
         "#SBATCH --job-name=fvx-" + plan.job + "\n"
         "#SBATCH --output=" + plan.folder + "/slurm/%x-%j.out\n"
         "# fvx batch " + plan.job + ": " + n + " tasks (the lines of tasks.txt), then merge.sh once all succeed.\n"
         "# 'sbatch slurm.sbatch' submits this script again as an array of the tasks, and the\n"
         "# merge as a job that waits for all of them (afterok); each array task runs its line.\n"
         "if [ -z \"$SLURM_ARRAY_TASK_ID\" ]; then\n"
         "  array=$(sbatch --parsable --array=1-" + n + " --output=" + shell_quote(plan.folder + "/slurm/%x-%A_%a.out") +
         " " + self + ") || exit 1\n"
         "  sbatch --parsable --dependency=afterok:\"${array%%;*}\" --job-name=fvx-merge \\\n"
         "    --output=" + shell_quote(plan.folder + "/slurm/merge-%j.out") + " --wrap=" +
         shell_quote("sh " + shell_quote(plan.folder + "/merge.sh")) + "\n"
         "  exit\n"
         "fi\n"
         "exec sh -c \"$(sed -n \"${SLURM_ARRAY_TASK_ID}p\" " + shell_quote(plan.folder + "/tasks.txt") + ")\"\n";
}

}  // namespace

void write_plan(const Plan& plan) {
  const std::string plan_path = plan.folder + "/plan.json";
  if (fs::exists(plan_path)) {  // the same plan again is fine; another would mix its outputs with these
    const Plan there = read_plan(plan.folder);
    bool same = there.merge_command == plan.merge_command && there.tasks.size() == plan.tasks.size();
    for (std::size_t i = 0; same && i < plan.tasks.size(); ++i) same = there.tasks[i].command == plan.tasks[i].command;
    if (!same) throw FileError(plan.folder, "holds a plan of other tasks; give another folder");
  }
  for (const std::string& folder : {plan.folder, plan.folder + "/parts", plan.folder + "/slurm"}) create_folder(folder);
  std::string tasks;
  for (const Task& t : plan.tasks) tasks += t.command + "\n";
  write_text_atomically(plan.folder + "/tasks.txt", tasks);
  write_text_atomically(plan.folder + "/merge.sh", "#!/bin/sh\n# fvx batch " + plan.job +
                                                       ": joins the outputs of tasks.txt.\nexec " + plan.merge_command + "\n");
  write_text_atomically(plan.folder + "/slurm.sbatch", slurm_script(plan));
  write_text_atomically(plan_path, plan_json(plan).dump(2) + "\n");
}

Plan read_plan(const std::string& folder) {
  const std::string path = folder + "/plan.json";
  if (!fs::is_regular_file(path)) throw FileError(folder, "no batch plan here (plan.json); make one with fvx batch");
  try {
    std::ifstream in(path);
    const auto j = nlohmann::json::parse(in);
    Plan plan{j.at("job"), j.at("folder"), {}, j.at("merge"), j.at("result")};
    for (const auto& t : j.at("tasks")) plan.tasks.push_back({t.at("command"), t.at("output")});
    return plan;
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("not a batch plan: ") + e.what());
  }
}

namespace {

/// GNU parallel's --joblog: a header line, then per finished job Seq, Host, Starttime,
/// JobRuntime, Send, Receive, Exitval, Signal, Command (tab-separated). The exit status of
/// each command's last run (128 + signal when a signal ended it).
std::map<std::string, int> read_job_log(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) || line.rfind("Seq\tHost\tStarttime", 0) != 0)
    throw FileError(path, "not a GNU parallel job log (its first line names Seq, Host, Starttime, ...)");
  std::map<std::string, int> last;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (int f = 0; f < 8; ++f) {
      const std::size_t tab = line.find('\t', start);
      if (tab == std::string::npos) throw FileError(path, "a job log line has fewer than nine fields");
      fields.push_back(line.substr(start, tab - start));
      start = tab + 1;
    }
    const int exit = std::atoi(fields[6].c_str()), signal = std::atoi(fields[7].c_str());
    last[line.substr(start)] = signal ? 128 + signal : exit;
  }
  return last;
}

}  // namespace

Status plan_status(const std::string& folder, const std::string& job_log) {
  const Plan plan = read_plan(folder);
  Status s;
  std::map<std::string, int> log;
  if (!job_log.empty() && fs::exists(job_log)) {
    log = read_job_log(job_log);
    s.job_log = true;
  }
  for (std::size_t i = 0; i < plan.tasks.size(); ++i) {
    const auto it = log.find(plan.tasks[i].command);
    if (fs::exists(plan.tasks[i].output)) {  // a file (capmap) or a folder (replay), whole once it exists
      s.done.push_back(i);
    } else if (it != log.end() && it->second != 0) {
      s.failed.push_back(i);
      s.exit_status.push_back(it->second);
    } else {
      s.remaining.push_back(i);
    }
  }
  s.merged = fs::exists(plan.result);
  return s;
}

}  // namespace fvx::batch
