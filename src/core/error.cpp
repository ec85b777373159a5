#include "fvx/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace fvx {

std::string join_problems(const std::vector<std::string>& problems) {
  std::string joined;
  for (const std::string& p : problems) joined += (joined.empty() ? "" : "; ") + p;
  return joined;
}

void throw_if_problems(const std::string& what, const std::vector<std::string>& problems) {
  if (!problems.empty()) throw UsageError(what + ": " + join_problems(problems));
}

}  // namespace fvx

namespace fvx::detail {

std::string one_line(const std::string& message) {
  std::string line;
  line.reserve(message.size());
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') line += "\\n";
    else if (c == '\r') line += "\\r";
    else if (u < 0x20 && c != '\t') {
      static const char kHex[] = "0123456789abcdef";
      line += "\\x";
      line += kHex[u >> 4];
      line += kHex[u & 15];
    } else {
      line += c;
    }
  }
  return line;
}

void assert_failed(const char* expression, const char* file, int line,
                   const std::string& message) {
  std::fprintf(stderr, "fvx: internal error: %s:%d: assertion '%s' failed: %s\n", file, line,
               expression, message.c_str());
  std::abort();
}

}  // namespace fvx::detail
