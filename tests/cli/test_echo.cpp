// Every option of every command declares where its report holds the option's effective value
// (OptionSpec::echo), and a run of each command holds a value there; a number given on the
// command line comes back as given.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_support.hpp"
#include "command_table.hpp"

namespace fvx::test {
namespace {

using nlohmann::json;

std::string source(const std::string& path) { return std::string(std::getenv("FVX_SOURCE_DIR")) + "/" + path; }

/// Whether `pointer` ("/config/seed") leads to a value in `report`. A null on the way counts:
/// the run did not use that object at all (no intrinsics given, no capability map).
bool resolves(const json& report, const std::string& pointer, const json** value) {
  const json* at = &report;
  std::stringstream tokens(pointer.substr(1));
  for (std::string token; std::getline(tokens, token, '/');) {
    if (at->is_null()) break;
    if (at->is_object()) {
      if (!at->contains(token)) return false;
      at = &(*at)[token];
    } else if (at->is_array()) {
      const std::size_t i = std::stoul(token);
      if (i >= at->size()) return false;
      at = &(*at)[i];
    } else {
      return false;
    }
  }
  *value = at;
  return true;
}

/// "--name value" pairs of a command line (values that do not start with "--").
std::map<std::string, std::string> given_values(const std::string& arguments) {
  std::map<std::string, std::string> given;
  std::stringstream words(arguments);
  std::string word, previous;
  while (words >> word) {
    if (previous.rfind("--", 0) == 0 && word.rfind("--", 0) != 0) given[previous.substr(2)] = word;
    previous = word;
  }
  return given;
}

const cli::CommandSpec& spec_of(const std::string& name) {
  for (const cli::Command& c : cli::commands())
    if (name == c.spec.name) return c.spec;
  throw std::runtime_error("no command " + name);
}

/// Checks `report` against every option of `command` for which `applies` holds.
void expect_echoes(const json& report, const std::string& command, const std::string& arguments,
                   const std::function<bool(const cli::OptionSpec&)>& applies = {}) {
  const std::map<std::string, std::string> given = given_values(arguments);
  for (const cli::OptionSpec& o : spec_of(command).options) {
    if (o.echo == cli::kNotASetting || (applies && !applies(o))) continue;
    const json* value = nullptr;
    ASSERT_TRUE(resolves(report, o.echo, &value)) << command << " --" << o.name << ": no " << o.echo << " in the report";
    const auto it = given.find(o.name);
    if (it == given.end() || !value->is_number()) continue;
    double number = 0;
    std::istringstream in(it->second);
    if (!(in >> number) || !in.eof()) continue;  // not a plain number (a pose, a list, a name)
    EXPECT_NEAR(value->get<double>(), number, 1e-9) << command << " --" << o.name << " at " << o.echo;
  }
}

TEST(Echo, EveryOptionSaysWhereItsValueIsEchoed) {
  for (const cli::Command& c : cli::commands())
    for (const cli::OptionSpec& o : c.spec.options)
      EXPECT_TRUE(o.echo == cli::kNotASetting || o.echo.rfind('/', 0) == 0)
          << c.spec.name << " --" << o.name << ": echo '" << o.echo << "'";
}

TEST(Echo, EveryCommandsReportHoldsEveryOptionsEffectiveValue) {
  const TempDir dir;
  const std::string scene = " '" + source("data/scenes/crates.ply") + "'";
  const std::string arm = " --capmap '" + source("data/arms/fvx-arm.fcm") + "' --base 0.2,0,0,0,0,0 --arm '" +
                          source("data/arms/fvx-arm.urdf") + "'";
  const std::string camera = " --width 320 --height 240 --fx 262 --fy 263 --cx 160 --cy 120 --depth-scale 1000";
  auto run = [&](const std::string& command, const std::string& arguments) {
    const RunResult r = run_fvx(dir, command + " " + arguments);
    EXPECT_EQ(r.status, 0) << command << ": " << r.err;
    return r.status == 0 ? json::parse(r.out) : json();
  };

  std::string args = scene + " --look-at 0.1,0,0.9,0.8,0,0.15 -o a.pcd --depth-min 0.4 --depth-max 3.5 --noise kinect "
                     "--dropout-deg 80 --seed 5 --threads 1 --ground-truth gt.bt -r 0.05" + camera;
  expect_echoes(run("simulate", args), "simulate", args);

  args = "-o m.ot -r 0.05 --max-range 3.5 --depth-min 0.1 --depth-max 3.9 --downsample 0.01 --max-time-diff 0.05 "
         "--reg-voxel 0.04 --reg-max-corr 0.25 --reg-fine-corr 0.08 --reg-max-iter 30 --fx 262 a.pcd";
  expect_echoes(run("integrate", args), "integrate", args);

  args = "m.ot --bounds 0.4,-0.8,0.0,1.2,0.75,0.55 --min-fit-score 0.6 --seed 3";
  expect_echoes(run("voids", args), "voids", args);
  args = "m.ot --bounds 0.4,-0.8,0.0,1.2,0.75,0.55";
  expect_echoes(run("frontiers", args), "frontiers", args);

  args = "m.ot" + arm + " --top 3 --poses 20 --orientations 3 --separation 0.1 --refine 2 --polish 1 --climb 1 "
         "--jitter 4 --clearance 0.05 --rolls 3 --min-fit-score 0.6 --seed 2 --threads 1 --target-size 0.1 "
         "--utility-vectors 100000 --coarse-rays 20x15 --depth-min 0.4 --depth-max 3.5" + camera;
  expect_echoes(run("nbv", args), "nbv", args);

  args = scene + arm + " --max-views 2 --resolution 0.05 --seed 2 --threads 1 --target-size 0.1 "
         "--utility-vectors 100000 --depth-min 0.4 --depth-max 3.5 --format json -o s";
  expect_echoes(run("explore", args), "explore", args);

  args = "s -o r --format json --to 2 --search-every 2 --seed 4 --threads 1 --target-size 0.05 --utility-vectors 90000";
  expect_echoes(run("replay", args), "replay", args);

  args = "'" + source("data/arms/fvx-arm.urdf") + "' --base base_link --tip kinect_optical --voxel 0.2 --directions 20 "
         "--fk-samples 2000 --restarts 3 --position-tolerance 0.004 --seed 7 --threads 1 -o arm.fcm";
  expect_echoes(run("capmap build", args), "capmap", args,
                [](const cli::OptionSpec& o) { return std::string(o.help).rfind("build", 0) == 0; });

  args = "'" + source("data/arms/fvx-arm.urdf") + "' --base base_link --tip kinect_optical --voxel 0.2 --directions 20 "
         "--shards 2 --map m.fcm -o plan";
  expect_echoes(run("batch capmap", args), "batch", args, [](const cli::OptionSpec& o) {
    return std::string(o.name) != "joblog" && std::string(o.name) != "list" && std::string(o.help).rfind("sweep", 0) != 0;
  });
  args = "--scenes 2,closed-box --planners random --seeds 1-2 --max-views 3 -o splan -- --no-capmap";
  expect_echoes(run("batch sweep", args), "batch", args, [](const cli::OptionSpec& o) {
    return std::string(o.help).rfind("sweep", 0) == 0 || std::string(o.name) == "output";
  });
  std::ofstream(dir / "sequences.txt") << "session/\n";
  args = "--list sequences.txt --map t.csv -o rplan -- --no-capmap";
  expect_echoes(run("batch replay", args), "batch", args, [](const cli::OptionSpec& o) {
    return std::string(o.name) == "list" || std::string(o.name) == "map";
  });
  args = "plan --joblog none.log";
  expect_echoes(run("batch status", args), "batch", args, [](const cli::OptionSpec& o) { return std::string(o.name) == "joblog"; });
}

}  // namespace
}  // namespace fvx::test
