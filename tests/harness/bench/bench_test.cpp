// The bench workflow end to end: `sabus proxy` between a client and
// `sabus sim`, its log, `sabus record` of the log and of a run JSON, `sabus
// run` of the recording (passing against the same controller, failing
// against one with a fault), and `sabus decode` of both capture formats.
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include "sabus/harness/capture.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/harness/recording.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/receiver.hpp"
#include "sabus/protocol/structured.hpp"
#include "process.hpp"
#include "proxy_log_check.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"
#include "yaml_text.hpp"

namespace sabus::harness {
namespace {

using test::hex;
using test::Process;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

std::string temp_path(const std::string& name) { return test::temp_path("bench", name); }

// Writes a request (parity in bit 7) and returns the wire bytes that came
// back until a reply frame is complete and the line is quiet.
Bytes ask(Line& line, ByteView chars) {
  line.write(add_even_parity(chars));
  struct Count : ReceiverSink {
    int frames = 0;
    void on_frame(const FrameView&) override { ++frames; }
    void on_discard(const Discard&) override {}
  } count;
  Receiver rx(ReceiverOptions::master());
  Bytes wire;
  std::uint8_t buf[512];
  const auto end = std::chrono::steady_clock::now() + 2s;
  while (std::chrono::steady_clock::now() < end) {
    const std::size_t n = line.read(buf, 50ms);
    wire.insert(wire.end(), buf, buf + n);
    rx.feed(ByteView(buf, n), count);
    if (count.frames > 0 && n == 0) break;
  }
  return wire;
}

Bytes strip_parity_for_test(const Bytes& wire) {
  Bytes out;
  for (auto b : wire) out.push_back(b & 0x7F);
  return out;
}

std::vector<nlohmann::json> read_log(const std::string& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> out;
  for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
  return out;
}

// The proxy log's problems as tools/PROXY-LOG.md documents it
// (proxy_log_check.hpp), one a line; "" for a log as documented.
std::string log_problems(const std::string& text) {
  static const test::ProxyLogSpec spec = test::read_proxy_log_spec(test::slurp(SABUS_SOURCE_DIR "/tools/PROXY-LOG.md"));
  std::string out;
  for (const auto& p : test::proxy_log_problems(text, spec)) out += p + "\n";
  return out;
}

// Waits up to 5 s for the log to hold `text` `count` times (the proxy writes
// it as it reads); the count found.
int wait_for_log(const std::string& path, const std::string& text, int count = 1) {
  int found = 0;
  for (auto end = std::chrono::steady_clock::now() + 5s; std::chrono::steady_clock::now() < end; std::this_thread::sleep_for(10ms)) {
    const std::string log = test::slurp(path);
    found = 0;
    for (auto at = log.find(text); at != std::string::npos; at = log.find(text, at + 1)) ++found;
    if (found >= count) break;
  }
  return found;
}

int run_sabus(std::vector<std::string> args, std::string* output = nullptr) {
  args.insert(args.begin(), SABUS_BIN);
  Process p(args);
  std::string out = p.read_all(60s);
  if (output) *output = out;
  return p.wait_exit_for(10s);
}

// A proxy session against `sabus sim`: a status poll and a device type
// query from a client on the proxy's pty. Returns the log's path.
struct Session {
  std::string log = temp_path("proxy.jsonl");
  Bytes direct_status, proxied_status, proxied_type;
  int proxy_exit = -1;
};

Session proxy_session() {
  Session s;
  const std::string a = temp_path("dev"), b = temp_path("mc");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", a});
  EXPECT_EQ(sim.line(5s), "READY " + a);
  {
    auto direct = TermiosSerialLine::open(a, 9600);
    s.direct_status = ask(*direct, encode_request(StatusPoll{}, '2'));
  }
  Process proxy({SABUS_BIN, "proxy", "--listen-pty", b, "--port", a, "--log", s.log});
  EXPECT_EQ(proxy.line(5s), "READY " + b);
  {
    auto client = TermiosSerialLine::open(b, 9600);
    s.proxied_status = ask(*client, encode_request(StatusPoll{}, '2'));
    s.proxied_type = ask(*client, encode_request(DeviceTypeQuery{}, '2'));
  }
  s.proxy_exit = proxy.interrupt();
  EXPECT_EQ(sim.interrupt(), 0);
  return s;
}

TEST(Proxy, ForwardsRepliesUnchangedAndLogsDecodedPairedFrames) {
  Session s = proxy_session();
  EXPECT_EQ(s.proxy_exit, 0) << "SIGINT ends the proxy with 0";
  ASSERT_EQ(s.direct_status.size(), 52u);
  EXPECT_EQ(s.proxied_status, s.direct_status) << "the reply through the proxy is the direct reply, byte for byte";
  EXPECT_EQ(s.proxied_type.size(), 11u);

  const auto log = read_log(s.log);
  ASSERT_GE(log.size(), 5u);
  EXPECT_EQ(log[0]["schema"], "sabus-proxy-log");
  EXPECT_EQ(log[0]["version"], 1);
  std::vector<nlohmann::json> frames, chunks;
  for (const auto& r : log) {
    if (r.value("type", "") == "frame") frames.push_back(r);
    if (r.value("type", "") == "chunk") chunks.push_back(r);
  }
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[0]["dir"], "mc->dev");
  EXPECT_EQ(frames[0]["seq"], 1);
  EXPECT_EQ(frames[0]["hex"], to_hex(encode_request(StatusPoll{}, '2')));
  EXPECT_EQ(frames[0]["summary"].get<std::string>().rfind("command 31h Device Status Poll", 0), 0u) << frames[0]["summary"];
  EXPECT_EQ(frames[1]["dir"], "dev->mc");
  EXPECT_EQ(frames[1]["reply_to"], 1);
  EXPECT_EQ(frames[1]["hex"], to_hex(strip_parity_for_test(s.direct_status)));
  EXPECT_NE(frames[1]["summary"].get<std::string>().find("ACK 31h"), std::string::npos) << frames[1]["summary"];
  EXPECT_TRUE(frames[1]["error"].is_null());
  bool named_agc = false;
  for (const auto& f : frames[1]["fields"]) named_agc |= f["name"] == "agc";
  EXPECT_TRUE(named_agc) << "the reply is logged field by field";
  EXPECT_EQ(frames[2]["seq"], 2);
  EXPECT_EQ(frames[3]["reply_to"], 2);
  // The chunks carry the wire bytes, parity bit included, in order.
  std::string wire_from_device;
  for (const auto& c : chunks)
    if (c["dir"] == "dev->mc") {
      if (!wire_from_device.empty()) wire_from_device += ' ';
      wire_from_device += c["hex"].get<std::string>();
    }
  EXPECT_EQ(wire_from_device, to_hex(s.proxied_status) + " " + to_hex(s.proxied_type));
  EXPECT_EQ(log.back()["type"], "event");
  EXPECT_EQ(log.back()["what"], "stop");
  EXPECT_EQ(log_problems(test::slurp(s.log)), "");
  for (const auto& r : log)
    if (r.contains("t_ms")) {
      EXPECT_TRUE(r["wall"].is_string());
    }
  fs::remove(s.log);
}

// A device lost while the proxy forwards ends it with the code of a stopped
// run (4), its log kept; 3 is for a device that does not open.
TEST(Proxy, ExitsFourWhenTheDeviceIsLost) {
  const std::string a = temp_path("lost-dev"), b = temp_path("lost-mc"), log = temp_path("lost.jsonl");
  auto sim = std::make_unique<Process>(std::vector<std::string>{SABUS_BIN, "sim", "--pty", "--link", a});
  ASSERT_EQ(sim->line(5s), "READY " + a);
  Process proxy({SABUS_BIN, "proxy", "--listen-pty", b, "--port", a, "--log", log});
  ASSERT_EQ(proxy.line(5s), "READY " + b);
  sim.reset();  // SIGKILL: the pty goes away under the proxy
  EXPECT_EQ(proxy.wait_exit_for(5s), 4);
  const auto records = read_log(log);
  ASSERT_FALSE(records.empty());
  EXPECT_EQ(records.back()["what"], "device lost");
  EXPECT_EQ(log_problems(test::slurp(log)), "");
  fs::remove(log);
  fs::remove(a);  // the killed sim's link
}

// Wire bytes as the M&C side sends them: 7-bit characters with the even
// parity bit (line.hpp).
Bytes wire(const Frame& f) { return add_even_parity(encode_frame(f)); }

// A command stream with a run of each discard the M&C side's receiver
// (every address, parity in bit 7) can make, and every byte value.
Bytes hostile_commands() {
  Bytes out;
  auto add = [&](const Bytes& b) { out.insert(out.end(), b.begin(), b.end()); };
  Bytes bad_lrc = wire(Frame{FrameKind::kCommand, '2', 0x31, {}});
  bad_lrc.back() ^= 0x41;                                                      // bad LRC (parity kept: 0x41 has two bits)
  add(bad_lrc);
  add(wire(Frame{FrameKind::kCommand, 0x20, 0x31, {}}));                       // other address
  add(wire(Frame{FrameKind::kCommand, '2', 0x3D, {0x01, '1'}}));               // control character in the body
  add(wire(Frame{FrameKind::kCommand, '2', 0x3B, Bytes(400, '0')}));           // overrun
  Bytes wrong_parity = add_even_parity(Bytes{0x02, '2', 0x31});
  wrong_parity[1] ^= 0x80;
  add(wrong_parity);                                                           // parity error: the address byte's bit 7
  add(add_even_parity(Bytes{'h', 'e', 'l', 'l', 'o'}));                        // unknown bytes
  add({0xC1, 0xC1});                                                           // parity error outside a frame
  add(add_even_parity(Bytes{0x02, '2', 0x31}));                                // incomplete: a new start follows
  add(wire(Frame{FrameKind::kCommand, '2', 0x30, {}}));                        // a frame: seq 2
  for (int b = 0; b < 256; ++b) out.push_back(static_cast<std::uint8_t>(b));  // every byte value
  return out;
}

// A session over TCP on both sides, the device side played by the test:
// two clients, a frame each way, every kind of discard and every byte value
// both ways, a frame cut short at the stop. Every line is one JSON object as
// PROXY-LOG.md documents it, and the records the session must make are there.
TEST(Proxy, ATcpSessionWithEveryDiscardAndEveryByteIsDocumentedJsonLines) {
  auto device = TcpListener::listen("127.0.0.1", 0);
  const std::string log = temp_path("tcp.jsonl");
  Process proxy({SABUS_BIN, "proxy", "--listen-tcp", "127.0.0.1:0", "--tcp", "127.0.0.1:" + std::to_string(device->port()),
                 "--log", log});
  const std::string ready = proxy.line(5s);
  ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
  const auto port = static_cast<std::uint16_t>(std::stoi(ready.substr(ready.rfind(':') + 1)));
  auto dev = device->accept(5s);
  ASSERT_TRUE(dev);
  {
    auto mc = TcpLine::connect("127.0.0.1", port, 2s);
    ASSERT_EQ(wait_for_log(log, "\"client connected\""), 1);
    mc->write(wire(Frame{FrameKind::kCommand, '2', 0x31, {}}));
    ASSERT_EQ(wait_for_log(log, "\"seq\":1"), 1);
    dev->write(add_even_parity(encode_reply(StatusReply{}, '2', 0x31).value()));
    ASSERT_EQ(wait_for_log(log, "\"reply_to\":1"), 1);
    mc->write(hostile_commands());
    ASSERT_EQ(wait_for_log(log, "\"seq\":2"), 1);
    Bytes replies = add_even_parity(encode_frame(Frame{FrameKind::kAck, '2', 0x30, {'3', 'K', '1', '.', '5', '9'}}));
    for (int b = 0; b < 256; ++b) replies.push_back(static_cast<std::uint8_t>(b));
    dev->write(replies);
    ASSERT_GE(wait_for_log(log, "\"reply_to\":2"), 1);
  }
  ASSERT_EQ(wait_for_log(log, "\"client lost\""), 1);
  auto second = TcpLine::connect("127.0.0.1", port, 2s);
  ASSERT_EQ(wait_for_log(log, "\"client connected\"", 2), 2);
  second->write(add_even_parity(Bytes{0x02, '2', 0x31}));  // cut short by the stop
  ASSERT_EQ(wait_for_log(log, "\"hex\":\"82 b2 b1\",\"t_ms\""), 1) << "its chunk (a discard's hex is followed by length)";
  EXPECT_EQ(proxy.interrupt(), 0);

  const std::string text = test::slurp(log);
  EXPECT_EQ(log_problems(text), "");
  std::set<std::string> command_discards, reply_discards;
  std::vector<std::string> events;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const auto r = nlohmann::json::parse(line);
    if (r.value("type", "") == "discard") (r["dir"] == "mc->dev" ? command_discards : reply_discards).insert(r["reason"].get<std::string>());
    if (r.value("type", "") == "event") events.push_back(r["what"]);
  }
  EXPECT_EQ(command_discards, (std::set<std::string>{"bad LRC", "other address", "control character in the body", "overrun",
                                                     "parity error", "unknown bytes", "incomplete"}));
  EXPECT_TRUE(reply_discards.count("parity error") && reply_discards.count("unknown bytes")) << text;
  EXPECT_EQ(events, (std::vector<std::string>{"client connected", "client lost", "client connected", "stop"}));
  fs::remove(log);
}

