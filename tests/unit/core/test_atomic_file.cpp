#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "fvx/core/atomic_file.hpp"
#include "fvx/core/error.hpp"
#include "test_support.hpp"

namespace fvx {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST(AtomicFile, WritesAndReplaces) {
  const test::TempDir dir;
  write_file_atomically(dir / "a.txt", [](std::ostream& out) { out << "one"; });
  EXPECT_EQ(read(dir / "a.txt"), "one");
  write_file_atomically(dir / "a.txt", [](std::ostream& out) { out << "two"; });
  EXPECT_EQ(read(dir / "a.txt"), "two");
}

TEST(AtomicFile, AFailingWriterLeavesTheOldFileAndNoTemporary) {
  const test::TempDir dir;
  write_file_atomically(dir / "a.txt", [](std::ostream& out) { out << "old"; });
  EXPECT_THROW(write_file_atomically(dir / "a.txt",
                                     [](std::ostream& out) {
                                       out << "half";
                                       throw Error("input went bad");
                                     }),
               Error);
  EXPECT_EQ(read(dir / "a.txt"), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

TEST(AtomicFile, MissingFolderIsAFileError) {
  const test::TempDir dir;
  EXPECT_THROW(write_file_atomically(dir / "nope/a.txt", [](std::ostream&) {}), FileError);
}

// A rename onto a device or pipe would put a plain file in the node's place (as root,
// `-o /dev/null` replaced /dev/null); the content must go into the stream instead.
TEST(AtomicFile, APipeIsWrittenIntoAndStaysAPipe) {
  const test::TempDir dir;
  const std::string fifo = dir / "out.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // The read end opened first, without blocking, so that a writer that does not open the
  // pipe fails the test instead of hanging it; the content fits the pipe's buffer.
  const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(fd, 0);
  write_file_atomically(fifo, [](std::ostream& out) { out << "through the pipe"; });
  char buffer[64] = {};
  const ssize_t n = ::read(fd, buffer, sizeof buffer);
  ::close(fd);
  EXPECT_EQ(std::string(buffer, std::size_t(std::max<ssize_t>(n, 0))), "through the pipe");
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_TRUE(is_stream_path(fifo));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);  // no temporary left
}

TEST(AtomicFile, DevNullStaysADevice) {
  write_file_atomically("/dev/null", [](std::ostream& out) { out << "gone"; });
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
  EXPECT_TRUE(is_stream_path("/dev/null"));
  EXPECT_FALSE(is_stream_path("/"));
  EXPECT_FALSE(is_stream_path("/nonexistent-fvx-path"));
}

// `{ echo first; fvx … -o /dev/stdout; } > out.txt`: a rename onto the file behind the
// descriptor would drop what the shell wrote there before.
TEST(AtomicFile, StandardOutputIsWrittenThroughItsDescriptorEvenWhenItIsAFile) {
  const test::TempDir dir;
  EXPECT_TRUE(is_stream_path("/dev/stdout"));
  EXPECT_TRUE(is_stream_path("/dev/fd/1"));
  EXPECT_TRUE(is_stream_path("-"));
  const int fd = ::dup(1);
  ASSERT_GE(fd, 0);
  ASSERT_NE(std::freopen((dir / "out.txt").c_str(), "w", stdout), nullptr);
  std::fputs("first\n", stdout);
  std::fflush(stdout);
  write_file_atomically("/dev/stdout", [](std::ostream& out) { out << "second\n"; });
  std::fflush(stdout);
  ::dup2(fd, 1);
  ::close(fd);
  EXPECT_EQ(read(dir / "out.txt"), "first\nsecond\n");
}

// /proc/P/fd/N with P this process's own id names a descriptor it holds, as /proc/self/fd/N
// does: reopening it would write from the file's start over what the descriptor wrote before.
TEST(AtomicFile, ItsOwnProcessIdsDescriptorNameIsWrittenThrough) {
  const test::TempDir dir;
  const int fd = ::open((dir / "out.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::write(fd, "first\n", 6), 6);
  const std::string name = "/proc/" + std::to_string(::getpid()) + "/fd/" + std::to_string(fd);
  EXPECT_TRUE(is_stream_path(name));
  write_file_atomically(name, [](std::ostream& out) { out << "second\n"; });
  ::close(fd);
  EXPECT_EQ(read(dir / "out.txt"), "first\nsecond\n");
}

TEST(AtomicFile, ALinkToAFileStaysALinkAndTheFileChanges) {
  const test::TempDir dir;
  write_file_atomically(dir / "real.txt", [](std::ostream& out) { out << "old"; });
  std::filesystem::create_symlink("real.txt", dir / "link.txt");
  write_file_atomically(dir / "link.txt", [](std::ostream& out) { out << "new"; });
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "link.txt"));
  EXPECT_EQ(read(dir / "real.txt"), "new");
  EXPECT_FALSE(is_stream_path(dir / "link.txt"));
}

TEST(AtomicFile, RequireReadable) {
  const test::TempDir dir;
  EXPECT_THROW(require_readable_file(dir / "missing"), FileError);
  EXPECT_THROW(require_readable_file(dir.path().string()), FileError);  // a folder
}

}  // namespace
}  // namespace fvx
