// `sabus fuzz` as a process: with an injected fault, a fixed seed and a fixed
// budget it finds the fault, and its minimized reproducer fails under
// `sabus run` with the fault and passes without it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "process.hpp"
#include "yaml_text.hpp"

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
// `kind`: the finding kind expected first (the lockstep oracle's: nak-rule,
// value, effect), nullptr for any; `allow`: the session and the runs with
// --allow-motion --allow-destructive.
struct Case {
  const char* fault;
  int run_exit;
  const char* kind = nullptr;
  bool allow = false;
  const char* frames = nullptr;  // --max-frames (default 500; 3000 with `allow`)
};

class FuzzFindsFault : public ::testing::TestWithParam<Case> {};

TEST_P(FuzzFindsFault, AndItsReproducerFailsUnderRun) {
  const std::string fault = GetParam().fault;
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-" + fault + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const bool allow = GetParam().allow;
  auto with_allow = [allow](std::vector<std::string> args) {
    if (allow) args.insert(args.end(), {"--allow-motion", "--allow-destructive"});
    return args;
  };
  Process fuzz(with_allow({SABUS_BIN, "fuzz", "--sim", "--fault", fault, "--seed", "1", "--max-frames",
                           GetParam().frames ? GetParam().frames : allow ? "3000" : "500",
                           "--findings", dir.string()}));
  EXPECT_EQ(fuzz.wait_exit(), 1);
  std::vector<fs::path> files;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  ASSERT_FALSE(files.empty()) << "no finding written for " << fault;
  std::sort(files.begin(), files.end());
  if (GetParam().kind) {  // the first finding: fuzz-1-1-KIND.yaml
    EXPECT_EQ(files.front().filename().string(), "fuzz-1-1-" + std::string(GetParam().kind) + ".yaml");
  }
  for (const fs::path& file : files) {
    const std::string text = read_file(file);
    EXPECT_NE(text.find("--seed 1"), std::string::npos) << text;
    EXPECT_NE(text.find("paragraph: framing"), std::string::npos) << text;
    EXPECT_EQ(Process({SABUS_BIN, "vectors", "lint", file.string()}).wait_exit(), 0) << text;
    EXPECT_EQ(Process(with_allow({SABUS_BIN, "run", "--sim", "--fault", fault, "--vectors", file.string()})).wait_exit(),
              GetParam().run_exit)
        << text;
    EXPECT_EQ(Process(with_allow({SABUS_BIN, "run", "--sim", "--vectors", file.string()})).wait_exit(), 0) << text;
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Faults, FuzzFindsFault,
                         ::testing::Values(Case{"nak-bad-check-byte", 1}, Case{"answers-foreign-address", 1},
                                           Case{"ignores-parity", 1}, Case{"drops-reply-byte", 1},
                                           Case{"silent-unknown-command", 1}, Case{"executes-overlong", 1},
                                           Case{"lrc-skips-byte0", 1}, Case{"reply-address-0x30", 1},
                                           // The lockstep oracle's (issue 24): a reply in form, its
                                           // value or the rule behind it wrong.
                                           Case{"store-count-off-by-one", 1, "value"},
                                           Case{"query-name-zero-based", 1, "value"},
                                           // The mode a session starts in is the device's
                                           // (Session::synchronize): a mode it enters shows it.
                                           Case{"mode-enum-off-by-one", 1, "value", true},
                                           Case{"empty-slot-zeros", 1, "value"},
                                           Case{"extended-status-speed-bit", 1, "effect"},
                                           // 46h is held back while the STORE list is young
                                           // (the generator's kStoreKeptFor).
                                           Case{"write-nav-keeps-store", 1, "nak-rule", true, "5000"},
                                           // A search stopped while it moved (E-90), its
                                           // reproducer waiting for the search to run.
                                           Case{"search-stop-exit-no-peak", 1, "value", true, "40000"}),
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

// The lockstep oracle on every shipped profile, motion and stored writes
// allowed: no finding on the reference controller, and the summary says
// what it reached (issue 24).
TEST(Fuzz, EveryShippedProfileGivesNoFindingInLockstep) {
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-profiles-" + std::to_string(getpid()));
  std::size_t profiles = 0;
  for (const auto& e : fs::directory_iterator(fs::path(SABUS_SOURCE_DIR) / "vectors" / "profiles")) {
    if (e.path().extension() != ".yaml") continue;
    ++profiles;
    const auto r = sabus::test::shell("'" SABUS_BIN "' fuzz --sim --profile '" + e.path().string() +
                                      "' --seed 1 --max-frames 4000 --allow-motion --allow-destructive --findings '" +
                                      dir.string() + "' 2>&1");
    EXPECT_EQ(r.status, 0) << e.path() << "\n" << r.out;
    EXPECT_NE(r.out.find("\n0 finding(s)\n"), std::string::npos) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex("\nlockstep: [0-9]+ of 43 NAK rules fired on the device.*; [0-9]+ of "
                                                    "[0-9]+ reply fields compared; [0-9]+ resync\\(s\\)\n")))
        << r.out;
  }
  EXPECT_GE(profiles, 13u);
  EXPECT_FALSE(fs::exists(dir));
}

