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

/// "viewNNN" + ext: the file of a view (0-based) in a session or replay folder.
std::string view_file_name(int view, const char* ext);

/// The header and rows as markdown or csv (not json).
void print_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                 Format format, std::ostream& out);

}  // namespace fvx::cli
