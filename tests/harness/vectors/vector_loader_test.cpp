// Conformance vectors: the shipped files load and lint clean and pass against
// the reference controller (and fail against the faults they target); every
// class of load error with its line, column, vector id and key; lint's rules;
// raw templates and requirements; and no input makes the loader throw or
// hang. One suite, `vectors`, so that `ctest -R vectors` selects these tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::harness {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> shipped_files() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(default_vectors_dir()))
    if (e.path().extension() == ".yaml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string all_errors(const std::vector<LoadError>& errors) {
  std::string out;
  for (const auto& e : errors) out += "  " + e.text() + "\n";
  return out;
}

VectorFile load_ok(const std::string& yaml, const std::string& name = "test.yaml") {
  LoadResult r = load_vector_text(yaml, name);
  EXPECT_TRUE(r.ok()) << all_errors(r.errors) << "--- input:\n" << yaml;
  EXPECT_EQ(r.files.size(), r.ok() ? 1u : 0u);
  return r.files.empty() ? VectorFile{} : r.files[0];
}

// 1-based line and column of the n-th occurrence (from 1) of `token`.
std::pair<int, int> position_of(std::string_view yaml, std::string_view token, int occurrence = 1) {
  std::size_t at = std::string_view::npos, from = 0;
  for (int i = 0; i < occurrence; ++i, from = at + 1) at = yaml.find(token, from);
  if (at == std::string_view::npos) {
    ADD_FAILURE() << "token not in the input: " << token;
    return {0, 0};
  }
  const std::size_t line_start = yaml.rfind('\n', at == 0 ? 0 : at - 1);
  const int line = 1 + static_cast<int>(std::count(yaml.begin(), yaml.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  const int column = static_cast<int>(at - (line_start == std::string_view::npos || at == 0 ? std::size_t(-1) : line_start));
  return {line, column};
}

struct Want {
  std::string token;  // where the error points: the first character of this text
  int occurrence = 1;
  std::string id, key, message;
};

// Exactly one error, at the token, with this id, key and part of the message.
void expect_error(const std::string& yaml, const Want& w) {
  LoadResult r = load_vector_text(yaml, "test.yaml");
  ASSERT_EQ(r.errors.size(), 1u) << all_errors(r.errors) << "--- input:\n" << yaml;
  EXPECT_TRUE(r.files.empty());
  const LoadError& e = r.errors[0];
  const auto [line, column] = position_of(yaml, w.token, w.occurrence);
  EXPECT_EQ(e.where.file, "test.yaml");
  EXPECT_EQ(e.where.line, line) << e.text();
  EXPECT_EQ(e.where.column, column) << e.text();
  EXPECT_EQ(e.vector_id, w.id) << e.text();
  EXPECT_EQ(e.key, w.key) << e.text();
  EXPECT_NE(e.message.find(w.message), std::string::npos) << e.text() << "\n  expected to contain: " << w.message;
}

// A 3.2 file with one vector (id, spec paragraph, level) of one wait step;
// `extra` comes after the comment (line 5).
std::string vector_text(const std::string& id, const std::string& paragraph, const std::string& level,
                        const std::string& extra = "") {
  return "paragraph: \"3.2\"\ntitle: t\nvectors:\n  - id: " + id + "\n    comment: c\n" + extra + "    spec: {paragraph: \"" +
         paragraph + "\", quote: q}\n    level: " + level + "\n    steps: [{wait_ms: 1}]\n";
}

// A 3.2 file with one vector "3.2-x" whose steps follow (indented by six).
const std::string kHead = "paragraph: \"3.2\"\ntitle: t\nvectors:\n";
std::string one_vector(const std::string& steps, const std::string& extra = "") {
  return kHead + "  - id: 3.2-x\n    comment: c\n    spec: {paragraph: \"3.2\", quote: q}\n    level: must\n" + extra +
         "    steps:\n" + steps;
}

// ---------------------------------------------------------------------------
// The shipped suite
// ---------------------------------------------------------------------------

TEST(vectors, ShippedFilesLoadAndLintClean) {
  const auto files = shipped_files();
  EXPECT_GE(files.size(), 3u);
  LoadResult r = load_vectors({default_vectors_dir()});
  EXPECT_TRUE(r.ok()) << all_errors(r.errors);
  EXPECT_EQ(r.files.size(), files.size());  // profiles/ and examples/ are skipped
  const auto errors = lint(r.files);
  EXPECT_TRUE(errors.empty()) << all_errors(errors);
  std::size_t vectors = 0;
  for (const auto& f : r.files) {
    EXPECT_FALSE(f.vectors.empty()) << f.path;
    vectors += f.vectors.size();
    for (const auto& v : f.vectors) {
      EXPECT_FALSE(v.comment.empty()) << v.id;
      EXPECT_FALSE(v.quote.empty()) << v.id;
      EXPECT_EQ(v.id.rfind(f.paragraph + "-", 0), 0u) << v.id;
    }
  }
  EXPECT_GE(vectors, 12u);
}

TEST(vectors, ShippedFilesHaveTheStarterVectors) {
  LoadResult r = load_vectors({default_vectors_dir()});
  std::set<std::string> ids;
  for (const auto& f : r.files)
    for (const auto& v : f.vectors) ids.insert(v.id);
  for (const char* id : {"framing-check-byte-stx", "framing-stx-stx-restart", "framing-bad-lrc-silence",
                         "framing-chunks-with-pauses", "3.1-device-type-reply-length", "3.1-device-type-controller-3k",
                         "3.1-device-type-version-format", "3.2-status-reply-length", "3.2-status-reserved-bytes",
                         "3.2-status-agc-right-justified", "3.2-status-binary-high-bits"})
    EXPECT_TRUE(ids.count(id)) << id;
}

// ---------------------------------------------------------------------------
// Against the reference controller (until the runner exists): the shipped
// vectors pass, and each fails against the injected fault it is there to catch.
// ---------------------------------------------------------------------------

// The fields of a reply that a matcher names: all of them (31h has two "reserved").
std::vector<const FieldDescription*> fields_named(const FrameDescription& d, const std::string& name) {
  std::vector<const FieldDescription*> out;
  for (const auto& f : d.fields)
    if (f.name == name) out.push_back(&f);
  return out;
}

std::string matcher_text(const FieldDescription& f) {
  std::string s = f.raw;
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

bool matches(const FieldMatcher& m, const FieldDescription& f) {
  const std::string got = matcher_text(f);
  switch (m.kind) {
    case FieldMatcher::Kind::kAny: return true;
    case FieldMatcher::Kind::kEq:
    case FieldMatcher::Kind::kOneOf: return std::find(m.values.begin(), m.values.end(), got) != m.values.end();
    case FieldMatcher::Kind::kRegex: return std::regex_search(got, std::regex(m.values[0]));
    case FieldMatcher::Kind::kRange:
    case FieldMatcher::Kind::kNear:
    case FieldMatcher::Kind::kJogged: return false;  // not used by the starter files
  }
  return false;
}

struct Bench {
  explicit Bench(FaultSet faults) : bus({profile}, clock, faults, Parity::kNone) {}
  Profile profile;
  VirtualClock clock;
  Bus bus;

  Bytes frame(const Step& s) {
    if (s.raw) return expand_raw_bytes(expand_raw_expressions(s.raw->hex, ExprContext{profile}).text, profile.address).value();
    const CommandInfo* info = find_command(s.command->command);
    return encode_request(build_request(*info, s.command->form, s.command->fields).value(), profile.address);
  }
  Bytes exchange(const Step& s) {
    Bytes f = frame(s);
    if (s.modifiers.lrc_xor) f.back() ^= *s.modifiers.lrc_xor;
    Bytes out;
    std::size_t at = 0;
    for (std::size_t n : s.modifiers.chunks) {
      bus.receive(ByteView(f).subspan(at, n), out);
      clock.advance(s.modifiers.pause);
      at += n;
    }
    bus.receive(ByteView(f).subspan(at), out);
    return out;
  }
  // "" when the step's expectation holds, else why not.
  std::string check(const Step& s) {
    const Bytes reply = exchange(s);
    const Expectation& e = s.expect;
    if (e.kind == Expectation::Kind::kSilence) return reply.empty() ? "" : "a reply to a frame that must be ignored";
    if (reply.empty()) return "no reply";
    const FrameDescription d = describe_frame(reply);
    if (e.kind == Expectation::Kind::kAck && (reply[0] != ACK || d.error)) return "not a good ACK reply: " + d.summary;
    for (const auto& m : e.fields)
      for (const FieldDescription* f : fields_named(d, m.field))
        if (!matches(m, *f)) return m.field + " is " + f->raw;
    return "";
  }
  std::string run(const Vector& v) {
    for (const auto* list : {&v.setup, &v.steps, &v.teardown})
      for (const auto& s : *list)
        if (auto why = check(s); !why.empty()) return why;
    return "";
  }
};

std::map<std::string, Vector> shipped_vectors() {
  std::map<std::string, Vector> out;
  for (const auto& f : load_vectors({default_vectors_dir()}).files)
    for (const auto& v : f.vectors) out.emplace(v.id, v);
  return out;
}

// That every shipped vector passes on every shipped profile is checked with the
// runner itself (runner_test.cpp: Runner.ShippedVectorsPassOnTheShippedProfiles):
// the vectors use requirements, captures and whole-reply templates.

TEST(vectors, ShippedVectorsCatchTheirFaults) {
  const std::pair<const char*, Fault> cases[] = {
      {"framing-check-byte-stx", Fault::kCheckByteStxRestarts},
      {"framing-stx-stx-restart", Fault::kNoStxStxRestart},
      {"framing-bad-lrc-silence", Fault::kNakBadCheckByte},
      {"3.1-device-type-reply-length", Fault::kDropsReplyByte},
      {"3.1-device-type-version-format", Fault::kDeviceTypeNoDot},
      {"3.2-status-reply-length", Fault::kShortStatus},
      {"3.2-status-binary-high-bits", Fault::kWrongNibbleBase},
  };
  const auto vectors = shipped_vectors();
  for (const auto& [id, fault] : cases) {
    ASSERT_TRUE(vectors.count(id)) << id;
    Bench bench({fault});
    EXPECT_NE(bench.run(vectors.at(id)), "") << id << " passes with the fault it should catch";
  }
}

// ---------------------------------------------------------------------------
// A file using every feature reads into the data model
// ---------------------------------------------------------------------------

const std::string kFullFile = R"(paragraph: "3.3"
title: Auto move
notes:
  RemoteAutoMove: {description: az status 0x57 while moving, errata: E-13}
requires: {polarization: [single_port, dual_port]}
groups:
  - comment: moves
    requires:
      - dvb_receiver: false
      - errata.implements_iess: false
    level: should
    tags: [motion]
    flags: [RemoteAutoMove]
    setup:
      - send: {command: status}
        expect: {reply: ack, fields: {track: {capture: $track}}}
    teardown:
      - send: {command: jog, form: X, fields: {speed: S, duration: 0}}
        expect: ack
    vectors:
      - id: 3.3-form2A-basic
        comment: every feature
        spec: {paragraph: "3.3", quote: "For this form of the auto move command, only the blank character is accepted in the polarization field."}
        level: must
        tags: [timing]
        requires: {address: "2"}
        steps:
          - send: {command: auto_move, form: 2a, fields: {azimuth: "{home(az)}", elevation: "{at(el, 0.5)}"}, address: 51}
            expect: {reply: ack, fields: {"az status": {eq: 0x47}, azimuth: {range: ["{home(az) - 0.1}", "{home(az) + 0.1}"]}, "sat name": {one_of: ["SBS 6", ""]}, agc: {regex: "^ *[0-9]+$"}, "el status": any, pol status: 0x40}}
          - poll: {send: {command: status}, until: {"az status": 0x40, elevation: {near: "{at(el, 0.5)}"}}, interval_ms: 2000, expect: ack}
          - wait: {ms: 1100}
          - wait_ms: 1200
          - send: {raw: "02 {addr} 31 03 {lrc}"}
            modify: {lrc_xor: 0x01, address: 0x33, parity_flip: [1], extra_data_bytes: 1, truncate: 2, replace: [[3, 0x05]], chunks: [2, 1], pause_ms: 50}
            expect: silence
          - send: {raw: "02 {addr} 35 {$track} 03 {lrc}"}
            expect: {reply: any, bytes: "06 {addr} 35 30 31 30 31 53 42 53 20 36 20 20 20 20 20 03 {lrc}"}
          - send: {raw: "02 {addr} 31 41 03 {lrc}"}
            length_mismatch: true
            expect: nak
)";

TEST(vectors, EveryFeatureReadsIntoTheModel) {
  VectorFile f = load_ok(kFullFile);
  ASSERT_EQ(f.vectors.size(), 1u);
  EXPECT_EQ(f.paragraph, "3.3");
  ASSERT_EQ(f.notes.count("RemoteAutoMove"), 1u);
  EXPECT_EQ(f.notes.at("RemoteAutoMove").errata, "E-13");
  EXPECT_EQ(f.notes.at("RemoteAutoMove").where.line, 4);
  const Vector& v = f.vectors[0];
  EXPECT_EQ(v.id, "3.3-form2A-basic");
  EXPECT_EQ(v.paragraph, "3.3");
  EXPECT_EQ(v.level, Level::kMust);  // the vector's level over the group's
  EXPECT_EQ(v.where.text(), "test.yaml:21:9");
  EXPECT_EQ(v.tags, (std::vector<std::string>{"motion", "timing"}));
  EXPECT_EQ(v.flags, (std::vector<std::string>{"RemoteAutoMove"}));

  // Requirements: the file's, the group's, the vector's; values as to_yaml writes them.
  ASSERT_EQ(v.requires_.size(), 4u);
  EXPECT_EQ(v.requires_[0].key, "polarization");
  EXPECT_EQ(v.requires_[0].values, (std::vector<std::string>{"single_port", "dual_port"}));
  EXPECT_EQ(v.requires_[1].key, "dvb_receiver");
  EXPECT_EQ(v.requires_[2].key, "errata.implements_iess");
  EXPECT_EQ(v.requires_[2].values, (std::vector<std::string>{"false"}));
  EXPECT_EQ(v.requires_[3].key, "address");
  EXPECT_EQ(v.requires_[3].values, (std::vector<std::string>{"50"}));  // "2" is address 50

  // Setup and teardown: the group's around the vector's.
  ASSERT_EQ(v.setup.size(), 1u);
  ASSERT_EQ(v.teardown.size(), 1u);
  EXPECT_EQ(v.teardown[0].command->form, "X");

  ASSERT_EQ(v.steps.size(), 7u);
  const Step& move = v.steps[0];
  EXPECT_EQ(move.kind, Step::Kind::kSend);
  EXPECT_EQ(move.command->command, "auto_move");
  EXPECT_EQ(move.command->form, "2A");  // the catalog's spelling
  EXPECT_EQ(move.command->fields.at("azimuth"), "{home(az)}");  // profile expressions, computed at run time
  EXPECT_EQ(move.command->fields.at("elevation"), "{at(el, 0.5)}");
  EXPECT_EQ(move.command->address, std::optional<std::uint8_t>(0x33));
  const auto& m = move.expect.fields;
  ASSERT_EQ(m.size(), 6u);
  EXPECT_EQ(m[0].field, "az status");
  EXPECT_EQ(m[0].kind, FieldMatcher::Kind::kEq);
  EXPECT_EQ(m[0].values, (std::vector<std::string>{"0x47"}));  // the text as written
  EXPECT_EQ(m[1].kind, FieldMatcher::Kind::kRange);
  EXPECT_EQ(m[1].values, (std::vector<std::string>{"{home(az) - 0.1}", "{home(az) + 0.1}"}));
  EXPECT_EQ(m[2].kind, FieldMatcher::Kind::kOneOf);
  EXPECT_EQ(m[2].values, (std::vector<std::string>{"SBS 6", ""}));
  EXPECT_EQ(m[3].kind, FieldMatcher::Kind::kRegex);
  EXPECT_EQ(m[4].kind, FieldMatcher::Kind::kAny);
  EXPECT_EQ(m[5].kind, FieldMatcher::Kind::kEq);  // a scalar is eq
  EXPECT_EQ(v.setup[0].expect.fields[0].capture, "$track");

  const Step& poll = v.steps[1];
  EXPECT_EQ(poll.kind, Step::Kind::kPoll);
  EXPECT_EQ(poll.timeout, std::chrono::milliseconds(0));  // derived by the runner from distance and speed
  EXPECT_EQ(poll.interval, std::chrono::milliseconds(2000));
  EXPECT_EQ(poll.until[0].values, (std::vector<std::string>{"0x40"}));
  EXPECT_EQ(poll.until[1].kind, FieldMatcher::Kind::kNear);
  EXPECT_EQ(poll.until[1].values, (std::vector<std::string>{"{at(el, 0.5)}"}));
  EXPECT_EQ(v.steps[2].kind, Step::Kind::kWait);
  EXPECT_EQ(v.steps[2].timeout, std::chrono::milliseconds(1100));
  EXPECT_EQ(v.steps[3].timeout, std::chrono::milliseconds(1200));

  const Modifiers& mod = v.steps[4].modifiers;
  EXPECT_EQ(mod.lrc_xor, std::optional<std::uint8_t>(0x01));
  EXPECT_EQ(mod.address, std::optional<std::uint8_t>(0x33));
  EXPECT_EQ(mod.parity_flip, (std::vector<std::size_t>{1}));
  EXPECT_EQ(mod.extra_data_bytes, 1u);
  EXPECT_EQ(mod.truncate, 2u);
  EXPECT_EQ(mod.replace, (std::vector<std::pair<std::size_t, std::uint8_t>>{{3, 0x05}}));
  EXPECT_EQ(mod.chunks, (std::vector<std::size_t>{2, 1}));
  EXPECT_EQ(mod.pause, std::chrono::milliseconds(50));
  EXPECT_EQ(v.steps[4].expect.kind, Expectation::Kind::kSilence);
  EXPECT_EQ(v.steps[5].raw->hex, "02 {addr} 35 {$track} 03 {lrc}");
  EXPECT_TRUE(v.steps[5].expect.bytes.has_value());
  EXPECT_EQ(v.steps[6].expect.kind, Expectation::Kind::kNak);
  EXPECT_TRUE(lint({f}).empty()) << all_errors(lint({f}));
}

// The examples of vectors/README.md, as one vector.
TEST(vectors, ReadmeExamplesLoad) {
  load_ok(one_vector(R"(      - send: {command: status}
        modify: {lrc_xor: 0x01}
        expect: silence
      - send: {command: status}
        modify: {address: 0x33}
        expect: silence
      - send: {command: status}
        modify: {parity_flip: [1]}
        expect: silence
      - send: {command: status}
        modify: {extra_data_bytes: 1}
        expect: nak
      - send: {command: device_type}
        modify: {truncate: 2}
        expect: silence
      - send: {command: status}
        modify: {replace: [[3, 0x05]]}
        expect: silence
      - send: {command: status}
        modify: {chunks: [2, 3], pause_ms: 50}
        expect: ack
      - send: {raw: "02 {addr} 31 41 03 {lrc}"}
        length_mismatch: true
        expect: nak
      - send: {raw: "02 02 {addr} 31 03 {lrc}"}
        expect: ack
      - send: {command: device_type}
        expect:
          reply: ack
          bytes: "06 {addr} 30 33 4b 31 2e 35 39 03 {lrc}"
          fields: {version: "1.59"}
      - send: {command: status}
        expect:
          reply: ack
          fields:
            "az status": {eq: 0x47}
            azimuth: {range: [-152.6, -152.4]}
            "sat name": {one_of: ["SBS 6", ""]}
            agc: {regex: "^ *[0-9]+$"}
            "el status": any
            track: {capture: $track}
      - poll:
          send: {command: status}
          until: {"az status": {eq: 0x40}}
          timeout_ms: 120000
          interval_ms: 1000
          expect: ack
      - wait: {ms: 1100}
      - wait_ms: 1100
)"));
}

// ---------------------------------------------------------------------------
// Load errors: line, column, id and key of each class
// ---------------------------------------------------------------------------

TEST(vectors, UnknownKeys) {
  expect_error(kHead + "titel: x\n", {"titel", 1, "", "titel", "unknown key \"titel\"; allowed keys: paragraph, title"});
  expect_error(one_vector("      - send: {command: status}\n        expekt: ack\n"),
               {"expekt", 1, "3.2-x", "steps[0].expekt", "unknown key \"expekt\""});
  expect_error(one_vector("      - send: {command: status, adress: 51}\n        expect: ack\n"),
               {"adress", 1, "3.2-x", "steps[0].send.adress", "unknown key"});
  expect_error(kHead.substr(0, kHead.size() - 9) + "groups:\n  - levl: must\n    vectors: []\n",
               {"levl", 1, "", "groups[0].levl", "unknown key \"levl\""});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {eq: 1, regexp: x}}}\n"),
               {"regexp", 1, "3.2-x", "steps[0].expect.fields.agc.regexp", "unknown key"});
}

