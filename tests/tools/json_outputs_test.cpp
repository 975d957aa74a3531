// The JSON the commands print, read back with the JSON library on every
// path that prints it, the failing ones first: `sabus decode --json` of
// hostile captures, `sabus vectors list --json` and `coverage --json` with
// load errors, missing cells, an empty selection and a path that is not
// UTF-8, `sabus ports --json`; and the one file `sabus vectors errata
// --update` rewrites.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "process.hpp"
#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

using test::Process;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

struct Output {
  int status = -1;
  std::string out;  // standard output
};

Output sabus(std::vector<std::string> args) {
  args.insert(args.begin(), SABUS_BIN);
  Process p(args);
  Output o;
  o.out = p.read_all(120s);
  o.status = p.wait_exit_for(10s);
  return o;
}

// The text as one JSON document; a test failure naming the text otherwise.
nlohmann::json parsed(const Output& o) {
  const auto j = nlohmann::json::parse(o.out, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << "not JSON (exit " << o.status << "):\n" << o.out;
  return j;
}

std::string fmt_hex(unsigned char b) {
  static constexpr char kDigits[] = "0123456789abcdef";
  return {kDigits[b >> 4], kDigits[b & 0xF]};
}

std::set<std::string> keys_of(const nlohmann::json& j) {
  std::set<std::string> out;
  if (j.is_object())
    for (const auto& [k, v] : j.items()) out.insert(k);
  return out;
}

const std::string kShipped = SABUS_SOURCE_DIR "/vectors/3.1-device-type.yaml";

class JsonOutputs : public test::TempDirTest {
 protected:
  JsonOutputs() : TempDirTest("sabus-json-outputs-test") {}
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
};

// ---- sabus vectors list / coverage --json ---------------------------------------

const std::set<std::string> kVectorKeys = {"id", "paragraph", "level", "tags", "flags", "requires", "file", "line", "steps"};

// A folder named in Latin-1 (any bytes make a file name): its path is in
// every vector's "file"; json's dump() threw type_error 316 on it and the
// command ended in std::terminate (exit 134) with nothing printed.
TEST_F(JsonOutputs, VectorsListOfAFolderNamedInLatin1IsJson) {
  const std::string dir = path("caf\xe9");
  fs::create_directory(dir);
  fs::copy_file(kShipped, dir + "/3.1-device-type.yaml");
  const Output o = sabus({"vectors", "list", dir, "--json"});
  EXPECT_EQ(o.status, 0) << o.out;
  const auto j = parsed(o);
  ASSERT_TRUE(j.is_array() && !j.empty()) << o.out;
  for (const auto& v : j) EXPECT_EQ(keys_of(v), kVectorKeys) << v;
  EXPECT_NE(j[0]["file"].get<std::string>().find("caf\xEF\xBF\xBD/3.1-device-type.yaml"), std::string::npos) << j[0];
}

// A file that does not load (exit 1: the vectors that loaded are listed),
// and a selection with no vector (exit 5: an empty list).
TEST_F(JsonOutputs, VectorsListWithLoadErrorsAndAnEmptySelectionIsJson) {
  const std::string bad = write("bad.yaml", "paragraph: \"3.2\"\ntitle: t\nvectors:\n  - id: 3.2-x\n    comment: c\n    level: must\n");
  const Output errors = sabus({"vectors", "list", kShipped, bad, "--json"});
  EXPECT_EQ(errors.status, 1);
  const auto loaded = parsed(errors);
  ASSERT_TRUE(loaded.is_array() && !loaded.empty()) << errors.out;
  for (const auto& v : loaded) EXPECT_EQ(v["paragraph"], "3.1") << v;

  const Output none = sabus({"vectors", "list", kShipped, "--filter", "no-such-*", "--json"});
  EXPECT_EQ(none.status, 5);
  EXPECT_EQ(parsed(none), nlohmann::json::array());

  const Output all = sabus({"vectors", "list", "--json"});
  EXPECT_EQ(all.status, 0);
  const auto shipped = parsed(all);
  ASSERT_TRUE(shipped.is_array());
  EXPECT_GT(shipped.size(), 400u);
  for (const auto& v : shipped) EXPECT_EQ(keys_of(v), kVectorKeys) << v;
}

// One file leaves required cells without a vector (exit 1); the shipped
// suite leaves none, and its fields' gaps are the known ones (exit 0): the
// same document both times.
TEST_F(JsonOutputs, VectorsCoverageWithAndWithoutMissingCellsIsJson) {
  const std::string gaps = SABUS_SOURCE_DIR "/tests/tools/field_value_gaps.txt";
  for (const auto& [args, status] :
       {std::pair{std::vector<std::string>{"vectors", "coverage", kShipped, "--json", "--profiles", "3"}, 1},
        std::pair{std::vector<std::string>{"vectors", "coverage", "--json", "--known-gaps", gaps}, 0}}) {
    const Output o = sabus(args);
    EXPECT_EQ(o.status, status) << o.out;
    const auto j = parsed(o);
    EXPECT_EQ(keys_of(j),
              (std::set<std::string>{"rows", "unknown_codes", "nak_rules", "missing", "fields", "missing_values", "shares"}));
    EXPECT_EQ(j["missing"].empty(), status == 0) << j["missing"];
    ASSERT_TRUE(j["shares"].is_array() && !j["shares"].empty());
    for (const auto& share : j["shares"])
      EXPECT_EQ(keys_of(share), (std::set<std::string>{"reply", "field", "exists", "checked", "unchecked"})) << share;
    ASSERT_TRUE(j["rows"].is_array() && !j["rows"].empty());
    for (const auto& row : j["rows"])
      EXPECT_EQ(keys_of(row), (std::set<std::string>{"command", "key", "paragraph", "form", "cells"})) << row;
    ASSERT_TRUE(j["fields"].is_array() && !j["fields"].empty());
    for (const auto& field : j["fields"])
      EXPECT_EQ(keys_of(field),
                (std::set<std::string>{"reply", "field", "class", "paragraph", "required", "vectors", "literal_vectors"}))
          << field;
    ASSERT_TRUE(j["missing_values"].is_array());
    if (status == 1) EXPECT_FALSE(j["missing_values"].empty()) << "one file checks few fields";
  }
}

// ---- sabus decode --json -----------------------------------------------------------

const std::set<std::string> kBytesKeys = {"side", "parity", "bytes", "frames", "discarded_runs", "discarded_bytes", "valid",
                                          "events"};
const std::set<std::string> kCaptureKeys = {"source", "device", "frames", "ignored_runs", "valid", "session_events", "events"};

// Bytes that are no capture at all: every byte value three times (8-bit
// bytes that are not UTF-8), then a status poll with its parity bits; with
// each --parity and --side. Each is a document with its counts, exit 1.
TEST_F(JsonOutputs, DecodeOfEveryByteValueIsJson) {
  std::string raw;
  for (int round = 0; round < 3; ++round)
    for (int b = 0; b < 256; ++b) raw += static_cast<char>(b);
  raw += std::string("\x82\xb2\xb1\x83\x82", 5);
  const std::string file = write("every-byte.bin", raw);
  for (const char* parity : {"auto", "even", "none"})
    for (const char* side : {"auto", "slave", "master", "both"}) {
      const Output o = sabus({"decode", file, "--json", "--parity", parity, "--side", side});
      EXPECT_EQ(o.status, 1) << parity << " " << side;
      const auto j = parsed(o);
      EXPECT_EQ(keys_of(j), kBytesKeys) << parity << " " << side;
      EXPECT_EQ(j["bytes"], raw.size());
      EXPECT_GT(j["discarded_runs"].get<int>(), 0);
    }
}

// A proxy log and a run JSON whose hex holds 8-bit bytes, frames that are
// not frames and an event: each item is a frame or a discard in a document.
TEST_F(JsonOutputs, DecodeOfHostileCapturesIsJson) {
  const std::string log = write(
      "hostile.jsonl",
      "{\"schema\":\"sabus-proxy-log\",\"version\":1,\"start\":\"x\",\"mc\":\"m\",\"device\":\"d\\u00e9\",\"line\":\"8N1\"}\n"
      "{\"type\":\"frame\",\"t_ms\":1,\"wall\":\"w\",\"dir\":\"dev->mc\",\"hex\":\"06 32 b1 ff e9 03 00\",\"summary\":\"s\",\"seq\":null,\"reply_to\":null}\n"
      "{\"type\":\"frame\",\"t_ms\":2,\"wall\":\"w\",\"dir\":\"mc->dev\",\"hex\":\"02 32 31 03 02\",\"summary\":\"s\",\"seq\":1,\"reply_to\":null}\n"
      "{\"type\":\"discard\",\"t_ms\":3,\"wall\":\"w\",\"dir\":\"mc->dev\",\"hex\":\"ff fe c3 28\",\"message\":\"m\"}\n"
      "{\"type\":\"event\",\"t_ms\":4,\"what\":\"device lost\",\"detail\":\"\\u00ff\"}\n");
  const std::string run = write(
      "hostile-run.json",
      R"({"schema":"sabus-run","vectors":[{"id":"v","transcript":[)"
      R"({"t_ms":1,"dir":"tx","hex":"02 32 31 03 02 80 ff"},{"t_ms":2,"dir":"rx","hex":"86 b2 b1 83 86"},)"
      R"({"t_ms":3,"dir":"rx","hex":""}]}]})");
  for (const auto& [file, source] : {std::pair{log, "proxy log"}, std::pair{run, "run JSON"}}) {
    const Output o = sabus({"decode", file, "--json"});
    EXPECT_EQ(o.status, 1) << o.out;
    const auto j = parsed(o);
    EXPECT_EQ(keys_of(j), kCaptureKeys) << o.out;
    EXPECT_EQ(j["source"], source);
    EXPECT_EQ(j["frames"], 1) << "the one well-formed command: " << o.out;
    EXPECT_GE(j["ignored_runs"].get<int>(), 2) << o.out;
    for (const auto& e : j["events"]) EXPECT_TRUE(e["type"] == "frame" || e["type"] == "discard") << e;
  }
}

// A capture longer than decode's buffers (it reads 64 KiB at a time and
// keeps two such chunks): a run of zeros longer than both, letters (each
// with a parity error: runs of a few bytes), a status poll with its parity
// bits across a chunk boundary, letters, zeros. The document
// reads back with every byte in one event, in order, each discard's hex the
// bytes it covers, the frame whole; hex text on stdin (parsed into a
// temporary file) gives the same document, and the text form the same frame.
TEST_F(JsonOutputs, DecodeReadsACaptureLongerThanItsBuffersInPieces) {
  const std::size_t before = 4 * 65536 - 2, after = 100000;
  const std::string poll("\x82\xb2\xb1\x03\x82", 5);  // 02 32 31 03 02, even parity in bit 7
  std::string letters;
  for (std::size_t i = 0; i < 60000; ++i) letters += static_cast<char>('A' + i % 26);
  const std::string raw = std::string(before - letters.size(), '\0') + letters + poll + letters +
                          std::string(after - letters.size(), '\0');
  const std::string file = write("long.bin", raw);
  const Output o = sabus({"decode", file, "--json"});
  EXPECT_EQ(o.status, 1) << "discarded runs";
  const auto j = parsed(o);
  ASSERT_EQ(keys_of(j), kBytesKeys);
  EXPECT_EQ(j["bytes"], raw.size());
  EXPECT_EQ(j["frames"], 1);
  EXPECT_EQ(j["parity"], "even");
  EXPECT_EQ(j["discarded_bytes"], before + after);
  std::uint64_t next = 0, frames = 0, discards = 0;
  for (const auto& e : j["events"]) {
    ASSERT_EQ(e["offset"], next) << e.dump().substr(0, 200);
    const auto length = e["length"].get<std::uint64_t>();
    const auto hex = e["hex"].get<std::string>();
    if (e["type"] == "frame") {
      ++frames;
      EXPECT_EQ(e["offset"], before);
      EXPECT_EQ(hex, "02 32 31 03 02");
      EXPECT_EQ(e["summary"].get<std::string>().find("error"), std::string::npos) << e["summary"];
    } else {
      ++discards;
      std::string want;
      for (std::uint64_t i = 0; i < length; ++i)
        want += (i ? " " : "") + fmt_hex(static_cast<unsigned char>(raw[static_cast<std::size_t>(next + i)]));
      ASSERT_EQ(hex, want) << "the hex of every byte of the run at " << next;
    }
    next += length;
  }
  EXPECT_EQ(next, raw.size());
  EXPECT_EQ(frames, 1u);
  EXPECT_EQ(discards, j["discarded_runs"].get<std::uint64_t>());

  std::string hex_text = "# the same capture as hex text\n";
  for (std::size_t i = 0; i < raw.size(); ++i) hex_text += fmt_hex(static_cast<unsigned char>(raw[i])) + (i % 32 == 31 ? "\n" : " ");
  const std::string hex_file = write("long.hex", hex_text);
  const auto from_stdin = test::shell(std::string(SABUS_BIN) + " decode --json --hex - < " + hex_file);
  EXPECT_EQ(from_stdin.out, o.out) << "hex text on stdin decodes to the same document";
  const auto text = test::shell(std::string(SABUS_BIN) + " decode " + file);
  EXPECT_NE(text.out.find("\nframe at offset 262142 (5 bytes): "), std::string::npos);
  EXPECT_NE(text.out.find(std::to_string(raw.size()) + " bytes: 1 frame(s), " + std::to_string(discards) + " discarded run(s) (" +
                          std::to_string(before + after) + " bytes)"),
            std::string::npos);
}

// A proxy log file is decoded a record at a time, after a first pass that
// checks every line: a bad line near the end is an error naming it with
// nothing printed, as for a log held whole; a good log is one document with
// every frame in order and its session events.
TEST_F(JsonOutputs, AProxyLogIsCheckedWholeThenDecodedRecordByRecord) {
  std::string log =
      "{\"schema\":\"sabus-proxy-log\",\"version\":1,\"start\":\"x\",\"mc\":\"m\",\"device\":\"serial /dev/ttyUSB0\",\"line\":\"8N1\"}\n";
  const std::size_t polls = 3000;
  for (std::size_t i = 1; i <= polls; ++i) {
    log += "{\"type\":\"frame\",\"t_ms\":" + std::to_string(i) + ".5,\"wall\":\"w\",\"dir\":\"mc->dev\",\"hex\":\"02 32 31 03 02\","
           "\"summary\":\"s\",\"seq\":" + std::to_string(i) + ",\"reply_to\":null}\n";
    if (i == polls / 2) log += "{\"type\":\"event\",\"t_ms\":1.0,\"what\":\"client lost\",\"detail\":\"d\"}\n";
  }
  const Output good = sabus({"decode", write("good.jsonl", log), "--json"});
  EXPECT_EQ(good.status, 0);
  const auto j = parsed(good);
  ASSERT_EQ(keys_of(j), kCaptureKeys);
  EXPECT_EQ(j["device"], "serial /dev/ttyUSB0");
  EXPECT_EQ(j["frames"], polls);
  ASSERT_EQ(j["events"].size(), polls);
  for (std::size_t i = 0; i < polls; ++i) ASSERT_EQ(j["events"][i]["seq"], i + 1);
  EXPECT_EQ(j["session_events"], nlohmann::json::array({"client lost: d"}));

  const std::string bad = write("bad.jsonl", log + "{\"type\":\"frame\",\"t_ms\":1.0}\n");
  Process p({SABUS_BIN, "decode", bad});
  EXPECT_EQ(p.read_all(60s), "") << "nothing printed before the bad line is found";
  EXPECT_EQ(p.wait_exit_for(10s), 2);
  const auto said = test::shell(std::string(SABUS_BIN) + " decode " + bad + " 2>&1 >/dev/null");
  EXPECT_EQ(said.out, "sabus decode: " + bad + ": line " + std::to_string(polls + 3) + ": no \"dir\"\n");
}

// ---- sabus ports --json ------------------------------------------------------------

TEST_F(JsonOutputs, PortsIsAJsonListOfPortsWithTheirKeys) {
  const Output o = sabus({"ports", "--json"});
  EXPECT_EQ(o.status, 0);
  const auto j = parsed(o);
  ASSERT_TRUE(j.is_array()) << o.out;
  for (const auto& p : j)
    EXPECT_EQ(keys_of(p), (std::set<std::string>{"name", "description", "transport", "usb_vid", "usb_pid", "usb_bus",
                                                 "usb_address", "manufacturer", "product", "serial_number",
                                                 "bluetooth_address"}));
}

// ---- sabus vectors errata --update -------------------------------------------------

// What is not a regular file is not replaced (/dev/null read as an empty
// errata file); a copy of ERRATA.md with one entry's vector list out of date
// is rewritten whole, the only file in its folder after, a link to it kept.
TEST_F(JsonOutputs, ErrataUpdateReplacesOnlyTheFileItIsGivenWhole) {
  const Output device = sabus({"vectors", "errata", "--update", "/dev/null"});
  EXPECT_EQ(device.status, 1) << device.out;
  EXPECT_EQ(device.out, "") << "nothing said to be updated";

  const std::string errata = test::slurp(SABUS_SOURCE_DIR "/protocol/ERRATA.md");
  const auto at = errata.find("- **Vectors:** `");
  ASSERT_NE(at, std::string::npos);
  std::string stale = errata;
  stale.replace(at, errata.find('\n', at) - at, "- **Vectors:** `gone`");
  write("ERRATA.md", stale);
  fs::create_symlink(path("ERRATA.md"), path("link.md"));
  const Output o = sabus({"vectors", "errata", "--update", path("link.md")});
  EXPECT_EQ(o.status, 0) << o.out;
  EXPECT_EQ(o.out, "updated 1 entry of " + path("link.md") + "\n");
  EXPECT_EQ(test::slurp(path("ERRATA.md")), errata);
  EXPECT_TRUE(fs::is_symlink(path("link.md")));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), {}), 2) << "no temporary left";
  EXPECT_EQ(sabus({"vectors", "errata", "--check", path("ERRATA.md")}).status, 0);
}