// A path that is not UTF-8 (a file name is any bytes but / and NUL) reaches
// the header and the device-lost event: it is logged with U+FFFD, where
// json's dump() threw type_error 316 and the proxy aborted (exit 134) before
// its first line, leaving its link behind.
TEST(Proxy, PathsThatAreNotUtf8AreLoggedNotThrownOn) {
  const std::string a = temp_path("dev"), a_latin1 = a + "\xe9", b = temp_path("mc\xff"), log = temp_path("latin1.jsonl");
  auto sim = std::make_unique<Process>(std::vector<std::string>{SABUS_BIN, "sim", "--pty", "--link", a});
  ASSERT_EQ(sim->line(5s), "READY " + a);
  fs::create_symlink(a, a_latin1);
  Process proxy({SABUS_BIN, "proxy", "--listen-pty", b, "--port", a_latin1, "--log", log});
  ASSERT_EQ(proxy.line(5s), "READY " + b);
  sim.reset();
  EXPECT_EQ(proxy.wait_exit_for(5s), 4) << "device lost, not an abort";
  const std::string text = test::slurp(log);
  EXPECT_EQ(log_problems(text), "");
  const auto records = read_log(log);
  ASSERT_EQ(records.size(), 2u) << text;
  EXPECT_NE(records[0]["mc"].get<std::string>().find(temp_path("mc\xEF\xBF\xBD")), std::string::npos) << records[0];
  EXPECT_NE(records[0]["device"].get<std::string>().find(a + "\xEF\xBF\xBD"), std::string::npos) << records[0];
  EXPECT_EQ(records[1]["what"], "device lost");
  EXPECT_FALSE(fs::exists(fs::symlink_status(b))) << "the proxy's link is removed at its exit";
  fs::remove(a_latin1);
  fs::remove(a);  // the killed sim's link
  fs::remove(log);
}