TEST(vectors, DuplicateKeysAtEveryLevel) {
  expect_error("paragraph: \"3.2\"\ntitle: t\ntitle: u\nvectors: []\n",
               {"title", 2, "", "title", "duplicate key \"title\" (first at line 2, column 1)"});
  expect_error(one_vector("      - send: {command: status}\n        expect: ack\n", "    comment: again\n"),
               {"comment", 2, "3.2-x", "comment", "duplicate key \"comment\" (first at line 5, column 5)"});
  expect_error(one_vector("      - send: {command: auto_move, form: 2A, fields: {azimuth: 1, azimuth: 2}}\n        expect: ack\n"),
               {"azimuth", 2, "3.2-x", "steps[0].send.fields.azimuth", "duplicate key \"azimuth\""});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: any, agc: any}}\n"),
               {"agc", 2, "3.2-x", "steps[0].expect.fields.agc", "duplicate key"});
  expect_error(kHead + "  - id: 3.2-y\n    id: 3.2-z\n", {"id", 2, "3.2-y", "id", "duplicate key \"id\""});
  expect_error("paragraph: \"3.2\"\ntitle: t\nnotes:\n  A: {description: a}\n  A: {description: b}\nvectors: []\n",
               {"A:", 2, "", "notes.A", "duplicate key \"A\""});
}

