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

void assert_failed(const char* expression, const char* file, int line,
                   const std::string& message) {
  std::fprintf(stderr, "fvx: internal error: %s:%d: assertion '%s' failed: %s\n", file, line,
               expression, message.c_str());
  std::abort();
}

}  // namespace fvx::detail