// A log that cannot be written (a full disk: /dev/full) is said once on
// stderr; the proxy goes on forwarding, and a stop is still exit 0.
TEST(Proxy, ALogThatCannotBeWrittenIsSaidOnceAndForwardingGoesOn) {
  const std::string a = temp_path("full-dev"), b = temp_path("full-mc");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", a});
  ASSERT_EQ(sim.line(5s), "READY " + a);
  Process proxy({"/bin/sh", "-c", "exec \"$0\" proxy --listen-pty \"$1\" --port \"$2\" --log /dev/full 2>&1", SABUS_BIN, b, a});
  EXPECT_EQ(proxy.line(5s), "sabus proxy: the log cannot be written (No space left on device); forwarding goes on, unlogged");
  ASSERT_EQ(proxy.line(5s), "READY " + b);
  {
    auto client = TermiosSerialLine::open(b, 9600);
    EXPECT_EQ(ask(*client, encode_request(StatusPoll{}, '2')).size(), 52u) << "forwarded";
  }
  EXPECT_EQ(proxy.interrupt(), 0);
  EXPECT_EQ(proxy.read_all(1s), "") << "said once";
  EXPECT_EQ(sim.interrupt(), 0);
}

TEST(Proxy, UsageErrorsExitTwo) {
  EXPECT_EQ(run_sabus({"proxy", "--port", "/dev/null"}), 2) << "no M&C side";
  EXPECT_EQ(run_sabus({"proxy", "--listen-pty", temp_path("x"), "--tcp", "localhost:99999"}), 2);
}

TEST(Record, AProxySessionReplaysCleanAndCatchesAChangedStableField) {
  Session s = proxy_session();
  const std::string out = temp_path("regression/session.yaml");
  std::string text;
  ASSERT_EQ(run_sabus({"record", s.log, "--out", out}, &text), 0) << text;
  EXPECT_NE(text.find("recorded 2 vector(s)"), std::string::npos) << text;
  std::ifstream in(out);
  const std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(yaml.find("paragraph: \"framing\""), std::string::npos) << "two commands: a framing file\n" << yaml;
  EXPECT_NE(yaml.find("\"azimuth\": any"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("\"agc\": {regex:"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("\"version\": {eq: \"1.59\"}"), std::string::npos) << yaml;

  EXPECT_EQ(run_sabus({"vectors", "lint", out}, &text), 0) << text;
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out}, &text), 0) << text;
  EXPECT_NE(text.find("2 passed, 0 failed"), std::string::npos) << text;
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out, "--fault", "device-type-no-dot"}, &text), 1) << text;
  EXPECT_NE(text.find("version"), std::string::npos) << text;
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out, "--fault", "short-status"}, &text), 1) << text;
  fs::remove(s.log);
  fs::remove_all(fs::path(out).parent_path());
}

