// fvx — the one catch (ARCHITECTURE.md §2): input problems are fvx::Error (exit 1) or
// fvx::UsageError (exit 2), reported on one line of stderr.
#include <cstdio>
#include <exception>
#include <new>

#include "command_table.hpp"
#include "fvx/core/error.hpp"

int main(int argc, char** argv) {
  try {
    return fvx::cli::run(argc, argv);
  } catch (const fvx::UsageError& e) {
    std::fprintf(stderr, "fvx: %s\n", e.what());
    return 2;
  } catch (const fvx::Error& e) {
    std::fprintf(stderr, "fvx: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "fvx: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fvx: unexpected error: %s\n", e.what());
    return 1;
  }
}
