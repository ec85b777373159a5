#pragma once
// The option tables of the commands: fvx/core/options.hpp, named here as the CLI and its
// tests use them.
#include "fvx/core/options.hpp"

namespace fvx::cli {

using fvx::above;
using fvx::Args;
using fvx::CommandSpec;
using fvx::dflt;
using fvx::edit_distance;
using fvx::help_text;
using fvx::in;
using fvx::kNotASetting;
using fvx::OptionSpec;
using fvx::parse_args;
using fvx::Range;

}  // namespace fvx::cli
