#include "fvx/core/isolated.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <new>

#include "fvx/core/error.hpp"

namespace fvx {

namespace {

constexpr unsigned long long kChildMemoryBytes = 2ull << 30;  ///< what a reader's child may add

bool write_all(int fd, const std::string& bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += std::size_t(n);
  }
  return true;
}

std::string read_all(int fd) {
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return bytes;
    bytes.append(buffer, std::size_t(n));
  }
}

/// In the child: a kind byte ('K' result, 'F' FileError, 'U' UsageError, 'E' Error, 'M' out
/// of memory), then for F the path's length and the path, then the payload.
std::string child_answer(const std::function<std::string()>& work) {
  try {
    return "K" + work();
  } catch (const FileError& e) {
    const std::string what = e.what(), prefix = e.path() + ": ";
    const std::string message = what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
    return "F" + std::to_string(e.path().size()) + ":" + e.path() + message;
  } catch (const UsageError& e) {
    return std::string("U") + e.what();
  } catch (const std::bad_alloc&) {
    return "M";
  } catch (const std::exception& e) {
    return std::string("E") + e.what();
  }
}

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FVX_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define FVX_ASAN 1
#endif

/// Caps the child's address space at what it has now plus kChildMemoryBytes: a reader that
/// believes a corrupt length (librosbag allocates what a record header claims, up to 4 GB)
/// gets bad_alloc instead of the machine's memory. AddressSanitizer reserves terabytes of
/// address space, so a sanitized build runs without the cap (and reports such allocations).
void cap_memory() {
#ifndef FVX_ASAN
  std::ifstream statm("/proc/self/statm");
  unsigned long long pages = 0;
  if (!(statm >> pages)) return;
  const rlim_t limit = rlim_t(pages) * rlim_t(::sysconf(_SC_PAGESIZE)) + rlim_t(kChildMemoryBytes);
  const rlimit r{limit, limit};
  ::setrlimit(RLIMIT_AS, &r);
#endif
}

}  // namespace

std::string run_isolated(const std::string& path, const std::string& what, const std::function<std::string()>& work) {
  int fds[2];
  if (::pipe(fds) != 0) throw Error(std::string("cannot make a pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]), ::close(fds[1]);
    throw Error(std::string("cannot start a process: ") + std::strerror(errno));
  }
  if (pid == 0) {  // the child: compute, hand back, leave without the parent's exit handlers
    ::close(fds[0]);
    // A crash ends the child by its signal, which the parent reports; the handlers it
    // inherited (a sanitizer's, a fuzzer's) would report it as their own.
    for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
    cap_memory();
    // What the parser prints as it fails (librosbag's assertions) is not fvx's one line.
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDERR_FILENO);
    const bool sent = write_all(fds[1], child_answer(work));
    ::_exit(sent ? 0 : 1);
  }
  ::close(fds[1]);
  const std::string answer = read_all(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status))
    throw FileError(path, "corrupt " + what + ": the reader crashed on it (signal " + std::to_string(WTERMSIG(status)) + ")");
  if (answer.empty() || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Error("reading " + path + ": the reader's process ended without an answer");
  const std::string payload = answer.substr(1);
  switch (answer[0]) {
    case 'K': return payload;
    case 'U': throw UsageError(payload);
    case 'M':
      throw FileError(path, "corrupt " + what + ": reading it asked for more than " +
                                std::to_string(kChildMemoryBytes >> 30) + " GiB of memory");
    case 'E': throw Error(payload);
    case 'F': {
      const std::size_t colon = payload.find(':');
      const std::size_t length = std::stoul(payload.substr(0, colon));
      throw FileError(payload.substr(colon + 1, length), payload.substr(colon + 1 + length));
    }
  }
  throw Error("reading " + path + ": the reader's process gave an answer fvx cannot read");
}

}  // namespace fvx
