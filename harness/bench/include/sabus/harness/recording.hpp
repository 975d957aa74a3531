// `sabus record`: turns a capture (a proxy log or a run JSON, capture.hpp)
// into regression vectors (vectors/README.md, "Recorded regression vectors"):
// one vector per request/reply exchange of a proxy session, or per vector of
// a run; raw sends; replies checked field by field, with the fields that
// change between runs masked by ONE table (mask_rules()).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/harness/capture.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/fields.hpp"

namespace sabus::harness {

// How a recorded reply field is checked on replay.
enum class Mask : std::uint8_t {
  kAny,    // the field must exist; its value changes between runs
  kRegex,  // only its form is stable
};

// One row: the reply fields of a codec kind (and, when `names` is not empty,
// only those names, '|'-separated) that change between runs. Every field no
// row matches is stable and recorded with `eq` (or `one_of` when a reply has
// two fields of one name).
struct MaskRule {
  fields::Kind kind;
  std::string_view names;
  Mask mask;
  std::string_view regex;  // kRegex only
  std::string_view why;    // with the spec paragraph
};
std::span<const MaskRule> mask_rules();
// The rule for a described reply field; nullptr: stable (eq).
const MaskRule* mask_rule_for(const FieldDescription& field);

struct RecordOptions {
  std::string name;       // vector ids are "<paragraph>-<name>-..."; letters, digits, '.', '-', '_'
  std::string paragraph;  // the file's paragraph; empty: decided from the requests
  std::string source;     // the input's name, for the file's header comment
};

struct Recording {
  std::string yaml;                  // the vector file
  std::string paragraph;             // as decided
  std::size_t vectors = 0, steps = 0;
  std::vector<std::string> notes;    // what was left out, and why
};

// The file is written by yaml-cpp's Emitter: data (ids, raw templates,
// matcher texts) double-quoted exactly, and text from the capture meant for a
// person (the source and device in the header comment, a run's vector ids
// and outcomes in a vector's comment) made printable first
// (yaml_writer::printable_text). nullopt with `error` set when nothing can be
// recorded (no exchange), an option is bad, or a request holds a byte of 80h
// or more (a capture holds 7-bit characters; no raw send can carry it).
std::optional<Recording> record_vectors(const Capture& capture, const RecordOptions& options, std::string& error);

}  // namespace sabus::harness
