#include "table.hpp"

#include <cstdio>

#include "fvx/core/error.hpp"

namespace fvx::cli {

Format parse_format(const Args& args) {
  const std::string f = args.has("format") ? args.get("format") : "markdown";
  if (f == "markdown") return Format::markdown;
  if (f == "csv") return Format::csv;
  if (f == "json") return Format::json;
  throw UsageError("--format '" + f + "': expected markdown, csv or json");
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void print_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                 Format format, std::ostream& out) {
  const bool csv = format == Format::csv;
  auto line = [&](const std::vector<std::string>& cells) {
    if (!csv) out << "|";
    for (std::size_t i = 0; i < cells.size(); ++i) out << (csv ? (i ? "," : "") : " ") << cells[i] << (csv ? "" : " |");
    out << "\n";
  };
  line(header);
  if (!csv) {
    out << "|";
    for (std::size_t i = 0; i < header.size(); ++i) out << "---|";
    out << "\n";
  }
  for (const auto& r : rows) line(r);
}

}  // namespace fvx::cli