// --classes: one line per entry ("E-10 reading reference|other", "E-1 text"),
// then the counts; a copy with one Class line removed exits 1.
TEST_F(JsonOutputs, ErrataClassesListsEveryEntryThenTheCounts) {
  const Output o = sabus({"vectors", "errata", "--classes", SABUS_SOURCE_DIR "/protocol/ERRATA.md"});
  EXPECT_EQ(o.status, 0) << o.out;
  std::istringstream in(o.out);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_GE(lines.size(), 96u) << o.out;
  const std::regex entry(R"(E-[0-9]+ (text|reading|withdrawn)( reference\|other(\|other-[0-9]+)*)?)");
  for (std::size_t k = 0; k + 1 < lines.size(); ++k) EXPECT_TRUE(std::regex_match(lines[k], entry)) << lines[k];
  EXPECT_TRUE(std::regex_match(lines.back(), std::regex(R"(errata: [0-9]+ text, [0-9]+ reading, [0-9]+ withdrawn)")))
      << lines.back();

  std::string errata = test::slurp(SABUS_SOURCE_DIR "/protocol/ERRATA.md");
  const auto at = errata.find("- **Class:** ");
  ASSERT_NE(at, std::string::npos);
  errata.erase(at, errata.find('\n', at) + 1 - at);
  write("ERRATA.md", errata);
  EXPECT_EQ(sabus({"vectors", "errata", "--classes", path("ERRATA.md")}).status, 1);
  EXPECT_EQ(sabus({"vectors", "errata", "--check", path("ERRATA.md")}).status, 1);
}

}  // namespace
}  // namespace sabus::harness
