#include "fvx/core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "fvx/core/error.hpp"

namespace fvx {
namespace fs = std::filesystem;
namespace {

/// A temporary name beside `path` that keeps its extension: "dir/.name.tmp-<pid>-<n>.ext".
std::string temporary_path_for(const std::string& path) {
  static unsigned counter = 0;
  const fs::path target(path);
  const std::string stem = target.stem().string();
  const std::string ext = target.extension().string();
  const std::string name = "." + stem + ".tmp-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + ext;
  return (target.parent_path() / name).string();
}

void check_parent_folder(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw FileError(path, "cannot write: folder '" + parent.string() + "' does not exist");
  if (fs::is_directory(path, ec)) throw FileError(path, "cannot write: it is a folder");
}

/// Where the rename goes: for a link to an existing file, the file it names, so that the link
/// stays a link (a rename onto the link's own name would put a plain file in its place).
std::string rename_target(const std::string& path) {
  std::error_code ec;
  if (!fs::is_symlink(fs::symlink_status(path, ec))) return path;
  const fs::path resolved = fs::canonical(path, ec);
  return ec ? path : resolved.string();
}

/// The descriptor `path` names (-, /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N and
/// /proc/P/fd/N with P this process's own id), or -1.
int descriptor_of(const std::string& path) {
  if (path == "-" || path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  const std::string own = "/proc/" + std::to_string(::getpid()) + "/fd/";
  for (const std::string& prefix : {std::string("/dev/fd/"), std::string("/proc/self/fd/"), own}) {
    if (path.rfind(prefix, 0) != 0) continue;
    const std::string n = path.substr(prefix.size());
    if (!n.empty() && n.size() < 9 && std::all_of(n.begin(), n.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return std::stoi(n);
  }
  return -1;
}

/// Writes `n` bytes to descriptor `fd` (at its own offset: what was written there before stays).
bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t done = ::write(fd, data, n);
    if (done < 0 && errno == EINTR) continue;
    if (done <= 0) return false;
    data += done;
    n -= std::size_t(done);
  }
  return true;
}

/// Writes the whole finished temporary into the stream `path`, then removes the temporary. A
/// descriptor's name is written through the descriptor this process holds; any other stream
/// (a device, a pipe) is opened for writing.
void copy_into_stream(const std::string& temp, const std::string& path) {
  const int held = descriptor_of(path);
  if (held >= 0) std::fflush(held == 1 ? stdout : held == 2 ? stderr : nullptr);  // what it printed before comes first
  errno = 0;
  const int fd = held >= 0 ? held : ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  bool ok = fd >= 0;
  std::ifstream in(temp, std::ios::binary);
  char buffer[1 << 16];
  while (ok && in.read(buffer, sizeof buffer).gcount() > 0) ok = write_all(fd, buffer, std::size_t(in.gcount()));
  const std::string why = write_failure(errno);
  if (fd >= 0 && held < 0) ::close(fd);
  std::remove(temp.c_str());
  if (!ok) throw FileError(path, "cannot write" + (why.empty() ? std::string(": write failed") : why));
}

void commit(const std::string& temp, const std::string& path) {
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temp.c_str());
    throw FileError(path, "cannot write: " + reason);
  }
}

}  // namespace

void write_path_atomically(const std::string& path,
                           const std::function<void(const std::string& temp_path)>& write) {
  // A stream gets the whole content once it is complete; its temporary goes to the temporary
  // folder, since a stream's folder (/dev, /proc/self/fd) takes no new files.
  const bool stream = is_stream_path(path);
  const std::string target = stream ? path : rename_target(path);
  if (!stream) check_parent_folder(target);
  std::error_code ec;
  const std::string temp = stream ? temporary_path_for((fs::temp_directory_path(ec) / fs::path(path).filename()).string())
                                  : temporary_path_for(target);
  try {
    write(temp);
  } catch (...) {
    std::remove(temp.c_str());
    throw;
  }
  if (!fs::is_regular_file(temp, ec)) throw FileError(path, "cannot write: the writer produced no file");
  if (stream)
    copy_into_stream(temp, path);
  else
    commit(temp, target);
}

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  write_path_atomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw FileError(path, std::string("cannot write: ") + std::strerror(errno));
    errno = 0;  // what a failed write leaves here says why (write_failure)
    write(out);
    out.flush();
    if (!out) {
      const std::string why = write_failure(errno);
      throw FileError(path, "cannot write" + (why.empty() ? std::string(": write failed") : why));
    }
  });
}

std::string write_failure(int errno_value) {
  return errno_value == 0 ? "" : std::string(": ") + std::strerror(errno_value);
}

bool is_stream_path(const std::string& path) {
  // A name for an open descriptor is written through even when it leads to a regular file
  // (`> out.txt`): a rename would put a new file at that name while the descriptor keeps the
  // old one.
  if (path == "-" || path == "/dev/stdout" || path == "/dev/stderr" || path.rfind("/dev/fd/", 0) == 0 ||
      path.rfind("/proc/", 0) == 0)
    return true;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  return !ec && fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st);
}

std::string lowercase_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void require_readable_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw FileError(path, "no such file");
  if (fs::is_directory(path, ec)) throw FileError(path, "is a folder, expected a file");
  // A pipe would block the open until a writer comes, a device (/dev/zero) never ends.
  if (!fs::is_regular_file(path, ec)) throw FileError(path, "is not a regular file (a pipe, device or socket)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, std::string("cannot open: ") + std::strerror(errno));
}

void create_folder(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw FileError(path, "cannot create the folder: " + ec.message());
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace fvx