TEST(Record, ARunJsonReplaysCleanAndAOneCommandRecordingTakesItsParagraph) {
  const std::string json = temp_path("run.json"), out = temp_path("from-run.yaml");
  std::string text;
  ASSERT_EQ(run_sabus({"run", "--sim", "--vectors", SABUS_SOURCE_DIR "/vectors/3.1-device-type.yaml", "--json", json}, &text), 0)
      << text;
  ASSERT_EQ(run_sabus({"record", json, "--out", out, "--name", "fw159"}, &text), 0) << text;
  std::ifstream in(out);
  const std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(yaml.find("paragraph: \"3.1\""), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("id: \"3.1-fw159-3.1-"), std::string::npos) << yaml;
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out}, &text), 0) << text;
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out, "--fault", "device-type-no-dot"}, &text), 1) << text;

  // decode reads the run JSON: frames with their times and directions.
  ASSERT_EQ(run_sabus({"decode", json}, &text), 0) << text;
  EXPECT_NE(text.find("run JSON"), std::string::npos) << text;
  EXPECT_NE(text.find("mc->dev command 30h Device Type Query"), std::string::npos) << text;
  EXPECT_NE(text.find("dev->mc ACK 30h"), std::string::npos) << text;
  fs::remove(json);
  fs::remove(out);
}

TEST(Record, ARestartedFrameIsTaggedAndCheckedByItsLastFrameAsTheLinterReadsIt) {
  // framing.yaml sends 02 02 A 31 03 LRC: the 32h after the first STX is the
  // address, not an auto move, and the reply is the status poll's.
  const std::string json = temp_path("framing.json"), out = temp_path("framing.yaml");
  std::string text;
  ASSERT_EQ(run_sabus({"run", "--sim", "--vectors", SABUS_SOURCE_DIR "/vectors/framing.yaml", "--json", json}, &text), 0) << text;
  ASSERT_EQ(run_sabus({"record", json, "--out", out, "--name", "fr"}, &text), 0) << text;
  // "recorded N vector(s), ...": every one of them passes when replayed.
  const auto at = text.find("recorded ");
  ASSERT_NE(at, std::string::npos) << text;
  const std::string recorded = text.substr(at + 9, text.find(' ', at + 9) - at - 9);
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out}, &text), 0) << text;
  EXPECT_NE(text.find("\n" + recorded + " passed, 0 failed, 0 skipped"), std::string::npos) << recorded << "\n" << text;
  fs::remove(json);
  fs::remove(out);
}

TEST(Record, BadInputIsAUsageErrorNamingTheLine) {
  const std::string bad = temp_path("bad.jsonl"), out = temp_path("never.yaml");
  {
    std::ofstream f(bad);
    f << proxy_header("pty", "dev", "8N1").dump() << "\n{\"type\":\"frame\",\"t_ms\":1}\n";
  }
  std::string text;
  EXPECT_EQ(run_sabus({"record", bad, "--out", out}, &text), 2);
  EXPECT_FALSE(fs::exists(out));
  std::string error;
  std::ifstream in(bad);
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(read_capture(content, error));
  EXPECT_EQ(error, "line 2: no \"dir\"");
  fs::remove(bad);
}

TEST(Decode, ReadsAProxyLog) {
  Session s = proxy_session();
  std::string text;
  ASSERT_EQ(run_sabus({"decode", s.log}, &text), 0) << text;
  EXPECT_NE(text.find("proxy log of "), std::string::npos) << text;
  EXPECT_NE(text.find("mc->dev command 31h Device Status Poll"), std::string::npos) << text;
  EXPECT_NE(text.find("dev->mc ACK 31h"), std::string::npos) << text;
  EXPECT_NE(text.find("4 frame(s), 0 ignored run(s)"), std::string::npos) << text;
  ASSERT_EQ(run_sabus({"decode", "--json", s.log}, &text), 0) << text;
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["frames"], 4);
  EXPECT_EQ(j["events"][1]["reply_to"], 1);
  fs::remove(s.log);
}

// ---- what `sabus record` writes, read back ---------------------------------------
//
// Captures made here (proxy_frame, as `sabus proxy` logs; a run JSON as
// `sabus run --json` writes it) of requests and the reference controller's
// replies, and of replies no controller sends; every file recorded from them
// loads with the suite's loader, passes its lint with no error, holds only
// text a strict YAML reader takes, and replays against the controller the
// capture came from.

// A profile whose text fields hold YAML's own characters: the displayed name
// (the status reply's `sat name`) and a preset satellite's name (3Ah).
Profile hostile_text_profile() {
  Profile p;
  p.display.satellite = "A\"B\\C#: D";
  PresetSatellite preset;
  preset.index = 3;
  preset.data.name = "q\"\\'{x} #-";
  p.presets = {preset};
  return p;
}

// The frames (7-bit characters) the controller answers `request` with.
std::vector<Bytes> replies_of(InProcessTransport& t, const Bytes& request) {
  struct Frames : ReceiverSink {
    std::vector<Bytes> frames;
    void on_frame(const FrameView& f) override { frames.emplace_back(f.bytes.begin(), f.bytes.end()); }
    void on_discard(const Discard&) override {}
  } sink;
  t.send(request);
  Receiver rx(ReceiverOptions::master());
  std::uint8_t buf[512];
  for (std::size_t n; (n = t.receive(buf, 1ms)) > 0;) rx.feed(ByteView(buf, n), sink);
  rx.finish(sink);
  return sink.frames;
}

// A frame with its check byte computed: `body` is byte 0 through ETX.
Bytes with_lrc(Bytes body) {
  std::uint8_t x = 0;
  for (auto b : body) x ^= b;
  body.push_back(x);
  return body;
}

