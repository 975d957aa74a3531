// Conformance vectors: the loader of vectors/*.yaml (schema and worked
// examples: vectors/README.md) and the suite linter.
//
// The loader reads one file strictly (yaml_reader.hpp: every key checked,
// duplicates found, marks kept) and checks each send against the command
// catalog and the codecs: commands, forms, request fields, reply fields,
// frame lengths, raw hex. lint() checks what needs the whole suite or the
// errata: unique ids, flags against notes, errata entries, known tags, the
// spec quotes, and the motion/destructive tags that keep bench runs safe
// (READING-NOTES 26, ERRATA E-26).
#include "sabus/harness/vector_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <regex>
#include <set>
#include <span>
#include <sstream>
#include <tuple>

#include "sabus/harness/data_dir.hpp"
#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/lrc.hpp"
#include "sabus/protocol/structured.hpp"
#include "sabus/harness/yaml_reader.hpp"

namespace sabus::harness {
namespace {

using namespace yaml_reader;

// ---------------------------------------------------------------------------
// Limits and tables
// ---------------------------------------------------------------------------

// Bounds on what a hostile file can make the loader allocate or walk.
constexpr std::size_t kMaxFileBytes = 1 << 20;
constexpr std::size_t kMaxGroups = 100;
constexpr std::size_t kMaxVectors = 500;   // in one `vectors` list
constexpr std::size_t kMaxSteps = 64;      // in one setup, steps or teardown list
constexpr std::size_t kMaxEntries = 64;    // fields, matchers, notes, requirements, flags, tags
constexpr std::size_t kMaxValues = 32;     // one_of, requirement values, modifier lists
constexpr std::size_t kMaxText = 2000;     // comments, titles, descriptions
constexpr std::size_t kMaxQuote = 400;     // "the short spec quote it checks"
constexpr std::size_t kMaxHex = 2000;      // a raw template
constexpr std::size_t kMaxRegex = 200;
constexpr std::size_t kMaxRegexStates = 100000;  // product of bounded repeats (std::regex expands them)
// YAML aliases let a small file name the same vector many times: every
// vector, step and matcher read costs one unit, and the costly checks more
// (kCost*), so that no file takes more than about a second to read (half a
// minute under ASan in a debug build).
constexpr std::size_t kWorkBudget = 100000;
constexpr std::size_t kCostBuild = 2;         // build_request and encode_request
constexpr std::size_t kCostRegex = 10;        // compiling a std::regex
constexpr std::size_t kCostRequirement = 10;  // loading and writing a profile
constexpr long long kMaxMs = 3'600'000;          // a 360 degree move at 0.25 deg/s takes 24 minutes
constexpr long long kMinPollIntervalMs = 1000;   // §4 / ERRATA E-3: at most one request a second
constexpr std::uint8_t kSketchAddress = 0x32;    // the default profile's address, for length checks

constexpr std::pair<std::string_view, Level> kLevels[] = {
    {"must", Level::kMust}, {"should", Level::kShould}, {"informative", Level::kInformative}};

constexpr std::pair<std::string_view, Expectation::Kind> kReplyKinds[] = {{"ack", Expectation::Kind::kAck},
                                                                          {"nak", Expectation::Kind::kNak},
                                                                          {"offline", Expectation::Kind::kOffline},
                                                                          {"silence", Expectation::Kind::kSilence},
                                                                          {"any", Expectation::Kind::kAny}};

// Tags a run selects or skips vectors by (vectors/README.md). `motion` and
// `destructive` are required by the catalog's effects (READING-NOTES 26).
constexpr std::string_view kKnownTags[] = {"motion",          "destructive", "option:dvb", "pol:circular",
                                           "pol:single_port", "pol:dual_port", "parity",   "timing",
                                           "offline",         "multidrop",   "track"};

// Files that follow one behaviour through several paragraphs rather than
// testing one paragraph: their vectors may cite any paragraph.
constexpr std::string_view kCrossCutting[] = {"framing", "ignore",    "nak",   "offline",
                                              "parity",  "multidrop", "timing", "pacing"};

// In the data directory (data_dir.hpp).
constexpr std::string_view kErrataFile = "protocol/ERRATA.md";
// The spec text the quotes come from (protocol/ERRATA.md: "the project reads
// it from ../shared/spec/"), by its file name (spec_text_path says where).
constexpr std::string_view kSpecTextName = "000_ebbe2d50858e9e24.txt";

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

std::string level_names() {
  std::string out;
  for (const auto& level : kLevels) out += (out.empty() ? "" : ", ") + std::string(level.first);
  return out;
}

std::string hex_byte(std::uint8_t b) {
  static constexpr char kHex[] = "0123456789abcdef";
  return std::string("0x") + kHex[b >> 4] + kHex[b & 0xF];
}

// ---------------------------------------------------------------------------
// Names
// ---------------------------------------------------------------------------

bool is_lower_alnum(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }
bool is_alnum(char c) { return is_lower_alnum(c) || (c >= 'A' && c <= 'Z'); }

// first character, then the rest, at most `max` characters.
bool is_name(std::string_view s, std::size_t max, bool (*first)(char), bool (*rest)(char)) {
  return !s.empty() && s.size() <= max && first(s[0]) && std::all_of(s.begin() + 1, s.end(), rest);
}
bool is_letter(char c) { return is_alnum(c) && !(c >= '0' && c <= '9'); }
bool is_ident_char(char c) { return is_alnum(c) || c == '_'; }

// Flags, after Wycheproof ("ModifiedTag"): a letter, then letters, digits, '_'.
bool is_flag_name(std::string_view s) { return is_name(s, 64, is_letter, is_ident_char); }
// "motion", "option:dvb", "pol:single_port".
bool is_tag_text(std::string_view s) {
  return is_name(s, 32, [](char c) { return c >= 'a' && c <= 'z'; },
                 [](char c) { return is_lower_alnum(c) || c == '_' || c == ':' || c == '-'; });
}
// "3.2-status-reserved-bytes".
bool is_id_text(std::string_view s) {
  return is_name(s, 100, is_alnum, [](char c) { return is_alnum(c) || c == '.' || c == '-' || c == '_' || c == ':'; });
}
// "$track".
bool is_capture_name(std::string_view s) {
  return s.size() >= 2 && s[0] == '$' && is_name(s.substr(1), 32, [](char c) { return is_letter(c) || c == '_'; }, is_ident_char);
}
// A profile key path segment: "errata", "implements_iess".
bool is_key_segment(std::string_view s) {
  return is_name(s, 40, [](char c) { return (c >= 'a' && c <= 'z') || c == '_'; },
                 [](char c) { return is_lower_alnum(c) || c == '_'; });
}

// §1, §2, §3 (the RC3000 command set, NAK and offline replies), §4, and the
// catalog's §3.1-§3.25: one table of paragraphs, the catalog.
bool is_spec_paragraph(std::string_view p) {
  if (p == "1" || p == "2" || p == "3" || p == "4") return true;
  for (const auto& c : catalog())
    if (c.paragraph == p) return true;
  return false;
}

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> out;
  for (std::size_t pos = 0;;) {
    const std::size_t at = s.find(sep, pos);
    out.emplace_back(s.substr(pos, at == std::string_view::npos ? std::string_view::npos : at - pos));
    if (at == std::string_view::npos) return out;
    pos = at + 1;
  }
}

// ---------------------------------------------------------------------------
// Raw byte templates: "02 {addr} 31 03 {lrc}"
// ---------------------------------------------------------------------------

struct Element {
  enum class Kind : std::uint8_t { kByte, kAddr, kLrc, kCapture };
  Kind kind = Kind::kByte;
  std::uint8_t byte = 0;
  std::string capture;  // "$name"
};

// A run of hex text between placeholders; `offset` is where it starts in the
// template, for the message.
std::optional<std::string> append_hex(std::string_view run, std::size_t offset, std::vector<Element>& out) {
  auto bytes = parse_hex(run);
  if (!bytes) {
    const DecodeError& e = bytes.error();
    return "bad hex at character " + std::to_string(offset + e.offset + 1) + ": expected " + e.expected +
           (e.got.empty() ? "" : ", got " + quoted_clip(e.got));
  }
  for (auto b : *bytes) {
    // The line adds the parity bit (READING-NOTES 1); a template holds characters.
    if (b > 0x7F) return "byte " + hex_byte(b) + " is not a 7-bit character (use modify.parity_flip for a parity error)";
    out.push_back({Element::Kind::kByte, b, {}});
  }
  return std::nullopt;
}

std::optional<std::string> parse_template(std::string_view hex, std::vector<Element>& out) {
  for (std::size_t pos = 0;;) {
    const std::size_t open = hex.find('{', pos);
    const std::string_view run = hex.substr(pos, open == std::string_view::npos ? std::string_view::npos : open - pos);
    if (auto e = append_hex(run, pos, out)) return e;
    if (open == std::string_view::npos) return std::nullopt;
    const std::size_t close = hex.find('}', open);
    if (close == std::string_view::npos)
      return "the placeholder at character " + std::to_string(open + 1) + " has no closing '}'";
    const std::string_view name = hex.substr(open + 1, close - open - 1);
    if (name == "addr") out.push_back({Element::Kind::kAddr, 0, {}});
    else if (name == "lrc") out.push_back({Element::Kind::kLrc, 0, {}});
    else if (is_capture_name(name)) out.push_back({Element::Kind::kCapture, 0, std::string(name)});
    else return "unknown placeholder {" + std::string(name.substr(0, 40)) + "}: expected {addr}, {lrc} or {$name}";
    pos = close + 1;
  }
}

// Byte 0 of the frame that ends at `end` (READING-NOTES 7); 0 when none.
std::size_t frame_start(ByteView bytes, std::size_t end) {
  return last_frame_start(bytes.first(std::min(end, bytes.size()))).value_or(0);
}

Expected<Bytes> expand(const std::vector<Element>& elements, std::uint8_t address,
                       const std::map<std::string, std::string>& captures) {
  Bytes out;
  for (const auto& e : elements) {
    switch (e.kind) {
      case Element::Kind::kByte: out.push_back(e.byte); break;
      case Element::Kind::kAddr: out.push_back(address); break;
      case Element::Kind::kLrc: {
        const std::size_t start = frame_start(out, out.size());
        out.push_back(lrc(ByteView(out).subspan(start)));  // E-5: from byte 0 through ETX
        break;
      }
      case Element::Kind::kCapture: {
        auto it = captures.find(e.capture);
        if (it == captures.end()) return DecodeError{out.size(), "raw", "a value captured as " + e.capture, ""};
        for (char c : it->second) {
          if (static_cast<unsigned char>(c) > 0x7F)
            return DecodeError{out.size(), "raw", "7-bit characters in " + e.capture, describe_byte(static_cast<std::uint8_t>(c))};
          out.push_back(static_cast<std::uint8_t>(c));
        }
        break;
      }
    }
  }
  return out;
}

// What can be told about a frame before it is sent: its bytes up to the
// first capture (whose length is known only at run time), at address 50.
struct FrameSketch {
  Bytes bytes;
  bool complete = true;                  // no capture: `bytes` is the whole send
  std::size_t start = 0;                 // byte 0 of its last frame
  const CommandInfo* command = nullptr;  // from the command byte, when it can be read
  std::optional<std::uint8_t> selector;  // the form selector byte, when it can be read
};

FrameSketch sketch_of(Bytes bytes, bool complete) {
  FrameSketch s{std::move(bytes), complete, 0, nullptr, std::nullopt};
  s.start = frame_start(s.bytes, s.bytes.size());
  if (s.start + 2 < s.bytes.size()) s.command = find_command(s.bytes[s.start + 2]);
  if (s.command && s.command->form_selector_offset && s.start + *s.command->form_selector_offset < s.bytes.size())
    s.selector = s.bytes[s.start + *s.command->form_selector_offset];
  return s;
}

FrameSketch sketch_of(const std::vector<Element>& elements) {
  std::vector<Element> known;
  bool complete = true;
  for (const auto& e : elements) {
    if (e.kind == Element::Kind::kCapture) {
      complete = false;
      break;
    }
    known.push_back(e);
  }
  auto bytes = expand(known, kSketchAddress, {});  // cannot fail: no captures
  return sketch_of(bytes ? std::move(bytes).value() : Bytes{}, complete);
}

// What sending the frame can do on a bench (READING-NOTES 26): the form its
// selector byte chooses, or any form of the command.
std::optional<Effects> effects_of(const FrameSketch& s) {
  if (!s.command) return std::nullopt;
  if (s.selector)
    if (const FormInfo* f = s.command->form_for_selector(*s.selector)) return f->effects;
  return s.command->effects();
}

// ---------------------------------------------------------------------------
// Requirements: profile keys and values, as the profile loader reads them
// ---------------------------------------------------------------------------

// The values at a key path: a scalar's text, or each element of a list of
// scalars (bus_peers); nullopt when the path leads nowhere or to a map.
std::optional<std::vector<std::string>> values_at(const YAML::Node& node, std::span<const std::string> path) {
  if (path.empty()) {
    if (node.IsScalar()) return std::vector<std::string>{node.Scalar()};
    if (!node.IsSequence()) return std::nullopt;
    std::vector<std::string> out;
    for (const auto& e : node) {
      if (!e.IsScalar()) return std::nullopt;
      out.push_back(e.Scalar());
    }
    return out;
  }
  if (!node.IsMap()) return std::nullopt;
  const YAML::Node child = node[path.front()];  // const lookup: never inserts
  if (!child.IsDefined()) return std::nullopt;
  return values_at(child, path.subspan(1));
}

// A key's value as to_yaml writes it: the text requirements compare. A list
// key (bus_peers) is required to contain the value, so one value is given.
std::optional<std::string> written_value(const Profile& profile, const std::vector<std::string>& path) {
  const YAML::Node root = YAML::Load(to_yaml(profile));
  const auto values = values_at(root, path);
  if (!values || values->size() != 1) return std::nullopt;
  return values->front();
}

bool is_plain_word(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return is_alnum(c) || c == '_' || c == '.' || c == '+' || c == '-';
  });
}

