// Strict reading of YAML with yaml-cpp 0.7, shared by the loaders of device
// profiles (harness/profile/src/profile_loader.cpp) and conformance vectors
// (harness/vectors/src/).
// Internal to the harness: a header-only library of its own (harness/yaml),
// linked privately by the two loaders' libraries.
//
// yaml-cpp 0.7 (TOOLCHAIN-NOTES): marks are 0-based; a key's position is
// it->first.Mark(); duplicate keys are kept as separate map entries and a
// lookup returns the first, so MapReader and for_each_entry check keys
// themselves; as<T>() throws, so scalars are converted here with
// std::from_chars instead. Errors are thrown as Failure inside a loader and
// turned into that loader's error value at its entry point.
#pragma once

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "sabus/protocol/frame.hpp"

namespace sabus::harness::yaml_reader {

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

// Where a value sits: the dotted path of its key and the key's mark.
struct At {
  std::string path;
  YAML::Mark mark;
  At key(std::string_view k, const YAML::Mark& m) const {
    return {path.empty() ? std::string(k) : path + "." + std::string(k), m};
  }
  At element(std::size_t i, const YAML::Mark& m) const { return {path + "[" + std::to_string(i) + "]", m}; }
};

struct Failure {
  At at;
  std::string message;
};

[[noreturn]] inline void fail(const At& at, std::string message) { throw Failure{at, std::move(message)}; }

// User text in a message, cut short so a message stays one line.
// (Appended, not "\"" + std::string(...): GCC 12 warns falsely, -Wrestrict,
// where that operator+ is inlined.)
inline std::string quoted_clip(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string out = "\"";
  out.append(s.substr(0, kMax));
  out += s.size() > kMax ? "...\"" : "\"";
  return out;
}

// The shortest text that reads back to exactly `d`.
inline std::string number_text(double d) {
  std::array<char, 32> buf{};
  auto r = std::to_chars(buf.data(), buf.data() + buf.size(), d);
  return std::string(buf.data(), r.ptr);
}

// yaml-cpp marks are 0-based, -1 when unknown; errors are 1-based, 0 when unknown.
inline int one_based(int mark_value) { return mark_value >= 0 ? mark_value + 1 : 0; }

// ---------------------------------------------------------------------------
// Scalars
// ---------------------------------------------------------------------------

// "no value", "a list", "a map" or the scalar quoted, for "expected X, got Y".
inline std::string kind_of(const YAML::Node& v) {
  switch (v.Type()) {
    case YAML::NodeType::Null: return "no value";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Scalar: return quoted_clip(v.Scalar());
    default: return "nothing";
  }
}

inline const std::string& scalar(const YAML::Node& v, const At& at, std::string_view what) {
  if (!v.IsScalar()) fail(at, "expected " + std::string(what) + ", got " + kind_of(v));
  return v.Scalar();
}

// yaml-cpp tags every non-plain (quoted) scalar "!".
inline bool is_quoted(const YAML::Node& v) { return v.IsScalar() && v.Tag() == "!"; }

// Numbers and booleans must be plain scalars: quoting makes a YAML string.
inline const std::string& plain(const YAML::Node& v, const At& at, std::string_view what) {
  if (is_quoted(v)) fail(at, "expected " + std::string(what) + ", got the quoted string " + quoted_clip(v.Scalar()));
  return scalar(v, at, what);
}

// YAML 1.2 core schema booleans only (yaml-cpp's as<bool> also takes yes/no/on/off).
inline bool to_bool(const YAML::Node& v, const At& at) {
  const std::string& s = plain(v, at, "true or false");
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  fail(at, "expected true or false, got " + quoted_clip(s));
}

// from_chars takes no leading '+'; YAML numbers may have one.
inline std::string_view without_plus(std::string_view s) {
  return s.size() > 1 && s[0] == '+' && s[1] != '-' ? s.substr(1) : s;
}

template <class T>
bool parse_whole(std::string_view s, T& out) {
  s = without_plus(s);
  auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc{} && r.ptr == s.data() + s.size();
}

inline double to_number(const YAML::Node& v, const At& at) {
  const std::string& s = plain(v, at, "a number");
  double d = 0;
  if (!parse_whole(s, d) || !std::isfinite(d)) fail(at, "expected a number, got " + quoted_clip(s));
  return d;
}

inline long long to_integer_in(const YAML::Node& v, const At& at, long long lo, long long hi) {
  const std::string& s = plain(v, at, "a whole number");
  long long n = 0;
  if (!parse_whole(s, n)) fail(at, "expected a whole number, got " + quoted_clip(s));
  if (n < lo || n > hi) fail(at, s + " is out of range " + std::to_string(lo) + " to " + std::to_string(hi));
  return n;
}

// A whole number in decimal or as 0xNN (bytes, masks), lo..hi.
inline long long to_integer_or_hex_in(const YAML::Node& v, const At& at, long long lo, long long hi) {
  const std::string& s = plain(v, at, "a whole number or 0xNN");
  if (s.size() < 3 || s[0] != '0' || (s[1] != 'x' && s[1] != 'X')) return to_integer_in(v, at, lo, hi);
  long long n = 0;
  // from_chars takes a sign of its own: 0x-1 is not a hex number.
  auto r = std::from_chars(s.data() + 2, s.data() + s.size(), n, 16);
  if (s[2] == '-' || r.ec != std::errc{} || r.ptr != s.data() + s.size()) fail(at, "expected 0xNN, got " + quoted_clip(s));
  if (n < lo || n > hi) fail(at, s + " is out of range " + std::to_string(lo) + " to " + std::to_string(hi));
  return n;
}

// READING-NOTES 4 / ERRATA E-4: the controller's decimal setting 49-111, or
// the address character itself, quoted ("2"); parse_address reads both (and
// 0x32). An unquoted single digit is a decimal setting, hence out of range.
inline std::uint8_t to_address(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "an address");
  if (!is_quoted(v) && s.size() == 1 && s[0] >= '0' && s[0] <= '9')
    fail(at, "address " + s + " is out of range 49-111; quote it (\"" + s + "\") for the address character");
  auto a = parse_address(s);
  if (!a) fail(at, "bad address " + quoted_clip(s) + ": expected " + a.error().expected);
  return *a;
}

