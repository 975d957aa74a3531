// Conformance vectors as loaded from vectors/*.yaml (schema: vectors/README.md).
// One file per spec paragraph or cross-cutting path; groups share `requires`
// and setup; each vector has a stable id, the spec quote it checks, a level,
// flags, tags, requirements on the device profile, and steps.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/motion.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness {

struct SourceLocation {
  std::string file;
  int line = 0;    // 1-based
  int column = 0;  // 1-based
  std::string text() const;  // "file:line:column"
};

// READING-NOTES "Result levels": must fails the run, should warns, informative records.
enum class Level : std::uint8_t { kMust, kShould, kInformative };
std::string_view to_string(Level level);

// A command built by the codecs from its name (or code), form and named fields:
//   send: {command: auto_move, form: 2A, fields: {azimuth: -152.5, elevation: 45.6}}
struct StructuredCommand {
  std::string command;                       // catalog key, name, or code text ("32h")
  std::string form;                          // catalog form id, "" when the command has one form
  std::map<std::string, std::string> fields; // field name (as describe_frame names it) -> value text
  std::optional<std::uint8_t> address;       // default: the device's address
  SourceLocation where;
  // Instead of fields: the profile's stored record, as the codecs write it
  // (profile_records.hpp): a slot index (a number or a profile expression)
  // for 39h/3Bh/43h, "navigation" for 46h.
  std::string from_profile;
};

// Raw bytes of 7-bit characters, hex with placeholders: "02 {addr} 31 03 {lrc}".
// {addr} is the device's address, {lrc} the XOR of the frame's byte 0 through
// the byte before it; "{$name}" a captured value (its text, one byte a
// character). The frame's byte 0 is the last STX, ACK or NAK before {lrc}
// that is followed by an address byte (31h-6Fh): byte 0 of the send for one
// frame, the second STX of `02 02 {addr} 31 03 {lrc}` (READING-NOTES 7).
// expand_raw_bytes (vector_loader.hpp) implements this.
struct RawBytes {
  std::string hex;
  SourceLocation where;
};

// Changes made to an encoded frame before it is put on the wire, in this
// order: address, extra_data_bytes, lrc_xor, replace, truncate, parity_flip,
// then chunks (vectors/README.md).
struct Modifiers {
  std::optional<std::uint8_t> lrc_xor;          // XOR the check byte with this mask (a bad LRC)
  std::optional<std::uint8_t> address;          // put another address in byte 1 (LRC recomputed)
  std::string address_text;                     // the address as a profile expression ("{other_address(1)}"), resolved by the runner
  std::vector<std::size_t> parity_flip;         // byte indexes sent with the wrong parity bit
  std::size_t extra_data_bytes = 0;             // extra data bytes before ETX (LRC recomputed)
  std::size_t truncate = 0;                     // drop this many bytes from the end
  std::vector<std::pair<std::size_t, std::uint8_t>> replace;  // (index, byte), LRC not recomputed
  std::vector<std::size_t> chunks;              // chunk sizes; the rest goes in one last chunk
  std::chrono::milliseconds pause{0};           // pause between chunks
  bool operator==(const Modifiers&) const = default;
};

// How a reply field is checked. The field is named as describe_frame names it
// ("az status", "azimuth", "sat name"); a matcher compares the field's raw
// text ("0x47", "-152.5", "SBS 6" with trailing blanks removed) or, for
// `range`, `near` and `jogged`, its number (degrees, counts, the byte's data
// bits). When a reply has several fields of that name (31h "reserved": byte
// 13 and bytes 45-49), the matcher must hold for each of them.
//
// Values may hold profile expressions ("{home(az)}", expressions.hpp): the
// runner resolves such a matcher against the device's profile and the
// vector's captures before it checks it (resolve_matcher, runner.hpp).
// The text a matcher compares for a described field: one-byte fields as
// "0x47", text fields without their quotes and trailing blanks.
std::string matcher_text(const FieldDescription& field);

struct FieldMatcher {
  enum class Kind : std::uint8_t {
    kEq, kOneOf, kRegex, kRange, kAny,
    kNear,    // values[0]: the target; within the axis's tolerance_deg
    kJogged,  // values = {from, ms}: where a jog `jog` at `speed` from `from` for `ms` can end (motion.hpp)
  };
  std::string field;
  Kind kind = Kind::kAny;
  // eq: one value; one_of: several; regex: the pattern; range: {low, high}
  // as written; near: {target}; jogged: {from, ms}.
  std::vector<std::string> values;
  double low = 0, high = 0;         // range, inclusive, once resolved
  std::string capture;              // "$name": keep the field's text for later steps
  SourceLocation where;
  char jog = 0, speed = 0;          // jogged: the direction letter (E W D U O L) and F/S
  std::string near_axis;            // near: "az", "el", "pol" when the field does not name the axis
  std::string expected;             // a resolved matcher's own words for its failure message
  // Resolved for a compass heading (§3.2 NOTE: a fluxgate azimuth reads
  // 0.0-359.9): the reading is taken modulo 360, nearest the window.
  bool angular = false;
  // near and jogged, once resolved: the readings that hold, in whole display
  // units (motion.hpp, ERRATA E-76); low and high are their tenths in degrees.
  motion::PositionReadings readings;
  // Resolved on a mount with 0.01 deg feedback: a position read from a reply
  // that carries its hundredths digit (40h, §3.17 bytes 49-50) is read with
  // it, in hundredths (E-30).
  bool hundredths = false;
};

struct ReadingAlternative;