std::string yaml_double_quoted(std::string_view s, const At& at) {
  std::string out = "\"";
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) fail(at, "a requirement value cannot hold control characters");
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The profile schema is the profile loader's: the requirement is written into
// a profile of one key and loaded, so a key the schema lacks or a value it
// rejects is an error here too; the value is then read back as to_yaml writes
// it, so 50, 0x32 and "2" are one address (vectors/profiles/README.md).
std::string canonical_profile_value(const std::vector<std::string>& path, const YAML::Node& value, const At& at) {
  const std::string& text = scalar(value, at, "a profile value");
  std::string yaml_value;
  if (is_quoted(value)) yaml_value = yaml_double_quoted(text, at);
  else if (is_plain_word(text)) yaml_value = text;
  else fail(at, quoted_clip(text) + " is not a plain word or number; quote it");
  std::string doc;
  for (std::size_t i = 0; i < path.size(); ++i)
    doc += std::string(2 * i, ' ') + path[i] + ":" + (i + 1 == path.size() ? " " + yaml_value : "") + "\n";
  ProfileResult p = load_profile_text(doc, "requires");
  if (!p) fail(at, "not a device profile setting: " + (p.error->key.empty() ? "" : p.error->key + ": ") + p.error->message);
  auto written = written_value(*p.profile, path);
  if (!written) fail(at, "not a single value of a device profile (vectors/profiles/README.md)");
  return *written;
}

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
};

std::string to_text(const YAML::Node& v, const At& at, std::size_t max) {
  const std::string& s = scalar(v, at, "text");
  if (s.empty()) fail(at, "must not be empty");
  if (s.size() > max) fail(at, "has " + std::to_string(s.size()) + " characters, at most " + std::to_string(max));
  return s;
}

[[noreturn]] void fail_missing(const At& map_at, std::string_view key, const std::string& message) {
  fail(map_at.key(key, map_at.mark), message);
}

void require_keys(const MapReader& r, const At& at, std::initializer_list<std::string_view> keys, std::string_view what) {
  for (auto k : keys)
    if (!r.has(k)) fail_missing(at, k, std::string(what) + " needs " + std::string(k));
}

Level to_level(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a level");
  for (const auto& [name, level] : kLevels)
    if (s == name) return level;
  fail(at, quoted_clip(s) + " is not a level: " + level_names() + " (READING-NOTES \"Result levels\")");
}

std::vector<std::string> to_names(const YAML::Node& v, const At& at, bool (*valid)(std::string_view), std::string_view what) {
  std::vector<std::string> out;
  for_each_element(v, at, kMaxEntries, [&](const YAML::Node& e, const At& ea) {
    const std::string& s = scalar(e, ea, what);
    if (!valid(s)) fail(ea, quoted_clip(s) + " is not " + std::string(what));
    if (contains(out, s)) fail(ea, quoted_clip(s) + " is listed twice");
    out.push_back(s);
  });
  return out;
}

std::vector<std::string> merged(std::vector<std::string> a, const std::vector<std::string>& b) {
  for (const auto& s : b)
    if (!contains(a, s)) a.push_back(s);
  return a;
}

// --- requirements ---

