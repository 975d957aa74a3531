// Field matchers (vectors/README.md "Field matchers"): the text and number a
// matcher compares for a described reply field, and the check of one matcher
// against a reply. Pure functions; the step engine (steps.cpp) calls them.
#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>

#include "sabus/harness/motion.hpp"
#include "sabus/harness/runner.hpp"

namespace sabus::harness {
namespace {

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
    case FieldMatcher::Kind::kRange:
    case FieldMatcher::Kind::kNear:
    case FieldMatcher::Kind::kJogged: {
      auto n = matcher_number(field);
      if (n && m.angular) *n += 360.0 * std::round(((m.low + m.high) / 2 - *n) / 360.0);
      std::ostringstream want;
      want << m.low << " to " << m.high;
      if (!n || *n < m.low - 1e-9 || *n > m.high + 1e-9) return fail(m.expected.empty() ? want.str() : m.expected);
      return std::nullopt;
    }
  }
  return std::nullopt;
}

}  // namespace

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

namespace {

std::string degrees(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", x);
  std::string t = buf;
  while (t.back() == '0') t.pop_back();
  if (t.back() == '.') t.pop_back();
  return t;
}

ResolvedMatcher problem(Expansion::Kind kind, const FieldMatcher& m, std::string why) {
  return {kind, m, "matcher for \"" + m.field + "\": " + std::move(why)};
}

// near: the target within the axis's arrival tolerance (AxisProfile::tolerance_deg).
// The axis a matcher is about: near's `axis`, the jog's, or the field's.
std::optional<motion::Axis> matcher_axis(const FieldMatcher& m) {
  if (!m.near_axis.empty()) return motion::axis_named(m.near_axis);
  if (m.kind == FieldMatcher::Kind::kJogged)
    if (const auto dir = motion::jog_direction(m.jog)) return dir->axis;
  return motion::axis_of_field(m.field);
}

ResolvedMatcher resolve_near(FieldMatcher m, const ExprContext& cx) {
  const auto axis = matcher_axis(m);
  if (!axis) return problem(Expansion::Kind::kError, m, "near needs an axis: the field is not a position of one");
  const Number target = expand_number(m.values.at(0), cx);
  if (target.kind != Expansion::Kind::kValue) return problem(target.kind, m, target.text);
  const double tol = motion::profile_of(cx.profile, *axis).tolerance_deg;
  m.low = target.value - tol;
  m.high = target.value + tol;
  m.expected = degrees(target.value) + " within " + degrees(tol) + " (" + degrees(m.low) + " to " + degrees(m.high) + ")";
  return {Expansion::Kind::kValue, m, {}};
}

// A heading and a position of the axis's range (both within -180..360, the
// profile's positions) are at most one turn apart; a number a vector writes
// can be any, and subtracting 360 from 1e300 changes nothing: a loop of
// turns until it fits would never end.
constexpr int kTurnsAtMost = 2;

// jogged: where the jog can leave the axis (motion::jog_end).
ResolvedMatcher resolve_jogged(FieldMatcher m, const ExprContext& cx) {
  const auto dir = motion::jog_direction(m.jog);
  if (!dir) return problem(Expansion::Kind::kError, m, std::string("jogged: no jog direction '") + m.jog + "'");
  const Number from = expand_number(m.values.at(0), cx), ms = expand_number(m.values.at(1), cx);
  for (const Number* n : {&from, &ms})
    if (n->kind != Expansion::Kind::kValue) return problem(n->kind, m, n->text);
  const AxisProfile& a = motion::profile_of(cx.profile, dir->axis);
  // A fluxgate heading (0.0-359.9, §3.2 NOTE) read where the axis's range
  // says -180 to 180: the same position, a turn away.
  double start = from.value;
  for (int turn = 0; m.angular && turn < kTurnsAtMost; ++turn) {
    if (start > a.max_deg + 1e-9 && start - 360.0 >= a.min_deg - 1e-9) start -= 360.0;
    else if (start < a.min_deg - 1e-9 && start + 360.0 <= a.max_deg + 1e-9) start += 360.0;
  }
  const Count jog_ms = count_in(ms.value, 0, kMaxMs);
  if (jog_ms.error) return problem(Expansion::Kind::kError, m, "jogged: ms " + *jog_ms.error);
  const motion::Interval end = motion::jog_end(a, start, dir->sign, m.speed, static_cast<int>(jog_ms.value));
  m.low = end.low;
  m.high = end.high;
  m.expected = std::string("a '") + m.jog + "' jog at " + (m.speed == 'F' ? "fast" : "slow") + " speed (" +
               degrees(motion::speed_dps(a, m.speed)) + " deg/s) for " + format_number(ms.value) + " ms from " +
               degrees(from.value) + ": " + degrees(m.low) + " to " + degrees(m.high);
  return {Expansion::Kind::kValue, m, {}};
}

}  // namespace

ResolvedMatcher resolve_matcher(const FieldMatcher& in, const ExprContext& cx) {
  FieldMatcher m = in;
  // An azimuth on a fluxgate mount is a heading: compared modulo 360.
  m.angular = matcher_axis(m) == motion::Axis::kAz && cx.profile.az_sensor == AzSensor::kFluxgate;
  switch (m.kind) {
    case FieldMatcher::Kind::kNear: return resolve_near(std::move(m), cx);
    case FieldMatcher::Kind::kJogged: return resolve_jogged(std::move(m), cx);
    case FieldMatcher::Kind::kRange:
      if (m.values.size() == 2) {
        const Number low = expand_number(m.values[0], cx), high = expand_number(m.values[1], cx);
        for (const Number* n : {&low, &high})
          if (n->kind != Expansion::Kind::kValue) return problem(n->kind, m, n->text);
        m.low = low.value;
        m.high = high.value;
        // A heading (0.0-359.9) beside a bound of the axis's range (-180 to
        // 180): the same window, the low end a turn down.
        for (int turn = 0; m.angular && turn < kTurnsAtMost && m.low > m.high + 1e-9; ++turn) m.low -= 360.0;
      }
      return {Expansion::Kind::kValue, m, {}};
    case FieldMatcher::Kind::kRegex:  // a pattern is never a template: its braces are quantifiers
    case FieldMatcher::Kind::kAny: return {Expansion::Kind::kValue, m, {}};
    case FieldMatcher::Kind::kEq:
    case FieldMatcher::Kind::kOneOf:
      for (auto& v : m.values) {
        const Expansion e = expand_template(v, cx);
        if (!e.ok()) return problem(e.kind, m, e.text);
        v = e.text;
      }
      return {Expansion::Kind::kValue, m, {}};
  }
  return {Expansion::Kind::kValue, m, {}};
}

}  // namespace sabus::harness