TEST(vectors, WrongTypes) {
  expect_error(kHead + "  - id: 3.2-x\n    comment: c\n    spec: {paragraph: \"3.2\", quote: q}\n    level: must\n    steps: 5\n",
               {"steps", 1, "3.2-x", "steps", "expected a list, got \"5\""});
  expect_error(kHead + "  - id: 3.2-x\n    comment: [a]\n    spec: {paragraph: \"3.2\", quote: q}\n    level: must\n    steps: [{wait_ms: 1}]\n",
               {"comment", 1, "3.2-x", "comment", "expected text, got a list"});
  expect_error(one_vector("      - send: {command: status}\n        expect: ack\n", "    tags: motion\n"),
               {"tags", 1, "3.2-x", "tags", "expected a list"});
  expect_error(one_vector("      - poll: {send: {command: status}, until: {agc: any}, timeout_ms: \"1000\"}\n"),
               {"timeout_ms", 1, "3.2-x", "steps[0].poll.timeout_ms", "the quoted string \"1000\""});
  expect_error(one_vector("      - send: {command: status}\n        expect: ack\n        length_mismatch: yes\n"),
               {"length_mismatch", 1, "3.2-x", "steps[0].length_mismatch", "expected true or false"});
}

TEST(vectors, MissingKeys) {
  expect_error(kHead + "  - comment: c\n", {"comment", 1, "", "id", "a vector needs id"});
  expect_error(kHead + "  - id: 3.2-x\n    comment: c\n", {"id", 1, "3.2-x", "spec", "a vector needs spec"});
  expect_error(one_vector("      - send: {command: status}\n"), {"send", 1, "3.2-x", "steps[0].expect", "a send needs expect"});
  expect_error(kHead + "  - id: 3.2-x\n    comment: c\n    spec: {paragraph: \"3.2\", quote: q}\n    steps: [{wait_ms: 1}]\n",
               {"id", 1, "3.2-x", "level", "a vector needs level"});
  expect_error("title: t\nvectors: []\n", {"title", 1, "", "paragraph", "a vector file needs paragraph"});
  expect_error(one_vector("      - send: {command: jog}\n        expect: ack\n"),
               {"send", 1, "3.2-x", "steps[0].send.form", "jog needs form: one of E, W, D, U, O, L, X"});
}

TEST(vectors, CommandsFormsAndFieldsAreTheCatalogs) {
  expect_error(one_vector("      - send: {command: statuss}\n        expect: ack\n"),
               {"command", 1, "3.2-x", "steps[0].send.command", "unknown command \"statuss\""});
  expect_error(one_vector("      - send: {command: auto_move, form: 9}\n        expect: ack\n"),
               {"form", 1, "3.2-x", "steps[0].send.form", "unknown form \"9\" of auto_move: expected one of 1, 2A, 2B, 2C, 3"});
  expect_error(one_vector("      - send: {command: status, form: X}\n        expect: ack\n"),
               {"form", 1, "3.2-x", "steps[0].send.form", "status has one form: leave form out"});
  expect_error(one_vector("      - send: {command: auto_move, form: 2A, fields: {azimut: 1}}\n        expect: ack\n"),
               {"azimut", 1, "3.2-x", "steps[0].send.fields.azimut",
                "unknown field \"azimut\" of auto_move form 2A; its fields: polarization, azimuth, elevation"});
  // build_request's own error, at the field it names.
  expect_error(one_vector("      - send: {command: auto_move, form: 2A, fields: {elevation: 4, azimuth: abc}}\n        expect: ack\n"),
               {"azimuth", 1, "3.2-x", "steps[0].send.fields.azimuth", "field \"azimuth\": expected a number"});
  // Codes work too: "32h" is auto move.
  load_ok(one_vector("      - send: {command: 32h, form: \"3\", fields: {pol target: 50.0}}\n        expect: ack\n",
                     "    tags: [motion]\n"));
}