Requirement read_requirement(const std::string& key, const YAML::Node& value, const At& at, const FileInfo& file) {
  Requirement r{key, {}, file.loc(at.mark)};
  const std::vector<std::string> path = split(key, '.');
  if (path.size() > 3 || !std::all_of(path.begin(), path.end(), [](const std::string& s) { return is_key_segment(s); }))
    fail(at, quoted_clip(key) + " is not a profile key path (polarization, errata.implements_iess)");
  if (value.IsMap()) fail(at, "expected a value or a list of values; write nested profile keys dotted (errata.implements_iess)");
  auto one = [&](const YAML::Node& n, const At& a) {
    file.spend(a, kCostRequirement);
    std::string v = canonical_profile_value(path, n, a);
    if (!contains(r.values, v)) r.values.push_back(std::move(v));
  };
  if (value.IsSequence()) {
    for_each_element(value, at, kMaxValues, one);
    if (r.values.empty()) fail(at, "no value given");
  } else {
    one(value, at);
  }
  return r;
}

// A map of key path -> value(s), or a list of such maps: every one must hold.
std::vector<Requirement> read_requires(const YAML::Node& v, const At& at, const FileInfo& file) {
  std::vector<Requirement> out;
  auto read_map = [&](const YAML::Node& m, const At& ma) {
    for_each_entry(m, ma, kMaxEntries, [&](const std::string& key, const YAML::Node& value, const At& ka) {
      out.push_back(read_requirement(key, value, ka, file));
    });
  };
  if (v.IsSequence()) for_each_element(v, at, kMaxEntries, read_map);
  else read_map(v, at);
  if (out.empty()) fail(at, "no requirement given; leave requires out");
  return out;
}

// --- field matchers ---

// describe_frame writes a one-byte field as 0x and two lower-case digits: an
// upper-case "0x4A" could never match.
std::string to_match_text(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a value");
  const bool hex_byte_text = s.size() == 4 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X') &&
                             std::isxdigit(static_cast<unsigned char>(s[2])) && std::isxdigit(static_cast<unsigned char>(s[3]));
  if (hex_byte_text && (s[1] == 'X' || std::any_of(s.begin() + 2, s.end(), [](char c) { return c >= 'A' && c <= 'F'; })))
    fail(at, quoted_clip(s) + ": write one-byte values as describe_frame does, lower case (0x4a)");
  return s;
}

// std::regex expands bounded repeats ("a{5}") into states: their product is
// capped so that a pattern cannot make compiling it take all memory.
std::optional<std::string> repeat_problem(std::string_view p) {
  std::size_t states = 1;
  bool in_class = false;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const char c = p[i];
    if (c == '\\') ++i;
    else if (c == '[') in_class = true;
    else if (c == ']') in_class = false;
    else if (c == '{' && !in_class) {
      std::size_t bound = 0, j = i + 1;
      for (std::size_t n = 0; j < p.size() && (std::isdigit(static_cast<unsigned char>(p[j])) || p[j] == ','); ++j) {
        if (p[j] == ',') {
          n = 0;
          continue;
        }
        n = std::min<std::size_t>(n * 10 + static_cast<std::size_t>(p[j] - '0'), kMaxRegexStates);
        bound = std::max(bound, n);
      }
      states = std::min(states * (bound + 1), kMaxRegexStates + 1);
      if (states > kMaxRegexStates) return "its bounded repeats ({n,m}) are too large";
    }
  }
  return std::nullopt;
}

std::string to_regex(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a regular expression");
  if (s.empty() || s.size() > kMaxRegex) fail(at, "a regex has 1 to " + std::to_string(kMaxRegex) + " characters");
  if (auto e = repeat_problem(s)) fail(at, "regex " + quoted_clip(s) + ": " + *e);
  try {
    std::regex re(s, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    fail(at, "bad regex " + quoted_clip(s) + " (ECMAScript): " + e.what());
  }
  return s;
}

void read_range(const YAML::Node& v, const At& at, FieldMatcher& m) {
  if (!v.IsSequence() || v.size() != 2) fail(at, "expected [low, high], got " + kind_of(v));
  m.low = to_number(v[0], at);
  m.high = to_number(v[1], at);
  if (m.low > m.high) fail(at, "low " + number_text(m.low) + " is above high " + number_text(m.high));
}

FieldMatcher read_matcher(const std::string& name, const YAML::Node& v, const At& at, StepContext& cx) {
  FieldMatcher m{name, FieldMatcher::Kind::kAny, {}, 0, 0, "", cx.file.loc(at.mark)};
  if (v.IsNull()) fail(at, "expected a value, any, or a map of eq, one_of, regex, range, capture");
  if (v.IsScalar()) {
    if (!is_quoted(v) && v.Scalar() == "any") return m;
    m.kind = FieldMatcher::Kind::kEq;
    m.values = {to_match_text(v, at)};
    return m;
  }
  MapReader r(v, at, {"eq", "one_of", "regex", "range", "capture"});
  const int tests = r.has("eq") + r.has("one_of") + r.has("regex") + r.has("range");
  if (tests > 1) fail(at, "give one of eq, one_of, regex, range");
  if (tests == 0 && !r.has("capture")) fail(at, "expected eq, one_of, regex, range or capture");
  r.with("eq", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kEq;
    m.values = {to_match_text(n, a)};
  });
  r.with("one_of", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kOneOf;
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) { m.values.push_back(to_match_text(e, ea)); });
    if (m.values.empty()) fail(a, "no value given");
  });
  r.with("regex", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kRegex;
    cx.file.spend(a, kCostRegex);
    m.values = {to_regex(n, a)};
  });
  r.with("range", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kRange;
    read_range(n, a, m);
  });
  r.with("capture", [&](const YAML::Node& n, const At& a) {
    m.capture = scalar(n, a, "a capture name");
    if (!is_capture_name(m.capture)) fail(a, quoted_clip(m.capture) + " is not a capture name ($name)");
  });
  return m;
}

// The fields a reply can show, as describe_frame names them. A NAK or offline
// reply has only the frame fields every reply has (§3): reply_field_names
// lists them first (start, address, command) and last (offline, ETX, check
// byte). nullopt: the command is unknown, names are not checked.
struct ReplyFields {
  std::vector<std::string> names;
  std::string what;  // "the status reply"
};

std::optional<ReplyFields> reply_fields(const CommandInfo* command, Expectation::Kind kind) {
  if (kind == Expectation::Kind::kNak || kind == Expectation::Kind::kOffline) {
    const std::vector<std::string> all = reply_field_names(*find_command(kFirstCommand));
    const std::size_t tail = kind == Expectation::Kind::kNak ? 2 : 3;  // without / with "offline"
    std::vector<std::string> names(all.begin(), all.begin() + 3);
    names.insert(names.end(), all.end() - static_cast<std::ptrdiff_t>(tail), all.end());
    return ReplyFields{names, kind == Expectation::Kind::kNak ? "the NAK reply (§3)" : "the offline reply (§3)"};
  }
  if (!command) return std::nullopt;
  return ReplyFields{reply_field_names(*command), "the " + std::string(command->key) + " reply"};
}

std::vector<FieldMatcher> read_matchers(const YAML::Node& v, const At& at, const std::optional<ReplyFields>& reply,
                                        StepContext& cx) {
  std::vector<FieldMatcher> out;
  for_each_entry(v, at, kMaxEntries, [&](const std::string& name, const YAML::Node& value, const At& fa) {
    cx.file.spend(fa);
    if (reply && !contains(reply->names, name))
      fail(fa, "unknown field " + quoted_clip(name) + " of " + reply->what + "; its fields (as describe_frame names them): " +
                   joined(reply->names));
    out.push_back(read_matcher(name, value, fa, cx));
  });
  if (out.empty()) fail(at, "no field given");
  return out;
}

void keep_captures(const std::vector<FieldMatcher>& matchers, StepContext& cx) {
  for (const auto& m : matchers)
    if (!m.capture.empty()) cx.captures.insert(m.capture);
}

// --- expectations ---

Expectation::Kind to_reply_kind(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "ack, nak, offline, silence or any");
  for (const auto& [name, kind] : kReplyKinds)
    if (s == name) return kind;
  fail(at, quoted_clip(s) + " is not a reply: expected ack, nak, offline, silence or any");
}

std::string_view reply_kind_name(Expectation::Kind k) {
  for (const auto& [name, kind] : kReplyKinds)
    if (kind == k) return name;
  return "?";
}

