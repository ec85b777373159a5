#include "command_table.hpp"

#include <getopt.h>

#include <cstdio>
#include <sstream>
#include <string>

#include "fvx/core/error.hpp"
#include "fvx/core/output_check.hpp"
#include "fvx/core/pose.hpp"

namespace fvx::cli {

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {kIntegrateSpec, run_integrate},
      {kFrontiersSpec, run_frontiers},
      {kVoidsSpec, run_voids},
      {kCapmapSpec, run_capmap},
      {kNbvSpec, run_nbv},
      {kExploreSpec, run_explore},
      {kReplaySpec, run_replay},
      {kSimulateSpec, run_simulate},
      {batch_spec(), run_batch},
  };
  return table;
}

std::string top_level_help() {
  std::ostringstream out;
  out << "usage: fvx [--version] [--help] <command> [options] [args]\n\n"
         "fvx finds the next best view for a depth sensor searching unknown 3-D space\n"
         "(Dornhege & Kleiner, frontier-void exploration, SSRR 2011).\n\ncommands:\n";
  for (const Command& c : commands())
    out << "  " << c.spec.name << std::string(12 - std::string(c.spec.name).size(), ' ')
        << c.spec.summary << "\n";
  out << "  help        show the help of a command\n\n"
         "Run 'fvx <command> --help' or 'man fvx-<command>' for a command's options.\n"
         "Exit status: 0 success, 1 runtime or data error, 2 usage error.\n";
  return out.str();
}

namespace {

const Command* find_command(const std::string& name) {
  for (const Command& c : commands())
    if (name == c.spec.name) return &c;
  return nullptr;
}

std::string unknown_command_message(const std::string& name) {
  std::string best;
  std::size_t best_distance = 3;
  for (const Command& c : commands()) {
    const std::size_t d = edit_distance(name, c.spec.name);
    if (d < best_distance) {
      best = c.spec.name;
      best_distance = d;
    }
  }
  std::string message = "'" + name + "' is not an fvx command";
  if (!best.empty()) message += "; did you mean '" + best + "'?";
  return message + " (see 'fvx --help')";
}

}  // namespace

int run(int argc, char** argv) {
  static const option top_options[] = {{"help", no_argument, nullptr, 'h'},
                                       {"version", no_argument, nullptr, 'V'},
                                       {nullptr, 0, nullptr, 0}};
  optind = 0;
  opterr = 0;
  // '+': stop at the first non-option, the command; its options are parsed by the command.
  while (true) {
    const int c = getopt_long(argc, argv, "+hV", top_options, nullptr);
    if (c == -1) break;
    if (c == 'h') {
      std::fputs(top_level_help().c_str(), stdout);
      return 0;
    }
    if (c == 'V') {
      std::printf("fvx %s\n", version());
      return 0;
    }
    throw UsageError(std::string("unknown option '") + argv[optind - 1] + "' (see 'fvx --help')");
  }
  if (optind >= argc) {
    std::fputs(top_level_help().c_str(), stderr);
    throw UsageError("no command given");
  }
  const std::string name = argv[optind];
  if (name == "help") {
    if (optind + 1 >= argc) {
      std::fputs(top_level_help().c_str(), stdout);
      return 0;
    }
    const Command* command = find_command(argv[optind + 1]);
    if (!command) throw UsageError(unknown_command_message(argv[optind + 1]));
    std::fputs(help_text(command->spec).c_str(), stdout);
    return 0;
  }
  const Command* command = find_command(name);
  if (!command) throw UsageError(unknown_command_message(name));
  // The command sees argv[0] = "fvx <name>", so getopt's view matches the user's.
  std::string program = "fvx " + name;
  std::vector<char*> sub_argv;
  sub_argv.push_back(program.data());
  for (int i = optind + 1; i < argc; ++i) sub_argv.push_back(argv[i]);
  sub_argv.push_back(nullptr);
  const Args args = parse_args(command->spec, int(sub_argv.size() - 1), sub_argv.data());
  if (args.has("help")) {
    std::fputs(help_text(command->spec).c_str(), stdout);
    return 0;
  }
  check_outputs(command->spec, args);  // before any work: nothing is replaced and then lost
  return command->run(args);
}

}  // namespace fvx::cli
