#include "fvx/core/parse.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "fvx/core/error.hpp"

namespace fvx {
namespace {

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

double parse_double(const std::string& text, const std::string& what) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  if (text.empty() || end == begin || *end != '\0' || std::isspace(static_cast<unsigned char>(text[0])))
    throw UsageError(what + ": '" + text + "' is not a number");
  if (errno == ERANGE || !std::isfinite(value))
    throw UsageError(what + ": '" + text + "' is not a finite number");
  return value;
}

double parse_double_in(const std::string& text, const std::string& what, double min, double max,
                       bool min_exclusive) {
  const double value = parse_double(text, what);
  const bool low = min_exclusive ? !(value > min) : !(value >= min);
  if (low || !(value <= max)) {
    throw UsageError(what + ": " + text + " is out of range; expected " +
                     (min_exclusive ? "> " : ">= ") + format_number(min) + " and <= " +
                     format_number(max));
  }
  return value;
}

long long parse_int_in(const std::string& text, const std::string& what, long long min,
                       long long max) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(begin, &end, 10);
  if (text.empty() || end == begin || *end != '\0' || std::isspace(static_cast<unsigned char>(text[0])))
    throw UsageError(what + ": '" + text + "' is not a whole number");
  if (errno == ERANGE || value < min || value > max)
    throw UsageError(what + ": " + text + " is out of range; expected " + std::to_string(min) +
                     " to " + std::to_string(max));
  return value;
}

std::vector<double> parse_double_list(const std::string& text, const std::string& what,
                                      std::size_t count) {
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    values.push_back(parse_double(text.substr(start, comma - start), what));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (values.size() != count)
    throw UsageError(what + ": expected " + std::to_string(count) +
                     " comma-separated numbers, got " + std::to_string(values.size()) + " in '" +
                     text + "'");
  return values;
}

std::vector<std::string> split_whitespace(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  std::string field;
  while (in >> field) fields.push_back(field);
  return fields;
}

}  // namespace fvx