TEST(vectors, ReplyFieldNamesAreDescribeFramesNames) {
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {azimut: any}}\n"),
               {"azimut", 1, "3.2-x", "steps[0].expect.fields.azimut", "unknown field \"azimut\" of the status reply"});
  // A raw send: the command byte of the frame (30h) decides.
  expect_error(one_vector("      - send: {raw: \"02 {addr} 30 03 {lrc}\"}\n        expect: {reply: ack, fields: {azimuth: any}}\n"),
               {"azimuth", 1, "3.2-x", "steps[0].expect.fields.azimuth", "of the device_type reply"});
  // Unreadable command byte (a capture before it): names are not checked.
  load_ok(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {command: {capture: $c}}}\n"
                     "      - send: {raw: \"02 {addr} {$c} 03 {lrc}\"}\n        expect: {reply: ack, fields: {whatever: any}}\n"));
  // NAK and offline replies have the frame fields only (§3), whatever the command.
  expect_error(one_vector("      - send: {raw: \"02 {addr} 29 03 {lrc}\"}\n        expect: {reply: nak, fields: {agc: any}}\n"),
               {"agc", 1, "3.2-x", "steps[0].expect.fields.agc", "unknown field \"agc\" of the NAK reply (§3)"});
  load_ok(one_vector("      - send: {raw: \"02 {addr} 29 03 {lrc}\"}\n        expect: {reply: nak, fields: {command: 0x29}}\n"
                     "      - send: {command: status}\n        expect: {reply: offline, fields: {offline: 0x46}}\n"));
  expect_error(one_vector("      - poll: {send: {command: status}, until: {azimut: any}, timeout_ms: 1000}\n"),
               {"azimut", 1, "3.2-x", "steps[0].poll.until.azimut", "unknown field"});
}

TEST(vectors, RawTemplates) {
  expect_error(one_vector("      - send: {raw: \"02 {addr} 3G 03 {lrc}\"}\n        expect: ack\n"),
               {"raw", 1, "3.2-x", "steps[0].send.raw", "bad hex at character 12: expected a hex digit, got \"G\""});
  expect_error(one_vector("      - send: {raw: \"02 {adr} 31 03 {lrc}\"}\n        expect: ack\n"),
               {"raw", 1, "3.2-x", "steps[0].send.raw", "unknown placeholder {adr}"});
  expect_error(one_vector("      - send: {raw: \"02 {addr 31 03\"}\n        expect: ack\n"),
               {"raw", 1, "3.2-x", "steps[0].send.raw", "no closing '}'"});
  expect_error(one_vector("      - send: {raw: \"02 {addr} 31 {$x} 03 {lrc}\"}\n        expect: ack\n"),
               {"raw", 1, "3.2-x", "steps[0].send.raw", "no earlier step captures $x"});
  expect_error(one_vector("      - send: {raw: \"02 {addr} b1 03 {lrc}\"}\n        expect: ack\n"),
               {"raw", 1, "3.2-x", "steps[0].send.raw", "byte 0xb1 is not a 7-bit character"});
  expect_error(one_vector("      - send: {raw: \"02 {addr} 31 03 {lrc}\", address: 51}\n        expect: ack\n"),
               {"address", 1, "3.2-x", "steps[0].send.address", "a raw send has no address"});
}

TEST(vectors, RawLengthsFollowTheCatalog) {
  expect_error(one_vector("      - send: {raw: \"02 {addr} 31 41 03 {lrc}\"}\n        expect: nak\n"),
               {"raw", 1, "3.2-x", "steps[0].send.raw",
                "the frame is 6 bytes; the catalog says 5 for status (§3.2). If that is the test, write length_mismatch: true"});
  load_ok(one_vector("      - send: {raw: \"02 {addr} 31 41 03 {lrc}\"}\n        length_mismatch: true\n        expect: nak\n"));
  expect_error(one_vector("      - send: {raw: \"02 {addr} 31 03 {lrc}\"}\n        length_mismatch: true\n        expect: ack\n"),
               {"length_mismatch", 1, "3.2-x", "steps[0].length_mismatch", "but the frame has the catalog length of status (5 bytes)"});
  expect_error(one_vector("      - send: {command: status}\n        length_mismatch: true\n        expect: ack\n"),
               {"length_mismatch", 1, "3.2-x", "steps[0].length_mismatch", "length_mismatch is for raw sends"});
  // The frame starts at the STX before the address: STX STX and noise first are 5-byte polls.
  load_ok(one_vector("      - send: {raw: \"02 02 {addr} 31 03 {lrc}\"}\n        expect: ack\n"
                     "      - send: {raw: \"41 42 02 {addr} 31 03 {lrc}\"}\n        expect: ack\n"));
  // Modifiers that change the length need no flag; unknown codes are not checked.
  load_ok(one_vector("      - send: {command: status}\n        modify: {extra_data_bytes: 2}\n        expect: nak\n"
                     "      - send: {raw: \"02 {addr} 29 03 {lrc}\"}\n        expect: nak\n"));
  expect_error(one_vector("      - poll: {send: {raw: \"02 {addr} 31 41 03 {lrc}\"}, until: {agc: any}, timeout_ms: 1000}\n"),
               {"raw", 1, "3.2-x", "steps[0].poll.send.raw", "the frame is 6 bytes"});
}

TEST(vectors, ExpectationsAndMatchers) {
  expect_error(one_vector("      - send: {command: status}\n        expect: maybe\n"),
               {"expect", 1, "3.2-x", "steps[0].expect", "\"maybe\" is not a reply"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: silence, fields: {agc: any}}\n"),
               {"fields", 1, "3.2-x", "steps[0].expect.fields", "silence has no fields"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, bytes: \"06 {addr} 31 03 {lrc}\"}\n"),
               {"bytes", 1, "3.2-x", "steps[0].expect.bytes", "the reply is 5 bytes, not 52 (the catalog's reply to status)"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: nak, bytes: \"06 {addr} 31 03 {lrc}\"}\n"),
               {"bytes", 1, "3.2-x", "steps[0].expect.bytes", "a nak reply starts with 0x15"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {regex: \"((\"}}}\n"),
               {"regex", 1, "3.2-x", "steps[0].expect.fields.agc.regex", "bad regex"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {regex: \"((a{99}){99}){99}\"}}}\n"),
               {"regex", 1, "3.2-x", "steps[0].expect.fields.agc.regex", "bounded repeats"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {\"az status\": 0x4A}}\n"),
               {"\"az status\"", 1, "3.2-x", "steps[0].expect.fields.az status", "lower case (0x4a)"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {eq: 1, regex: x}}}\n"),
               {"agc", 1, "3.2-x", "steps[0].expect.fields.agc", "give one of eq, one_of, regex, range"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {range: [9, 1]}}}\n"),
               {"range", 1, "3.2-x", "steps[0].expect.fields.agc.range", "low 9 is above high 1"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {capture: track}}}\n"),
               {"capture", 1, "3.2-x", "steps[0].expect.fields.agc.capture", "is not a capture name"});
}

TEST(vectors, LevelsParagraphsAndIds) {
  expect_error(vector_text("3.2-x", "3.2", "shall"), {"level", 1, "3.2-x", "level", "\"shall\" is not a level: must, should, informative"});
  expect_error(vector_text("3.2-x", "3.3", "must"), {"paragraph", 2, "3.2-x", "spec.paragraph", "the file is about §3.2"});
  expect_error(vector_text("3.2-x", "3.26", "must"), {"paragraph", 2, "3.2-x", "spec.paragraph", "is not a paragraph of the spec"});
  expect_error(vector_text("3.3-x", "3.2", "must"), {"id", 1, "3.3-x", "id", "an id in this file starts with \"3.2-\""});
  expect_error(vector_text("\"3.2 x\"", "3.2", "must"), {"id", 1, "", "id", "is not an id"});
  expect_error("paragraph: framming\ntitle: t\nvectors: []\n", {"paragraph", 1, "", "paragraph", "nor a cross-cutting topic"});
  // A cross-cutting file cites any paragraph.
  load_ok("paragraph: nak\ntitle: t\nvectors:\n  - id: nak-x\n    comment: c\n    spec: {paragraph: \"3\", quote: q}\n"
          "    level: must\n    steps: [{wait_ms: 1}]\n");
}

TEST(vectors, RequirementsAreProfileKeys) {
  expect_error(one_vector("      - wait_ms: 1\n", "    requires: {polarisation: circular}\n"),
               {"polarisation", 1, "3.2-x", "requires.polarisation", "unknown key \"polarisation\""});
  expect_error(one_vector("      - wait_ms: 1\n", "    requires: {polarization: [circular, linear]}\n"),
               {"linear", 1, "3.2-x", "requires.polarization[1]", "\"linear\" is not one of circular, single_port, dual_port"});
  expect_error(one_vector("      - wait_ms: 1\n", "    requires: {errata.implements_iss: true}\n"),
               {"errata.implements_iss", 1, "3.2-x", "requires.errata.implements_iss", "errata.implements_iss: unknown key"});
  expect_error(one_vector("      - wait_ms: 1\n", "    requires: {errata: {implements_iess: true}}\n"),
               {"errata", 1, "3.2-x", "requires.errata", "write nested profile keys dotted"});
  expect_error(one_vector("      - wait_ms: 1\n", "    requires: {store: x}\n"),
               {"store", 1, "3.2-x", "requires.store", "expected a list"});
  expect_error(one_vector("      - wait_ms: 1\n", "    requires: {dvb_receiver: \"true\"}\n"),
               {"dvb_receiver", 1, "3.2-x", "requires.dvb_receiver", "the quoted string"});
  // The list form; values compared as the profile writer spells them.
  VectorFile f = load_ok(one_vector("      - wait_ms: 1\n", "    requires: [{address: 0x32}, {track.band: K}]\n"));
  ASSERT_EQ(f.vectors.at(0).requires_.size(), 2u);
  EXPECT_EQ(f.vectors[0].requires_[0].values, (std::vector<std::string>{"50"}));
  EXPECT_EQ(f.vectors[0].requires_[1].key, "track.band");
}

