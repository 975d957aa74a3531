// Field matchers (vectors/README.md "Field matchers"): the text and number a
// matcher compares for a described reply field, and the check of one matcher
// against a reply. Pure functions; the step engine (steps.cpp) calls them.
#include <cmath>
#include <cstdio>
#include <functional>
#include <regex>
#include <sstream>
#include <unordered_map>

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

// An expected value written as the field shows it: a code field reads
// "0x26", so an expression's 32 is named 0x20 beside it, not 32.
std::string as_field_shows(const std::string& want, const std::string& got) {
  if (got.rfind("0x", 0) != 0 || want.empty() || want.find_first_not_of("0123456789") != std::string::npos)
    return want;
  try {
    char hex[24];
    std::snprintf(hex, sizeof hex, "0x%02lx", std::stoul(want));
    return hex;
  } catch (...) {
    return want;
  }
}

// A number as a reply field shows it: a whole number of units, `per` of
// them to one (10^decimals: "-152.5" is -1525 tenths, "11050" 11050 units).
struct Reading {
  std::int64_t units = 0;
  int per = 1;
  bool negative = false;     // written with '-' ("-0.0" too)
  bool either_sign = false;  // read with a hundredths digit on a tenths field of 0.0: its sign unknown (E-30)
  // A negative tenths field with its digit as ERRATA E-87's other side adds
  // it (-0.2 and '8' is -0.12, where the reference's -0.2 and '8' is -0.28).
  std::optional<std::int64_t> digit_added;
};

constexpr int kMostDecimals = 6;

// The leading number of `text` ("-152.5 deg", "11050"), digit by digit:
// never through a double, so that -0.4 is -4 tenths, not -0.4000000000000001.
std::optional<Reading> leading_number(std::string_view text) {
  Reading r;
  std::size_t i = 0;
  while (i < text.size() && text[i] == ' ') ++i;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) r.negative = text[i++] == '-';
  bool digits = false;
  int decimals = -1;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '.' && decimals < 0) {
      decimals = 0;
      continue;
    }
    if (c < '0' || c > '9') break;
    if (decimals >= kMostDecimals || r.units > 99'999'999'999) return std::nullopt;  // no field holds such a number
    r.units = r.units * 10 + (c - '0');
    digits = true;
    if (decimals >= 0) {
      ++decimals;
      r.per *= 10;
    }
  }
  if (!digits) return std::nullopt;
  if (r.negative) r.units = -r.units;
  return r;
}

// The number a range, near or jogged matcher compares: a one-byte field's
// value, else the leading number of the field's meaning (matcher_number).
std::optional<Reading> field_reading(const FieldDescription& f) {
  if (f.first == f.last && f.raw.rfind("0x", 0) == 0) return Reading{std::stoi(f.raw.substr(2), nullptr, 16), 1};
  const std::string_view meaning = f.meaning;
  for (std::string_view prefix : {"index ", "heading "})
    if (meaning.rfind(prefix, 0) == 0) return leading_number(meaning.substr(prefix.size()));
  return leading_number(meaning);
}

// The 40h field holding an axis's hundredths digit (§3.17 bytes 49-50, as
// protocol/messages.hpp names them); the polarization has none.
std::optional<std::string_view> hundredths_field(motion::Axis a) {
  if (a == motion::Axis::kAz) return "az hundredths";
  if (a == motion::Axis::kEl) return "el hundredths";
  return std::nullopt;
}

// A position in tenths extended by the reply's hundredths digit of its axis
// when the matcher reads hundredths and the reply has one (E-30: the digit
// extends the magnitude; a tenths field of 0.0 without '-' leaves the sign
// to either).
Reading with_hundredths(Reading r, const FrameDescription& reply, const FieldDescription& field, const FieldMatcher& m) {
  const auto axis = motion::axis_of_field(field.name);
  const auto digit_field = axis ? hundredths_field(*axis) : std::nullopt;
  if (!m.hundredths || r.per != motion::kTenths || !digit_field) return r;
  for (const auto& f : reply.fields) {
    if (f.name != *digit_field) continue;
    const auto byte = field_reading(f);
    if (!byte || byte->per != 1 || byte->units < '0' || byte->units > '9') return r;
    const std::int64_t digit = byte->units - '0';
    r.either_sign = r.units == 0 && !r.negative && digit != 0;
    if (r.units < 0) r.digit_added = r.units * 10 + digit;
    r.units = r.units * 10 + (r.negative ? -digit : digit);
    r.per = motion::kHundredths;
    return r;
  }
  return r;
}