struct Exchange {
  Bytes request;
  std::vector<Bytes> replies;
  std::vector<Bytes> ignored;  // device bytes the receiver discarded, logged before the replies
};

std::string proxy_log_of(const std::vector<Exchange>& exchanges, const std::string& device) {
  std::string log = proxy_header("pty /dev/pts/9 (link /tmp/mc)", device, "8N1").dump() + "\n";
  std::uint64_t seq = 0;
  double t = 0;
  for (const auto& x : exchanges) {
    log += proxy_frame(t += 10, Direction::kToDevice, x.request, ++seq, std::nullopt).dump() + "\n";
    for (const auto& g : x.ignored)
      log += nlohmann::json{{"type", "discard"}, {"t_ms", t + 1}, {"wall", "2024-05-06T12:34:56.789Z"}, {"dir", "dev->mc"},
                            {"reason", "bad LRC"}, {"message", "bad LRC"}, {"length", g.size()}, {"hex", to_hex(g)}}
                 .dump() +
             "\n";
    for (const auto& r : x.replies) log += proxy_frame(t + 2, Direction::kFromDevice, r, std::nullopt, seq).dump() + "\n";
  }
  return log;
}

Recording record_ok(const std::string& capture_text, const RecordOptions& options) {
  std::string error;
  const auto capture = read_capture(capture_text, error);
  EXPECT_TRUE(capture) << error;
  if (!capture) return {};
  auto rec = record_vectors(*capture, options, error);
  EXPECT_TRUE(rec) << error;
  return rec.value_or(Recording{});
}

// The recording as the suite reads it: loaded and linted with no error, and
// its characters those a strict YAML reader takes.
std::vector<Vector> load_and_lint(const Recording& rec) {
  EXPECT_EQ(test::yaml_text_problem(rec.yaml), "") << rec.yaml;
  LoadResult loaded = load_vector_text(rec.yaml, "recorded.yaml");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.text() << "\n" << rec.yaml;
  if (!loaded.ok()) return {};
  for (const auto& e : lint(loaded.files)) ADD_FAILURE() << e.text() << "\n" << rec.yaml;
  return loaded.files.at(0).vectors;
}

RunResult replay(const std::vector<Vector>& vectors, const Profile& profile) {
  auto t = make_in_process_transport({profile});
  RunOptions o;
  o.backup_stored_data = false;
  return Runner(*t, profile, o).run(vectors);
}

// What the file says a step of vector `v` expects, read with yaml-cpp.
YAML::Node expect_of(const std::string& yaml, std::size_t v, std::size_t step = 0) {
  return YAML::Load(yaml)["vectors"][v]["steps"][step]["expect"];
}

TEST(RecordWrites, EveryExpectationOfAProxySessionLoadsLintsAndReplays) {
  const Profile p = hostile_text_profile();
  auto t = make_in_process_transport({p});
  const Bytes status = encode_request(StatusPoll{}, '2');
  ReadSatellite read;
  read.index = 3;
  const Bytes read_preset = encode_request(read, '2');
  const Bytes device_type = encode_request(DeviceTypeQuery{}, '2');
  const Bytes other_address = encode_request(StatusPoll{}, '3');
  const Bytes long_status = with_lrc({0x02, '2', 0x31, 'A', 0x03});  // a data byte too many: NAK (§3)
  const Bytes status_reply = replies_of(*t, status).at(0);
  // The status reply with a control character (01h) in the satellite name, and
  // with a byte of 80h or more: the check byte made right, so only the field
  // is wrong.
  Bytes control = status_reply, eight_bit = status_reply;
  control[5] = 0x01;
  eight_bit[5] = 0xFF;
  control = with_lrc(Bytes(control.begin(), control.end() - 1));
  eight_bit = with_lrc(Bytes(eight_bit.begin(), eight_bit.end() - 1));

  const std::vector<Exchange> session = {
      {status, replies_of(*t, status), {}},                         // 0: an exact reply, a name with quotes and a backslash
      {read_preset, replies_of(*t, read_preset), {}},               // 1: the same in a preset's name
      {device_type, replies_of(*t, device_type), {hex("06 b2 00")}},  // 2: bytes ignored before the reply
      {other_address, replies_of(*t, other_address), {}},           // 3: silence
      {long_status, replies_of(*t, long_status), {}},               // 4: nak, with length_mismatch
      {status, {status_reply, hex("15 32 31 03 15")}, {}},          // 5: two frames: any
      {status, {control}, {}},                                      // 6: a field that does not decode: any
      {status, {eight_bit}, {}},                                    // 7: a byte of 80h or more: any
      {status, {Bytes(status_reply.begin(), status_reply.end() - 3)}, {}},  // 8: cut short: no frame, any
  };
  ASSERT_EQ(session[3].replies.size(), 0u);
  ASSERT_EQ(session[4].replies.at(0).front(), NAK);
  const Recording rec = record_ok(proxy_log_of(session, "serial /dev/ttyUSB0 9600 8N1 (termios)"),
                                  {"hostile", "", "session.jsonl"});
  const std::vector<Vector> vectors = load_and_lint(rec);
  ASSERT_EQ(vectors.size(), session.size()) << rec.yaml;
  EXPECT_EQ(rec.paragraph, "framing");

  EXPECT_EQ(expect_of(rec.yaml, 0)["reply"].Scalar(), "ack");
  EXPECT_EQ(expect_of(rec.yaml, 0)["fields"]["sat name"]["eq"].Scalar(), "A\"B\\C#: D") << rec.yaml;
  EXPECT_EQ(expect_of(rec.yaml, 0)["fields"]["azimuth"].Scalar(), "any") << "masked: follows the mount";
  EXPECT_EQ(expect_of(rec.yaml, 1)["fields"]["sat name"]["eq"].Scalar(), "q\"\\'{{x}} #-")
      << "a matcher's value is a template: its braces doubled\n"
      << rec.yaml;
  EXPECT_EQ(expect_of(rec.yaml, 2)["fields"]["version"]["eq"].Scalar(), "1.59") << rec.yaml;
  EXPECT_EQ(expect_of(rec.yaml, 3).Scalar(), "silence");
  EXPECT_EQ(expect_of(rec.yaml, 4).Scalar(), "nak");
  EXPECT_TRUE(YAML::Load(rec.yaml)["vectors"][4]["steps"][0]["length_mismatch"].as<bool>()) << rec.yaml;
  for (std::size_t v : {5u, 6u, 7u, 8u}) EXPECT_EQ(expect_of(rec.yaml, v).Scalar(), "any") << v;
  std::size_t noted_any = 0;
  for (const auto& n : rec.notes) noted_any += n.find("recorded as `any`") != std::string::npos;
  EXPECT_EQ(noted_any, 4u);

  // Replayed against the controller it came from: every vector passes.
  const RunResult same = replay(vectors, p);
  EXPECT_EQ(same.exit_code(), 0);
  EXPECT_EQ(same.passed, session.size());
  for (const auto& v : same.vectors)
    EXPECT_EQ(v.verdict, Verdict::kPass) << v.id << ": " << (v.failures.empty() ? "" : v.failures.front());
  // And the names are checked: a controller with other names fails the two
  // vectors that read them.
  Profile renamed = p;
  renamed.display.satellite = "A\"B\\C#: E";
  renamed.presets[0].data.name = "q\"\\'{x} #+";
  const RunResult other = replay(vectors, renamed);
  EXPECT_EQ(other.exit_code(), 1);
  EXPECT_EQ(other.failed, 2u);
}