TEST(vectors, ModifiersAreCheckedAgainstTheFrame) {
  expect_error(one_vector("      - send: {command: status}\n        modify: {truncate: 5}\n        expect: silence\n"),
               {"truncate", 1, "3.2-x", "steps[0].modify.truncate", "5 is out of range 1 to 4"});
  expect_error(one_vector("      - send: {command: status}\n        modify: {parity_flip: [5]}\n        expect: silence\n"),
               {"5]", 1, "3.2-x", "steps[0].modify.parity_flip[0]", "5 is out of range 0 to 4"});
  expect_error(one_vector("      - send: {command: status}\n        modify: {pause_ms: 50}\n        expect: ack\n"),
               {"pause_ms", 1, "3.2-x", "steps[0].modify.pause_ms", "give chunks too"});
  expect_error(one_vector("      - send: {command: status}\n        modify: {chunks: [3, 3]}\n        expect: ack\n"),
               {"chunks", 1, "3.2-x", "steps[0].modify.chunks", "add up to 6 bytes; the frame has 5"});
  expect_error(one_vector("      - send: {command: status}\n        modify: {lrc_xor: 0x80}\n        expect: silence\n"),
               {"lrc_xor", 1, "3.2-x", "steps[0].modify.lrc_xor", "out of range 1 to 127"});
  expect_error(one_vector("      - send: {command: status}\n        modify: {replace: [[1, 0x-0]]}\n        expect: silence\n"),
               {"[1, 0x-0", 1, "3.2-x", "steps[0].modify.replace[0]", "expected 0xNN, got \"0x-0\""});
  expect_error(one_vector("      - send: {command: status}\n        modify: {}\n        expect: ack\n"),
               {"modify", 1, "3.2-x", "steps[0].modify", "no change given"});
  expect_error(one_vector("      - wait_ms: 1\n        modify: {truncate: 1}\n"),
               {"modify", 1, "3.2-x", "steps[0].modify", "modify belongs to a send step"});
}

TEST(vectors, StepsPollsAndWaits) {
  expect_error(one_vector("      - {send: {command: status}, wait_ms: 5}\n"),
               {"{send", 1, "3.2-x", "steps[0]", "a step is one of send, poll, survey, wait or wait_ms"});
  expect_error(one_vector("      - poll: {send: {command: status}, until: {agc: any}, timeout_ms: 5000, interval_ms: 500}\n"),
               {"interval_ms", 1, "3.2-x", "steps[0].poll.interval_ms", "500 is out of range 1000"});
  expect_error(one_vector("      - poll: {send: {command: status}, until: {agc: any}, timeout_ms: 1000, interval_ms: 2000}\n"),
               {"interval_ms", 1, "3.2-x", "steps[0].poll.interval_ms", "longer than timeout_ms"});
  expect_error(one_vector("      - poll: {send: {command: status}, until: {agc: any}, timeout_ms: 1000, expect: silence}\n"),
               {"expect", 1, "3.2-x", "steps[0].poll.expect", "a poll needs a reply"});
  // A survey (§4): its count and interval, named by key.
  expect_error(one_vector("      - survey: {send: {command: status}}\n"), {"survey", 1, "3.2-x", "steps[0].survey.count", "a survey needs count"});
  expect_error(one_vector("      - survey: {send: {command: status}, count: 9}\n"),
               {"count", 1, "3.2-x", "steps[0].survey.count", "9 is out of range 10"});
  expect_error(one_vector("      - survey: {send: {command: status}, count: 20, interval_ms: 999}\n"),
               {"interval_ms", 1, "3.2-x", "steps[0].survey.interval_ms", "999 is out of range 1000"});
  expect_error(one_vector("      - survey: {send: {command: status}, count: 20, until: {agc: any}}\n"),
               {"until", 1, "3.2-x", "steps[0].survey.until", "unknown key \"until\""});
  expect_error(one_vector("      - wait: {ms: 0}\n"), {"ms", 1, "3.2-x", "steps[0].wait.ms", "0 is out of range 1"});
  expect_error(kHead + "  - id: 3.2-x\n    comment: c\n    spec: {paragraph: \"3.2\", quote: q}\n    level: must\n    steps: []\n",
               {"steps", 1, "3.2-x", "steps", "at least one step"});
}

// precondition (vectors/README.md): words on a send or a poll of setup or
// steps; a load error on a wait, when empty, and on any step of a teardown
// (a vector's or a group's), at the key, with file:line:column.
TEST(vectors, PreconditionsAreForSendsAndPollsBeforeTheTeardown) {
  const VectorFile f = load_ok(one_vector("      - send: {command: extended_status}\n"
                                          "        expect: {reply: ack, fields: {current mode: 0x26}}\n"
                                          "        precondition: \"the search is still running when the stop goes out\"\n"
                                          "      - poll: {send: {command: status}, until: {agc: any}, timeout_ms: 5000}\n"
                                          "        precondition: the status answers\n"
                                          "      - send: {command: status}\n"
                                          "        expect: ack\n",
                                          "    setup:\n      - send: {command: status}\n        expect: ack\n"
                                          "        precondition: set up\n"));
  ASSERT_EQ(f.vectors.size(), 1u);
  const Vector& v = f.vectors[0];
  ASSERT_EQ(v.steps.size(), 3u);
  EXPECT_EQ(v.steps[0].precondition, "the search is still running when the stop goes out");
  EXPECT_EQ(v.steps[1].precondition, "the status answers");
  EXPECT_EQ(v.steps[2].precondition, "");
  ASSERT_EQ(v.setup.size(), 1u);
  EXPECT_EQ(v.setup[0].precondition, "set up");

  const std::string step = "      - send: {command: status}\n        expect: ack\n";
  const std::string teardown = "    teardown:\n" + step + "        precondition: the search runs\n";
  expect_error(one_vector(step, teardown), {"precondition", 1, "3.2-x", "teardown[0].precondition",
                                            "a teardown step has no precondition"});
  LoadResult r = load_vector_text(one_vector(step, teardown), "p.yaml");
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].text().rfind("p.yaml:11:9: [3.2-x] teardown[0].precondition: a teardown step has no precondition", 0), 0u)
      << r.errors[0].text();
  const std::string group = kHead.substr(0, kHead.size() - 9) +
                            "groups:\n  - level: must\n    teardown:\n      - send: {command: status}\n        expect: ack\n"
                            "        precondition: the search runs\n    vectors:\n      - id: 3.2-x\n        comment: c\n"
                            "        spec: {paragraph: \"3.2\", quote: q}\n        steps: [{wait_ms: 1}]\n";
  expect_error(group, {"precondition", 1, "", "groups[0].teardown[0].precondition", "a teardown step has no precondition"});
  expect_error(one_vector("      - wait_ms: 1000\n        precondition: time passes\n"),
               {"precondition", 1, "3.2-x", "steps[0].precondition", "a precondition belongs to a send or a poll step"});
  expect_error(one_vector(step + "        precondition: \"\"\n"),
               {"precondition", 1, "3.2-x", "steps[0].precondition", "say in words what must hold"});
  // precondition_reading: the switchable entry it rests on, with a precondition.
  expect_error(one_vector(step + "        precondition_reading: E-100\n"),
               {"precondition_reading", 1, "3.2-x", "steps[0].precondition_reading", "add the precondition"});
  expect_error(one_vector(step + "        precondition: TRACK peaks\n        precondition_reading: E-38\n"),
               {"precondition_reading", 1, "3.2-x", "steps[0].precondition_reading",
                "\"E-38\" is no ERRATA entry with a readings: switch"});
  const VectorFile on_reading = load_ok(one_vector(step + "        precondition: TRACK peaks\n        precondition_reading: E-100\n"));
  EXPECT_EQ(on_reading.vectors.at(0).steps.at(0).precondition_reading, "E-100");
  EXPECT_EQ(v.steps[0].precondition_reading, "") << "none unless written";
}

// each_slot: the steps read $slot, the setup and teardown may not; the list
// is one of the stored lists.
TEST(vectors, EachSlotBindsSlotInTheStepsOnly) {
  const std::string read = "      - send: {command: read_satellite, fields: {index: \"{$slot}\"}}\n"
                           "        expect: {reply: ack, from_profile: \"{$slot}\"}\n";
  const VectorFile f = load_ok(one_vector(read, "    each_slot: presets\n"));
  ASSERT_EQ(f.vectors.size(), 1u);
  EXPECT_EQ(f.vectors[0].each_slot, "presets");
  EXPECT_EQ(load_ok(one_vector("      - send: {command: query_name, fields: {index: \"{$slot}\"}}\n"
                               "        expect: {reply: ack, from_profile: \"{$slot}\"}\n",
                               "    each_slot: store\n"))
                .vectors.at(0)
                .each_slot,
            "store");
  expect_error(one_vector(read, "    each_slot: slots\n"),
               {"each_slot", 1, "3.2-x", "each_slot", "\"slots\" is not a stored list: presets, tles, signposts or store"});
  expect_error(one_vector(read), {"index: \"{$slot}", 1, "3.2-x", "steps[0].send.fields.index", "$slot is not captured by an earlier step"});
  expect_error(one_vector(read, "    each_slot: presets\n    setup:\n" + read),
               {"index: \"{$slot}", 1, "3.2-x", "setup[0].send.fields.index", "$slot is not captured by an earlier step"});
}

