// What the commands say while they run, as a user at a terminal and a CI
// log see it: on a terminal a progress line, failures in colour (none with
// NO_COLOR), every vector with -v; piped, one verdict line per vector as it
// finishes; -q only failures and the summary; the serial-backend notice only
// with -v; `sabus fuzz` progress and traffic figures; `sabus vectors list`
// previewing a selection.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <fstream>
#include <poll.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <filesystem>
#include <regex>

#include "process.hpp"
#include "shipped_suite.hpp"

namespace sabus::test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

const std::string kSabus = SABUS_BIN;

// A command run with its standard output and error on a pseudo-terminal, as
// at a user's terminal: everything it wrote (the terminal raw, so bytes come
// as written) and its exit status.
struct TerminalRun {
  int status = -1;
  std::string out;
};
TerminalRun on_terminal(std::vector<std::string> args, const std::vector<std::pair<std::string, std::string>>& env = {}) {
  TerminalRun r;
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) return r;
  const std::string slave_name = ::ptsname(master);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setsid();
    const int slave = ::open(slave_name.c_str(), O_RDWR);
    termios t{};
    ::tcgetattr(slave, &t);
    ::cfmakeraw(&t);
    ::tcsetattr(slave, TCSANOW, &t);
    ::dup2(slave, STDOUT_FILENO);
    ::dup2(slave, STDERR_FILENO);
    ::close(slave);
    ::close(master);
    ::unsetenv("NO_COLOR");
    ::setenv("TERM", "xterm", 1);
    for (const auto& [name, value] : env) ::setenv(name.c_str(), value.c_str(), 1);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  char buf[4096];
  const auto end = std::chrono::steady_clock::now() + 120s;
  while (std::chrono::steady_clock::now() < end) {
    pollfd p{master, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    const ssize_t n = ::read(master, buf, sizeof buf);
    if (n <= 0) break;  // EIO: the child and everything it started closed the terminal
    r.out.append(buf, static_cast<std::size_t>(n));
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(master);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}


// ---- sabus run ---------------------------------------------------------------

TEST(Console, OnATerminalAProgressLineAndTheFailuresInColour) {
  const auto r = on_terminal({kSabus, "run", "--fault", "short-status", "--paragraph", "3.2"});
  EXPECT_EQ(r.status, 1);
  // "[ 3/22] 0 pass 3 fail 0 skip  0:00 elapsed ..." rewritten in place.
  const std::string n = std::to_string(shipped_vectors_in(SABUS_SOURCE_DIR, "3.2-status.yaml", "3.2-"));
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\r\033\\[K\\[" + n + "/" + n + "\\] \\d+ pass \\d+ fail \\d+ skip  0:0\\d elapsed")))
      << r.out;
  EXPECT_NE(r.out.find("\033[1;31mFAIL\033[0m 3.2-status-reply-length §3.2 must: reply does not decode"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("PASS "), std::string::npos) << "passes only count in the progress line";
  EXPECT_NE(r.out.find("device: controller 3K, firmware 1.59\n"), std::string::npos) << r.out;
}

TEST(Console, NoColourWithNoColorAndEveryVectorWithVerbose) {
  const auto plain = on_terminal({kSabus, "run", "--fault", "short-status", "--paragraph", "3.2"}, {{"NO_COLOR", "1"}});
  EXPECT_EQ(plain.out.find("\033[1;31m"), std::string::npos) << plain.out;
  EXPECT_NE(plain.out.find("FAIL 3.2-status-reply-length §3.2 must: "), std::string::npos) << plain.out;
  const auto every = on_terminal({kSabus, "run", "-v", "--paragraph", "3.2"});
  EXPECT_EQ(every.status, 0);
  EXPECT_NE(every.out.find("\033[32mPASS\033[0m 3.2-status-reply-length §3.2 must\n"), std::string::npos) << every.out;
  EXPECT_NE(every.out.find("\033[33mSKIP\033[0m "), std::string::npos) << every.out;
}

TEST(Console, QuietSaysOnlyTheFailuresAndTheSummary) {
  const auto piped = shell(kSabus + " run -q --fault short-status --paragraph 3.2 2>&1");
  EXPECT_EQ(piped.status, 1);
  std::istringstream lines(piped.out);
  std::vector<std::string> all;
  for (std::string l; std::getline(lines, l);) all.push_back(l);
  ASSERT_GE(all.size(), 2u);
  for (std::size_t i = 0; i + 1 < all.size(); ++i) EXPECT_EQ(all[i].rfind("FAIL ", 0), 0u) << all[i];
  EXPECT_TRUE(std::regex_match(all.back(), std::regex(R"(\d+ passed, \d+ failed, \d+ skipped.*)"))) << all.back();
  const auto tty = on_terminal({kSabus, "run", "-q", "--paragraph", "3.2"});
  EXPECT_EQ(tty.out.find("\r"), std::string::npos) << "no progress line: " << tty.out;
  EXPECT_TRUE(std::regex_match(tty.out, std::regex(R"(\d+ passed, 0 failed, \d+ skipped \(.*\)\n)"))) << tty.out;
}

// Piped, as in CI: one line a vector, written as it finishes (not when the
// run ends), with the failure's reason or the skip's.
TEST(Console, PipedEachVectorsVerdictIsALineAsItFinishes) {
  Process sim({kSabus, "sim", "--tcp", "127.0.0.1:0"});
  const std::string ready = sim.line(5s);
  ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
  Process run({kSabus, "run", "--tcp", "127.0.0.1:" + ready.substr(ready.rfind(':') + 1), "--paragraph", "3.1", "--pace", "400"});
  EXPECT_EQ(run.line(10s), "device: controller 3K, firmware 1.59");
  EXPECT_EQ(run.line(10s), "PASS 3.1-device-type-reply-length §3.1 must");
  EXPECT_EQ(run.wait_exit_for(0ms), -1) << "the first verdict came while the run went on";
  const std::string rest = run.read_all(60s);
  EXPECT_NE(rest.find("SKIP 3.1-device-type-keeps-mode §3.1 should: moves the antenna: needs --allow-motion\n"),
            std::string::npos)
      << rest;
  EXPECT_EQ(run.wait_exit(), 0);
  EXPECT_EQ(sim.interrupt(), 0);
}

// "serial backend termios: ... libserialport 0.1.1 cannot open" is how the
// port was opened, not an error: said with -v only.
TEST(Console, TheSerialBackendNoticeOnlyWithVerbose) {
  const std::string link = (fs::temp_directory_path() / ("sabus-console-test-" + std::to_string(getpid()))).string();
  Process sim({kSabus, "sim", "--pty", "--link", link});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const std::string run = kSabus + " run --port " + link + " --filter 3.1-device-type-reply-length --pace 0";
  const auto normal = shell(run + " 2>&1");
  EXPECT_EQ(normal.status, 0) << normal.out;
  EXPECT_EQ(normal.out.find("serial backend"), std::string::npos) << normal.out;
  const auto verbose = shell(run + " -v 2>&1");
  EXPECT_NE(verbose.out.find("sabus run: serial backend termios: " + link +
                             " is a pseudo-terminal, which libserialport 0.1.1 cannot open."),
            std::string::npos)
      << verbose.out;
  EXPECT_EQ(sim.interrupt(), 0);
}

// ---- sabus vectors list ------------------------------------------------------

TEST(Console, VectorsListPreviewsASelection) {
  const std::size_t paragraph_3_2 = shipped_vectors_in(SABUS_SOURCE_DIR, "3.2-status.yaml", "3.2-");
  const auto exact = shell(kSabus + " vectors list --paragraph 3.2 2>&1");
  EXPECT_EQ(exact.status, 0);
  EXPECT_EQ(count(exact.out, " §3.2 "), paragraph_3_2) << exact.out;
  EXPECT_EQ(count(exact.out, " §3.20 "), 0u);
  EXPECT_TRUE(std::regex_search(exact.out, std::regex("\n" + std::to_string(paragraph_3_2) + " of [1-9][0-9]* vectors selected\n"))) << exact.out;
  const fs::path stderr_file = fs::temp_directory_path() / ("sabus-console-list-" + std::to_string(getpid()) + ".txt");
  const auto glob = shell(kSabus + " vectors list --filter '3.2*' 2>" + stderr_file.string());
  EXPECT_EQ(count(glob.out, " §3.2 "), paragraph_3_2) << glob.out;
  EXPECT_GT(count(glob.out, " §3.20 "), 0u) << "the glob takes §3.20 too: " << glob.out;
  const auto notes = shell("cat " + stderr_file.string());
  fs::remove(stderr_file);
  EXPECT_NE(notes.out.find("sabus vectors list: --filter '3.2*' matches vectors of 7 paragraphs (§3.2, §3.20, §3.21, §3.22, "
                           "§3.23, §3.24, §3.25); --paragraph 3.2 selects §3.2 alone\n"),
            std::string::npos)
      << notes.out;
  const auto none = shell(kSabus + " vectors list --filter '3.2-stauts*' 2>&1");
  EXPECT_EQ(none.status, 5);
  EXPECT_TRUE(std::regex_search(
      none.out, std::regex(R"(\n0 of [1-9][0-9]* vectors selected\nsabus vectors list: no vector matches --filter '3\.2-stauts\*'\n)")))
      << none.out;
  const auto exclude = shell(kSabus + " vectors list --paragraph 3.1 --exclude '*-keeps-mode' 2>/dev/null");
  EXPECT_EQ(count(exclude.out, "\n"), 5u) << exclude.out;
}

// ---- sabus fuzz --------------------------------------------------------------

// Piped, the fuzzer says how far it got at least every 10 s.
TEST(Console, FuzzProgressAtLeastEveryTenSeconds) {
  const auto r = shell(kSabus + " fuzz --sim --seed 3 --max-time 11.5 --findings " +
                       (fs::temp_directory_path() / "sabus-console-fuzz").string());
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\nfuzz: \\d+ writes, 0 finding\\(s\\), 0:1\\d elapsed\n"))) << r.out;
  EXPECT_EQ(r.out.find('\r'), std::string::npos);
}

// A pseudo-terminal carries bytes at once whatever its baud rate: no
// line-busy percentage there, the wire time the bytes would take instead.
TEST(Console, FuzzOnAPtyGivesNoLineBusyFigure) {
  const std::string link = (fs::temp_directory_path() / ("sabus-console-fuzz-" + std::to_string(getpid()))).string();
  Process sim({kSabus, "sim", "--pty", "--link", link});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const auto r = shell(kSabus + " fuzz --port " + link + " --pace 0 --seed 1 --max-frames 60 --findings " +
                       (fs::temp_directory_path() / "sabus-console-fuzz").string());
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\ntraffic: bytes_sent=\\d+ bytes_received=\\d+ wall_s=[0-9.]+ baud=9600 "
                                                  "wire_s=[0-9.]+ \\(at that baud rate; a pseudo-terminal has none, so no "
                                                  "line_busy\\)\n")))
      << r.out;
  EXPECT_EQ(r.out.find("line_busy="), std::string::npos) << r.out;
  EXPECT_EQ(sim.interrupt(), 0);
}

}  // namespace
}  // namespace sabus::test