TEST(RecordWrites, AnOfflineSessionRecordsTheOfflineReply) {
  Profile p;
  p.remote_enabled = false;
  auto t = make_in_process_transport({p});
  const Bytes status = encode_request(StatusPoll{}, '2');
  const Recording rec = record_ok(proxy_log_of({{status, replies_of(*t, status), {}}}, "dev"), {"offline", "", "off.jsonl"});
  const std::vector<Vector> vectors = load_and_lint(rec);
  ASSERT_EQ(vectors.size(), 1u);
  EXPECT_EQ(expect_of(rec.yaml, 0).Scalar(), "offline") << rec.yaml;
  EXPECT_EQ(replay(vectors, p).exit_code(), 0);
  EXPECT_EQ(replay(vectors, Profile{}).exit_code(), 1) << "an enabled controller answers";
}

// The header comment names the capture's file and device, which may hold
// anything a file name or a JSON string can: a line break there made the
// rest of the line YAML (a device "dev\nline2: x" was an unknown key, a file
// name "b\nparagraph: x" a duplicate one, and the recording was refused).
TEST(RecordWrites, TheHeaderTakesAnyFileAndDeviceName) {
  auto t = make_in_process_transport({Profile{}});
  const Bytes status = encode_request(StatusPoll{}, '2');
  const std::string device = "dev\nline2: x\r\nvectors: []\x01\x7f \xe2\x80\xa8 # \xc3\xa9";
  const std::string source = "b\xff\nparagraph: \"x\".jsonl";
  const Recording rec = record_ok(proxy_log_of({{status, replies_of(*t, status), {}}}, device), {"header", "", source});
  const std::vector<Vector> vectors = load_and_lint(rec);
  ASSERT_EQ(vectors.size(), 1u);
  EXPECT_NE(rec.yaml.find("from b\\xff\n# paragraph: \"x\".jsonl (proxy log, device dev\n# line2: x\\x0d\n# vectors: []\\x01\\x7f "
                          "\\xe2\\x80\\xa8 # \xc3\xa9)."),
            std::string::npos)
      << rec.yaml;
  EXPECT_EQ(replay(vectors, Profile{}).exit_code(), 0);
}

// A run JSON's vector ids, paragraphs and outcomes reach each vector's
// comment: printable there, and the ids made of id characters.
TEST(RecordWrites, ARunJsonWithAnyTextInItsIdsAndOutcomesLoadsLintsAndReplays) {
  const Profile p = hostile_text_profile();
  auto t = make_in_process_transport({p});
  const Bytes status = encode_request(StatusPoll{}, '2');
  const Bytes device_type = encode_request(DeviceTypeQuery{}, '2');
  auto entry = [](double t_ms, const char* dir, const Bytes& b) {
    return nlohmann::json{{"t_ms", t_ms}, {"dir", dir}, {"hex", to_hex(b)}, {"note", "x"}};
  };
  nlohmann::json run = {{"schema", "sabus-run"}, {"version", 2}, {"device", "dev\r\nx: y"}, {"vectors", nlohmann::json::array()}};
  const std::string hostile = "a\"b\\c\nd: e\r\x01\x7f\xc2\x85\xe2\x80\xa8 # \xc3\xa9";
  run["vectors"].push_back({{"id", "3.2-" + hostile},
                            {"paragraph", hostile},
                            {"level", "must"},
                            {"outcome", "fail: " + hostile},
                            {"transcript",
                             {entry(1, "tx", status), entry(2, "rx", replies_of(*t, status).at(0)), entry(3, "rx", {}),
                              entry(4, "tx", device_type), entry(5, "rx", replies_of(*t, device_type).at(0))}}});
  run["vectors"].push_back({{"id", "3.2-plain"}, {"transcript", {entry(1, "tx", encode_request(StatusPoll{}, '3'))}}});  // silence
  const Recording rec = record_ok(run.dump(), {"fw", "", "run.json"});
  const std::vector<Vector> vectors = load_and_lint(rec);
  ASSERT_EQ(vectors.size(), 2u) << rec.yaml;
  EXPECT_EQ(vectors[0].id, "framing-fw-3.2-a-b-c-d--e-------------") << rec.yaml;
  EXPECT_EQ(vectors[0].comment,
            "Recorded from run vector 3.2-a\"b\\c\nd: e\\x0d\\x01\\x7f\\xc2\\x85\\xe2\\x80\\xa8 # \xc3\xa9 (\xc2\xa7" +
                std::string("a\"b\\c\nd: e\\x0d\\x01\\x7f\\xc2\\x85\\xe2\\x80\\xa8 # \xc3\xa9, must, outcome fail: a\"b\\c\nd: "
                            "e\\x0d\\x01\\x7f\\xc2\\x85\\xe2\\x80\\xa8 # \xc3\xa9)."))
      << rec.yaml;
  EXPECT_EQ(expect_of(rec.yaml, 0, 0)["fields"]["sat name"]["eq"].Scalar(), "A\"B\\C#: D");
  EXPECT_EQ(expect_of(rec.yaml, 1, 0).Scalar(), "silence");
  EXPECT_EQ(replay(vectors, p).exit_code(), 0);
}