// A whole expected reply must fit the catalog: ACK or NAK first, the step's
// command byte, and the length of that kind of reply (§3 NAK and offline replies).
void check_reply_bytes(const FrameSketch& s, Expectation::Kind kind, const CommandInfo* command, const At& at) {
  if (kind == Expectation::Kind::kAny || s.bytes.empty()) return;
  const std::uint8_t start = kind == Expectation::Kind::kNak ? NAK : ACK;
  if (s.bytes[0] != start)
    fail(at, "a " + std::string(reply_kind_name(kind)) + " reply starts with " + describe_byte(start) + ", not " + describe_byte(s.bytes[0]));
  if (command && s.bytes.size() > 2 && s.bytes[2] != command->code)
    fail(at, "the reply's command byte is " + hex_byte(s.bytes[2]) + "; the step sends " + hex_byte(command->code));
  if (!s.complete) return;
  std::optional<std::size_t> want = command ? command->reply_length : std::nullopt;
  std::string what = command ? "the catalog's reply to " + std::string(command->key) : "";
  if (kind == Expectation::Kind::kNak) {
    want = kNakReplyLength;
    what = "the NAK reply, §3";
  } else if (kind == Expectation::Kind::kOffline) {
    want = kOfflineReplyLength;
    what = "the offline reply, §3";
  }
  if (want && s.bytes.size() != *want)
    fail(at, "the reply is " + std::to_string(s.bytes.size()) + " bytes, not " + std::to_string(*want) + " (" + what + ")");
}

RawBytes read_raw(const YAML::Node& v, const At& at, StepContext& cx, std::vector<Element>& elements) {
  const std::string& hex = scalar(v, at, "hex bytes");
  if (hex.size() > kMaxHex) fail(at, "has " + std::to_string(hex.size()) + " characters, at most " + std::to_string(kMaxHex));
  if (auto e = parse_template(hex, elements)) fail(at, *e);
  if (elements.empty()) fail(at, "no bytes given");
  for (const auto& e : elements)
    if (e.kind == Element::Kind::kCapture && !cx.captures.count(e.capture))
      fail(at, "{" + e.capture + "}: no earlier step captures " + e.capture);
  return RawBytes{hex, cx.file.loc(at.mark)};
}

Expectation read_expectation(const YAML::Node& v, const At& at, const CommandInfo* command, StepContext& cx) {
  Expectation e;
  e.where = cx.file.loc(at.mark);
  if (v.IsScalar()) {
    e.kind = to_reply_kind(v, at);
    return e;
  }
  MapReader r(v, at, {"reply", "bytes", "fields", "rule"});
  require_keys(r, at, {"reply"}, "expect");
  r.read("reply", e.kind, to_reply_kind);
  r.with("rule", [&](const YAML::Node& n, const At& a) {
    if (e.kind != Expectation::Kind::kNak) fail(a, "only a nak reply names a rule");
    const std::string& s = scalar(n, a, "a NAK rule");
    if (!find_nak_rule(s)) {
      std::string names;
      for (NakRule rule : all_nak_rules()) names += (names.empty() ? "" : ", ") + std::string(name(rule));
      fail(a, quoted_clip(s) + " is not a NAK rule of harness/controller/include/sabus/harness/nak_rules.hpp: " + names);
    }
    e.nak_rule = s;
  });
  if (e.kind == Expectation::Kind::kSilence)
    for (auto k : {"bytes", "fields"})
      if (r.has(k)) fail(r.at(k), std::string("silence has no ") + k);
  r.with("bytes", [&](const YAML::Node& n, const At& a) {
    std::vector<Element> elements;
    e.bytes = read_raw(n, a, cx, elements);
    check_reply_bytes(sketch_of(elements), e.kind, command, a);
  });
  r.with("fields", [&](const YAML::Node& n, const At& a) { e.fields = read_matchers(n, a, reply_fields(command, e.kind), cx); });
  keep_captures(e.fields, cx);
  return e;
}

// --- sends ---

struct Send {
  std::optional<StructuredCommand> command;
  std::optional<RawBytes> raw;
  At raw_at;
  FrameSketch sketch;
};

std::string form_ids(const CommandInfo& info) {
  std::string out;
  for (const auto& f : info.forms) out += (out.empty() ? "" : ", ") + std::string(f.id);
  return out;
}

const CommandInfo& to_command(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a command");
  if (const CommandInfo* c = find_command(s)) return *c;
  std::string keys;
  for (const auto& c : catalog()) keys += (keys.empty() ? "" : ", ") + std::string(c.key);
  fail(at, "unknown command " + quoted_clip(s) + ": expected a catalog key (" + keys + "), name or code (\"31h\")");
}

// The catalog's spelling of the form ("2a" -> "2A"); "" for one-form commands.
std::string to_form(const MapReader& r, const At& at, const CommandInfo& info) {
  std::string text;
  r.read("form", text, [](const YAML::Node& n, const At& a) { return scalar(n, a, "a form"); });
  if (info.forms.size() <= 1) {
    if (!text.empty()) fail(r.at("form"), std::string(info.key) + " has one form: leave form out");
    return "";
  }
  if (!r.has("form")) fail_missing(at, "form", std::string(info.key) + " needs form: one of " + form_ids(info));
  const FormInfo* f = info.form_by_id(text);
  if (!f) fail(r.at("form"), "unknown form " + quoted_clip(text) + " of " + std::string(info.key) + ": expected one of " + form_ids(info));
  return std::string(f->id);
}

// A field value is its text as written: 45.6, -152.5, 0x47, "SBS 6".
std::string to_field_value(const YAML::Node& v, const At& at) {
  if (!v.IsScalar()) fail(at, "expected a value, got " + kind_of(v) + " (quote \"\" for an empty text)");
  return v.Scalar();
}

// Where build_request's error points: `field "NAME": ...` names a field key.
At build_error_at(const DecodeError& e, const std::map<std::string, At>& field_at, const At& fallback) {
  for (const auto& [name, at] : field_at)
    if (e.expected.rfind("field \"" + name + "\"", 0) == 0) return at;
  return fallback;
}

std::string build_error_text(const DecodeError& e) {
  return "the codecs cannot build this request: " + e.expected + (e.got.empty() ? "" : ", got " + e.got);
}

StructuredCommand read_structured(const MapReader& r, const At& at, StepContext& cx, FrameSketch& sketch) {
  StructuredCommand sc;
  sc.where = cx.file.loc(at.mark);
  const CommandInfo* info = nullptr;
  r.with("command", [&](const YAML::Node& n, const At& a) {
    info = &to_command(n, a);
    sc.command = n.Scalar();
  });
  sc.form = to_form(r, at, *info);
  const std::vector<std::string> names = request_field_names(*info, sc.form);
  std::map<std::string, At> field_at;
  r.with("fields", [&](const YAML::Node& n, const At& a) {
    for_each_entry(n, a, kMaxEntries, [&](const std::string& name, const YAML::Node& value, const At& fa) {
      if (!contains(names, name))
        fail(fa, "unknown field " + quoted_clip(name) + " of " + std::string(info->key) +
                     (sc.form.empty() ? "" : " form " + sc.form) + "; its fields: " + joined(names));
      sc.fields[name] = to_field_value(value, fa);
      field_at.emplace(name, fa);
    });
  });
  r.with("address", [&](const YAML::Node& n, const At& a) { sc.address = to_address(n, a); });
  auto built = build_request(*info, sc.form, sc.fields);
  if (!built) fail(build_error_at(built.error(), field_at, r.at("fields")), build_error_text(built.error()));
  sketch = sketch_of(encode_request(*built, sc.address.value_or(kSketchAddress)), true);
  return sc;
}

Send read_send(const YAML::Node& v, const At& at, StepContext& cx) {
  MapReader r(v, at, {"command", "form", "fields", "address", "raw"});
  Send s;
  if (r.has("raw")) {
    for (auto k : {"command", "form", "fields", "address"})
      if (r.has(k)) fail(r.at(k), std::string("a raw send has no ") + k + ": write the bytes in raw");
    r.with("raw", [&](const YAML::Node& n, const At& a) {
      std::vector<Element> elements;
      s.raw = read_raw(n, a, cx, elements);
      s.raw_at = a;
      s.sketch = sketch_of(elements);
    });
    return s;
  }
  if (!r.has("command")) fail(at, "a send needs command (a catalog command) or raw (hex bytes)");
  cx.file.spend(at, kCostBuild);
  s.command = read_structured(r, at, cx, s.sketch);
  return s;
}

// Whether the length rule below applies to a send: a complete command frame
// of a code whose request length the catalog knows.
bool has_checked_length(const FrameSketch& k) {
  return k.complete && k.command && k.command->request_length && !k.bytes.empty() && k.bytes[k.start] == STX;
}