// ---------------------------------------------------------------------------
// Maps and lists
// ---------------------------------------------------------------------------

namespace detail {

inline std::string join(std::span<const std::string_view> keys) {
  std::string out;
  for (auto k : keys) out += (out.empty() ? "" : ", ") + std::string(k);
  return out;
}

inline std::string first_at(const YAML::Mark& m) {
  return "(first at line " + std::to_string(one_based(m.line)) + ", column " + std::to_string(one_based(m.column)) + ")";
}

// Every key a scalar and not seen before; `allowed` (when given) names the
// keys that may appear. Calls keep(key, mark, value) for each entry.
template <class F>
void check_keys(const YAML::Node& node, const At& at, const std::span<const std::string_view>* allowed, F&& keep) {
  if (!node.IsMap()) fail(at, "expected a map, got " + kind_of(node));
  std::vector<std::pair<std::string, YAML::Mark>> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const YAML::Mark mark = it->first.Mark();
    if (!it->first.IsScalar()) fail(at.key("?", mark), "a key must be a plain name, got " + kind_of(it->first));
    const std::string& k = it->first.Scalar();
    if (allowed && std::find(allowed->begin(), allowed->end(), k) == allowed->end())
      fail(at.key(k, mark), "unknown key " + quoted_clip(k) + "; allowed keys: " + join(*allowed));
    for (const auto& [name, first] : seen)
      if (name == k) fail(at.key(k, mark), "duplicate key " + quoted_clip(k) + " " + first_at(first));
    seen.emplace_back(k, mark);
    keep(k, mark, it->second);
  }
}

}  // namespace detail

// A YAML map with a fixed set of keys. The constructor checks every key once:
// a scalar, one of `allowed`, and not seen before. So at most allowed.size()
// entries are kept, whatever the input.
class MapReader {
 public:
  MapReader(const YAML::Node& node, const At& at, std::initializer_list<std::string_view> allowed)
      : MapReader(node, at, std::span<const std::string_view>(allowed.begin(), allowed.size())) {}
  // Keys from a table (readings.hpp's ids, say).
  MapReader(const YAML::Node& node, const At& at, std::span<const std::string_view> allowed) : at_(at) {
    detail::check_keys(node, at, &allowed, [this](const std::string& k, const YAML::Mark& m, const YAML::Node& v) {
      entries_.push_back({k, m, v});
    });
  }

