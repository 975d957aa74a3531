// What the parts of the vector loader share (not part of its API): the bounds
// on hostile input, the reading context of one file, the name rules, raw
// templates and frame sketches, and the readers one layer hands to another.
//
// The parts, one file each:
//   vector_document.cpp      the document layer: file, notes, groups, vectors
//   vector_steps.cpp         the step schema: steps, sends, modifiers,
//                            expectations, field matchers
//   vector_frames.cpp        raw templates and frame sketches
//   vector_requirements.cpp  requirements against device profiles
//   vector_names.cpp         what ids, flags, tags and capture names look like
//   vector_lint.cpp          the suite linter (errata, spec quotes, tags)
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sabus/harness/vector_loader.hpp"
#include "sabus/harness/yaml_reader.hpp"
#include "sabus/protocol/catalog.hpp"

namespace sabus::harness::vector_loader_internal {

using namespace yaml_reader;

// ---------------------------------------------------------------------------
// Limits and tables
// ---------------------------------------------------------------------------

// Bounds on what a hostile file can make the loader allocate or walk (and the
// list bounds of vector_loader.hpp, kMaxGroups ... kMaxValues).
inline constexpr std::size_t kMaxFileBytes = 1 << 20;
inline constexpr std::size_t kMaxText = 2000;     // comments, titles, descriptions
inline constexpr std::size_t kMaxQuote = 400;     // "the short spec quote it checks"
inline constexpr std::size_t kMaxHex = 2000;      // a raw template
inline constexpr std::size_t kMaxRegex = 200;
inline constexpr std::size_t kMaxRegexStates = 100000;  // product of bounded repeats (std::regex expands them)
// YAML aliases let a small file name the same vector many times: every
// vector, step and matcher read costs one unit, and the costly checks more
// (kCost*), so that no file takes more than about a second to read (half a
// minute under ASan in a debug build).
inline constexpr std::size_t kWorkBudget = 100000;
inline constexpr std::size_t kCostBuild = 2;         // build_request and encode_request
inline constexpr std::size_t kCostRegex = 10;        // compiling a std::regex
inline constexpr std::size_t kCostRequirement = 10;  // loading and writing a profile
inline constexpr long long kMinPollIntervalMs = 1000;   // §4 / ERRATA E-3: at most one request a second
inline constexpr std::uint8_t kSketchAddress = 0x32;    // the default profile's address, for length checks

inline constexpr std::pair<std::string_view, Level> kLevels[] = {
    {"must", Level::kMust}, {"should", Level::kShould}, {"informative", Level::kInformative}};

template <class Range>
bool contains(const Range& range, std::string_view s) {
  return std::find(std::begin(range), std::end(range), s) != std::end(range);
}

template <class Range>
std::string joined(const Range& range) {
  std::string out;
  for (const auto& s : range) out += (out.empty() ? "" : ", ") + std::string(s);
  return out;
}

// ---------------------------------------------------------------------------
// Names (vector_names.cpp)
// ---------------------------------------------------------------------------

bool is_alnum(char c);
// Flags, after Wycheproof ("ModifiedTag"): a letter, then letters, digits, '_'.
bool is_flag_name(std::string_view s);
// "motion", "option:dvb", "pol:single_port".
bool is_tag_text(std::string_view s);
// "3.2-status-reserved-bytes".
bool is_id_text(std::string_view s);
// "$track".
bool is_capture_name(std::string_view s);
// A profile key path segment: "errata", "implements_iess".
bool is_key_segment(std::string_view s);
// §1, §2, §3 (the RC3000 command set, NAK and offline replies), §4, and the
// catalog's §3.1-§3.25.
bool is_spec_paragraph(std::string_view p);

// ---------------------------------------------------------------------------
// Raw byte templates and frame sketches (vector_frames.cpp)
// ---------------------------------------------------------------------------

// "0x4a".
std::string hex_byte(std::uint8_t b);

// One element of a raw template "02 {addr} 31 03 {lrc}".
struct Element {
  enum class Kind : std::uint8_t {
    kByte, kAddr, kLrc,
    kCapture,  // {$name}: the text a step captured
    kExpr,     // {expr}: a profile expression (expressions.hpp), expanded by the runner
  };
  Kind kind = Kind::kByte;
  std::uint8_t byte = 0;
  std::string capture;  // kCapture: "$name"; kExpr: the expression
};

// Appends the elements of `hex`; the reason when it is not a template.
std::optional<std::string> parse_template(std::string_view hex, std::vector<Element>& out);

// What can be told about a frame before it is sent: its bytes up to the
// first capture (whose length is known only at run time), at address 50.
struct FrameSketch {
  Bytes bytes;
  bool complete = true;                  // no capture: `bytes` is the whole send
  std::size_t start = 0;                 // byte 0 of its last frame
  const CommandInfo* command = nullptr;  // from the command byte, when it can be read
  std::optional<std::uint8_t> selector;  // the form selector byte, when it can be read
};

FrameSketch sketch_of(Bytes bytes, bool complete);
FrameSketch sketch_of(const std::vector<Element>& elements);
// The frame a step sends, as far as it can be told without a device.
std::optional<FrameSketch> step_sketch(const Step& s, std::string& problem);
// What sending the frame can do on a bench (READING-NOTES 26).
std::optional<Effects> effects_of(const FrameSketch& s);
// Whether the catalog's request length applies to a send: a complete command
// frame of a code whose request length the catalog knows.
bool has_checked_length(const FrameSketch& k);
// A structured command's fields as a static check can build them: profile
// expressions expanded against the default profile (captures read 0); a
// field it cannot give is left to the codec's default.
std::map<std::string, std::string> static_fields(const std::map<std::string, std::string>& fields);
// Why build_request refused a structured command.
std::string build_error_text(const DecodeError& e);

// ---------------------------------------------------------------------------
// Reading one file
// ---------------------------------------------------------------------------

// Thrown when the work budget is spent: ends the file, not just the vector.
struct OverBudget {
  At at;
};

// What every part of a file needs.
struct FileInfo {
  std::string name;
  std::string paragraph;
  bool cross_cutting = false;
  std::vector<Requirement> requires_;
  std::vector<std::string> needs;
  std::size_t* work = nullptr;
  SourceLocation loc(const YAML::Mark& m) const { return {name, one_based(m.line), one_based(m.column)}; }
  void spend(const At& at, std::size_t units = 1) const {
    *work += units;
    if (*work > kWorkBudget) throw OverBudget{at};
  }
};

// The values captured by the steps read so far ("$track").
using Captures = std::set<std::string>;

struct StepContext {
  const FileInfo& file;
  Captures captures;
  // Reading a teardown: its steps carry no precondition (the vector's test
  // purpose is decided before the teardown runs).
  bool teardown = false;
  // Reading a vector's `steps` (not a setup or teardown): an alternative's
  // `ends` may end them.
  bool steps = false;
};

[[noreturn]] inline void fail_missing(const At& map_at, std::string_view key, const std::string& message) {
  fail(map_at.key(key, map_at.mark), message);
}

inline void require_keys(const MapReader& r, const At& at, std::initializer_list<std::string_view> keys,
                         std::string_view what) {
  for (auto k : keys)
    if (!r.has(k)) fail_missing(at, k, std::string(what) + " needs " + std::string(k));
}

// A setup, steps or teardown list (vector_steps.cpp); the captures its
// matchers make are added to cx.
std::vector<Step> read_steps(const YAML::Node& v, const At& at, StepContext& cx);

// A reply of the kind as its codec encodes the defaults, to the first
// command that answers with it (coverage.cpp): the coverage matrix and the
// linter put a field's values in it to see how the layout reads them.
std::optional<Bytes> sample_reply(ReplyKind reply);
// How the layout reads `field`, the byte at `at` of `frame`, holding `code`
// (the check byte mended).
std::optional<FieldDescription> field_with_code(Bytes frame, std::size_t at, std::uint8_t code, std::string_view field);

// A `requires` map of key path -> value(s), or a list of such maps
// (vector_requirements.cpp).
std::vector<Requirement> read_requires(const YAML::Node& v, const At& at, const FileInfo& file);

}  // namespace sabus::harness::vector_loader_internal
