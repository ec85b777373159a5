#pragma once
/// \file
/// Two tiers of errors (ARCHITECTURE.md §2):
///  - a broken invariant is a bug: FVX_ASSERT prints the values and aborts;
///  - anything caused by input throws a subclass of fvx::Error whose message names the file,
///    option or value and what would fix it. `main` has the one catch and maps the kind to an
///    exit status (UsageError → 2, everything else → 1).
#include <stdexcept>
#include <string>
#include <vector>

namespace fvx {

namespace detail {
/// The message with control characters written as escapes (\n, \r, \xNN): a file's bytes
/// that become part of a message (a key, a token) cannot break its one line.
std::string one_line(const std::string& message);
}  // namespace detail

/// Input or runtime problem: bad data, unreadable file, failed write. Exit status 1.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(detail::one_line(message)) {}
};

/// The command line itself is wrong (unknown option, non-numeric value, value out of range).
/// Exit status 2.
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(message) {}
};

/// A file could not be opened, read, parsed or written. The message starts with the path.
class FileError : public Error {
 public:
  FileError(const std::string& path, const std::string& problem)
      : Error(path + ": " + problem), path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// All of a config's problems on one line, "p1; p2; …" (validate() lists every problem, so
/// a user fixes them in one go).
std::string join_problems(const std::vector<std::string>& problems);

/// Throws UsageError("<what>: " + join_problems(problems)) when there is any.
void throw_if_problems(const std::string& what, const std::vector<std::string>& problems);

namespace detail {
[[noreturn]] void assert_failed(const char* expression, const char* file, int line,
                                const std::string& message);
}  // namespace detail

}  // namespace fvx

/// Invariant check that stays on in release builds; `message` may use operator+ on strings.
#define FVX_ASSERT(condition, message)                                              \
  do {                                                                              \
    if (!(condition)) ::fvx::detail::assert_failed(#condition, __FILE__, __LINE__, \
                                                   (message));                      \
  } while (false)