// A reading as the field writes it: "-0.4", "359.6", "11050".
std::string reading_text(std::int64_t units, int per) {
  const std::uint64_t magnitude = units < 0 ? 0 - static_cast<std::uint64_t>(units) : static_cast<std::uint64_t>(units);
  std::string digits = std::to_string(magnitude);
  std::size_t decimals = 0;
  for (int p = per; p > 1; p /= 10) ++decimals;
  if (decimals > 0) {
    if (digits.size() <= decimals) digits.insert(0, decimals + 1 - digits.size(), '0');
    digits.insert(digits.size() - decimals, 1, '.');
  }
  return (units < 0 ? "-" : "") + digits;
}

std::string window_text(const motion::Readings& w, int per) {
  if (w.low > w.high) return "none (" + reading_text(w.low, per) + " is above " + reading_text(w.high, per) + ")";
  return reading_text(w.low, per) + " to " + reading_text(w.high, per);
}

// Whether a reading is in the window, a heading taken modulo 360 nearest it.
bool reads_within(const Reading& r, const motion::Readings& w, bool angular) {
  const std::int64_t turn = std::int64_t{360} * r.per;
  if (r.digit_added) {  // either reading of the digit (E-87)
    Reading added = r;
    added.units = *r.digit_added;
    added.digit_added.reset();
    if (reads_within(added, w, angular)) return true;
  }
  for (const std::int64_t sign : {1, -1}) {
    if (sign < 0 && !r.either_sign) break;
    std::int64_t u = sign * r.units;
    if (angular && w.low <= w.high) {
      const long double middle = (static_cast<long double>(w.low) + static_cast<long double>(w.high)) / 2;
      u += turn * static_cast<std::int64_t>(std::llround((middle - static_cast<long double>(u)) / turn));
    }
    if (w.contains(u)) return true;
  }
  return false;
}

// range, near and jogged: the field's reading, as a whole number of the units
// it is written in (hundredths with the 40h digit), against the window in
// those units; never a number of degrees against a bound computed in doubles.
std::optional<std::string> check_reading(const FrameDescription& reply, const FieldDescription& field,
                                         const FieldMatcher& m, const std::function<std::string(const std::string&)>& fail) {
  const auto raw = field_reading(field);
  if (!raw)
    return fail(m.kind == FieldMatcher::Kind::kRange ? format_number(m.low) + " to " + format_number(m.high)
                                                     : m.expected + ": " + window_text(m.readings.tenths, motion::kTenths));
  const Reading r = with_hundredths(*raw, reply, field, m);
  motion::Readings window;
  if (m.kind == FieldMatcher::Kind::kRange) window = motion::readings_between(m.low, m.high, r.per);
  else if (r.per == motion::kHundredths && m.readings.hundredths) window = *m.readings.hundredths;
  else if (r.per == motion::kTenths) window = m.readings.tenths;
  else return fail(m.expected + ", a position in tenths (§3.2 bytes 14-31)");
  if (reads_within(r, window, m.angular)) return std::nullopt;
  std::string want = window_text(window, r.per);
  if (!m.expected.empty()) want = m.expected + (m.kind == FieldMatcher::Kind::kRange ? " (" + want + ")" : ": " + want);
  if (r.per == motion::kHundredths && raw->per == motion::kTenths)
    want += ", read with the hundredths digit as " + std::string(r.either_sign ? "+/-" : "") + reading_text(r.units, r.per);
  return fail(want);
}

// A regex matcher's pattern, compiled once per thread: compiling a
// std::regex costs far more than the search (each check compiling its
// pattern was a third of a sweep's time), and a suite has a few dozen
// patterns. Per thread, so the sweep's parallel profiles share nothing; a
// pattern that does not compile throws as before and is not kept.
const std::regex& compiled_regex(const std::string& pattern) {
  thread_local std::unordered_map<std::string, std::regex> kept;
  auto it = kept.find(pattern);
  if (it == kept.end()) {
    std::regex re(pattern);
    if (kept.size() >= 1024) kept.clear();  // patterns built from captures could grow it without end
    it = kept.emplace(pattern, std::move(re)).first;
  }
  return it->second;
}

