#pragma once
/// \file
/// Before any work, refuse outputs that would destroy an input or could not be written, so
/// that a command never replaces one output and then fails on the next, or writes its report
/// over the map it read (`fvx voids m.bt -o m.bt`).
#include "fvx/core/options.hpp"

namespace fvx {

/// The options that name outputs, whichever command declares them.
inline constexpr const char* kOutputOptions[] = {"output",        "report",     "cloud",       "picture",
                                                 "picture-top",   "utility-cloud", "ellipsoids", "ground-truth"};

/// UsageError (exit 2) for an output that is an existing input file (a positional argument or
/// another option's value) or names the same file as another output; FileError (exit 1) for a
/// file output whose folder does not exist or cannot be written, or that is a folder. Folder
/// outputs (metavariable DIR) need a writable existing ancestor.
void check_outputs(const CommandSpec& spec, const Args& args);

}  // namespace fvx