// §3 table: a raw command frame has its command's catalog length unless the
// step says `length_mismatch: true`. modify.extra_data_bytes and truncate
// make a wrong length out of a right frame and need no flag.
void check_length(const Send& s, const std::optional<At>& mismatch_at) {
  if (s.command) {
    if (mismatch_at) fail(*mismatch_at, "length_mismatch is for raw sends: a command built from fields has its catalog length");
    return;
  }
  const FrameSketch& k = s.sketch;
  if (!has_checked_length(k)) return;
  const std::size_t got = k.bytes.size() - k.start, want = *k.command->request_length;
  const std::string key(k.command->key);
  if (got != want && !mismatch_at)
    fail(s.raw_at, "the frame is " + std::to_string(got) + " bytes; the catalog says " + std::to_string(want) + " for " + key +
                       " (§" + std::string(k.command->paragraph) + "). If that is the test, write length_mismatch: true on the step");
  if (got == want && mismatch_at)
    fail(*mismatch_at, "length_mismatch: true, but the frame has the catalog length of " + key + " (" + std::to_string(want) + " bytes)");
}

// --- modifiers ---

// Any 7-bit character: modify.address sends to other or invalid addresses on purpose.
std::uint8_t to_modified_address(const YAML::Node& v, const At& at) {
  if (is_quoted(v) && v.Scalar().size() == 1) {
    const auto c = static_cast<std::uint8_t>(v.Scalar()[0]);
    if (c < 0x20 || c > 0x7F) fail(at, "expected a printable address character, got " + describe_byte(c));
    return c;
  }
  return static_cast<std::uint8_t>(to_integer_or_hex_in(v, at, 0x20, 0x7F));
}

std::size_t to_index(const YAML::Node& v, const At& at, std::optional<std::size_t> length) {
  const long long hi = length ? static_cast<long long>(*length) - 1 : 1000;
  if (hi < 0) fail(at, "the frame has no bytes left");
  return static_cast<std::size_t>(to_integer_in(v, at, 0, hi));
}

// Length checks follow the order the runner applies the modifiers in
// (vectors/README.md): address, extra_data_bytes, lrc_xor, replace, truncate,
// parity_flip, then chunks.
Modifiers read_modifiers(const YAML::Node& v, const At& at, std::optional<std::size_t> length) {
  MapReader r(v, at, {"lrc_xor", "address", "parity_flip", "extra_data_bytes", "truncate", "replace", "chunks", "pause_ms"});
  Modifiers m;
  auto byte = [](const YAML::Node& n, const At& a, long long lo) { return static_cast<std::uint8_t>(to_integer_or_hex_in(n, a, lo, 0x7F)); };
  r.read("lrc_xor", m.lrc_xor, [&](const YAML::Node& n, const At& a) { return byte(n, a, 1); });
  r.read("address", m.address, to_modified_address);
  r.read("extra_data_bytes", m.extra_data_bytes, [](const YAML::Node& n, const At& a) { return static_cast<std::size_t>(to_integer_in(n, a, 1, 200)); });
  if (length) *length += m.extra_data_bytes;
  r.with("replace", [&](const YAML::Node& n, const At& a) {
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) {
      if (!e.IsSequence() || e.size() != 2) fail(ea, "expected [index, byte], got " + kind_of(e));
      m.replace.emplace_back(to_index(e[0], ea, length), byte(e[1], ea, 0));
    });
  });
  r.read("truncate", m.truncate, [&](const YAML::Node& n, const At& a) {
    return static_cast<std::size_t>(to_integer_in(n, a, 1, length ? static_cast<long long>(*length) - 1 : 1000));
  });
  if (length) *length -= m.truncate;
  r.with("parity_flip", [&](const YAML::Node& n, const At& a) {
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) {
      const std::size_t i = to_index(e, ea, length);
      if (std::find(m.parity_flip.begin(), m.parity_flip.end(), i) != m.parity_flip.end()) fail(ea, "index " + std::to_string(i) + " is listed twice");
      m.parity_flip.push_back(i);
    });
  });
  r.with("chunks", [&](const YAML::Node& n, const At& a) {
    std::size_t total = 0;
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) {
      m.chunks.push_back(static_cast<std::size_t>(to_integer_in(e, ea, 1, 1000)));
      total += m.chunks.back();
    });
    if (m.chunks.empty()) fail(a, "no chunk size given");
    if (length && total > *length) fail(a, "the chunks add up to " + std::to_string(total) + " bytes; the frame has " + std::to_string(*length));
  });
  r.with("pause_ms", [&](const YAML::Node& n, const At& a) {
    if (m.chunks.empty()) fail(a, "pause_ms is the pause between chunks: give chunks too");
    m.pause = std::chrono::milliseconds(to_integer_in(n, a, 1, 60000));
  });
  if (m == Modifiers{}) fail(at, "no change given; leave modify out");
  return m;
}

// --- steps ---

Step read_send_step(const MapReader& r, const At& at, StepContext& cx) {
  Step step;
  step.kind = Step::Kind::kSend;
  Send send;
  r.with("send", [&](const YAML::Node& n, const At& a) { send = read_send(n, a, cx); });
  step.command = send.command;
  step.raw = send.raw;
  const std::optional<std::size_t> length =
      send.sketch.complete ? std::optional<std::size_t>(send.sketch.bytes.size()) : std::nullopt;
  r.with("modify", [&](const YAML::Node& n, const At& a) { step.modifiers = read_modifiers(n, a, length); });
  bool mismatch = false;
  r.read("length_mismatch", mismatch, to_bool);
  check_length(send, mismatch ? std::optional<At>(r.at("length_mismatch")) : std::nullopt);
  if (r.has("length_mismatch") && !mismatch) fail(r.at("length_mismatch"), "length_mismatch: false is the default; leave it out");
  require_keys(r, at, {"expect"}, "a send");
  r.with("expect", [&](const YAML::Node& n, const At& a) { step.expect = read_expectation(n, a, send.sketch.command, cx); });
  return step;
}

Step read_poll(const YAML::Node& v, const At& at, StepContext& cx) {
  MapReader r(v, at, {"send", "until", "timeout_ms", "interval_ms", "expect"});
  require_keys(r, at, {"send", "until", "timeout_ms"}, "a poll");
  Step step;
  step.kind = Step::Kind::kPoll;
  Send send;
  r.with("send", [&](const YAML::Node& n, const At& a) { send = read_send(n, a, cx); });
  check_length(send, std::nullopt);
  step.command = send.command;
  step.raw = send.raw;
  step.expect.where = cx.file.loc(at.mark);
  r.with("expect", [&](const YAML::Node& n, const At& a) {
    step.expect = read_expectation(n, a, send.sketch.command, cx);
    if (step.expect.kind == Expectation::Kind::kSilence) fail(a, "a poll needs a reply to test until against");
  });
  r.with("until", [&](const YAML::Node& n, const At& a) {
    step.until = read_matchers(n, a, reply_fields(send.sketch.command, step.expect.kind), cx);
  });
  keep_captures(step.until, cx);
  r.read("timeout_ms", step.timeout, [](const YAML::Node& n, const At& a) { return std::chrono::milliseconds(to_integer_in(n, a, 1, kMaxMs)); });
  r.read("interval_ms", step.interval, [](const YAML::Node& n, const At& a) {
    return std::chrono::milliseconds(to_integer_in(n, a, kMinPollIntervalMs, kMaxMs));  // §4, E-3
  });
  if (step.interval > step.timeout) fail(r.at("interval_ms"), "interval_ms is longer than timeout_ms");
  return step;
}

std::chrono::milliseconds to_wait(const YAML::Node& v, const At& at) { return std::chrono::milliseconds(to_integer_in(v, at, 1, kMaxMs)); }

Step read_step(const YAML::Node& v, const At& at, StepContext& cx) {
  cx.file.spend(at);
  MapReader r(v, at, {"send", "modify", "expect", "length_mismatch", "poll", "wait", "wait_ms"});
  const int kinds = r.has("send") + r.has("poll") + r.has("wait") + r.has("wait_ms");
  if (kinds != 1) fail(at, "a step is one of send, poll, wait or wait_ms");
  if (!r.has("send"))
    for (auto k : {"modify", "expect", "length_mismatch"})
      if (r.has(k)) fail(r.at(k), std::string(k) + " belongs to a send step (a poll has its own expect)");
  Step step;
  if (r.has("send")) {
    step = read_send_step(r, at, cx);
  } else if (r.has("poll")) {
    r.with("poll", [&](const YAML::Node& n, const At& a) { step = read_poll(n, a, cx); });
  } else {
    step.kind = Step::Kind::kWait;
    r.read("wait_ms", step.timeout, to_wait);
    r.with("wait", [&](const YAML::Node& n, const At& a) {
      MapReader w(n, a, {"ms"});
      require_keys(w, a, {"ms"}, "wait");
      w.read("ms", step.timeout, to_wait);
    });
  }
  step.where = cx.file.loc(at.mark);
  return step;
}

