#pragma once
// The command table (Ninja-style): {spec, run} in pipeline order. `fvx --help` prints it.
#include <vector>

#include "options.hpp"

namespace fvx::cli {

struct Command {
  const CommandSpec& spec;
  /// Runs the command on its parsed options (--help is handled before); returns the exit status.
  int (*run)(const Args& args);
};

/// Every command, in the order of the pipeline (ARCHITECTURE.md §1).
const std::vector<Command>& commands();

/// The whole program below main(): top-level options, `help`, dispatch. Throws fvx::Error.
int run(int argc, char** argv);

/// `fvx --help`.
std::string top_level_help();

// Commands (one cmd_<name>.cpp each).
extern const CommandSpec kIntegrateSpec;
int run_integrate(const Args& args);
extern const CommandSpec kFrontiersSpec;
int run_frontiers(const Args& args);
extern const CommandSpec kVoidsSpec;
int run_voids(const Args& args);
extern const CommandSpec kCapmapSpec;
int run_capmap(const Args& args);
extern const CommandSpec kNbvSpec;
int run_nbv(const Args& args);
extern const CommandSpec kSimulateSpec;
extern const CommandSpec kExploreSpec;
int run_simulate(const Args& args);
int run_explore(const Args& args);
extern const CommandSpec kReplaySpec;
int run_replay(const Args& args);
/// Built from capmap build's options (kCapmapSpec) on first use.
const CommandSpec& batch_spec();
int run_batch(const Args& args);

}  // namespace fvx::cli