TEST(RecordWrites, ARequestOfEightBitCharactersIsAnErrorNamingTheExchange) {
  const std::string log = proxy_log_of({{encode_request(StatusPoll{}, '2'), {}, {}}, {hex("02 32 30 ff 03 fe"), {}, {}}}, "dev");
  std::string error;
  const auto capture = read_capture(log, error);
  ASSERT_TRUE(capture) << error;
  EXPECT_FALSE(record_vectors(*capture, {"x", "", "log.jsonl"}, error));
  EXPECT_EQ(error,
            "exchange 2 (t=20.0 ms): byte 3 of the request is 0xff, not a 7-bit character; a capture holds the characters "
            "sent, without the parity bit");
}

// `sabus record` as a process, on a log whose file name holds a line break
// and a byte that is not UTF-8: it records, and what it wrote lints clean.
TEST(Record, AFileNamedWithALineBreakAndAByteThatIsNotUtf8) {
  auto t = make_in_process_transport({Profile{}});
  const Bytes status = encode_request(StatusPoll{}, '2');
  const std::string log = temp_path("b\xff\nparagraph: x.jsonl"), out = temp_path("named.yaml");
  {
    std::ofstream f(log);
    f << proxy_log_of({{status, replies_of(*t, status), {}}}, "dev");
  }
  std::string text;
  ASSERT_EQ(run_sabus({"record", log, "--out", out}, &text), 0) << text;
  EXPECT_EQ(run_sabus({"vectors", "lint", out}, &text), 0) << text;
  EXPECT_EQ(test::yaml_text_problem(test::slurp(out)), "") << test::slurp(out);
  fs::remove(log);
  fs::remove(out);
}

// ---- the proxy log's records (capture.hpp) --------------------------------------

// The checker itself fails on what PROXY-LOG.md does not document: it reads
// the document's table, and a log that breaks it is named line by line.
TEST(ProxyLogChecker, ReadsTheDocumentAndNamesEachBrokenLine) {
  const auto spec = test::read_proxy_log_spec(test::slurp(SABUS_SOURCE_DIR "/tools/PROXY-LOG.md"));
  EXPECT_EQ(spec.keys.at("frame"),
            (std::set<std::string>{"type", "t_ms", "wall", "dir", "hex", "seq", "reply_to", "summary", "error", "fields"}));
  EXPECT_EQ(spec.keys.at("(header)"), (std::set<std::string>{"schema", "version", "start", "mc", "device", "line"}));
  EXPECT_EQ(spec.field_keys, (std::set<std::string>{"first", "last", "name", "raw", "meaning", "ok"}));
  EXPECT_EQ(spec.events, (std::set<std::string>{"client connected", "client lost", "device lost", "error", "stop"}));
  const std::string header = proxy_log_line(proxy_header("pty", "dev", "8N1"));
  const std::string chunk = proxy_log_line(proxy_chunk(1, Direction::kToDevice, Bytes{0x82, 0xB2, 0xB1, 0x83, 0x82}));
  const std::string frame = proxy_log_line(proxy_frame(1, Direction::kToDevice, Bytes{0x02, 0x32, 0x31, 0x03, 0x02}, 1, std::nullopt));
  EXPECT_EQ(log_problems(header + chunk + frame), "");
  auto edited = [](std::string line, const std::string& from, const std::string& to) {
    return line.replace(line.find(from), from.size(), to);
  };
  const struct {
    std::string log, problem;
  } broken[] = {
      {header + chunk + "{\"type\":\"chunk\"\n", "line 3: not a JSON object"},
      {header + edited(chunk, "\"dir\"", "\"extra\":1,\"dir\""), "line 2: keys other than PROXY-LOG.md's for chunk"},
      {header + chunk + edited(frame, "\"seq\":1", "\"seq\":2"), "line 3: a command frame's seq is not the next count"},
      {header + chunk + edited(frame, "\"ok\":true", "\"ok\":1"), "line 3: a field not as PROXY-LOG.md gives it"},
      {header + edited(chunk, "\"type\":\"chunk\"", "\"type\":\"bytes\""), "line 2: a record of type \"bytes\""},
      {header + chunk.substr(0, chunk.size() - 1), "the log does not end with a newline"},
  };
  for (const auto& b : broken) EXPECT_NE(log_problems(b.log).find(b.problem), std::string::npos) << b.log << log_problems(b.log);
}

// A string that is not UTF-8 is written with U+FFFD on one line that
// parses; json's own dump() throws on the same record.
TEST(ProxyLogRecords, TextThatIsNotUtf8IsReplacedNotThrownOn) {
  const auto header = proxy_header("pty /dev/pts/1 (link /tmp/mc\xff\xfe)", "serial /tmp/\xc3( 9600 8N1", "8N1");
  EXPECT_THROW((void)header.dump(), nlohmann::json::type_error) << "the input is one json's default refuses";
  const std::string log = proxy_log_line(header) +
                          proxy_log_line(proxy_event(1, "device lost", "serial /tmp/\xc3(: end of file\n\x01\x80")) +
                          proxy_log_line(proxy_event(2, "stop", "signal"));
  EXPECT_EQ(log_problems(log), "");
  std::istringstream lines(log);
  std::string first;
  std::getline(lines, first);
  EXPECT_EQ(nlohmann::json::parse(first)["mc"], "pty /dev/pts/1 (link /tmp/mc\xEF\xBF\xBD\xEF\xBF\xBD)");
}