std::vector<Step> read_steps(const YAML::Node& v, const At& at, StepContext& cx) {
  std::vector<Step> out;
  for_each_element(v, at, kMaxSteps, [&](const YAML::Node& e, const At& ea) { out.push_back(read_step(e, ea, cx)); });
  return out;
}

// --- vectors, groups, notes, the file ---

// What a group gives each of its vectors.
struct GroupDefaults {
  std::vector<Requirement> requires_;
  std::vector<Step> setup, teardown;
  std::vector<std::string> tags, flags;
  std::optional<Level> level;
  Captures captures;  // captured by the group's setup
};

void read_spec(const YAML::Node& v, const At& at, const FileInfo& file, Vector& vec) {
  MapReader r(v, at, {"paragraph", "quote"});
  require_keys(r, at, {"paragraph", "quote"}, "spec");
  r.with("paragraph", [&](const YAML::Node& n, const At& a) {
    vec.paragraph = scalar(n, a, "a paragraph");
    if (!is_spec_paragraph(vec.paragraph))
      fail(a, quoted_clip(vec.paragraph) + " is not a paragraph of the spec (1, 2, 3, 4, 3.1 ... 3.25)");
    if (!file.cross_cutting && vec.paragraph != file.paragraph)
      fail(a, "the file is about §" + file.paragraph + "; only cross-cutting files (" + joined(kCrossCutting) +
                  ") cite other paragraphs");
  });
  r.read("quote", vec.quote, [](const YAML::Node& n, const At& a) { return to_text(n, a, kMaxQuote); });
}

// The id as written, so that an error found before it is read (a duplicate
// key, an unknown key) still names the vector.
std::string peek_id(const YAML::Node& v) {
  if (!v.IsMap()) return "";
  const YAML::Node id = v["id"];  // const lookup: never inserts; invalid when absent
  return id.IsDefined() && id.IsScalar() && is_id_text(id.Scalar()) ? id.Scalar() : "";
}

Vector read_vector(const YAML::Node& v, const At& at, const FileInfo& file, const GroupDefaults& g, std::string& id) {
  file.spend(at);
  id = peek_id(v);
  MapReader r(v, at, {"id", "comment", "spec", "level", "flags", "tags", "requires", "setup", "steps", "teardown"});
  Vector vec;
  vec.where = file.loc(at.mark);
  require_keys(r, at, {"id"}, "a vector");
  r.with("id", [&](const YAML::Node& n, const At& a) {
    const std::string& text = scalar(n, a, "an id");
    if (!is_id_text(text)) fail(a, quoted_clip(text) + " is not an id: letters, digits, '.', '-', '_', ':'");
    vec.id = id = text;
    if (vec.id.rfind(file.paragraph + "-", 0) != 0) fail(a, "an id in this file starts with \"" + file.paragraph + "-\"");
  });
  require_keys(r, at, {"comment", "spec", "steps"}, "a vector");
  r.read("comment", vec.comment, [](const YAML::Node& n, const At& a) { return to_text(n, a, kMaxText); });
  r.with("spec", [&](const YAML::Node& n, const At& a) { read_spec(n, a, file, vec); });
  if (!r.has("level") && !g.level) fail_missing(at, "level", "a vector needs level (must, should or informative), here or in its group");
  vec.level = g.level.value_or(Level::kMust);
  r.read("level", vec.level, to_level);
  std::vector<std::string> flags, tags;
  r.read("flags", flags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_flag_name, "a flag name"); });
  r.read("tags", tags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_tag_text, "a tag"); });
  vec.flags = merged(g.flags, flags);
  vec.tags = merged(g.tags, tags);
  vec.requires_ = file.requires_;
  vec.requires_.insert(vec.requires_.end(), g.requires_.begin(), g.requires_.end());
  r.with("requires", [&](const YAML::Node& n, const At& a) {
    auto own = read_requires(n, a, file);
    vec.requires_.insert(vec.requires_.end(), own.begin(), own.end());
  });
  StepContext cx{file, g.captures};
  vec.setup = g.setup;
  r.with("setup", [&](const YAML::Node& n, const At& a) {
    auto own = read_steps(n, a, cx);
    vec.setup.insert(vec.setup.end(), own.begin(), own.end());
  });
  r.read("steps", vec.steps, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  if (vec.steps.empty()) fail(r.at("steps"), "a vector needs at least one step");
  r.read("teardown", vec.teardown, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  vec.teardown.insert(vec.teardown.end(), g.teardown.begin(), g.teardown.end());
  return vec;
}

LoadError to_error(const std::string& file, const Failure& f, const std::string& id) {
  return LoadError{SourceLocation{file, one_based(f.at.mark.line), one_based(f.at.mark.column)}, id, f.at.path, f.message};
}

// One vector's error does not stop the others: each is read on its own, with
// paths relative to it ("steps[1].send.command") and its id in the error.
void read_vector_list(const YAML::Node& v, const At& at, const FileInfo& file, const GroupDefaults& g,
                      std::vector<Vector>& out, std::vector<LoadError>& errors) {
  for_each_element(v, at, kMaxVectors, [&](const YAML::Node& e, const At& ea) {
    std::string id;
    try {
      out.push_back(read_vector(e, At{"", ea.mark}, file, g, id));
    } catch (const Failure& f) {
      errors.push_back(to_error(file.name, f, id));
    }
  });
  if (v.size() == 0) fail(at, "no vector given");
}

void read_group(const YAML::Node& v, const At& at, const FileInfo& file, std::vector<Vector>& out,
                std::vector<LoadError>& errors) {
  MapReader r(v, at, {"comment", "requires", "setup", "teardown", "tags", "flags", "level", "vectors"});
  require_keys(r, at, {"vectors"}, "a group");
  GroupDefaults g;
  r.with("comment", [](const YAML::Node& n, const At& a) { to_text(n, a, kMaxText); });
  r.read("requires", g.requires_, [&](const YAML::Node& n, const At& a) { return read_requires(n, a, file); });
  r.read("tags", g.tags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_tag_text, "a tag"); });
  r.read("flags", g.flags, [](const YAML::Node& n, const At& a) { return to_names(n, a, is_flag_name, "a flag name"); });
  r.with("level", [&](const YAML::Node& n, const At& a) { g.level = to_level(n, a); });
  StepContext cx{file, {}};
  r.read("setup", g.setup, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  g.captures = cx.captures;
  // A group's teardown runs after each vector's steps but may only use what
  // the group's own setup captured: it cannot know any one vector's.
  r.read("teardown", g.teardown, [&](const YAML::Node& n, const At& a) { return read_steps(n, a, cx); });
  r.with("vectors", [&](const YAML::Node& n, const At& a) { read_vector_list(n, a, file, g, out, errors); });
}

// "E-7": the form of an ERRATA.md entry id (that it exists is lint's check).
std::string to_errata_ref(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "an errata entry (E-7)");
  std::size_t n = 0;
  if (s.size() < 3 || s.size() > 6 || s.compare(0, 2, "E-") != 0 || s[2] == '0' || !parse_whole(std::string_view(s).substr(2), n))
    fail(at, quoted_clip(s) + " is not an errata entry id like E-7 (protocol/ERRATA.md)");
  return s;
}

std::map<std::string, Note> read_notes(const YAML::Node& v, const At& at, const FileInfo& file) {
  std::map<std::string, Note> notes;
  for_each_entry(v, at, kMaxEntries, [&](const std::string& flag, const YAML::Node& value, const At& fa) {
    if (!is_flag_name(flag)) fail(fa, quoted_clip(flag) + " is not a flag name: a letter, then letters, digits, '_'");
    MapReader r(value, fa, {"description", "errata"});
    require_keys(r, fa, {"description"}, "a note");
    Note n;
    r.read("description", n.description, [](const YAML::Node& d, const At& a) { return to_text(d, a, kMaxText); });
    r.read("errata", n.errata, to_errata_ref);
    n.where = file.loc(fa.mark);
    notes.emplace(flag, std::move(n));
  });
  return notes;
}

std::string to_file_paragraph(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a paragraph");
  if (!is_spec_paragraph(s) && !contains(kCrossCutting, s))
    fail(at, quoted_clip(s) + " is neither a spec paragraph (3.2) nor a cross-cutting topic (" + joined(kCrossCutting) + ")");
  return s;
}

