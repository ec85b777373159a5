#pragma once
// Helpers shared by the tests: real data through FVX_REAL_DATA, temporary folders.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fvx::test {

/// Absolute path of `relative` inside FVX_REAL_DATA (../shared/data). Tests that need real
/// data call this through FVX_REAL_DATA_OR_SKIP; CI always sets the variable.
inline std::string real_data(const std::string& relative) {
  const char* root = std::getenv("FVX_REAL_DATA");
  if (!root || !*root) return {};
  return (std::filesystem::path(root) / relative).string();
}

/// The whole file, or "" when it cannot be read.
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A file of the repository (FVX_SOURCE_DIR, which ctest sets).
inline std::string source(const std::string& relative) {
  const char* root = std::getenv("FVX_SOURCE_DIR");
  return std::string(root ? root : ".") + "/" + relative;
}

/// A fresh folder under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("fvx-test-") + (info ? info->name() : "x");
    for (auto& c : name)
      if (c == '/') c = '_';
    path_ = std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace fvx::test

/// Binds `var` to the real-data path, or skips the test when FVX_REAL_DATA is not set
/// (scripts/test.sh and CI set it; a bare `ctest` on a machine without the data skips).
#define FVX_REAL_DATA_OR_SKIP(var, relative)                                          \
  const std::string var = ::fvx::test::real_data(relative);                          \
  if (var.empty()) GTEST_SKIP() << "FVX_REAL_DATA is not set";                        \
  ASSERT_TRUE(std::filesystem::exists(var)) << var << " is missing from FVX_REAL_DATA"