TEST(vectors, YamlSyntaxAndDocuments) {
  LoadResult syntax = load_vector_text("paragraph: \"3.2\"\ntitle: [\n", "test.yaml");
  ASSERT_EQ(syntax.errors.size(), 1u);
  EXPECT_GT(syntax.errors[0].where.line, 0);
  EXPECT_EQ(syntax.errors[0].message.rfind("YAML syntax: ", 0), 0u) << syntax.errors[0].text();
  LoadResult stray = load_vector_text(", x\n", "test.yaml");  // yaml-cpp would loop on it (yaml_reader.hpp)
  ASSERT_EQ(stray.errors.size(), 1u);
  EXPECT_NE(stray.errors[0].message.find("after the end of the document"), std::string::npos) << stray.errors[0].text();
  expect_error("paragraph: \"3.2\"\ntitle: t\nvectors: []\n---\nx: 1\n",
               {"---", 1, "", "", "more than one YAML document; a vector file is a single document"});
  LoadResult empty = load_vector_text("", "test.yaml");
  ASSERT_EQ(empty.errors.size(), 1u);
  EXPECT_NE(empty.errors[0].message.find("an empty file"), std::string::npos);
}

// Each vector is read on its own: two bad vectors give two errors, and the
// file is left out of `files`.
TEST(vectors, OneErrorPerBadVectorAndTheFileIsLeftOut) {
  const std::string yaml = one_vector("      - send: {command: statuss}\n        expect: ack\n") +
                           "  - id: 3.2-y\n    comment: c\n    spec: {paragraph: \"3.2\", quote: q}\n    level: maybe\n"
                           "    steps: [{wait_ms: 1}]\n";
  LoadResult r = load_vector_text(yaml, "test.yaml");
  ASSERT_EQ(r.errors.size(), 2u) << all_errors(r.errors);
  EXPECT_EQ(r.errors[0].vector_id, "3.2-x");
  EXPECT_EQ(r.errors[1].vector_id, "3.2-y");
  EXPECT_TRUE(r.files.empty());
  EXPECT_EQ(r.errors[1].text(), "test.yaml:14:5: [3.2-y] level: \"maybe\" is not a level: must, should, informative "
                                "(READING-NOTES \"Result levels\")");
}

// ---------------------------------------------------------------------------
// Lint
// ---------------------------------------------------------------------------

std::vector<LoadError> lint_text(const std::string& yaml, const std::string& name = "test.yaml") {
  VectorFile f = load_ok(yaml, name);
  return lint({f});
}

void expect_lint(const std::string& yaml, const Want& w) {
  const auto errors = lint_text(yaml);
  ASSERT_EQ(errors.size(), 1u) << all_errors(errors) << "--- input:\n" << yaml;
  const LoadError& e = errors[0];
  const auto [line, column] = position_of(yaml, w.token, w.occurrence);
  EXPECT_EQ(e.where.line, line) << e.text();
  EXPECT_EQ(e.where.column, column) << e.text();
  EXPECT_EQ(e.vector_id, w.id) << e.text();
  EXPECT_EQ(e.key, w.key) << e.text();
  EXPECT_NE(e.message.find(w.message), std::string::npos) << e.text() << "\n  expected to contain: " << w.message;
}

// A clean 3.2 vector (a real quote) with `extra` keys and these steps.
std::string lint_vector(const std::string& steps, const std::string& extra = "", const std::string& notes = "") {
  return "paragraph: \"3.2\"\ntitle: t\n" + notes +
         "vectors:\n  - id: 3.2-x\n    comment: c\n"
         "    spec: {paragraph: \"3.2\", quote: \"The response to this command will consist of 52 bytes\"}\n"
         "    level: must\n" +
         extra + "    steps:\n" + steps;
}

TEST(vectors, LintMotionNeedsTheMotionTag) {
  const std::string move =
      "      - send: {command: auto_move, form: 2A, fields: {azimuth: \"{home(az)}\", elevation: \"{home(el)}\"}}\n        expect: ack\n";
  expect_lint(lint_vector(move), {"send", 1, "3.2-x", "steps[0]", "sends auto_move (0x32), which can move the antenna: tag the vector motion"});
  EXPECT_TRUE(lint_text(lint_vector(move, "    tags: [motion]\n")).empty());
  // A raw frame is read for its command byte; a setup step counts too.
  expect_lint(lint_vector("      - wait_ms: 1\n", "    setup:\n      - send: {raw: \"02 {addr} 47 45 46 30 30 35 30 03 {lrc}\"}\n        expect: ack\n"),
              {"send", 1, "3.2-x", "setup[0]", "sends jog_minimal (0x47), which can move the antenna"});
  // The form decides: misc R (drive reset) does not move, misc T does (E-26).
  EXPECT_TRUE(lint_text(lint_vector("      - send: {command: misc, form: R, fields: {parameter: A}}\n        expect: ack\n")).empty());
  expect_lint(lint_vector("      - send: {command: misc, form: T, fields: {parameter: R}}\n        expect: ack\n"),
              {"send", 1, "3.2-x", "steps[0]", "sends misc (0x36), which can move the antenna"});
  // A damaged frame still needs the tag: a faulty controller may act on it.
  expect_lint(lint_vector("      - send: {command: keypress, fields: {key code: \"1\"}}\n        modify: {lrc_xor: 1}\n        expect: silence\n"),
              {"send", 1, "3.2-x", "steps[0]", "sends keypress (0x48), which can move the antenna"});
}

// A vector that moves the antenna rests on the device's profile: no literal
// position window, no literal target the device acts on, no literal poll
// timeout (vectors/README.md, "Profile expressions").
TEST(vectors, LintMotionRestsOnTheProfile) {
  const std::string tags = "    tags: [motion]\n";
  expect_lint(lint_vector("      - send: {command: auto_move, form: 2A, fields: {azimuth: 30.0, elevation: \"{home(el)}\"}}\n"
                          "        expect: ack\n", tags),
              {"send", 1, "3.2-x", "steps[0].send.fields.azimuth", "a literal target in a vector that moves the antenna"});
  expect_lint(lint_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {elevation: {range: [9.9, 10.1]}}}\n", tags),
              {"elevation", 1, "3.2-x", "steps[0].expect.fields.elevation", "a literal position window"});
  expect_lint(lint_vector("      - poll: {send: {command: status}, until: {az status: 0x40}, timeout_ms: 600000}\n", tags),
              {"poll", 1, "3.2-x", "steps[0].timeout_ms", "a literal timeout in a vector that moves the antenna"});
  expect_lint(lint_vector("      - send: {raw: \"02 {addr} 32 20 30 30 33 30 30 30 30 31 30 30 03 {lrc}\"}\n        expect: ack\n", tags),
              {"send", 1, "3.2-x", "steps[0].send.raw", "a raw auto move to a literal target"});
  // Near, jogged, expression ranges and a derived timeout are the profile's;
  // a target the device must refuse (NAK) is not acted on.
  EXPECT_TRUE(lint_text(lint_vector(
                  "      - send: {command: jog, form: U, fields: {speed: S, duration: \"{jog_ms(el, S)}\"}}\n"
                  "        expect: {reply: ack, fields: {elevation: {capture: $from}}}\n"
                  "      - poll: {send: {command: status}, until: {el status: {regex: \"^0x[45]0$\"}, elevation: {near: \"{home(el)}\"}}}\n"
                  "      - send: {command: status}\n"
                  "        expect: {reply: ack, fields: {elevation: {jogged: {jog: U, speed: S, from: \"{$from}\", ms: 50}}, azimuth: {range: [\"{min_deg(az)}\", \"{max_deg(az)}\"]}}}\n"
                  "      - send: {command: auto_move, form: 2A, fields: {azimuth: 999.0, elevation: 0.0}}\n        expect: nak\n",
                  tags))
                  .empty());
}