void read_file(const YAML::Node& root, FileInfo& info, VectorFile& f, std::vector<LoadError>& errors) {
  const At at{"", root.Mark()};
  if (root.IsNull()) fail(at, "an empty file: a vector file needs paragraph, title and vectors");
  MapReader r(root, at, {"paragraph", "title", "notes", "requires", "groups", "vectors"});
  require_keys(r, at, {"paragraph", "title"}, "a vector file");
  if (!r.has("groups") && !r.has("vectors")) fail_missing(at, "vectors", "a vector file needs vectors or groups");
  r.read("paragraph", f.paragraph, to_file_paragraph);
  r.read("title", f.title, [](const YAML::Node& n, const At& a) { return to_text(n, a, kMaxText); });
  r.read("notes", f.notes, [&](const YAML::Node& n, const At& a) { return read_notes(n, a, info); });
  info.paragraph = f.paragraph;
  info.cross_cutting = contains(kCrossCutting, f.paragraph);
  r.read("requires", info.requires_, [&](const YAML::Node& n, const At& a) { return read_requires(n, a, info); });
  r.with("groups", [&](const YAML::Node& n, const At& a) {
    for_each_element(n, a, kMaxGroups, [&](const YAML::Node& g, const At& ga) {
      try {
        read_group(g, ga, info, f.vectors, errors);
      } catch (const Failure& fl) {
        errors.push_back(to_error(info.name, fl, ""));
      }
    });
  });
  r.with("vectors", [&](const YAML::Node& n, const At& a) { read_vector_list(n, a, info, GroupDefaults{}, f.vectors, errors); });
}

LoadError file_error(const std::string& file, std::string message) {
  return LoadError{SourceLocation{file, 0, 0}, "", "", std::move(message)};
}

bool by_position(const LoadError& a, const LoadError& b) {
  return std::tie(a.where.file, a.where.line, a.where.column) < std::tie(b.where.file, b.where.line, b.where.column);
}

// ---------------------------------------------------------------------------
// Lint
// ---------------------------------------------------------------------------

// ERRATA.md entries by number ("### E-7: ..."), and whether each is withdrawn.
struct ErrataIndex {
  std::string path;
  std::optional<std::string> error;
  std::map<std::size_t, bool> withdrawn;
};

