// The bench workflow end to end: `sabus proxy` between a client and
// `sabus sim`, its log, `sabus record` of the log and of a run JSON, `sabus
// run` of the recording (passing against the same controller, failing
// against one with a fault), and `sabus decode` of both capture formats.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sabus/harness/capture.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/harness/recording.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/receiver.hpp"
#include "sabus/protocol/structured.hpp"
#include "process.hpp"
#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

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
  for (const auto& r : log)
    if (r.contains("t_ms")) {
      EXPECT_TRUE(r["wall"].is_string());
    }
  fs::remove(s.log);
}

TEST(Proxy, ExitsThreeWhenTheDeviceIsLost) {
  const std::string a = temp_path("lost-dev"), b = temp_path("lost-mc"), log = temp_path("lost.jsonl");
  auto sim = std::make_unique<Process>(std::vector<std::string>{SABUS_BIN, "sim", "--pty", "--link", a});
  ASSERT_EQ(sim->line(5s), "READY " + a);
  Process proxy({SABUS_BIN, "proxy", "--listen-pty", b, "--port", a, "--log", log});
  ASSERT_EQ(proxy.line(5s), "READY " + b);
  sim.reset();  // SIGKILL: the pty goes away under the proxy
  EXPECT_EQ(proxy.wait_exit_for(5s), 3);
  const auto records = read_log(log);
  ASSERT_FALSE(records.empty());
  EXPECT_EQ(records.back()["what"], "device lost");
  fs::remove(log);
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
  EXPECT_EQ(run_sabus({"run", "--sim", "--vectors", out}, &text), 0) << text;
  EXPECT_NE(text.find("4 passed, 0 failed, 0 skipped"), std::string::npos) << text;
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