struct Expectation {
  // kAnswered: an ACK or NAK reply to the frame sent, either (a frame whose
  // check byte or address a vector computes, where only its receipt matters).
  enum class Kind : std::uint8_t { kAck, kNak, kOffline, kSilence, kAny, kAnswered };
  Kind kind = Kind::kAck;
  std::optional<RawBytes> bytes;    // the whole reply, exactly
  std::vector<FieldMatcher> fields;
  // nak: the reference controller's rule that must have fired (nak_rules.hpp,
  // "StoreListFull"). A device on a line cannot say why it NAKs; the check
  // holds against the reference controller only, so that a vector written
  // for one rule cannot pass by tripping another (a wrong length, say).
  std::string nak_rule;
  // ack of 3Ah/3Ch/44h/45h: the reply must be what the profile says the slot
  // (an index, a number or a profile expression) or the navigation data holds.
  std::string from_profile;
  SourceLocation where;
  // `readings:`: what a controller answers that takes the other side of an
  // open point of the spec (an ERRATA entry of class reading, readings.hpp).
  // This expectation is the reference side's. The reply passes when it meets
  // any side the device's profile does not pin away (side_pinned), and a
  // failure names every side it was held to.
  std::vector<ReadingAlternative> readings;
  // An alternative's `ends: true`: when it holds and the reference side does
  // not, the vector's steps end there, passed (the rest needs the reference
  // side, e.g. a move the other side refused).
  bool ends = false;
};
struct ReadingAlternative {
  std::string errata;                          // "E-91"
  Expectation expect;                          // the whole expectation of that side
  ReadingSide side = ReadingSide::kOther;      // `E-23/other-2` in a file: the third side
};
// The reply kinds as vector files spell them: ack, nak, offline, silence, any.
std::string_view to_string(Expectation::Kind kind);

// The longest wait, poll timeout or jog a step may name, in milliseconds: a
// 360 degree move at 0.25 deg/s takes 24 minutes.
inline constexpr long long kMaxMs = 3'600'000;

struct Step {
  // kSurvey: the send `survey_count` times at `interval`, counting the
  // replies the line garbled (§4 "a garbled status reply"): a controller
  // that garbles its own replies fails it (RunOptions::max_line_fault_rate).
  enum class Kind : std::uint8_t { kSend, kPoll, kWait, kSurvey };
  Kind kind = Kind::kSend;
  std::optional<StructuredCommand> command;  // send / poll: one of command or raw
  std::optional<RawBytes> raw;
  Modifiers modifiers;
  Expectation expect;                         // send: what must come back; poll: the reply each time
  std::vector<FieldMatcher> until;            // poll: repeat until these hold
  std::chrono::milliseconds timeout{0};       // poll: give up after (0: derived, see the runner); wait: how long
  std::string timeout_text;                   // wait / poll timeout as a profile expression, when written so
  std::chrono::milliseconds interval{1000};   // poll, survey: between sends (§4 pacing)
  std::size_t survey_count = 0;               // survey: how many sends
  // send / poll in setup or steps: what must hold for the vector's test
  // purpose, in words ("the search is still running when the stop goes
  // out"). When the step's expectation does not hold, the device never got
  // into the state the purpose needs: the vector ends inconclusive (TTCN-3
  // `inconc`), not failed. "" for an ordinary step. Never in a teardown.
  std::string precondition;
  // The ERRATA entry (class reading) whose other side lets the precondition
  // fail on a legal device: a profile that pins its reference side holds
  // the step as an ordinary one, its failure the vector's (ERRATA: a
  // pinned reading is checked strictly). "" for none.
  std::string precondition_reading;
  SourceLocation where;
};

// A predicate on the device profile: `key` is a profile key path
// ("polarization", "dvb_receiver", "errata.implements_iess"), `values` the
// accepted values as text (any of them).
struct Requirement {
  std::string key;
  std::vector<std::string> values;
  SourceLocation where;
};

struct Vector {
  std::string id;                    // "3.3-form2A-basic", unique across the suite
  std::string comment;               // what and why
  std::string paragraph;             // "3.3"
  std::string quote;                 // the short spec quote it checks
  Level level = Level::kMust;
  std::vector<std::string> flags;    // defined in the file's notes
  std::vector<std::string> tags;     // motion, destructive, option:dvb, pol:circular, parity, ...
  std::vector<Requirement> requires_;  // the file's, the group's and the vector's
  // Profile expressions that must be available on the device's profile (a
  // capability: "{store_room('SABUS TEST')}", "{first_empty(presets)}"):
  // the file's, the group's and the vector's.
  std::vector<std::string> needs;
  std::vector<Step> setup;           // the group's, then the vector's
  // "presets", "tles", "signposts" or "store": the steps run once for each
  // slot of that list the profile fills, with its index as $slot (setup and
  // teardown once); "" runs them once.
  std::string each_slot;
  std::vector<Step> steps;
  std::vector<Step> teardown;
  SourceLocation where;
  bool has_tag(std::string_view tag) const;
};

struct Note {                        // a flag, after Wycheproof's notes
  std::string description;
  std::string errata;                // "E-7" or "" when the flag rests on no errata entry
  SourceLocation where;              // the flag's key under `notes` (lint reports unused notes there)
};

struct VectorFile {
  std::string path;
  std::string paragraph;
  std::string title;
  std::map<std::string, Note> notes;
  std::vector<Vector> vectors;
};

struct LoadError {
  SourceLocation where;
  std::string vector_id;  // "" when the error is outside a vector
  std::string key;        // the offending key path
  std::string message;
  std::string text() const;  // "file:line:column: [id] key: message"
};

}  // namespace sabus::harness
