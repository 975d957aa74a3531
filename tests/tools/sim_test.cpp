// `sabus sim` end to end: started as a process, reached through the serial
// transport over its pty (and over TCP), stopped with SIGINT.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "sabus/harness/line.hpp"
#include "process.hpp"
#include "temp_dir.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness {
namespace {

using test::Process;

using namespace std::chrono_literals;
namespace fs = std::filesystem;

struct Replies : ReceiverSink {
  std::vector<Frame> frames;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard&) override {}
};

// Sends a command with even parity in bit 7 and reads what comes back
// within `window`.
std::vector<Frame> talk(Line& line, ByteView command_chars, std::chrono::milliseconds window = 400ms) {
  line.write(add_even_parity(command_chars));
  Receiver rx(ReceiverOptions::master());
  Replies replies;
  std::uint8_t buf[256];
  const auto end = std::chrono::steady_clock::now() + window;
  while (std::chrono::steady_clock::now() < end) {
    const std::size_t n = line.read(buf, 20ms);
    rx.feed(ByteView(buf, n), replies);
    if (!replies.frames.empty() && n == 0) break;
  }
  return replies.frames;
}

std::string temp_path(const std::string& name) { return test::temp_path("sim", name); }

TEST(Sim, PtyStatusPollWriteReadRoundTripAndIgnoredBadLrc) {
  const std::string link = temp_path("pty");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  auto line = TermiosSerialLine::open(link, 9600);

  auto status = talk(*line, encode_request(StatusPoll{}, '2'));
  ASSERT_EQ(status.size(), 1u);
  EXPECT_EQ(encode_frame(status[0]).size(), 52u);
  ASSERT_TRUE(decode_reply(status[0]).ok());

  WriteSatellite w;
  w.index = 12;
  w.sat = {"TEST SAT", -1234, 5, '1', '0', 455};
  auto ack = talk(*line, encode_request(w, '2'));
  ASSERT_EQ(ack.size(), 1u);
  EXPECT_EQ(ack[0].kind, FrameKind::kAck);
  auto back = talk(*line, encode_request(ReadSatellite{{12}}, '2'));
  ASSERT_EQ(back.size(), 1u);
  auto sat = decode_reply(back[0]);
  ASSERT_TRUE(sat.ok());
  EXPECT_EQ(std::get<SatelliteDataReply>(sat.value()).sat, w.sat);

  Bytes bad = encode_request(StatusPoll{}, '2');
  bad.back() ^= 0x01;
  EXPECT_TRUE(talk(*line, bad, 300ms).empty()) << "a bad LRC is ignored";
  EXPECT_EQ(talk(*line, encode_request(DeviceTypeQuery{}, '2')).size(), 1u) << "and the controller lives";

  line.reset();
  EXPECT_EQ(sim.interrupt(), 0);
  EXPECT_FALSE(fs::exists(fs::symlink_status(link))) << "the link is removed on exit";
}

TEST(Sim, MultiDropAnswersOnlyTheAddressedController) {
  const std::string link = temp_path("bus");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--address", "50,51,60"});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  auto line = TermiosSerialLine::open(link, 9600);
  for (std::uint8_t a : {'2', '3', '<'}) {
    auto r = talk(*line, encode_request(DeviceTypeQuery{}, a));
    ASSERT_EQ(r.size(), 1u) << a;
    EXPECT_EQ(r[0].address, a);
  }
  EXPECT_TRUE(talk(*line, encode_request(DeviceTypeQuery{}, '4'), 300ms).empty());
  line.reset();
  EXPECT_EQ(sim.interrupt(), 0);
}

