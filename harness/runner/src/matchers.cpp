// Field matchers (vectors/README.md "Field matchers"): the text and number a
// matcher compares for a described reply field, and the check of one matcher
// against a reply. Pure functions; the step engine (steps.cpp) calls them.
#include <regex>
#include <sstream>

#include "sabus/harness/runner.hpp"

namespace sabus::harness {
namespace {

std::string trim_right(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string range_text(const FieldDescription& f) {
  return f.first == f.last ? "byte " + std::to_string(f.first)
                           : "bytes " + std::to_string(f.first) + "-" + std::to_string(f.last);
}

// Numbers may be written as 0x47 or 71 in a vector.
bool values_equal(const std::string& want, const std::string& got) {
  if (want == got) return true;
  try {
    std::size_t a = 0, b = 0;
    const long x = std::stol(want, &a, 0), y = std::stol(got, &b, 0);
    return a == want.size() && b == got.size() && x == y;
  } catch (...) {
    return false;
  }
}

std::optional<std::string> check_one_field(const FieldDescription& field, const FieldMatcher& m, Captures& captures) {
  const std::string got = matcher_text(field);
  auto fail = [&](const std::string& expected) {
    return range_text(field) + " " + field.name + ": expected " + expected + ", got " + got + " (" + field.meaning + ")";
  };
  if (!m.capture.empty()) captures[m.capture] = got;
  switch (m.kind) {
    case FieldMatcher::Kind::kAny: return std::nullopt;
    case FieldMatcher::Kind::kEq:
      if (!m.values.empty() && !values_equal(m.values[0], got)) return fail(m.values[0]);
      return std::nullopt;
    case FieldMatcher::Kind::kOneOf: {
      std::string list;
      for (const auto& v : m.values) {
        if (values_equal(v, got)) return std::nullopt;
        list += (list.empty() ? "" : ", ") + v;
      }
      return fail("one of " + list);
    }
    case FieldMatcher::Kind::kRegex:
      try {
        if (!m.values.empty() && !std::regex_search(got, std::regex(m.values[0]))) return fail("/" + m.values[0] + "/");
      } catch (const std::regex_error&) {
        return "matcher for \"" + m.field + "\": bad regex /" + m.values[0] + "/";
      }
      return std::nullopt;
    case FieldMatcher::Kind::kRange: {
      const auto n = matcher_number(field);
      std::ostringstream want;
      want << m.low << " to " << m.high;
      if (!n || *n < m.low - 1e-9 || *n > m.high + 1e-9) return fail(want.str());
      return std::nullopt;
    }
  }
  return std::nullopt;
}

}  // namespace

std::string matcher_text(const FieldDescription& f) {
  if (f.raw.size() >= 2 && f.raw.front() == '"' && f.raw.back() == '"') return trim_right(f.raw.substr(1, f.raw.size() - 2));
  return f.raw;
}

std::optional<double> matcher_number(const FieldDescription& f) {
  // One-byte fields: the byte's value; text fields: a leading number in the
  // meaning ("-152.5 deg", "11050", "index 12").
  if (f.first == f.last && f.raw.rfind("0x", 0) == 0) return static_cast<double>(std::stoi(f.raw.substr(2), nullptr, 16));
  std::istringstream in(f.meaning.rfind("index ", 0) == 0 ? f.meaning.substr(6)
                        : f.meaning.rfind("heading ", 0) == 0 ? f.meaning.substr(8)
                                                              : f.meaning);
  double v = 0;
  if (in >> v) return v;
  return std::nullopt;
}

std::optional<std::string> check_field(const FrameDescription& reply, const FieldMatcher& m, Captures& captures) {
  // A matcher holds for every field of its name (the status reply has two
  // "reserved" fields: byte 13 and bytes 45-49).
  bool found = false;
  for (const auto& f : reply.fields) {
    if (f.name != m.field) continue;
    found = true;
    if (auto e = check_one_field(f, m, captures)) return e;
  }
  if (!found) return "field \"" + m.field + "\" is not in the reply (" + reply.summary + ")";
  return std::nullopt;
}

}  // namespace sabus::harness
