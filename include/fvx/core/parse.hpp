#pragma once
/// \file
/// Strict text-to-number parsing for options and text files: the whole string must be a
/// number ("1.5cm", "", "nan", "1e999" are refused), and ranges are checked. Every failure
/// throws UsageError naming the option (or file:line) and the accepted range.
#include <string>
#include <vector>

namespace fvx {

/// Parses a finite double; `what` names the source for the message (e.g. "--resolution").
double parse_double(const std::string& text, const std::string& what);

/// parse_double, then checks `min <= value <= max` (or `min < value` when `min_exclusive`).
double parse_double_in(const std::string& text, const std::string& what, double min, double max,
                       bool min_exclusive = false);

/// Parses a base-10 integer that must lie in [min, max].
long long parse_int_in(const std::string& text, const std::string& what, long long min,
                       long long max);

/// Parses exactly `count` comma-separated finite doubles ("x,y,z").
std::vector<double> parse_double_list(const std::string& text, const std::string& what,
                                      std::size_t count);

/// Splits on ASCII whitespace; empty fields are dropped.
std::vector<std::string> split_whitespace(const std::string& line);

}  // namespace fvx