  // Calls read(value, at) when the key is present.
  template <class F>
  void with(std::string_view key, F&& read) const {
    if (const Entry* e = find(key)) read(e->value, at_.key(key, e->mark));
  }
  // out = parse(value, at) when the key is present.
  template <class T, class F>
  void read(std::string_view key, T& out, F&& parse) const {
    with(key, [&](const YAML::Node& v, const At& at) { out = parse(v, at); });
  }
  bool has(std::string_view key) const { return find(key) != nullptr; }
  // Where to report a rule that involves `key`: the key, or the map when absent.
  At at(std::string_view key) const {
    const Entry* e = find(key);
    return e ? at_.key(key, e->mark) : at_;
  }

 private:
  struct Entry {
    std::string key;
    YAML::Mark mark;
    YAML::Node value;
  };
  const Entry* find(std::string_view key) const {
    for (const auto& e : entries_)
      if (e.key == key) return &e;
    return nullptr;
  }
  At at_;
  std::vector<Entry> entries_;
};

// Calls read(element, at) for each element of a list of at most `max` entries
// (checked before anything is read).
template <class F>
void for_each_element(const YAML::Node& v, const At& at, std::size_t max, F&& read) {
  if (!v.IsSequence()) fail(at, "expected a list, got " + kind_of(v));
  if (v.size() > max)
    fail(at, "has " + std::to_string(v.size()) + " entries, at most " + std::to_string(max) + " are allowed");
  std::size_t i = 0;
  for (const auto& element : v) {
    read(element, at.element(i, element.Mark()));
    ++i;
  }
}

// A map whose keys are data (field names, flags, profile keys): every key a
// scalar, no key twice, at most `max` entries (checked before anything is
// read). Calls read(key, value, at) in document order.
template <class F>
void for_each_entry(const YAML::Node& v, const At& at, std::size_t max, F&& read) {
  if (v.IsMap() && v.size() > max)
    fail(at, "has " + std::to_string(v.size()) + " entries, at most " + std::to_string(max) + " are allowed");
  std::vector<std::pair<std::string, YAML::Node>> entries;
  std::vector<YAML::Mark> marks;
  detail::check_keys(v, at, nullptr, [&](const std::string& k, const YAML::Mark& m, const YAML::Node& value) {
    entries.emplace_back(k, value);
    marks.push_back(m);
  });
  for (std::size_t i = 0; i < entries.size(); ++i) read(entries[i].first, entries[i].second, at.key(entries[i].first, marks[i]));
}

// ---------------------------------------------------------------------------
// Documents and files
// ---------------------------------------------------------------------------

namespace detail {

// Records where a document starts.
struct DocumentStart : YAML::EventHandler {
  std::optional<YAML::Mark> mark;
  void OnDocumentStart(const YAML::Mark& m) override { mark = m; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

}  // namespace detail

// A file is one YAML document. yaml-cpp 0.7 never consumes a stray ','
// outside [ ] or { }: YAML::Load silently returns what came before it, and
// YAML::LoadAll returns empty documents without end until memory runs out
// (found by the test profile.NeverThrowsOnMutatedFiles). So the parser is
// asked for at most two documents, and a second one is an error. `what`
// names the kind of file in the message ("a profile").
inline void require_single_document(const std::string& text, std::string_view what) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  detail::DocumentStart first, second;
  if (!parser.HandleNextDocument(first) || !parser.HandleNextDocument(second) || !second.mark) return;
  const YAML::Mark& m = *second.mark;
  auto pos = std::min(static_cast<std::size_t>(std::max(0, m.pos)), text.size());
  if (text.compare(pos, 3, "---") == 0)
    fail(At{"", m}, "more than one YAML document; " + std::string(what) + " is a single document");
  fail(At{"", m}, "YAML syntax: unexpected " + quoted_clip(std::string_view(text).substr(pos, 1)) +
                      " after the end of the document (a ',' belongs inside [ ] or { })");
}

// Reads at most `cap` + 1 bytes, so an oversized file is rejected by the
// caller without being read whole. nullopt with `error` set on failure.
inline std::optional<std::string> read_capped(const std::string& path, std::size_t cap, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = std::string("cannot open: ") + std::strerror(errno);
    return std::nullopt;
  }
  std::string text(cap + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) {
    error = "read error";
    return std::nullopt;
  }
  return text;
}

}  // namespace sabus::harness::yaml_reader
