// The sweep plan (sweep.hpp): scenes × planners × seeds as one fvx explore per task.
#include "fvx/batch/sweep.hpp"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "fvx/nbv/nbv.hpp"
#include "fvx/sim/builtin_scenes.hpp"

namespace fvx::batch {

namespace fs = std::filesystem;

namespace {

/// The items of a list separated by commas or spaces.
std::vector<std::string> items_of(const std::string& text) {
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ',', ' ');
  std::stringstream in(spaced);
  std::vector<std::string> items;
  for (std::string item; in >> item;) items.push_back(item);
  return items;
}

/// "A-B" (numbers) → A … B; any other item as it is.
std::vector<std::string> expand_ranges(const std::string& text, const std::string& what) {
  static const std::regex range("([0-9]{1,6})-([0-9]{1,6})");
  std::vector<std::string> out;
  for (const std::string& item : items_of(text)) {
    std::smatch m;
    if (!std::regex_match(item, m, range)) {
      out.push_back(item);
      continue;
    }
    const int from = std::stoi(m[1]), to = std::stoi(m[2]);
    if (from > to) throw UsageError(what + " " + item + ": the range runs backwards");
    for (int i = from; i <= to; ++i) out.push_back(std::to_string(i));
  }
  if (out.empty()) throw UsageError(what + ": the list is empty");
  return out;
}

bool is_number(const std::string& s) {
  return !s.empty() && s.size() <= 6 && s.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

std::vector<std::string> parse_scene_list(const std::string& text) {
  const std::vector<std::string> names = sim::builtin_scene_names();
  std::vector<std::string> scenes;
  for (const std::string& item : expand_ranges(text, "--scenes")) {
    if (is_number(item)) scenes.push_back("builtin:suite/" + item);
    else if (std::find(names.begin(), names.end(), item) != names.end()) scenes.push_back("builtin:" + item);
    else scenes.push_back(item);
  }
  return scenes;
}

std::vector<int> parse_seed_list(const std::string& text) {
  std::vector<int> seeds;
  for (const std::string& item : expand_ranges(text, "--seeds")) {
    if (!is_number(item)) throw UsageError("--seeds " + item + ": expected seeds (numbers) and ranges A-B");
    seeds.push_back(std::stoi(item));
  }
  return seeds;
}

std::vector<Planner> parse_planner_list(const std::string& text) {
  static const std::regex label_chars("[A-Za-z0-9.+-]+");
  std::stringstream in(text);
  std::vector<Planner> planners;
  for (std::string item; in >> item;) {
    const std::size_t eq = item.find('=');
    std::vector<std::string> words = items_of(eq == std::string::npos ? item : item.substr(eq + 1));
    if (words.empty()) throw UsageError("--planners " + item + ": no strategy after '='");
    if (eq == std::string::npos) {  // strategies under their own names
      for (const std::string& s : words) planners.push_back({s, s, {}});
    } else {
      planners.push_back({item.substr(0, eq), words[0], {words.begin() + 1, words.end()}});
    }
  }
  if (planners.empty()) throw UsageError("--planners: the list is empty");
  std::set<std::string> labels;
  for (const Planner& p : planners) {
    nbv::parse_strategy(p.strategy, "--planners");
    if (!std::regex_match(p.label, label_chars))
      throw UsageError("--planners: label '" + p.label + "': letters, digits, '.', '+' and '-' only");
    if (!labels.insert(p.label).second) throw UsageError("--planners: '" + p.label + "' is given twice");
  }
  return planners;
}

namespace {

/// "builtin:suite/3" → "suite-3"; a mesh "scenes/shelf.ply" → "shelf.ply".
std::string scene_name(const std::string& scene) {
  std::string name = scene.rfind("builtin:", 0) == 0 ? scene.substr(8) : fs::path(scene).filename().string();
  for (char& c : name)
    if (c == '/' || c == ' ' || c == '_') c = '-';
  return name;
}

/// Every scene and every file the runs' options name exists, before a task is written.
void check_inputs(const Sweep& sweep) {
  std::set<std::string> names;
  for (const std::string& scene : sweep.scenes) {
    if (scene.rfind("builtin:", 0) == 0) sim::scene_from(scene, "");  // UsageError for an unknown name
    else require_readable_file(scene);
    if (!names.insert(scene_name(scene)).second)
      throw UsageError("--scenes: two scenes are named '" + scene_name(scene) + "' (their outputs would collide)");
  }
  for (std::size_t i = 0; i + 1 < sweep.options.size(); ++i)
    if (sweep.options[i] == "--capmap" || sweep.options[i] == "--arm" || sweep.options[i] == "--scene-info")
      require_readable_file(sweep.options[i + 1]);
}

std::string words(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& w : list) out += " " + shell_quote(w);
  return out;
}

}  // namespace

Plan sweep_plan(const std::string& fvx, const Sweep& sweep, const std::string& folder) {
  if (sweep.max_views < 1) throw UsageError("--max-views must be at least 1");
  check_inputs(sweep);
  const std::string here = fs::current_path().string();
  const std::string plan_folder = absolute_path(folder);
  const std::string binary = shell_quote(fs::absolute(fvx).lexically_normal().string());
  Plan plan{"sweep", plan_folder, {}, binary + " batch merge " + shell_quote(plan_folder), plan_folder + "/summary.md"};
  const std::string tail = " --max-views " + std::to_string(sweep.max_views) + " --timing --format json";
  for (const std::string& scene : sweep.scenes)
    for (const Planner& p : sweep.planners)
      for (const int seed : sweep.seeds) {
        const std::string part = plan_folder + "/parts/" + scene_name(scene) + "_" + p.label + "_" + std::to_string(seed);
        const std::string out = shell_quote(part + ".json"), tmp = shell_quote(part + ".json.tmp"),
                          session = shell_quote(part + ".session"), log = shell_quote(part + ".log");
        plan.tasks.push_back(
            {"cd " + shell_quote(here) + " && { test -s " + out + " || { rm -rf " + session + " && " + binary + " explore " +
                 shell_quote(scene) + words(sweep.options) + " --strategy " + shell_quote(p.strategy) + words(p.flags) +
                 " --seed " + std::to_string(seed) + tail + " -o " + session + " > " + tmp + " 2> " + log + " && mv " +
                 tmp + " " + out + "; } || { tail -n 1 " + log + " >&2; exit 1; }; }",
             part + ".json"});
      }
  return plan;
}

}  // namespace fvx::batch
