// A fresh folder per test under the system's temporary folder, removed when
// the test passes (kept for a look when it fails), and reading a file whole.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace sabus::test {

// "<tmp>/sabus-<program>-test-<pid>-<name>": a path no other test program
// (nor another run of this one) uses.
inline std::string temp_path(const std::string& program, const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("sabus-" + program + "-test-" + std::to_string(getpid()) + "-" + name))
      .string();
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Fixture: dir_ is "<tmp>/<prefix>-<pid>-<test name>", empty at the start.
class TempDirTest : public ::testing::Test {
 protected:
  explicit TempDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + "-" + std::to_string(getpid()) + "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace sabus::test
