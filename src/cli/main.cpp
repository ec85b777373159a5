// fvx — the one catch (ARCHITECTURE.md §2): input problems are fvx::Error (exit 1) or
// fvx::UsageError (exit 2), reported on one line of stderr.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "command_table.hpp"
#include "fvx/core/error.hpp"
#include "fvx/core/memory.hpp"

namespace {

/// One line: messages from a command already start with "fvx <command>: ".
void report(const char* message) {
  const bool named = std::string(message).rfind("fvx ", 0) == 0;
  std::fprintf(stderr, "%s%s\n", named ? "" : "fvx: ", message);
}

}  // namespace

int main(int argc, char** argv) {
  fvx::core::use_huge_page_heap();
  try {
    return fvx::cli::run(argc, argv);
  } catch (const fvx::UsageError& e) {
    report(e.what());
    return 2;
  } catch (const fvx::Error& e) {
    report(e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    report("out of memory");
    return 1;
  } catch (const std::exception& e) {
    report((std::string("unexpected error: ") + e.what()).c_str());
    return 1;
  }
}