TEST(Sim, TcpAndTheStateFileSurviveARestart) {
  const std::string state = temp_path("state.json");
  fs::remove(state);
  {
    Process sim({SABUS_BIN, "sim", "--tcp", "127.0.0.1:0", "--state-file", state});
    const std::string ready = sim.line(5s);
    ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
    const auto port = static_cast<std::uint16_t>(std::stoi(ready.substr(ready.rfind(':') + 1)));
    auto line = TcpLine::connect("127.0.0.1", port, 2s);
    ASSERT_EQ(talk(*line, encode_request(WriteNavigation{1234, -7530, 1234, ""}, '2')).size(), 1u);
    line.reset();
    EXPECT_EQ(sim.interrupt(), 0);
  }
  ASSERT_TRUE(fs::exists(state));
  Process again({SABUS_BIN, "sim", "--tcp", "127.0.0.1:0", "--state-file", state});
  const std::string ready = again.line(5s);
  const auto port = static_cast<std::uint16_t>(std::stoi(ready.substr(ready.rfind(':') + 1)));
  auto line = TcpLine::connect("127.0.0.1", port, 2s);
  auto nav = talk(*line, encode_request(NavigationQuery{}, '2'));
  ASSERT_EQ(nav.size(), 1u);
  EXPECT_EQ(std::get<NavigationDataReply>(decode_reply(nav[0]).value()).latitude, 12 * 60 + 34);
  auto name = talk(*line, encode_request(QueryName{{1}}, '2'));
  ASSERT_EQ(name.size(), 1u);
  EXPECT_EQ(name[0].kind, FrameKind::kNak) << "the STORE list stayed deleted";
  line.reset();
  EXPECT_EQ(again.interrupt(), 0);
  fs::remove(state);
}

TEST(Sim, EmulatedLineTakesTheWireTime) {
  const std::string link = temp_path("slow");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--emulate-line"});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  auto line = TermiosSerialLine::open(link, 9600);
  const auto start = std::chrono::steady_clock::now();
  auto r = talk(*line, encode_request(StatusPoll{}, '2'), 1000ms);
  const auto took = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.size(), 1u);
  // 5 bytes out and 52 back at 10 bit times each: at least 59.4 ms at 9600 baud.
  EXPECT_GE(took, 57 * 10 * 1000.0 / 9600);
  std::printf("status poll round trip on an emulated 9600-baud line: %.1f ms\n", took);
  line.reset();
  EXPECT_EQ(sim.interrupt(), 0);
}

// The profile's turnaround_ms is the device's reply turnaround: with
// --emulate-line the first reply byte comes no sooner.
TEST(Sim, EmulatedLineWaitsTheProfilesTurnaround) {
  const std::string profile = temp_path("slow.yaml");
  std::ofstream(profile) << "turnaround_ms: 400\n";
  const std::string link = temp_path("turnaround");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--emulate-line", "--profile", profile});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  auto line = TermiosSerialLine::open(link, 9600);
  const auto start = std::chrono::steady_clock::now();
  auto r = talk(*line, encode_request(DeviceTypeQuery{}, '2'), 2000ms);
  const auto took = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_GE(took, 400.0) << "the reply came before the profile's 400 ms turnaround";
  std::printf("device type round trip with a 400 ms turnaround: %.1f ms\n", took);
  line.reset();
  EXPECT_EQ(sim.interrupt(), 0);
  fs::remove(profile);
}

// A master set to 8N1 sends its characters without the parity bit: the log
// names the bytes parity errors and says once what to check.
TEST(Sim, LogNamesParityErrorsAndHintsAt7E1) {
  const std::string log = temp_path("parity.log");
  fs::remove(log);
  const std::string link = temp_path("parity");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--log", log});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  auto line = TermiosSerialLine::open(link, 9600);
  for (int i = 0; i < 10; ++i) line->write(encode_request(StatusPoll{}, '2'));  // no parity bit
  EXPECT_EQ(talk(*line, encode_request(DeviceTypeQuery{}, '2')).size(), 1u) << "a 7E1 frame is still answered";
  line.reset();
  EXPECT_EQ(sim.interrupt(), 0);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("parity error: 0x02 (STX)"), std::string::npos) << text;
  EXPECT_EQ(text.find("unknown bytes: 0x02"), std::string::npos) << text;
  const auto hint = text.find("is the master set to 7E1?");
  EXPECT_NE(hint, std::string::npos) << text;
  EXPECT_EQ(text.find("is the master set to 7E1?", hint + 1), std::string::npos) << text;
  fs::remove(log);
}

