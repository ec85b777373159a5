#pragma once
// Runs the fvx binary as a user would and captures exit status, stdout and stderr.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace fvx::test {

struct RunResult {
  int status = -1;
  std::string out, err;
};

/// `fvx <arguments>` in `dir`; arguments are passed through the shell as written, after the
/// variable assignments in `environment` ("NAME=value ...").
/// A shell prefix that caps the binary's address space at 4 GB, so that a reader that
/// allocates what a lying header claims fails the test instead of the machine. Under
/// AddressSanitizer (scripts/sanitize.sh), whose shadow memory needs terabytes of address
/// space, ASAN_OPTIONS' max_allocation_size_mb caps it instead.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FVX_TEST_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define FVX_TEST_UNDER_ASAN 1
#endif
inline std::string memory_limit() {
#ifdef FVX_TEST_UNDER_ASAN
  return "";
#else
  return "ulimit -v 4000000; ";
#endif
}

inline RunResult run_fvx(const TempDir& dir, const std::string& arguments, const std::string& environment = "") {
  const std::string out = dir / ".stdout", err = dir / ".stderr";
  const std::string command = "cd '" + dir.path().string() + "' && " + environment + " '" FVX_BINARY "' " + arguments +
                              " > '" + out + "' 2> '" + err + "' < /dev/null";
  const int raw = std::system(command.c_str());
  RunResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = slurp(out);
  r.err = slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

/// A map of the crates scene seen from two views, map.ot in `dir`, built with the binary.
inline void make_crates_map(const TempDir& dir) {
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0,0.9,0.8,0,0.15 -o a.pcd").status, 0);
  ASSERT_EQ(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0.5,0.8,0.8,0,0.15 -o b.pcd").status, 0);
  ASSERT_EQ(run_fvx(dir, "integrate -o map.ot -r 0.025 --no-register a.pcd b.pcd").status, 0);
}

inline std::size_t line_count(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

}  // namespace fvx::test