// Every discard reason, with every byte value as the deciding (and the
// expected) byte and 8-bit wire bytes that are not UTF-8: one documented line
// each, its message Discard::message() unchanged.
TEST(ProxyLogRecords, EveryDiscardWithEveryByteIsOneDocumentedLine) {
  std::string log = proxy_log_line(proxy_header("pty", "dev", "8N1"));
  std::vector<std::string> messages;
  const Bytes wire_bytes{0x80, 0xFF, 0xC3, 0x28, 0x02};
  constexpr DiscardReason kReasons[] = {
#define SABUS_X(id, name, description) DiscardReason::id,
      SABUS_DISCARD_REASONS(SABUS_X)
#undef SABUS_X
  };
  for (DiscardReason reason : kReasons) {
    for (int b = 0; b < 256; ++b)
      for (std::uint64_t at : {14u, 15u}) {  // kIncomplete's branches: the last byte of the run, one past it
        const Discard d{reason, 10, 5, at, static_cast<std::uint8_t>(b), static_cast<std::uint8_t>(255 - b)};
        log += proxy_log_line(proxy_discard(1, b % 2 ? Direction::kToDevice : Direction::kFromDevice, d, wire_bytes));
        messages.push_back(d.message());
      }
  }
  EXPECT_EQ(log_problems(log), "");
  std::istringstream lines(log);
  std::string line;
  std::getline(lines, line);
  for (const auto& m : messages) {
    ASSERT_TRUE(std::getline(lines, line));
    EXPECT_EQ(nlohmann::json::parse(line)["message"], m);
  }
}

// The proxy's own records of a stream (ProxyLogger, tools/sabus/proxy.cpp),
// made here from the same functions: a chunk, then each frame and discard
// the direction's receiver finds in it, commands counted, replies paired.
struct RecordLog : ReceiverSink {
  std::string text = proxy_log_line(proxy_header("pty", "dev", "8N1"));
  std::uint64_t seq = 0;
  Direction dir = Direction::kToDevice;
  Bytes stream;
  double t = 0;
  void on_frame(const FrameView& f) override {
    const bool command = dir == Direction::kToDevice;
    if (command) ++seq;
    text += proxy_log_line(proxy_frame(t, dir, f.bytes, command ? std::optional(seq) : std::nullopt,
                                       command || seq == 0 ? std::nullopt : std::optional(seq)));
  }
  void on_discard(const Discard& d) override {
    text += proxy_log_line(proxy_discard(t, dir, d, ByteView(stream).subspan(d.offset, d.length)));
  }
  void chunk(Receiver& rx, Direction d, const Bytes& wire) {
    dir = d;
    t += 1;
    stream.insert(stream.end(), wire.begin(), wire.end());
    text += proxy_log_line(proxy_chunk(t, d, wire));
    rx.feed(wire, *this);
  }
};

// Every byte value in every position of a command and of a reply, as wire
// bytes with the parity bit set right and wrong, through the proxy's
// receivers: every record one documented line.
TEST(ProxyLogRecords, EveryByteInEveryPositionOfAFrameMakesDocumentedLines) {
  const Bytes command = encode_request(WriteTle{3, std::string(69, '1'), std::string(69, '2')}, '2');
  const Bytes reply = encode_reply(StatusReply{}, '2', 0x31).value();
  RecordLog commands, replies;
  Receiver to_device(ReceiverOptions::slave_any_address()), from_device(ReceiverOptions::master());
  std::size_t records = 0;
  for (auto [frame, rx, log, dir] : {std::tuple{&command, &to_device, &commands, Direction::kToDevice},
                                     std::tuple{&reply, &from_device, &replies, Direction::kFromDevice}}) {
    for (std::size_t pos = 0; pos < frame->size(); ++pos)
      for (int b = 0; b < 256; ++b) {
        Bytes w = add_even_parity(*frame);
        w[pos] = static_cast<std::uint8_t>(b);
        log->chunk(*rx, dir, w);
      }
    rx->finish(*log);
    EXPECT_EQ(log_problems(log->text), "") << to_string(dir);
    records += static_cast<std::size_t>(std::count(log->text.begin(), log->text.end(), '\n'));
  }
  EXPECT_GT(records, 2 * (command.size() + reply.size()) * 256) << "a chunk and at least one frame or discard each";
}

// ---- the mask table -------------------------------------------------------------

TEST(MaskTable, MasksPositionsAgcAndMotionBitsAndKeepsStableFields) {
  StatusReply r;
  const Bytes reply = encode_reply(r, '2', 0x31).value();
  const FrameDescription d = describe_frame(reply);
  std::map<std::string, const MaskRule*> rule;
  for (const auto& f : d.fields) rule[f.name] = mask_rule_for(f);
  ASSERT_NE(rule["azimuth"], nullptr);
  EXPECT_EQ(rule["azimuth"]->mask, Mask::kAny);
  ASSERT_NE(rule["agc"], nullptr);
  EXPECT_EQ(rule["agc"]->mask, Mask::kRegex);
  ASSERT_NE(rule["az status"], nullptr);
  EXPECT_EQ(rule["sat name"], nullptr) << "the satellite name is stable";
  EXPECT_EQ(rule["pol equipment"], nullptr);
  EXPECT_EQ(rule["alarm code"], nullptr);
}

TEST(MaskTable, EveryNamedFieldExistsInSomeReplyWithThatKind) {
  for (const auto& r : mask_rules()) {
    std::string_view names = r.names;
    while (!names.empty()) {
      const auto bar = names.find('|');
      const std::string name(names.substr(0, bar));
      bool found = false;
      for (const auto& c : catalog())
        for (const auto& n : reply_field_names(c)) found |= n == name;
      EXPECT_TRUE(found) << "mask row names \"" << name << "\", which no reply has";
      if (bar == std::string_view::npos) break;
      names.remove_prefix(bar + 1);
    }
  }
}

}  // namespace
}  // namespace sabus::harness