// Issue 32: no expectation wider than the spec's answer. A range on an
// enumerated field (§3.17 exit status) takes codes of every mode's list: a
// controller that never updates byte 48 passes with 0x20.
TEST(vectors, LintEnumeratedFieldsTakeTheirEntriesNotARangeOfCodes) {
  expect_lint(lint_vector("      - send: {command: extended_status}\n"
                          "        expect: {reply: ack, fields: {last exited mode: 0x25, exit status: {range: [\"{0x20}\", "
                          "\"{locate_exit('LOCATE_FUNCTION_COMPLETED') - 1}\"]}}}\n"),
              {"exit status", 1, "3.2-x", "steps[0].expect.fields.exit status", "a range on an enumerated field"});
  {
    const auto errors = lint_text(lint_vector("      - send: {command: extended_status}\n"
                                              "        expect: {reply: ack, fields: {exit status: {range: [\"{0x20}\", \"{0x37}\"]}}}\n"));
    ASSERT_EQ(errors.size(), 1u) << all_errors(errors);
    EXPECT_EQ(errors[0].text().rfind("test.yaml:10:39: ", 0), 0u) << errors[0].text();  // file and line
    EXPECT_NE(errors[0].text().find("[3.2-x] steps[0].expect.fields.exit status: "), std::string::npos) << errors[0].text();
  }
  // A regex that picks some codes of a list that hangs on the mode (byte 46 on byte 45).
  expect_lint(lint_vector("      - send: {command: extended_status}\n"
                          "        expect: {reply: ack, fields: {current state: {regex: \"^0x2[0-7]$\"}}}\n"),
              {"current state", 1, "3.2-x", "steps[0].expect.fields.current state", "hangs on the mode"});
  // A regex on the mode that takes codes past the mode list (5Dh-5Fh are no mode).
  expect_lint(lint_vector("      - send: {command: extended_status}\n"
                          "        expect: {reply: ack, fields: {current mode: {regex: \"^0x(?!25$)[2-5][0-9a-f]$\"}}}\n"),
              {"current mode", 1, "3.2-x", "steps[0].expect.fields.current mode", "no entry of its list (0x5d and 2 more)"});
  // In the until of a poll too.
  expect_lint(lint_vector("      - poll: {send: {command: extended_status}, until: {exit status: {range: [32, 40]}}}\n"),
              {"exit status", 1, "3.2-x", "steps[0].until.exit status", "a range on an enumerated field"});
  // The legal entries named, a regex within the mode list, and a form check
  // that takes every code, pass.
  EXPECT_TRUE(lint_text(lint_vector("      - send: {command: extended_status}\n"
                                    "        expect:\n          reply: ack\n          fields:\n"
                                    "            current mode: {regex: \"^0x(?!25$)([2-4][0-9a-f]|5[0-9a-c])$\"}\n"
                                    "            current state: {regex: \"^0x[2-7][0-9a-f]$\"}\n"
                                    "            exit status: {one_of: [\"{locate_exit('LOCATE_AZIM_MOVEMENT_STOP_KEY')}\", "
                                    "\"{locate_exit('LOCATE_AZIM_MOVEMENT_MODE_CHANGED')}\"]}\n"))
                  .empty());
}

TEST(vectors, RequirementsNameCapabilitiesNeverAProfile) {
  expect_error(one_vector("      - send: {command: status}\n        expect: ack\n", "    requires: {name: rc3000-1.59}\n"),
               {"name", 1, "3.2-x", "requires.name", "a vector requires capabilities, never a profile's name"});
  VectorFile f = load_ok(one_vector("      - send: {command: status}\n        expect: ack\n",
                                    "    needs: [\"{first_empty(presets)}\", \"{store_room(7)}\"]\n"));
  ASSERT_EQ(f.vectors.size(), 1u);
  EXPECT_EQ(f.vectors[0].needs, (std::vector<std::string>{"{first_empty(presets)}", "{store_room(7)}"}));
  expect_error(one_vector("      - send: {command: status}\n        expect: ack\n", "    needs: [first_empty]\n"),
               {"first_empty", 1, "3.2-x", "needs[0]", "is not a profile expression"});
  expect_error(one_vector("      - send: {command: status}\n        expect: ack\n", "    needs: [\"{nope()}\"]\n"),
               {"\"{nope()}", 1, "3.2-x", "needs[0]", "unknown function nope()"});
}

TEST(vectors, ProfileExpressionsAreCheckedWhenLoaded) {
  expect_error(one_vector("      - send: {command: auto_move, form: 2A, fields: {azimuth: \"{home(az, el)}\", elevation: 0}}\n        expect: nak\n"),
               {"azimuth", 1, "3.2-x", "steps[0].send.fields.azimuth", "home() takes 1 argument"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {elevation: {near: \"{$x}\"}}}\n"),
               {"near", 1, "3.2-x", "steps[0].expect.fields.elevation.near", "$x is not captured by an earlier step"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: {near: 5}}}\n"),
               {"near", 1, "3.2-x", "steps[0].expect.fields.agc.near", "not an axis position"});
  expect_error(one_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {azimuth: {jogged: {jog: U, speed: F, from: 0, ms: 50}}}}\n"),
               {"jogged", 1, "3.2-x", "steps[0].expect.fields.azimuth.jogged", "a 'U' jog moves the elevation"});
  expect_error(one_vector("      - send: {command: read_satellite, fields: {index: 1}}\n        expect: {reply: ack, from_profile: navigation}\n"),
               {"from_profile", 1, "3.2-x", "steps[0].expect.from_profile", "expected a whole number"});
  expect_error(one_vector("      - send: {command: status, from_profile: 1}\n        expect: ack\n"),
               {"from_profile", 1, "3.2-x", "steps[0].send.from_profile", "from_profile sends a record of the profile"});
  // A list of matchers for one field: each must hold.
  VectorFile f = load_ok(one_vector(
      "      - send: {command: status}\n        expect: {reply: ack, fields: {azimuth: [{regex: \"^ \"}, {near: \"{home(az)}\"}]}}\n"));
  ASSERT_EQ(f.vectors.size(), 1u);
  ASSERT_EQ(f.vectors[0].steps[0].expect.fields.size(), 2u);
  EXPECT_EQ(f.vectors[0].steps[0].expect.fields[1].kind, FieldMatcher::Kind::kNear);
}

TEST(vectors, LintStoredDataNeedsTheDestructiveTag) {
  expect_lint(lint_vector("      - send: {command: write_navigation}\n        expect: ack\n"),
              {"send", 1, "3.2-x", "steps[0]", "sends write_navigation (0x46), which changes stored data: tag the vector destructive"});
  EXPECT_TRUE(lint_text(lint_vector("      - send: {command: write_navigation}\n        expect: ack\n", "    tags: [destructive]\n")).empty());
}

TEST(vectors, LintFlagsNotesAndErrata) {
  const std::string status = "      - send: {command: status}\n        expect: ack\n";
  expect_lint(lint_vector(status, "    flags: [Undefined]\n"),
              {"id: 3.2-x", 1, "3.2-x", "flags", "flag \"Undefined\" is not defined in the file's notes"});
  expect_lint(lint_vector(status, "", "notes:\n  Unused: {description: d}\n"),
              {"Unused", 1, "", "notes.Unused", "note \"Unused\" is used by no vector"});
  expect_lint(lint_vector(status, "    flags: [F]\n", "notes:\n  F: {description: d, errata: E-999}\n"),
              {"F:", 1, "", "notes.F.errata", "E-999 is not an entry of protocol/ERRATA.md"});
  EXPECT_TRUE(lint_text(lint_vector(status, "    flags: [F]\n", "notes:\n  F: {description: d, errata: E-62}\n")).empty());
  // The form of the reference is the loader's check.
  expect_error(lint_vector(status, "    flags: [F]\n", "notes:\n  F: {description: d, errata: E7}\n"),
               {"errata", 1, "", "notes.F.errata", "\"E7\" is not an errata entry id like E-7"});
  expect_lint(lint_vector(status, "    tags: [moving]\n"), {"id: 3.2-x", 1, "3.2-x", "tags", "unknown tag \"moving\"; known tags: motion"});
}

TEST(vectors, LintQuotesAreVerbatim) {
  // A spec text of the same layout as the scanned manual's: a sentence
  // broken over lines, with runs of blanks.
  const std::string spec = "3.2 Device Status Poll\n  The response to this command will\nconsist of 52 bytes,  which will be a\n"
                           "combination of ASCII characters.\n";
  auto lint_with_spec = [&](const std::string& yaml) { return lint({load_ok(yaml, "test.yaml")}, spec); };
  const std::string quote = "The response to this command will consist of 52 bytes";
  std::string yaml = lint_vector("      - wait_ms: 1\n");
  EXPECT_TRUE(lint_with_spec(yaml).empty()) << all_errors(lint_with_spec(yaml));
  yaml.replace(yaml.find(quote), quote.size(), "The response to this command shall consist of 52 bytes");
  auto errors = lint_with_spec(yaml);
  ASSERT_EQ(errors.size(), 1u) << all_errors(errors);
  EXPECT_EQ(errors[0].key, "spec.quote");
  EXPECT_NE(errors[0].message.find("not found verbatim in the spec text"), std::string::npos) << errors[0].message;
  // Without a spec text, quotes are not checked.
  EXPECT_TRUE(lint({load_ok(yaml, "test.yaml")}, std::nullopt).empty());
  // Line breaks are blanks, and parts may be joined by an ellipsis, in order.
  yaml = lint_vector("      - wait_ms: 1\n");
  yaml.replace(yaml.find(quote), quote.size(), "The response to this command \\u2026 of 52 bytes, which will be a combination");
  EXPECT_TRUE(lint_with_spec(yaml).empty()) << all_errors(lint_with_spec(yaml));
  yaml = lint_vector("      - wait_ms: 1\n");
  yaml.replace(yaml.find(quote), quote.size(), "of 52 bytes \\u2026 The response to this command");
  EXPECT_EQ(lint_with_spec(yaml).size(), 1u);
}