TEST(Sim, UsageErrorsExit2) {
  EXPECT_EQ(Process({SABUS_BIN, "sim", "--pty", "--link", temp_path("x"), "--fault", "no-such-fault"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "sim", "--pty", "--link", temp_path("y"), "--profile", "/nonexistent.yaml"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "sim"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "sim", "--tcp", "127.0.0.1:port"}).wait_exit(), 2);
  const std::string bad = temp_path("bad.yaml");
  std::ofstream(bad) << "address: 50\nnot_a_key: 1\n";
  EXPECT_EQ(Process({SABUS_BIN, "sim", "--pty", "--link", temp_path("z"), "--profile", bad}).wait_exit(), 2);
  fs::remove(bad);
}

// A second simulator on the link of a running one is refused: the first
// keeps its link and its clients, and removes the link when it stops.
TEST(Sim, ASecondSimDoesNotTakeOverALiveLink) {
  const std::string link = temp_path("live");
  Process first({SABUS_BIN, "sim", "--pty", "--link", link});
  ASSERT_EQ(first.line(5s), "READY " + link);
  const fs::path target = fs::read_symlink(link);
  auto client = TermiosSerialLine::open(link, 9600);

  const auto second = test::shell(std::string(SABUS_BIN) + " sim --pty --link " + link + " 2>&1");
  EXPECT_EQ(second.status, 1);
  EXPECT_NE(second.out.find("pty link " + link + " points to " + target.string() +
                            ", a pseudo-terminal in use (another sabus sim or proxy serves it); refusing to take it over"),
            std::string::npos)
      << second.out;
  EXPECT_EQ(second.out.find("READY"), std::string::npos) << second.out;
  ASSERT_TRUE(fs::is_symlink(fs::symlink_status(link))) << "the second one left the link alone on exit";
  EXPECT_EQ(fs::read_symlink(link), target);
  EXPECT_EQ(talk(*client, encode_request(DeviceTypeQuery{}, '2')).size(), 1u) << "the first one still serves its client";

  client.reset();
  EXPECT_EQ(first.interrupt(), 0);
  EXPECT_FALSE(fs::exists(fs::symlink_status(link))) << "the first one removes its own link";
}

// Only a link to nothing (left by a simulator that died) is replaced; a
// link to anything else, and any other file, stays as it is.
TEST(Sim, ALinkToAFileOrAFileIsLeftAloneAndAStaleLinkReplaced) {
  const std::string file = temp_path("a-file");
  std::ofstream(file) << "keep";
  const std::string to_file = temp_path("to-file");
  fs::create_symlink(file, to_file);
  const auto refused = test::shell(std::string(SABUS_BIN) + " sim --pty --link " + to_file + " 2>&1");
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.out.find("points to " + file + ", which is not a pseudo-terminal; refusing to replace it"),
            std::string::npos)
      << refused.out;
  EXPECT_EQ(fs::read_symlink(to_file), file);
  const auto regular = test::shell(std::string(SABUS_BIN) + " sim --pty --link " + file + " 2>&1");
  EXPECT_EQ(regular.status, 1);
  EXPECT_NE(regular.out.find("exists and is not a symbolic link; refusing to replace it"), std::string::npos) << regular.out;
  std::ifstream in(file);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "keep");
  fs::remove(to_file);
  fs::remove(file);

  const std::string stale = temp_path("stale");
  fs::create_symlink("/dev/pts/no-such-pty", stale);
  Process sim({SABUS_BIN, "sim", "--pty", "--link", stale});
  ASSERT_EQ(sim.line(5s), "READY " + stale);
  EXPECT_TRUE(is_pseudo_terminal(stale));
  EXPECT_EQ(sim.interrupt(), 0);
  EXPECT_FALSE(fs::exists(fs::symlink_status(stale)));
}

TEST(Sim, ListFaults) {
  Process p({SABUS_BIN, "sim", "--list-faults"});
  EXPECT_EQ(p.line(5s).rfind("lrc-skips-byte0", 0), 0u);
  EXPECT_EQ(p.wait_exit(), 0);
}

}  // namespace
}  // namespace sabus::harness
