#pragma once
// One option table per command yields both the getopt_long options and the --help text
// (Ninja-style), so the two cannot drift apart.
#include <map>
#include <string>
#include <vector>

namespace fvx::cli {

struct OptionSpec {
  const char* name;        ///< long name, without dashes
  char short_name;         ///< 0 when there is none
  const char* arg;         ///< metavariable ("M", "FILE"); nullptr for a flag
  const char* help;        ///< one line: meaning, unit, default
  /// Where the report holds the option's effective value, as a JSON pointer
  /// ("/config/pipeline/resolution_m"), or kNotASetting for an option that names an output or
  /// changes only how results are shown. A test checks every command's report against it.
  std::string echo;
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
  /// The option's value parsed as a double in [min, max] (or (min, max] when
  /// `min_exclusive`), or `fallback` when absent.
  double number(const std::string& name, double fallback, double min, double max,
                bool min_exclusive = false) const;
  long long integer(const std::string& name, long long fallback, long long min, long long max) const;

  std::vector<std::string> positional;

 private:
  friend Args parse_args(const CommandSpec&, int, char**);
  std::map<std::string, std::string> values_;
};

/// Parses argv (argv[0] is the command, e.g. "fvx integrate") with getopt_long. Unknown
/// options, missing values and stray values throw UsageError, with a suggestion when an
/// option name is close to a known one.
Args parse_args(const CommandSpec& spec, int argc, char** argv);

/// `fvx <command> --help`: usage line, summary, and the option table.
std::string help_text(const CommandSpec& spec);

/// Levenshtein distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace fvx::cli