std::optional<std::string> check_one_field(const FrameDescription& reply, const FieldDescription& field,
                                           const FieldMatcher& m, Captures& captures) {
  const std::string got = matcher_text(field);
  auto fail = [&](const std::string& expected) {
    return range_text(field) + " " + field.name + ": expected " + expected + ", got " + got + " (" + field.meaning + ")";
  };
  if (!m.capture.empty()) captures[m.capture] = got;
  switch (m.kind) {
    case FieldMatcher::Kind::kAny: return std::nullopt;
    case FieldMatcher::Kind::kEq:
      if (!m.values.empty() && !values_equal(m.values[0], got)) return fail(as_field_shows(m.values[0], got));
      return std::nullopt;
    case FieldMatcher::Kind::kOneOf: {
      std::string list;
      for (const auto& v : m.values) {
        if (values_equal(v, got)) return std::nullopt;
        list += (list.empty() ? "" : ", ") + as_field_shows(v, got);
      }
      return fail("one of " + list);
    }
    case FieldMatcher::Kind::kRegex:
      try {
        if (!m.values.empty() && !std::regex_search(got, compiled_regex(m.values[0]))) return fail("/" + m.values[0] + "/");
      } catch (const std::regex_error&) {
        return "matcher for \"" + m.field + "\": bad regex /" + m.values[0] + "/";
      }
      return std::nullopt;
    case FieldMatcher::Kind::kRange:
    case FieldMatcher::Kind::kNear:
    case FieldMatcher::Kind::kJogged: return check_reading(reply, field, m, fail);
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
    if (auto e = check_one_field(reply, f, m, captures)) return e;
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
  const int per = motion::display_units(cx.profile);
  m.readings = motion::near_readings(target.value, tol, per);
  m.hundredths = per == motion::kHundredths;
  m.low = static_cast<double>(m.readings.tenths.low) / motion::kTenths;
  m.high = static_cast<double>(m.readings.tenths.high) / motion::kTenths;
  m.expected = degrees(target.value) + " within " + degrees(tol);
  return {Expansion::Kind::kValue, m, {}};
}

// A heading and a position of the axis's range (both within -180..360, the
// profile's positions) are at most one turn apart; a number a vector writes
// can be any, and subtracting 360 from 1e300 changes nothing: a loop of
// turns until it fits would never end.
constexpr int kTurnsAtMost = 2;

// jogged: the readings where the jog can leave the axis (motion::jog_readings).
ResolvedMatcher resolve_jogged(FieldMatcher m, const ExprContext& cx) {
  const auto dir = motion::jog_direction(m.jog);
  if (!dir) return problem(Expansion::Kind::kError, m, std::string("jogged: no jog direction '") + m.jog + "'");
  const Number from = expand_number(m.values.at(0), cx), ms = expand_number(m.values.at(1), cx);
  for (const Number* n : {&from, &ms})
    if (n->kind != Expansion::Kind::kValue) return problem(n->kind, m, n->text);
  const AxisProfile& a = motion::profile_of(cx.profile, dir->axis);
  // `from` is a reading of a position field, in tenths (§3.2 bytes 14-31).
  const double from_tenths = from.value * motion::kTenths;
  if (!(std::abs(from_tenths) < 1e12) || std::abs(from_tenths - std::round(from_tenths)) > 1e-6)
    return problem(Expansion::Kind::kError, m,
                   "jogged: from " + format_number(from.value) + " is not a reading in tenths (a position field, §3.2 bytes 14-31)");
  auto start = static_cast<std::int64_t>(std::llround(from_tenths));
  // A fluxgate heading (0.0-359.9, §3.2 NOTE) read where the axis's range
  // says -180 to 180: the same position, a turn away.
  const double low = a.min_deg * motion::kTenths, high = a.max_deg * motion::kTenths;
  constexpr std::int64_t kTurn = 360 * motion::kTenths;
  for (int turn = 0; m.angular && turn < kTurnsAtMost; ++turn) {
    const auto x = static_cast<double>(start);
    if (x > high + 1e-6 && x - kTurn >= low - 1e-6) start -= kTurn;
    else if (x < low - 1e-6 && x + kTurn <= high + 1e-6) start += kTurn;
  }
  const Count jog_ms = count_in(ms.value, 0, kMaxMs);
  if (jog_ms.error) return problem(Expansion::Kind::kError, m, "jogged: ms " + *jog_ms.error);
  const int per = motion::display_units(cx.profile);
  m.readings = motion::jog_readings(a, per, start, dir->sign, m.speed, static_cast<int>(jog_ms.value), m.angular);
  m.hundredths = per == motion::kHundredths;
  m.low = static_cast<double>(m.readings.tenths.low) / motion::kTenths;
  m.high = static_cast<double>(m.readings.tenths.high) / motion::kTenths;
  m.expected = std::string("a '") + m.jog + "' jog at " + (m.speed == 'F' ? "fast" : "slow") + " speed (" +
               degrees(motion::speed_dps(a, m.speed)) + " deg/s) for " + format_number(ms.value) + " ms from " +
               degrees(from.value) + ", read rounded or truncated";
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
      // A position read with its 40h hundredths digit on a mount that has them (E-30).
      m.hundredths = motion::display_units(cx.profile) == motion::kHundredths;
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
