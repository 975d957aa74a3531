// The vector file's keys (vector_schema.hpp). The loader's MapReaders take
// their allowed keys from here; the order of each list is the order an
// unknown-key error names them in.
#include "sabus/harness/vector_schema.hpp"

#include <array>
#include <cctype>
#include <cstddef>
#include <vector>

namespace sabus::harness {
namespace {

constexpr SchemaKey kFileKeys[] = {
    {"paragraph", "yes",
     "the spec paragraph the file is about (\"3.2\"; quote it) or a cross-cutting topic: framing, ignore, nak, "
     "offline, parity, multidrop, timing, pacing"},
    {"title", "yes", "the file's title"},
    {"notes", "", "the flags its vectors use, flag name -> note"},
    {"requires", "", "requirements on the device's profile, for every vector of the file"},
    {"needs", "", "profile expressions that must be available, for every vector of the file"},
    {"groups", "unless `vectors`", "groups of vectors that share requirements, setup, teardown, tags, flags, level"},
    {"vectors", "unless `groups`", "vectors on their own"},
};

constexpr SchemaKey kNoteKeys[] = {
    {"description", "yes", "the reading of the spec the flag marks"},
    {"errata", "", "the protocol/ERRATA.md entry it rests on (E-7); it must exist and not be withdrawn"},
};

constexpr SchemaKey kGroupKeys[] = {
    {"comment", "", "what the group's vectors have in common"},
    {"requires", "", "requirements added to the file's and each vector's"},
    {"needs", "", "profile expressions added to each vector's needs"},
    {"setup", "", "steps run before each vector's setup"},
    {"teardown", "", "steps run after each vector's teardown; they use only what the group's setup captured"},
    {"tags", "", "tags added to each vector's"},
    {"flags", "", "flags added to each vector's"},
    {"level", "", "the level of a vector that gives none"},
    {"vectors", "yes", "the group's vectors"},
};

constexpr SchemaKey kVectorKeys[] = {
    {"id", "yes",
     "stable and unique in the suite; starts with the file's paragraph and '-'; letters, digits, '.', '-', '_', ':'"},
    {"comment", "yes", "what the vector checks and why"},
    {"spec", "yes", "the paragraph and a verbatim quote of the spec"},
    {"level", "unless the group gives it", "must (fails the run), should (warns) or informative (records)"},
    {"flags", "", "flags defined in the file's notes: the readings of the spec the vector depends on"},
    {"tags", "", "motion, destructive, option:dvb, pol:..., parity, timing, offline, multidrop, track, as-found"},
    {"requires", "", "requirements on the device's profile; the vector runs only where all hold"},
    {"needs", "", "profile expressions that must be available, or the vector is skipped"},
    {"setup", "", "steps run first"},
    {"each_slot", "",
     "presets, tles, signposts or store: run the steps once for each slot the profile fills, its index as $slot"},
    {"steps", "yes", "the steps, at least one"},
    {"teardown", "", "steps run last, also after a failure or an inconclusive end"},
};

constexpr SchemaKey kSpecKeys[] = {
    {"paragraph", "yes", "the spec paragraph (1, 2, 3, 4, 3.1 ... 3.25); the file's own, except in a cross-cutting file"},
    {"quote", "yes", "a short verbatim quote of that paragraph; parts may be joined by '…'"},
};

constexpr SchemaKey kStepKeys[] = {
    {"send", "one of `send`, `poll`, `survey`, `wait`, `wait_ms`", "send a frame: a command built from fields, or raw bytes"},
    {"modify", "", "on a send: damage the frame on purpose"},
    {"expect", "with `send`", "what must come back after the send"},
    {"length_mismatch", "",
     "on a raw send: true when the frame's length differs from the catalog's on purpose (§3 table)"},
    {"poll", "one of `send`, `poll`, `survey`, `wait`, `wait_ms`", "send a frame again and again until the reply meets a condition"},
    {"survey", "one of `send`, `poll`, `survey`, `wait`, `wait_ms`",
     "send a frame many times and count the replies that come garbled (§4); fails above --max-line-fault-rate"},
    {"wait", "one of `send`, `poll`, `survey`, `wait`, `wait_ms`", "wait `ms` milliseconds (the same as `wait_ms`)"},
    {"wait_ms", "one of `send`, `poll`, `survey`, `wait`, `wait_ms`", "wait this many milliseconds (1 to 3600000, or a profile expression)"},
    {"precondition", "",
     "on a send or poll outside a teardown: what must hold for the test purpose, in words; when it does not, the "
     "vector ends inconclusive"},
    {"precondition_reading", "",
     "with `precondition`: the ERRATA entry whose other side lets it fail (E-100); a profile pinning the "
     "reference side makes the step an ordinary one"},
};

constexpr SchemaKey kWaitKeys[] = {
    {"ms", "yes", "milliseconds, 1 to 3600000, or a profile expression"},
};

constexpr SchemaKey kSendKeys[] = {
    {"command", "unless `raw`", "a catalog key (auto_move), name (\"Auto Move\") or code (\"32h\")"},
    {"form", "for a command with several forms", "the catalog's form id (2A, E, R, preset)"},
    {"fields", "", "request field -> value; unnamed fields keep the codec's defaults"},
    {"address", "", "send to another address than the profile's (49 to 111, the quoted character, or 0x32)"},
    {"raw", "unless `command`", "the bytes in hex, with {addr}, {lrc}, {$capture} and profile expressions"},
    {"from_profile", "",
     "a write of stored data (39h, 3Bh, 43h, 46h) sends the profile's record of this slot, or navigation"},
};

constexpr SchemaKey kModifyKeys[] = {
    {"lrc_xor", "", "XOR the check byte with this mask, 1 to 0x7f (a bad LRC)"},
    {"address", "", "put this byte (32 to 127, or a quoted character) in byte 1; the LRC is recomputed"},
    {"parity_flip", "", "indexes of bytes sent with the wrong parity bit (E-1)"},
    {"extra_data_bytes", "", "insert 1 to 200 data bytes before ETX; the LRC is recomputed"},
    {"truncate", "", "drop this many bytes from the end"},
    {"replace", "", "[index, byte] pairs to set; the LRC is not recomputed"},
    {"chunks", "", "write the frame in pieces of these sizes, the rest in one last piece"},
    {"pause_ms", "with `chunks`", "the pause between pieces, 1 to 60000 ms"},
};

constexpr SchemaKey kPollKeys[] = {
    {"send", "yes", "the frame to send, as a step's send"},
    {"until", "yes", "reply field -> matcher: the poll ends when every one holds"},
    {"timeout_ms", "", "give up after this long (up to 3600000, or a profile expression); derived when left out"},
    {"interval_ms", "", "between sends, at least 1000 (§4, E-3); default 1000"},
    {"expect", "", "what each reply must meet; default ack, never silence"},
};

constexpr SchemaKey kSurveyKeys[] = {
    {"send", "yes", "the frame to send, as a step's send; its reply must be an ACK"},
    {"count", "yes", "how many times, 10 to 1000"},
    {"interval_ms", "", "between sends, at least 1000 (§4, E-3); default 1000"},
};

constexpr SchemaKey kExpectKeys[] = {
    {"reply", "yes", "ack, nak, offline, silence, any or answered (a scalar expect is this alone)"},
    {"bytes", "", "the whole reply, exactly: a raw template like a send's raw"},
    {"fields", "", "reply field -> matcher, or a list of matchers that must all hold"},
    {"rule", "", "on a nak: the reference controller's NAK rule that must fire (nak_rules.hpp)"},
    {"from_profile", "",
     "on an ack to a read of stored data (35h, 3Ah, 3Ch, 44h, 45h): the reply equals the profile's record of this slot"},
    {"readings", "", "ERRATA id (its other side) or ID/other-2 (a third side) -> what a controller of that side of the open point answers instead"},
};

constexpr SchemaKey kMatcherKeys[] = {
    {"eq", "", "the field's text equals this"},
    {"one_of", "", "the text equals one of these"},
    {"regex", "", "this ECMAScript regex is found in the text; anchor it"},
    {"range", "", "[low, high]: the field's number is within, inclusive"},
    {"near", "", "a position within the axis's arrival tolerance of this value"},
    {"jogged", "", "where a jog can leave the axis (motion.hpp)"},
    {"capture", "", "keep the text as $name for later steps; may go with one of the others"},
};

constexpr SchemaKey kNearKeys[] = {
    {"value", "yes", "the position"},
    {"axis", "", "az, el or pol: the axis whose tolerance applies, for a field that is not an axis position"},
};

constexpr SchemaKey kJoggedKeys[] = {
    {"jog", "yes", "the jog direction: E, W, D, U, O or L (§3.4)"},
    {"speed", "yes", "F or S"},
    {"from", "yes", "where the jog started"},
    {"ms", "yes", "how long the jog ran"},
};

constexpr std::string_view kOneOfTests = "one of `eq`, `one_of`, `regex`, `range`, `near`, `jogged`, or `capture` alone";

// An alternative takes an expectation's keys but `readings` (an alternative
// has no alternatives), and none is required: without reply it keeps the
// expectation's reply and checks.
std::vector<SchemaKey> reading_keys() {
  std::vector<SchemaKey> out;
  for (const SchemaKey& k : kExpectKeys) {
    if (k.key == "readings") continue;
    out.push_back({k.key, "", k.key == "reply" ? "its own reply kind; left out, the expectation's reply and checks are kept"
                                                : k.meaning});
  }
  out.push_back({"ends", "",
                 "true: when this side holds and the reference does not, the vector's steps end here, passed (what "
                 "follows needs the reference side: a move the other side refused); a send step's, in `steps` only"});
  return out;
}

struct Table {
  std::vector<SchemaKey> readings = reading_keys();
  std::vector<SchemaNodeInfo> nodes;
  std::vector<std::vector<std::string_view>> keys;  // by node, in the nodes' order
  Table() {
    nodes = {
        {SchemaNode::kFile, "The file", "the root of a `vectors/*.yaml` file", kFileKeys},
        {SchemaNode::kNote, "A note", "the value of a flag under the file's `notes`", kNoteKeys},
        {SchemaNode::kGroup, "A group", "an entry of the file's `groups`", kGroupKeys},
        {SchemaNode::kVector, "A vector", "an entry of `vectors`, in the file or in a group", kVectorKeys},
        {SchemaNode::kSpec, "`spec`", "a vector's `spec`", kSpecKeys},
        {SchemaNode::kStep, "A step", "an entry of `setup`, `steps` or `teardown` (a vector's or a group's)", kStepKeys},
        {SchemaNode::kWait, "`wait`", "a step's `wait`", kWaitKeys},
        {SchemaNode::kSend, "`send`", "a step's or a poll's `send`", kSendKeys},
        {SchemaNode::kModify, "`modify`", "a send step's `modify`", kModifyKeys},
        {SchemaNode::kPoll, "`poll`", "a step's `poll`", kPollKeys},
        {SchemaNode::kSurvey, "`survey`", "a step's `survey`", kSurveyKeys},
        {SchemaNode::kExpect, "An expectation", "a send step's or a poll's `expect`, when it is a map (a scalar is the reply alone)", kExpectKeys},
        {SchemaNode::kReading, "A `readings` alternative", "the value of an ERRATA id (or ID/other-2) under an expectation's `readings`: an expectation's keys but `readings`, none required",
         readings},
        {SchemaNode::kMatcher, "A field matcher",
         "the value of a field under `fields` or `until`, when it is a map (a scalar is `eq`; `any` always holds)",
         kMatcherKeys},
        {SchemaNode::kNear, "`near`", "a matcher's `near`, when it is a map (a scalar is the value)", kNearKeys},
        {SchemaNode::kJogged, "`jogged`", "a matcher's `jogged`", kJoggedKeys},
    };
    for (const SchemaNodeInfo& n : nodes) {
      keys.emplace_back();
      for (const SchemaKey& k : n.keys) keys.back().push_back(k.key);
    }
  }
};

const Table& table() {
  static const Table t;
  return t;
}

std::size_t index_of(SchemaNode node) {
  const auto& nodes = table().nodes;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].node == node) return i;
  return 0;  // unreachable: every node is in the table (vector_schema_test)
}

std::string cell(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

std::span<const SchemaNodeInfo> vector_schema() { return table().nodes; }

const SchemaNodeInfo& schema_node(SchemaNode node) { return table().nodes[index_of(node)]; }

std::span<const std::string_view> schema_keys(SchemaNode node) { return table().keys[index_of(node)]; }

std::string schema_markdown() {
  std::string out;
  for (const SchemaNodeInfo& n : vector_schema()) {
    out += "## " + std::string(n.name) + "\n\n";
    std::string where(n.where);
    where[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(where[0])));
    out += where + ".";
    if (n.node == SchemaNode::kMatcher) out += " It has " + std::string(kOneOfTests) + ".";
    out += "\n\n| key | required | meaning |\n|---|---|---|\n";
    for (const SchemaKey& k : n.keys)
      out += "| `" + std::string(k.key) + "` | " + cell(k.required) + " | " + cell(k.meaning) + " |\n";
    out += "\n";
  }
  return out;
}

}  // namespace sabus::harness
