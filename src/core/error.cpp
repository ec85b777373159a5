#include "fvx/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace fvx::detail {

void assert_failed(const char* expression, const char* file, int line,
                   const std::string& message) {
  std::fprintf(stderr, "fvx: internal error: %s:%d: assertion '%s' failed: %s\n", file, line,
               expression, message.c_str());
  std::abort();
}

}  // namespace fvx::detail