ErrataIndex read_errata() {
  ErrataIndex index;
  index.path = data_path(kErrataFile);
  std::string error;
  auto text = read_capped(index.path, 4 << 20, error);
  if (!text) {
    index.error = error;
    return index;
  }
  std::istringstream in(*text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("### E-", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    std::size_t n = 0;
    if (colon == std::string::npos || !parse_whole(std::string_view(line).substr(6, colon - 6), n)) continue;
    std::string lower = line;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    index.withdrawn[n] = lower.find("withdrawn") != std::string::npos;
  }
  return index;
}

// Whitespace runs as one blank: the spec text is extracted from a PDF with
// line breaks and tabs where the quote has blanks.
std::string squeezed(std::string_view s) {
  std::string out;
  for (char c : s) {
    const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// A quote is verbatim, or verbatim parts joined by "…" that appear in order.
bool quote_found(const std::string& spec, const std::string& quote) {
  static constexpr std::string_view kEllipsis = "\xE2\x80\xA6";
  std::size_t pos = 0;
  for (std::size_t from = 0;;) {
    const std::size_t at = quote.find(kEllipsis, from);
    const std::string part = squeezed(std::string_view(quote).substr(from, at == std::string::npos ? std::string::npos : at - from));
    if (!part.empty()) {
      const std::size_t hit = spec.find(part, pos);
      if (hit == std::string::npos) return false;
      pos = hit + part.size();
    }
    if (at == std::string::npos) return true;
    from = at + kEllipsis.size();
  }
}

LoadError vector_error(const Vector& v, std::string key, std::string message) {
  return LoadError{v.where, v.id, std::move(key), std::move(message)};
}

void lint_notes(const VectorFile& f, const ErrataIndex& errata, std::vector<LoadError>& errors) {
  std::set<std::string> used;
  for (const auto& v : f.vectors) used.insert(v.flags.begin(), v.flags.end());
  for (const auto& [flag, note] : f.notes) {
    if (!used.count(flag)) errors.push_back({note.where, "", "notes." + flag, "note " + quoted_clip(flag) + " is used by no vector"});
    if (note.errata.empty()) continue;
    std::size_t n = 0;
    const std::string key = "notes." + flag + ".errata";
    if (note.errata.rfind("E-", 0) != 0 || !parse_whole(std::string_view(note.errata).substr(2), n))
      errors.push_back({note.where, "", key, quoted_clip(note.errata) + " is not an errata entry id like E-7"});
    else if (errata.error)
      errors.push_back({note.where, "", key, "cannot check " + note.errata + ": " + errata.path + ": " + *errata.error});
    else if (!errata.withdrawn.count(n))
      errors.push_back({note.where, "", key, note.errata + " is not an entry of protocol/ERRATA.md"});
    else if (errata.withdrawn.at(n))
      errors.push_back({note.where, "", key, note.errata + " is withdrawn (protocol/ERRATA.md)"});
  }
}

void lint_flags_and_tags(const VectorFile& f, const Vector& v, std::vector<LoadError>& errors) {
  for (const auto& flag : v.flags)
    if (!f.notes.count(flag)) errors.push_back(vector_error(v, "flags", "flag " + quoted_clip(flag) + " is not defined in the file's notes"));
  for (const auto& tag : v.tags)
    if (!contains(kKnownTags, tag))
      errors.push_back(vector_error(v, "tags", "unknown tag " + quoted_clip(tag) + "; known tags: " + joined(kKnownTags)));
}

// The frame a step sends, as far as it can be told without a device.
std::optional<FrameSketch> step_sketch(const Step& s, std::string& problem) {
  if (s.command) {
    const CommandInfo* info = find_command(s.command->command);
    if (!info) {
      problem = "unknown command " + quoted_clip(s.command->command);
      return std::nullopt;
    }
    auto built = build_request(*info, s.command->form, s.command->fields);
    if (!built) {
      problem = build_error_text(built.error());
      return std::nullopt;
    }
    return sketch_of(encode_request(*built, s.command->address.value_or(kSketchAddress)), true);
  }
  if (s.raw) {
    std::vector<Element> elements;
    if (auto e = parse_template(s.raw->hex, elements)) {
      problem = *e;
      return std::nullopt;
    }
    return sketch_of(elements);
  }
  return std::nullopt;
}

void lint_matchers(const Vector& v, const std::vector<FieldMatcher>& matchers, const CommandInfo* command,
                   const std::string& key, std::vector<LoadError>& errors) {
  if (!command) return;
  const auto names = reply_field_names(*command);
  for (const auto& m : matchers)
    if (!contains(names, m.field))
      errors.push_back({m.where, v.id, key, "unknown field " + quoted_clip(m.field) + " of the " + std::string(command->key) + " reply"});
}

// READING-NOTES 26 / ERRATA E-26: a vector that sends a command that can move
// the antenna or change stored data says so, so a bench run can leave it out.
void lint_effects(const Vector& v, const Step& s, const Effects& e, const std::string& key, const CommandInfo& c,
                  std::vector<LoadError>& errors) {
  const std::string what = std::string(c.key) + " (" + hex_byte(c.code) + ")";
  if (e.moves_antenna && !v.has_tag("motion"))
    errors.push_back({s.where, v.id, key, "sends " + what + ", which can move the antenna: tag the vector motion (READING-NOTES 26, E-26)"});
  if (e.changes_stored_data && !v.has_tag("destructive"))
    errors.push_back({s.where, v.id, key, "sends " + what + ", which changes stored data: tag the vector destructive (READING-NOTES 26, E-26)"});
}

void lint_step_list(const Vector& v, const std::vector<Step>& steps, const std::string& list, std::vector<LoadError>& errors) {
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    if (s.kind == Step::Kind::kWait) continue;
    const std::string key = list + "[" + std::to_string(i) + "]";
    std::string problem;
    auto sketch = step_sketch(s, problem);
    if (!problem.empty()) errors.push_back({s.where, v.id, key, problem});
    if (!sketch || !sketch->command) continue;
    if (auto e = effects_of(*sketch)) lint_effects(v, s, *e, key, *sketch->command, errors);
    lint_matchers(v, s.expect.fields, sketch->command, key + ".expect.fields", errors);
    lint_matchers(v, s.until, sketch->command, key + ".until", errors);
  }
}

void lint_vector(const VectorFile& f, const Vector& v, const std::optional<std::string>& spec, std::vector<LoadError>& errors) {
  lint_flags_and_tags(f, v, errors);
  lint_step_list(v, v.setup, "setup", errors);
  lint_step_list(v, v.steps, "steps", errors);
  lint_step_list(v, v.teardown, "teardown", errors);
  if (spec && !quote_found(*spec, v.quote))
    errors.push_back(vector_error(v, "spec.quote", "not found verbatim in the spec text (" + spec_text_path() +
                                                       "; line breaks may be blanks, parts may be joined by \"\xE2\x80\xA6\")"));
}

}  // namespace

// ---------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------

std::string SourceLocation::text() const {
  return line > 0 ? file + ":" + std::to_string(line) + ":" + std::to_string(column) : file;
}

std::string_view to_string(Level level) {
  for (const auto& [name, l] : kLevels)
    if (l == level) return name;
  return "?";
}

bool Vector::has_tag(std::string_view tag) const { return contains(tags, tag); }

std::string LoadError::text() const {
  std::string out = where.text() + ": ";
  if (!vector_id.empty()) out += "[" + vector_id + "] ";
  if (!key.empty()) out += key + ": ";
  return out + message;
}

LoadResult load_vector_text(const std::string& yaml, const std::string& name) {
  LoadResult result;
  if (yaml.size() > kMaxFileBytes) {
    result.errors.push_back(file_error(name, "larger than " + std::to_string(kMaxFileBytes) + " bytes"));
    return result;
  }
  std::size_t work = 0;
  FileInfo info{name, "", false, {}, &work};
  VectorFile file;
  file.path = name;
  try {
    require_single_document(yaml, "a vector file");
    read_file(YAML::Load(yaml), info, file, result.errors);
  } catch (const Failure& f) {
    result.errors.push_back(to_error(name, f, ""));
  } catch (const OverBudget& o) {
    result.errors.push_back(to_error(name, Failure{o.at, "more than " + std::to_string(kWorkBudget) +
                                                             " units of checking (a vector, step or matcher is one, a regex or a"
                                                             " requirement value ten; an alias counts each time); split the file"}, ""));
  } catch (const YAML::Exception& e) {  // syntax errors, including DeepRecursion
    result.errors.push_back({SourceLocation{name, one_based(e.mark.line), one_based(e.mark.column)}, "", "", "YAML syntax: " + e.msg});
  } catch (const std::exception& e) {  // bad_alloc and anything else: never out of the loader
    result.errors.push_back(file_error(name, std::string("cannot read the file: ") + e.what()));
  }
  std::stable_sort(result.errors.begin(), result.errors.end(), by_position);
  if (result.errors.empty()) result.files.push_back(std::move(file));
  return result;
}

LoadResult load_vector_file(const std::string& path) {
  std::string error;
  auto text = read_capped(path, kMaxFileBytes, error);
  if (!text) return LoadResult{{}, {file_error(path, error)}};
  return load_vector_text(*text, path);
}

LoadResult load_vectors(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  LoadResult result;
  std::vector<std::string> files;
  for (const auto& p : paths) {
    std::error_code ec;
    if (!fs::is_directory(p, ec)) {
      files.push_back(p);  // a missing file is reported by load_vector_file
      continue;
    }
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator(p, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const fs::path& path = it->path();
      const std::string leaf = path.filename().string();
      // Not vector files: profiles/ and examples/. regression/ holds vectors
      // recorded from one controller (`sabus record`), not conformance: run
      // them by naming the folder or a file (vectors/README.md).
      if (it->is_directory(ec) && (leaf == "profiles" || leaf == "examples" || leaf == "regression"))
        it.disable_recursion_pending();
      else if (path.extension() == ".yaml" && it->is_regular_file(ec)) found.push_back(path.string());
    }
    if (ec) result.errors.push_back(file_error(p, "cannot list: " + ec.message()));
    std::sort(found.begin(), found.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  for (const auto& f : files) {
    LoadResult one = load_vector_file(f);
    for (auto& vf : one.files) result.files.push_back(std::move(vf));
    for (auto& e : one.errors) result.errors.push_back(std::move(e));
  }
  return result;
}

std::string spec_text_path() {
  const DataDir data = require_data_dir();
  // The vendor's manual is not ours to ship: a source tree finds it where
  // the project keeps it, beside the repository; an installation (or any
  // data directory given) where its owner puts a copy, spec/ inside it.
  const std::filesystem::path dir = std::filesystem::path(*data.path) /
                                    (data.source == DataDirSource::kSourceTree ? "../shared/spec" : "spec");
  return (dir / kSpecTextName).lexically_normal().string();
}

std::optional<std::string> read_spec_text() {
  std::string error;
  return read_capped(spec_text_path(), 4 << 20, error);
}

std::vector<LoadError> lint(const std::vector<VectorFile>& files) {
  if (files.empty()) return {};  // the errata and the spec text are read only when there is something to check
  return lint(files, read_spec_text());
}

std::vector<LoadError> lint(const std::vector<VectorFile>& files, const std::optional<std::string>& spec_text) {
  std::vector<LoadError> errors;
  if (files.empty()) return errors;
  const ErrataIndex errata = read_errata();
  const std::optional<std::string> spec = spec_text ? std::optional(squeezed(*spec_text)) : std::nullopt;
  std::map<std::string, SourceLocation> first;
  for (const auto& f : files) {
    lint_notes(f, errata, errors);
    for (const auto& v : f.vectors) {
      auto [it, fresh] = first.emplace(v.id, v.where);
      if (!fresh) errors.push_back(vector_error(v, "id", "duplicate id; first at " + it->second.text()));
      lint_vector(f, v, spec, errors);
    }
  }
  return errors;
}

std::string default_vectors_dir() { return data_path("vectors"); }

Expected<Bytes> expand_raw_bytes(std::string_view hex, std::uint8_t address, const std::map<std::string, std::string>& captures) {
  std::vector<Element> elements;
  if (auto e = parse_template(hex, elements)) return DecodeError{0, "raw", *e, ""};
  return expand(elements, address, captures);
}

std::optional<std::string> unmet_requirement(const Profile& profile, const Requirement& r) {
  try {
    // The profile as YAML is the one place its keys and value spellings live.
    // A run checks every vector's requirements against one profile: parse
    // its text once, not once a requirement.
    thread_local std::string last_text;
    thread_local YAML::Node last_root;
    std::string text = to_yaml(profile);
    if (text != last_text || !last_root.IsDefined() || last_root.IsNull()) {
      last_root = YAML::Load(text);
      last_text = std::move(text);
    }
    const YAML::Node& root = last_root;
    // A scalar key holds one of the values; a list key (bus_peers) holds one
    // of them among its elements.
    const auto values = values_at(root, split(r.key, '.'));
    if (!values) return "the profile has no key " + r.key;
    for (const auto& v : *values)
      if (contains(r.values, v)) return std::nullopt;
    std::string wanted, has;
    for (const auto& w : r.values) wanted += (wanted.empty() ? "" : " or ") + w;
    for (const auto& v : *values) has += (has.empty() ? "" : ", ") + v;
    if (values->size() != 1) return r.key + " is [" + has + "], needs one of " + wanted;
    return r.key + " is " + has + ", needs " + wanted;
  } catch (const YAML::Exception& e) {
    return std::string("cannot read the profile: ") + e.what();
  }
}

bool requirements_hold(const Profile& profile, const std::vector<Requirement>& requirements) {
  for (const auto& r : requirements)
    if (unmet_requirement(profile, r)) return false;
  return true;
}

Expected<Bytes> step_bytes(const Step& s, std::uint8_t address, const std::map<std::string, std::string>& captures,
                           bool blank_missing_captures) {
  if (s.raw) {
    if (!blank_missing_captures) return expand_raw_bytes(s.raw->hex, address, captures);
    std::string hex = s.raw->hex;
    for (std::size_t at = hex.find("{$"); at != std::string::npos; at = hex.find("{$", at)) {
      const auto end = hex.find('}', at);
      if (end == std::string::npos) break;
      if (captures.count(hex.substr(at + 1, end - at - 1))) {
        at = end;
        continue;
      }
      hex.replace(at, end - at + 1, "20");
    }
    return expand_raw_bytes(hex, address, captures);
  }
  if (!s.command) return DecodeError{0, "step", "a send with a command or raw bytes", "neither"};
  const CommandInfo* info = find_command(s.command->command);
  if (!info) return DecodeError{0, "command", "a command of the catalog", s.command->command};
  auto r = build_request(*info, s.command->form, s.command->fields);
  if (!r) return r.error();
  return encode_request(r.value(), s.command->address.value_or(address));
}

bool needs_length_mismatch(ByteView raw_send) {
  const FrameSketch k = sketch_of(Bytes(raw_send.begin(), raw_send.end()), true);
  return has_checked_length(k) && k.bytes.size() - k.start != *k.command->request_length;
}

}  // namespace sabus::harness
