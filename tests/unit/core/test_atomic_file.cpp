#include <gtest/gtest.h>

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

TEST(AtomicFile, RequireReadable) {
  const test::TempDir dir;
  EXPECT_THROW(require_readable_file(dir / "missing"), FileError);
  EXPECT_THROW(require_readable_file(dir.path().string()), FileError);  // a folder
}

}  // namespace
}  // namespace fvx
