#pragma once
// Per-view tables on stdout (fvx explore, fvx replay): markdown (the paper's layout), csv, or
// json (written by the command itself).
#include <ostream>
#include <string>
#include <vector>

#include "options.hpp"

namespace fvx::cli {

enum class Format { markdown, csv, json };  // as --format spells them

/// --format markdown (default) | csv | json; UsageError otherwise.
Format parse_format(const Args& args);

/// `v` with `digits` decimals.
std::string fixed(double v, int digits);

/// The header and rows as markdown or csv (not json).
void print_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                 Format format, std::ostream& out);

}  // namespace fvx::cli
