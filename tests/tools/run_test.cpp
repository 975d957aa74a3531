// `sabus run` end to end: against `sabus sim --pty --emulate-line` through the
// serial transport, against `sabus sim --tcp`, and in-process with a fault.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "process.hpp"

namespace sabus::harness {
namespace {

using test::Process;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("sabus-run-test-" + std::to_string(getpid()) + "-" + name)).string();
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return nlohmann::json::parse(ss.str());
}

const std::string kVectors = std::string(SABUS_SOURCE_DIR) + "/vectors/framing.yaml";

TEST(Run, OverAPtyWithAnEmulatedLine) {
  const std::string link = temp_path("pty");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--emulate-line"});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const std::string json = temp_path("pty.json");
  Process run({SABUS_BIN, "run", "--port", link, "--vectors", kVectors, "--pace", "0", "--json", json});
  EXPECT_EQ(run.wait_exit(), 0);
  const auto doc = read_json(json);
  EXPECT_EQ(doc["status"], "complete");
  EXPECT_GT(doc["summary"]["passed"].get<int>(), 0);
  EXPECT_EQ(doc["summary"]["failed"].get<int>(), 0);
  EXPECT_NE(doc["device"].get<std::string>().find("termios"), std::string::npos) << "a pty takes the termios backend";
  EXPECT_EQ(sim.interrupt(), 0);
  fs::remove(json);
}

// A controller whose replies take 300 ms (the profile's turnaround_ms, which
// `sabus sim --emulate-line` applies): the runner waits for them from the
// first command on, and a silence window lasts longer than the turnaround,
// so no reply spills into the next step.
TEST(Run, ASlowControllerWithinItsStatedTurnaround) {
  const std::string profile = temp_path("slow.yaml");
  {
    std::ofstream out(profile);
    out << "name: slow\nturnaround_ms: 300\n";
  }
  const std::string link = temp_path("slow-pty");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--emulate-line", "--profile", profile});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const std::string json = temp_path("slow.json");
  Process run({SABUS_BIN, "run", "--port", link, "--profile", profile, "--vectors", kVectors, "--filter",
               "framing-*-silence", "--filter", "framing-check-byte-*", "--pace", "0", "--json", json});
  EXPECT_EQ(run.wait_exit_for(60s), 0);
  const auto doc = read_json(json);
  EXPECT_GT(doc["summary"]["passed"].get<int>(), 3);
  EXPECT_EQ(doc["summary"]["failed"].get<int>(), 0);
  EXPECT_EQ(sim.interrupt(), 0);
  fs::remove(json);
  fs::remove(profile);
}

TEST(Run, OverTcp) {
  Process sim({SABUS_BIN, "sim", "--tcp", "127.0.0.1:0"});
  const std::string ready = sim.line(5s);
  ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
  const std::string port = ready.substr(ready.rfind(':') + 1);
  Process run({SABUS_BIN, "run", "--tcp", "127.0.0.1:" + port, "--vectors", kVectors, "--pace", "0"});
  EXPECT_EQ(run.wait_exit(), 0);
  EXPECT_EQ(sim.interrupt(), 0);
}

TEST(Run, InProcessWithAFaultFailsAndWritesJUnit) {
  const std::string junit = temp_path("junit.xml");
  Process run({SABUS_BIN, "run", "--sim", "--fault", "short-status", "--junit", junit});
  EXPECT_EQ(run.wait_exit(), 1);
  std::ifstream in(junit);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("<testsuite name=\"§"), std::string::npos);
  EXPECT_NE(ss.str().find("<failure message="), std::string::npos);
  fs::remove(junit);
}

TEST(Run, UnreachableDeviceExits3AndUsageExits2) {
  // A device that answers some frames is reachable: its failures exit 1.
  EXPECT_EQ(Process({SABUS_BIN, "run", "--sim", "--fault", "check-byte-stx-restarts"}).wait_exit(), 1);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--port", "/nonexistent/tty"}).wait_exit(), 3);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--level", "sometimes"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--sim", "--fault", "no-such-fault"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--tcp", "127.0.0.1:abc"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--tcp", "127.0.0.1:70000"}).wait_exit(), 2);
}

}  // namespace
}  // namespace sabus::harness
