#pragma once
/// \file
/// Command-line options declared once (Ninja-style tables): each option's name, value, help,
/// default, range and where a report echoes it. One table yields the getopt_long options,
/// the --help text, the range checks of parsing and what the man-page test checks. Library
/// stages declare the options of their configs next to them (e.g. io/intrinsics_options.hpp).
#include <limits>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace fvx {

/// The values a numeric option accepts: [min, max], or (min, max] when min_exclusive.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
};
/// [min, max]; above(min, max): (min, max].
inline Range in(double min, double max) { return {min, max, false}; }
inline Range above(double min, double max = std::numeric_limits<double>::infinity()) { return {min, max, true}; }

/// The default as --help and the man page show it: a config field's initial value
/// (`dflt(nbv::Config{}.top)`), so that it cannot drift from the code's default.
template <typename T>
std::string dflt(const T& value) {
  std::ostringstream out;
  if constexpr (std::is_same_v<T, bool>) out << (value ? "on" : "off");
  else out << value;
  return out.str();
}

struct OptionSpec {
  const char* name;        ///< long name, without dashes
  char short_name;         ///< 0 when there is none
  const char* arg;         ///< metavariable ("M", "FILE"); nullptr for a flag
  const char* help;        ///< one line: meaning and unit (the default follows from default_text)
  /// Where the report holds the option's effective value, as a JSON pointer
  /// ("/config/pipeline/resolution_m"), or kNotASetting for an option that names an output or
  /// changes only how results are shown. A test checks every command's report against it.
  std::string echo;
  /// --help appends "(default <default_text>)"; the man page must say "default <value>" for
  /// the option (value: default_text up to a ':' or ';'). Empty: the help says what applies.
  std::string default_text = {};
  /// Numeric options: what Args::read and Args::number accept.
  std::optional<Range> range = {};
};

/// OptionSpec::echo of an option that sets nothing a report would echo (-o, --help, --format).
inline const char* const kNotASetting = "-";

struct CommandSpec {
  const char* name;                 ///< "integrate"
  const char* usage;                ///< "[options] SCAN..."
  const char* summary;              ///< one line for `fvx --help`
  std::vector<OptionSpec> options;  ///< in the order --help lists them
};

/// Parsed command line of one command: options by long name (last value wins; flags have an
/// empty value) and positional arguments.
class Args {
 public:
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  /// Value of an option that was given; empty string for a flag.
  const std::string& get(const std::string& name) const;
  /// The option's value within its declared range (OptionSpec::range), or `fallback` when
  /// absent. UsageError naming the option and its range otherwise.
  double number(const std::string& name, double fallback) const;
  long long integer(const std::string& name, long long fallback) const;
  /// Sets `field` to the option's value (in its declared range) when it was given.
  template <typename T>
  void read(const std::string& name, T& field) const {
    if (!has(name)) return;
    if constexpr (std::is_floating_point_v<T>) field = T(number(name, double(field)));
    else field = T(integer(name, (long long)(field)));
  }

  std::vector<std::string> positional;

 private:
  friend Args parse_args(const CommandSpec&, int, char**);
  const Range& range_of(const std::string& name) const;
  const CommandSpec* spec_ = nullptr;
  std::map<std::string, std::string> values_;
};

/// The largest value of an int option.
inline constexpr double kMaxInt = double(std::numeric_limits<int>::max());

/// --seed N (N >= 0) with its default `value`, and --threads N (0 to 1024, default 0: all
/// cores, then `note`), described by `help`.
OptionSpec seed_option(const std::string& echo, const char* help, std::uint64_t value);
OptionSpec threads_option(const std::string& echo, const char* help, const std::string& note = "");

/// Concatenates option tables.
std::vector<OptionSpec> options(std::initializer_list<std::vector<OptionSpec>> tables);

/// Parses argv (argv[0] is the command, e.g. "fvx integrate") with getopt_long. Unknown
/// options, missing values and stray values throw UsageError, with a suggestion when an
/// option name is close to a known one.
Args parse_args(const CommandSpec& spec, int argc, char** argv);

/// The values a range accepts as --help shows them: an interval, "(0, 10]", "[1, inf)".
std::string range_text(const Range& range);

/// `fvx <command> --help`: usage line, summary, and the option table; each option's help
/// ends with "(default D; range R)" for what it declares.
std::string help_text(const CommandSpec& spec);

/// Levenshtein distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace fvx
