#include "fvx/report/table.hpp"

#include <cstdio>

#include "fvx/core/error.hpp"

namespace fvx::report {

Format parse_format(const std::string& name, const std::string& what) {
  if (name == "markdown") return Format::markdown;
  if (name == "csv") return Format::csv;
  if (name == "json") return Format::json;
  throw UsageError(what + " '" + name + "': expected markdown, csv or json");
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

}  // namespace fvx::report
