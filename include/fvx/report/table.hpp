#pragma once
/// \file
/// Per-view tables (fvx explore, fvx replay): markdown (the paper's layout) or csv; json is
/// the report itself.
#include <ostream>
#include <string>
#include <vector>

namespace fvx::report {

enum class Format { markdown, csv, json };  // as --format spells them

/// "markdown", "csv" or "json"; UsageError naming `what` otherwise.
Format parse_format(const std::string& name, const std::string& what = "--format");

/// `v` with `digits` decimals.
std::string fixed(double v, int digits);

/// The header and rows as markdown or csv (not json).
void print_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                 Format format, std::ostream& out);

}  // namespace fvx::report