TEST(vectors, LintDuplicateIdsAcrossFilesNameBothPlaces) {
  const std::string yaml = lint_vector("      - wait_ms: 1\n");
  VectorFile a = load_ok(yaml, "a.yaml"), b = load_ok("# another file\n" + yaml, "b.yaml");
  const auto errors = lint({a, b});
  ASSERT_EQ(errors.size(), 1u) << all_errors(errors);
  EXPECT_EQ(errors[0].text(), "b.yaml:5:5: [3.2-x] id: duplicate id; first at a.yaml:4:5");
}

// lint works on the data model too: a file built in code is checked for the
// codecs' commands, forms and fields.
TEST(vectors, LintChecksFilesBuiltInCode) {
  VectorFile f = load_ok(lint_vector("      - send: {command: status}\n        expect: {reply: ack, fields: {agc: any}}\n"));
  f.vectors[0].steps[0].command->command = "stattus";
  f.vectors[0].steps.push_back(f.vectors[0].steps[0]);
  f.vectors[0].steps[1].command->command = "status";
  f.vectors[0].steps[1].expect.fields[0].field = "agcc";
  const auto errors = lint({f});
  ASSERT_EQ(errors.size(), 2u) << all_errors(errors);
  EXPECT_EQ(errors[0].key, "steps[0]");
  EXPECT_NE(errors[0].message.find("unknown command \"stattus\""), std::string::npos);
  EXPECT_EQ(errors[1].key, "steps[1].expect.fields");
  EXPECT_NE(errors[1].message.find("unknown field \"agcc\""), std::string::npos);
}

// ---------------------------------------------------------------------------
// Raw templates and requirements (for the runner)
// ---------------------------------------------------------------------------

TEST(vectors, ExpandRawBytes) {
  EXPECT_EQ(to_hex(expand_raw_bytes("02 {addr} 31 03 {lrc}", 0x32).value()), "02 32 31 03 02");
  // {lrc} starts at the frame's byte 0: the second STX, after noise (READING-NOTES 7).
  EXPECT_EQ(to_hex(expand_raw_bytes("02 02 {addr} 31 03 {lrc}", 0x32).value()), "02 02 32 31 03 02");
  EXPECT_EQ(to_hex(expand_raw_bytes("41 42 02 {addr} 30 03 {lrc}", 0x32).value()), "41 42 02 32 30 03 03");
  // Captured text, one byte a character: the manual's Query Name of index 01.
  EXPECT_EQ(to_hex(expand_raw_bytes("02 {addr} 35 {$i} 03 {lrc}", 0x32, {{"$i", "01"}}).value()), "02 32 35 30 31 03 07");
  EXPECT_FALSE(expand_raw_bytes("02 {addr} 35 {$i} 03 {lrc}", 0x32).ok());
  EXPECT_FALSE(expand_raw_bytes("02 {address}", 0x32).ok());
  EXPECT_FALSE(expand_raw_bytes("02 3", 0x32).ok());
}

TEST(vectors, RequirementsHold) {
  Profile p;  // rc3000-1.59 defaults: single port feed, no DVB, address 50
  auto req = [](std::string key, std::vector<std::string> values) { return Requirement{std::move(key), std::move(values), {}}; };
  EXPECT_TRUE(requirements_hold(p, {}));
  EXPECT_TRUE(requirements_hold(p, {req("polarization", {"single_port", "dual_port"}), req("address", {"50"})}));
  EXPECT_FALSE(requirements_hold(p, {req("dvb_receiver", {"true"})}));
  EXPECT_TRUE(requirements_hold(p, {req("errata.implements_iess", {"false"})}));
  EXPECT_FALSE(requirements_hold(p, {req("no.such.key", {"x"})}));
  // A requirement as loaded holds for the profile its values describe.
  VectorFile f = load_ok(one_vector("      - wait_ms: 1\n", "    requires: {address: \"2\", polarization: circular}\n"));
  EXPECT_FALSE(requirements_hold(p, f.vectors[0].requires_));
  p.pol_type = PolType::kCircular;
  EXPECT_TRUE(requirements_hold(p, f.vectors[0].requires_));
}

TEST(vectors, LoadVectorsSkipsProfilesAndReportsMissingPaths) {
  const std::string dir = default_vectors_dir();
  LoadResult r = load_vectors({dir, "/no/such/vectors.yaml"});
  // Below the vectors folder: the checkout's own path may hold "/profiles/".
  for (const auto& f : r.files) EXPECT_EQ(f.path.find("/profiles/", dir.size()), std::string::npos) << f.path;
  ASSERT_EQ(r.errors.size(), 1u) << all_errors(r.errors);
  EXPECT_EQ(r.errors[0].where.file, "/no/such/vectors.yaml");
  EXPECT_NE(r.errors[0].message.find("cannot open"), std::string::npos);
}

// ---------------------------------------------------------------------------
// Robustness: no input makes the loader throw or hang
// ---------------------------------------------------------------------------

void expect_sane(const LoadResult& r) {
  EXPECT_NE(r.ok(), r.files.empty());
  for (const auto& e : r.errors) EXPECT_FALSE(e.message.empty()) << e.text();
}

TEST(vectors, NeverThrowsOnTruncatedShippedFiles) {
  std::size_t loads = 0, errors = 0;
  for (const auto& f : shipped_files()) {
    const std::string text = read_text(f);
    // A bounded number of prefixes a file keeps the whole test to seconds
    // however large the suite grows (each load reads the prefix whole); the
    // vector loader's fuzz target tries the rest.
    const std::size_t stride = std::max<std::size_t>(1, text.size() / 80);
    for (std::size_t n = 0; n <= text.size(); n += stride) {
      LoadResult r;
      ASSERT_NO_THROW(r = load_vector_text(text.substr(0, n), f.string())) << "prefix " << n;
      expect_sane(r);
      ASSERT_NO_THROW(lint(r.files));
      errors += r.ok() ? 0 : 1;
      ++loads;
    }
  }
  EXPECT_GT(errors, 0u);
  EXPECT_GT(loads, errors);
}

TEST(vectors, NeverThrowsOnMutatedFiles) {
  const std::string sources[] = {read_text(fs::path(default_vectors_dir()) / "framing.yaml"), kFullFile};
  std::mt19937 rng(4242);
  const std::string alphabet = "-:{}[],#&*!|>'\"%@`? \n\t.0123456789aZ\x7f\x80\xff$";
  for (const auto& source : sources) {
    for (int i = 0; i < 1500; ++i) {
      std::string s = source;
      for (int k = 0; k < 3; ++k) {
        const std::size_t at = rng() % s.size();
        switch (rng() % 3) {
          case 0: s[at] = alphabet[rng() % alphabet.size()]; break;
          case 1: s.erase(at, 1 + rng() % 8); break;
          default: s.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
        }
      }
      LoadResult r;
      ASSERT_NO_THROW(r = load_vector_text(s, "mutated.yaml")) << s;
      expect_sane(r);
      ASSERT_NO_THROW(lint(r.files)) << s;
    }
  }
}

// A hang here is caught by the test's ctest TIMEOUT (tests/CMakeLists.txt),
// not by a clock in the test: under the sanitizers on a loaded machine the
// same inputs took from 17 to 45 s.
TEST(vectors, NeverThrowsOrHangsOnHostileInputs) {
  EXPECT_FALSE(load_vector_text(std::string(100000, '['), "deep.yaml").ok());
  EXPECT_FALSE(load_vector_text(std::string(2 << 20, ' '), "big.yaml").ok());
  EXPECT_NO_THROW(load_vector_text(std::string("paragraph: \0x", 13), "nul.yaml"));
  // Aliases: 100 groups naming one list of 500 vectors is over the work budget.
  std::string bomb = "paragraph: \"3.2\"\ntitle: t\ngroups:\n  - level: must\n    vectors: &l [&v {id: 3.2-a, comment: c, "
                     "spec: {paragraph: \"3.2\", quote: q}, steps: [{send: {command: status}, expect: {reply: ack, fields: "
                     "{agc: {regex: \"^[0-9]+$\"}}}}]}";
  for (int i = 0; i < 499; ++i) bomb += ", *v";
  bomb += "]\n";
  for (int i = 0; i < 99; ++i) bomb += "  - {level: must, vectors: *l}\n";
  LoadResult r = load_vector_text(bomb, "bomb.yaml");
  ASSERT_EQ(r.errors.size(), 1u) << all_errors(r.errors);
  EXPECT_NE(r.errors[0].message.find("more than 100000"), std::string::npos) << r.errors[0].text();
}

}  // namespace
}  // namespace sabus::harness