// Over a pty (sabus sim --pty, the device's clock real time), a few seconds of
// lockstep fuzzing with motion and stored writes: no finding.
TEST(Fuzz, OverAPtyTheLockstepOracleGivesNoFinding) {
  using namespace std::chrono_literals;
  const std::string link = (fs::temp_directory_path() / ("sabus-fuzz-lockstep-pty-" + std::to_string(getpid()))).string();
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-pty-" + std::to_string(getpid()));
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const auto r = sabus::test::shell("'" SABUS_BIN "' fuzz --port '" + link +
                                    "' --pace 0 --seed 3 --max-time 4 --allow-motion --allow-destructive --findings '" +
                                    dir.string() + "' 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\n0 finding(s)\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nlockstep: "), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_EQ(sim.interrupt(), 0);
}

// A session with no limit ends by a signal: SIGINT and SIGTERM stop it with
// the code of a stopped run (4), its totals printed, no finding written.
TEST(Fuzz, ASignalStopsAnEndlessSessionWithItsOwnExitCode) {
  using namespace std::chrono_literals;
  for (const int signal : {SIGINT, SIGTERM}) {
    const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-stopped-" + std::to_string(getpid()));
    Process fuzz({SABUS_BIN, "fuzz", "--sim", "--seed", "2", "--findings", dir.string()});
    ASSERT_EQ(fuzz.line(5s).rfind("sabus fuzz: in-process reference controller", 0), 0u);
    std::this_thread::sleep_for(300ms);  // some writes
    EXPECT_EQ(fuzz.stop_with(signal), 4) << signal;
    const std::string out = fuzz.read_all(5s);
    EXPECT_NE(out.find(signal == SIGINT ? "ABORTED: stopped by SIGINT\n" : "ABORTED: stopped by SIGTERM\n"), std::string::npos) << out;
    EXPECT_NE(out.find("\n0 finding(s)\n"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir));
  }
}

// ---- the finding files: new files, each written or said not to be -----------------------

// `sabus fuzz --sim --fault ignores-parity --seed 1` in `dir` (its one
// finding), with any other options; stdout and stderr, and the exit status.
sabus::test::ShellResult fuzz_in(const fs::path& dir, const std::string& before = "", const std::string& options = "") {
  return sabus::test::shell(before + "'" SABUS_BIN "' fuzz --sim --fault ignores-parity --seed 1 --max-frames 500 --findings '" +
                            dir.string() + "' " + options + " 2>&1");
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzFindingFiles, AFileAtTheNameIsNeverReplacedNorFollowed) {
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-files-" + std::to_string(getpid()));
  fs::remove_all(dir);
  ASSERT_EQ(fuzz_in(dir).status, 1);
  const auto first = files_in(dir);
  ASSERT_EQ(first.size(), 1u);
  const fs::path name = first[0];  // fuzz-1-1-KIND.yaml
  const fs::path second = dir / (name.stem().string() + "-2.yaml"), third = dir / (name.stem().string() + "-3.yaml");
  // An earlier finding kept by hand, and a link planted at the next name.
  { std::ofstream(name) << "# kept by hand\n"; }
  fs::create_symlink("/dev/full", second);
  const auto r = fuzz_in(dir);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_EQ(read_file(name), "# kept by hand\n");
  EXPECT_TRUE(fs::is_symlink(second));
  ASSERT_TRUE(fs::exists(third)) << r.out;
  EXPECT_NE(r.out.find(third.string()), std::string::npos) << r.out;
  EXPECT_EQ(Process({SABUS_BIN, "vectors", "lint", third.string()}).wait_exit(), 0) << read_file(third);
  fs::remove_all(dir);
}

TEST(FuzzFindingFiles, AFindingThatCannotBeWrittenIsSaidToBeAndTheRunGoesOn) {
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-unwritable-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A folder that cannot be made: it was an uncaught exception (exit by abort).
  { std::ofstream(dir / "a-file") << "x"; }
  auto r = fuzz_in(dir / "a-file" / "findings");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("sabus fuzz: the finding is not written: cannot create the folder"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 finding(s)\n  (not written) "), std::string::npos) << r.out;
  // A write that fails (no file may grow past 0 bytes): said, and no file left.
  r = fuzz_in(dir / "findings", "ulimit -f 0; trap '' XFSZ; ");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("write failed: File too large"), std::string::npos) << r.out;
  EXPECT_TRUE(files_in(dir / "findings").empty());
  fs::remove_all(dir);
}

// The command line in the finding's comment holds what a person typed: a
// profile path with a line break made the rest of it YAML.
TEST(FuzzFindingFiles, ACommandLineWithALineBreakStaysInTheComment) {
  const fs::path dir = fs::temp_directory_path() / ("sabus-fuzz-test-argv-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const fs::path profile = dir / "profiles\nparagraph: x\r" / "rc3000.yaml";
  fs::create_directories(profile.parent_path());
  fs::copy_file(SABUS_SOURCE_DIR "/vectors/profiles/rc3000-1.59.yaml", profile);
  const auto r = fuzz_in(dir / "findings", "", "--profile '" + profile.string() + "'");
  EXPECT_EQ(r.status, 1) << r.out;
  const auto files = files_in(dir / "findings");
  ASSERT_EQ(files.size(), 1u) << r.out;
  const std::string text = read_file(files[0]);
  EXPECT_EQ(sabus::test::yaml_text_problem(text), "") << text;
  EXPECT_NE(text.find("--profile " + (dir / "profiles").string() + "\n# paragraph: x\\x0d/rc3000.yaml"), std::string::npos) << text;
  EXPECT_EQ(Process({SABUS_BIN, "vectors", "lint", files[0].string()}).wait_exit(), 0) << text;
  fs::remove_all(dir);
}

}  // namespace
