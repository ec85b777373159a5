#include "fvx/core/options.hpp"

#include <getopt.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"

namespace fvx {

const std::string& Args::get(const std::string& name) const {
  const auto it = values_.find(name);
  FVX_ASSERT(it != values_.end(), "option --" + name + " was not given; check has() first");
  return it->second;
}

const Range& Args::range_of(const std::string& name) const {
  FVX_ASSERT(spec_ != nullptr, "Args without a CommandSpec");
  for (const OptionSpec& o : spec_->options)
    if (name == o.name) {
      FVX_ASSERT(o.range.has_value(), "option --" + name + " declares no range");
      return *o.range;
    }
  FVX_ASSERT(false, "option --" + name + " is not in the table of fvx " + spec_->name);
  std::abort();
}

double Args::number(const std::string& name, double fallback) const {
  const Range& r = range_of(name);
  if (!has(name)) return fallback;
  return parse_double_in(get(name), "--" + name, r.min, r.max, r.min_exclusive);
}

long long Args::integer(const std::string& name, long long fallback) const {
  const Range& r = range_of(name);
  if (!has(name)) return fallback;
  const auto limit = [](double v) {  // ±infinity and beyond: the integer type's own limits
    constexpr auto lo = std::numeric_limits<long long>::min(), hi = std::numeric_limits<long long>::max();
    return v <= double(lo) ? lo : v >= double(hi) ? hi : (long long)v;
  };
  return parse_int_in(get(name), "--" + name, limit(r.min_exclusive ? std::floor(r.min) + 1 : std::ceil(r.min)),
                      limit(r.max));
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

namespace {

std::string suggestion(const CommandSpec& spec, std::string given) {
  given = given.substr(0, given.find('='));
  while (!given.empty() && given[0] == '-') given.erase(0, 1);
  const OptionSpec* best = nullptr;
  std::size_t best_distance = 3;  // suggest only close names
  for (const auto& o : spec.options) {
    const std::size_t d = edit_distance(given, o.name);
    if (d < best_distance) {
      best = &o;
      best_distance = d;
    }
  }
  return best ? std::string("; did you mean --") + best->name + "?" : std::string();
}

}  // namespace

Args parse_args(const CommandSpec& spec, int argc, char** argv) {
  std::vector<option> long_options;
  std::string short_options = ":";  // leading ':' — report a missing value as ':'
  for (std::size_t i = 0; i < spec.options.size(); ++i) {
    const OptionSpec& o = spec.options[i];
    const int has_arg = o.arg ? required_argument : no_argument;
    long_options.push_back({o.name, has_arg, nullptr, int(256 + i)});
    if (o.short_name) {
      short_options += o.short_name;
      if (o.arg) short_options += ':';
    }
  }
  long_options.push_back({nullptr, 0, nullptr, 0});

  const std::string where = std::string("fvx ") + spec.name;
  Args args;
  args.spec_ = &spec;
  optind = 0;  // re-initialise getopt for this command (GNU)
  opterr = 0;  // fvx reports errors itself
  int long_index = -1;
  while (true) {
    const int c = getopt_long(argc, argv, short_options.c_str(), long_options.data(), &long_index);
    if (c == -1) break;
    const std::string token = argv[optind - 1] ? argv[optind - 1] : "";
    if (c == '?') {
      const std::string shown = optopt && optopt < 256 ? std::string("-") + char(optopt) : token;
      throw UsageError(where + ": unknown option '" + shown + "'" + suggestion(spec, shown) +
                       " (see 'fvx " + spec.name + " --help')");
    }
    if (c == ':') {
      const std::string shown = optopt && optopt < 256 ? std::string("-") + char(optopt) : token;
      throw UsageError(where + ": option '" + shown + "' needs a value");
    }
    const OptionSpec* o = nullptr;
    if (c >= 256) {
      o = &spec.options[std::size_t(c - 256)];
    } else {
      for (const auto& candidate : spec.options)
        if (candidate.short_name == c) o = &candidate;
    }
    FVX_ASSERT(o != nullptr, "getopt returned an option that is not in the table");
    args.values_[o->name] = optarg ? optarg : "";
  }
  for (int i = optind; i < argc; ++i) args.positional.emplace_back(argv[i]);
  return args;
}

std::string range_text(const Range& range) {
  const auto bound = [](double v) {
    if (std::isinf(v)) return std::string(v < 0 ? "-inf" : "inf");
    if (v >= 0x1p63) return std::string("2^63-1");  // a 64-bit integer option's own limit
    std::ostringstream out;
    if (v == std::floor(v) && std::abs(v) < 1e15) out << (long long)v;  // whole numbers in full
    else out << v;
    return out.str();
  };
  return (range.min_exclusive || std::isinf(range.min) ? "(" : "[") + bound(range.min) + ", " + bound(range.max) +
         (std::isinf(range.max) ? ")" : "]");
}

std::string help_text(const CommandSpec& spec) {
  std::ostringstream out;
  out << "usage: fvx " << spec.name << " " << spec.usage << "\n\n" << spec.summary << "\n\noptions:\n";
  std::vector<std::string> left;
  std::size_t width = 0;
  for (const auto& o : spec.options) {
    std::string l = o.short_name ? std::string("  -") + o.short_name + ", " : std::string("      ");
    l += std::string("--") + o.name;
    if (o.arg) l += std::string(" ") + o.arg;
    width = std::max(width, l.size());
    left.push_back(l);
  }
  for (std::size_t i = 0; i < left.size(); ++i) {
    const OptionSpec& o = spec.options[i];
    // "(default D; range R)"; a help that ends in its own "(default: …)" takes the range inside.
    std::string help = o.help, notes = o.default_text.empty() ? "" : "default " + o.default_text;
    if (o.range) notes += (notes.empty() ? "" : "; ") + std::string("range ") + range_text(*o.range);
    if (!notes.empty() && o.default_text.empty() && !help.empty() && help.back() == ')') {
      help.pop_back();
      help += "; " + notes + ")";
    } else if (!notes.empty()) {
      help += " (" + notes + ")";
    }
    out << left[i] << std::string(width + 2 - left[i].size(), ' ') << help << "\n";
  }
  out << "\nSee 'man fvx-" << spec.name << "' for details.\n";
  return out.str();
}

OptionSpec seed_option(const std::string& echo, const char* help, std::uint64_t value) {
  return {"seed", 0, "N", help, echo, dflt(value), in(0, double(std::numeric_limits<long long>::max()))};
}

OptionSpec threads_option(const std::string& echo, const char* help, const std::string& note) {
  return {"threads", 0, "N", help, echo, "0: all cores" + note, in(0, 1024)};
}

std::vector<OptionSpec> options(std::initializer_list<std::vector<OptionSpec>> tables) {
  std::vector<OptionSpec> all;
  for (const auto& table : tables) all.insert(all.end(), table.begin(), table.end());
  return all;
}

}  // namespace fvx
