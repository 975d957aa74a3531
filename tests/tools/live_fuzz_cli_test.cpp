// `sabus fuzz` as a process: with an injected fault, a fixed seed and a fixed
// budget it finds the fault, and its minimized reproducer fails under
// `sabus run` with the fault and passes without it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "process.hpp"

namespace {

namespace fs = std::filesystem;
using sabus::test::Process;

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A fault, and the exit status of `sabus run --sim --fault F` on its
// reproducer: 1, a vector fails (also where no reply of the faulty device can
// be read: it sends bytes, so it is reachable and its vectors run).
struct Case {
  const char* fault;
  int run_exit;
};

class FuzzFindsFault : public ::testing::TestWithParam<Case> {};

TEST_P(FuzzFindsFault, AndItsReproducerFailsUnderRun) {
  const std::string fault = GetParam().fault;
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-" + fault + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  Process fuzz({SABUS_BIN, "fuzz", "--sim", "--fault", fault, "--seed", "1", "--max-frames", "500", "--findings", dir.string()});
  EXPECT_EQ(fuzz.wait_exit(), 1);
  std::vector<fs::path> files;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  ASSERT_FALSE(files.empty()) << "no finding written for " << fault;
  for (const fs::path& file : files) {
    const std::string text = read_file(file);
    EXPECT_NE(text.find("--seed 1"), std::string::npos) << text;
    EXPECT_NE(text.find("paragraph: framing"), std::string::npos) << text;
    EXPECT_EQ(Process({SABUS_BIN, "vectors", "lint", file.string()}).wait_exit(), 0) << text;
    EXPECT_EQ(Process({SABUS_BIN, "run", "--sim", "--fault", fault, "--vectors", file.string()}).wait_exit(), GetParam().run_exit) << text;
    EXPECT_EQ(Process({SABUS_BIN, "run", "--sim", "--vectors", file.string()}).wait_exit(), 0) << text;
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Faults, FuzzFindsFault,
                         ::testing::Values(Case{"nak-bad-check-byte", 1}, Case{"answers-foreign-address", 1},
                                           Case{"ignores-parity", 1}, Case{"drops-reply-byte", 1},
                                           Case{"silent-unknown-command", 1}, Case{"executes-overlong", 1},
                                           Case{"lrc-skips-byte0", 1}, Case{"reply-address-0x30", 1}),
                         [](const auto& info) {
                           std::string s = info.param.fault;
                           for (auto& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(Fuzz, NoFaultNoFindingAndUsageErrors) {
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-clean-" + std::to_string(getpid()));
  EXPECT_EQ(Process({SABUS_BIN, "fuzz", "--sim", "--seed", "2", "--max-frames", "2000", "--findings", dir.string()}).wait_exit(), 0);
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_EQ(Process({SABUS_BIN, "fuzz", "--sim", "--fault", "no-such-fault"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "fuzz", "--sim", "--port", "/dev/null"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "fuzz", "--port", "/nonexistent/tty"}).wait_exit(), 3);
}

}  // namespace
