// Profile expressions (expressions.hpp): a small evaluating parser over
// numbers, captures ($name), symbols (az, F, presets) and the functions of
// one table, kFunctions.
//
//   expr    := sum
//   sum     := product (('+' | '-') product)*
//   product := unary (('*' | '/') unary)*
//   unary   := '-' unary | primary
//   primary := number | '$' name | name '(' [expr (',' expr)*] ')' | name | '(' expr ')' | "'" text "'"
#include "sabus/harness/expressions.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>

#include "sabus/harness/locate_targets.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/motion.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/enumerations.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus::harness {
namespace {

using Kind = Expansion::Kind;

struct Value {
  bool is_number = false;
  double number = 0;
  std::string text;  // a symbol or a text value
};

struct Result {
  Kind kind = Kind::kValue;
  Value value;
  std::string message;  // the reason (kUnavailable) or the error (kError)
  bool ok() const { return kind == Kind::kValue; }
};

Result number(double x) { return {Kind::kValue, {true, x, {}}, {}}; }
Result text(std::string t) { return {Kind::kValue, {false, 0, std::move(t)}, {}}; }
Result error(std::string m) { return {Kind::kError, {}, std::move(m)}; }
Result unavailable(std::string m) { return {Kind::kUnavailable, {}, std::move(m)}; }

// A finite decimal number, or a byte's 0xNN (a one-byte field's text), filling
// the text but for spaces around it (strtod read "12abc" as 12, "1-2" as 1,
// and took "nan" and "inf").
std::optional<double> parse_double(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X') && s[2] != '-' && s[2] != '+') {
    std::uint32_t h = 0;
    const auto [end, ec] = std::from_chars(s.data() + 2, s.data() + s.size(), h, 16);
    if (ec != std::errc{} || end != s.data() + s.size()) return std::nullopt;
    return static_cast<double>(h);
  }
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);  // from_chars takes no '+'
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc{} || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// A captured value is read as a number when it holds one. An azimuth from a
// fluxgate compass holds its heading followed by the reference, 'M' or 'T'
// (§3.2, ERRATA E-12: "180.0T").
std::optional<double> captured_number(std::string_view s) {
  if (auto v = parse_double(s)) return v;
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (s.size() < 2 || (s.back() != 'M' && s.back() != 'T')) return std::nullopt;
  return parse_double(s.substr(0, s.size() - 1));
}

// ---- arguments ----------------------------------------------------------------

using Args = std::vector<Value>;

// bitxor and bitand take whole numbers 0 to this (bytes and masks, with room).
constexpr long long kMaxBits = 0xFFFFFFFF;

struct Call {
  const ExprContext& cx;
  const Args& args;
  std::string_view name;

  std::optional<std::string> numbers(std::initializer_list<std::size_t> at) const {
    for (std::size_t i : at)
      if (!args[i].is_number || !std::isfinite(args[i].number))
        return std::string(name) + ": argument " + std::to_string(i + 1) + " must be a number";
    return std::nullopt;
  }
  // Argument i (checked by numbers()) as an int, for an index, a count of ms
  // or an address step: its fraction dropped and held within +-1e9, because
  // converting a double beyond int's range is undefined behaviour. Every such
  // function's own range is far narrower, so a held value fails its check as
  // the number itself would.
  int integer(std::size_t i) const { return static_cast<int>(std::clamp(std::trunc(args[i].number), -1e9, 1e9)); }
};

// A value as text: a capture as it was read, a computed number formatted.
std::string as_read_text(const Value& v) {
  if (!v.is_number || !v.text.empty()) return v.text;
  return format_number(v.number);
}

std::optional<motion::Axis> axis_arg(const Value& v) { return v.is_number ? std::nullopt : motion::axis_named(v.text); }

Result with_axis(const Call& c, const std::function<Result(motion::Axis, const AxisProfile&)>& f) {
  const auto axis = axis_arg(c.args[0]);
  if (!axis) return error(std::string(c.name) + ": argument 1 must be an axis: az, el or pol");
  return f(*axis, motion::profile_of(c.cx.profile, *axis));
}

// What an axis without a position reading lacks (ad_error: '*' in every
// position field, §3.2 bytes 14-31, E-42).
Result no_reading(motion::Axis axis) {
  return unavailable("a position reading of the " + std::string(motion::name_of(axis)) +
                     " (its A/D converter reports an error, ad_error)");
}

// As with_axis, for the functions that place an axis where a vector then
// reads it: unavailable when the profile's axis has no position reading.
Result with_read_axis(const Call& c, const std::function<Result(motion::Axis, const AxisProfile&)>& f) {
  return with_axis(c, [&](motion::Axis axis, const AxisProfile& a) { return a.ad_error ? no_reading(axis) : f(axis, a); });
}

std::optional<char> speed_arg(const Value& v) {
  if (!v.is_number && (v.text == "F" || v.text == "S")) return v.text[0];
  return std::nullopt;
}

// The indexed lists of stored data and their slot counts (§3.10, §3.12, §3.20).
struct SlotList {
  std::string_view name, what;
  int slots;
  std::function<bool(const Profile&, int)> filled;
};
template <class T>
bool has_index(const std::vector<T>& list, int i) {
  return std::any_of(list.begin(), list.end(), [&](const T& e) { return e.index == i; });
}
const SlotList kSlotLists[] = {
    {"presets", "preset satellite", 20, [](const Profile& p, int i) { return has_index(p.presets, i); }},
    {"tles", "TLE", 10, [](const Profile& p, int i) { return has_index(p.tles, i); }},
    {"signposts", "signpost", 20, [](const Profile& p, int i) { return has_index(p.signposts, i); }},
};

// The slot list argument 1 names (presets, tles, signposts); null when it
// names none.
const SlotList* slot_list_arg(const Call& c) {
  const Value& v = c.args[0];
  for (const auto& l : kSlotLists)
    if (!v.is_number && v.text == l.name) return &l;
  return nullptr;
}

// The first (or last) slot of a list, up to index `upto`, that the profile
// fills (or leaves empty).
Result slot(const Call& c, bool want_filled, bool from_end, int upto = 99) {
  const SlotList* list = slot_list_arg(c);
  if (!list) return error(std::string(c.name) + ": argument 1 must be presets, tles or signposts");
  const int slots = std::min(list->slots, upto);
  for (int k = 0; k < slots; ++k) {
    const int i = from_end ? slots - k : k + 1;
    if (list->filled(c.cx.profile, i) == want_filled) return number(i);
  }
  const std::string where = slots < list->slots ? " among the first " + std::to_string(slots) : "";
  return unavailable(std::string(want_filled ? "a filled " : "an empty ") + std::string(list->what) + " slot" + where +
                     ": the profile has " + (want_filled ? "none stored there" : "every one filled"));
}

// filled(list, i): the index when the profile fills that slot, so that a
// vector that overwrites it can write the profile's record back.
Result filled_slot(const Call& c) {
  const SlotList* list = slot_list_arg(c);
  if (!list) return error("filled: argument 1 must be presets, tles or signposts");
  if (c.numbers({1})) return error("filled: argument 2 must be an index");
  const int i = c.integer(1);
  if (i < 1 || i > list->slots || i != c.args[1].number)
    return error("filled: " + format_number(c.args[1].number) + " is not an index of " + std::string(list->name));
  if (list->filled(c.cx.profile, i)) return number(i);
  return unavailable(std::string(list->what) + " " + std::to_string(i) +
                     " filled in the profile (a write there could not be undone: a slot cannot be emptied)");
}

// second_filled(list): the second-lowest index the profile fills, for a
// vector that writes two different slots and reads each back (issue 32: a
// controller that stores every record into one slot).
Result second_filled_slot(const Call& c) {
  const SlotList* list = slot_list_arg(c);
  if (!list) return error("second_filled: argument 1 must be presets, tles or signposts");
  bool first = true;
  for (int i = 1; i <= list->slots; ++i) {
    if (!list->filled(c.cx.profile, i)) continue;
    if (!first) return number(i);
    first = false;
  }
  return unavailable("two filled " + std::string(list->what) + " slots: the profile has " + (first ? "none" : "one"));
}

}  // namespace

// The STORE list (§3.6) beside kSlotLists: its entries are 1..n, none empty.
constexpr std::string_view kStoreList = "store";

std::optional<std::string_view> slot_what(std::string_view list) {
  if (list == kStoreList) return "STORE entry";
  for (const auto& l : kSlotLists)
    if (l.name == list) return l.what;
  return std::nullopt;
}

std::string slot_list_names() {
  std::string out;
  for (const auto& l : kSlotLists) out += std::string(l.name) + ", ";
  return out.substr(0, out.size() - 2) + " or " + std::string(kStoreList);
}

std::optional<std::vector<int>> filled_slots(const Profile& profile, std::string_view list) {
  std::vector<int> out;
  if (list == kStoreList) {
    for (std::size_t i = 1; i <= profile.store.size(); ++i) out.push_back(static_cast<int>(i));
    return out;
  }
  for (const auto& l : kSlotLists)
    if (l.name == list) {
      for (int i = 1; i <= l.slots; ++i)
        if (l.filled(profile, i)) out.push_back(i);
      return out;
    }
  return std::nullopt;
}

namespace {

// Addresses a vector may send to that no controller on the line answers: not
// the profile's own, not a bus peer's (§1 multi-drop).
bool on_the_line(const Profile& p, int address) {
  if (address == p.address) return true;
  return std::any_of(p.bus_peers.begin(), p.bus_peers.end(), [&](std::uint8_t a) { return a == address; });
}

// frame_with_check(x): a complete frame to the profile's address whose check
// byte is x (§1 Check Character, E-5), which the device must answer: a read
// without data (31h, 30h, 45h), a read of an index (3Ah 01-20, 3Ch 01-10,
// 35h 01-50: ACK, or the NAK of a list without that entry), else an unknown
// command code without data (the NAK of §3). The first that fits.
std::optional<Bytes> frame_with_check(std::uint8_t address, std::uint8_t check) {
  auto fits = [&](std::uint8_t code, std::string_view data) -> std::optional<Bytes> {
    const Bytes f = encode_frame(Frame{FrameKind::kCommand, address, code, Bytes(data.begin(), data.end())});
    if (f.back() == check) return f;
    return std::nullopt;
  };
  for (std::uint8_t code : {0x31, 0x30, 0x45})
    if (auto f = fits(code, "")) return f;
  for (auto [code, last] : {std::pair{0x3A, 20}, std::pair{0x3C, 10}, std::pair{0x35, 50}})
    for (int i = 1; i <= last; ++i) {
      const char digits[3] = {static_cast<char>('0' + i / 10), static_cast<char>('0' + i % 10), 0};
      if (auto f = fits(static_cast<std::uint8_t>(code), digits)) return f;
    }
  for (int code = 0x20; code < 0x80; ++code)
    if ((code < 0x30 || code > 0x48))
      if (auto f = fits(static_cast<std::uint8_t>(code), "")) return f;
  return std::nullopt;
}

Result maybe(const motion::Maybe<double>& m) { return m.value ? number(*m.value) : unavailable(m.reason); }
Result maybe(const motion::Maybe<int>& m) { return m.value ? number(*m.value) : unavailable(m.reason); }

// ---- value checks of state-dependent fields -------------------------------------
// The functions of the block "values the state gives" of kFunctions: where a
// field's value follows from the profile and the commands before it (a pulse
// count, a hundredths digit).

// A position reading at its display resolution (tenths, §3.2 bytes 14-31)
// stands for a position within this of it, whether the controller rounds
// or truncates (with 0.01 deg feedback the tenths are truncated, E-30).
constexpr double kReadingSpan = 0.1;
// The highest 5-digit pulse count (§3.16 bytes 3-7).
constexpr double kMaxCount = 99999;

// count_low / count_high (axis, deg): the counts a controller at a position
// read as `deg` can report (§3.16; ERRATA E-85): count_offset + position x
// counts_per_degree for every position the reading stands for, one count
// either way for the sensor's own rounding. A position whose count lies past
// five digits (below 0 or above 99999) may show any count: held at the end or
// wrapped, §3.16 gives no rule (ERRATA E-85), so its bounds are 0 and 99999.
Result count_bound(const Call& c, int side) {
  // An axis without a reading ('*', E-42) gives no capture to count from.
  return with_read_axis(c, [&](motion::Axis, const AxisProfile&) {
    if (auto e = c.numbers({1})) return error(*e);
    const Profile& p = c.cx.profile;
    const double low = p.count_offset + (c.args[1].number - kReadingSpan) * p.counts_per_degree;
    const double high = p.count_offset + (c.args[1].number + kReadingSpan) * p.counts_per_degree;
    if (low < 0 || high > kMaxCount) return number(side < 0 ? 0.0 : kMaxCount);
    const double bound = side < 0 ? std::floor(low) - 1 : std::ceil(high) + 1;
    return number(std::clamp(bound, 0.0, kMaxCount));
  });
}

// negative(axis) and positive(axis): a position of that sign inside the
// range, in the middle of the part clear of 0 and of the limits by the
// tolerance and half a degree, in tenths rounded away from 0; with `within`,
// no farther from 0 than that (padded_negative: 99.9, so that a 32h target's
// tenths in 5 characters keep a padding zero, where ERRATA E-45's two
// spellings differ).
Result position_of_sign(const Call& c, int sign, std::optional<double> within = std::nullopt) {
  return with_read_axis(c, [sign, within](motion::Axis axis, const AxisProfile& a) {
    const double margin = a.tolerance_deg + 0.5;
    double bottom = (sign > 0 ? std::max(a.min_deg, 0.0) : a.min_deg) + margin;
    double top = (sign > 0 ? a.max_deg : std::min(a.max_deg, 0.0)) - margin;
    if (within && sign > 0) top = std::min(top, *within);
    if (within && sign < 0) bottom = std::max(bottom, -*within);
    if (top - bottom < 0.1)
      return unavailable(std::string(sign > 0 ? "a positive " : "a negative ") + std::string(motion::name_of(axis)) +
                         (within ? " within " + format_number(*within) + " deg of 0" : "") + " inside its range");
    const double middle_tenths = (top + bottom) / 2 * 10;
    return number((sign > 0 ? std::ceil(middle_tenths) : std::floor(middle_tenths)) / 10);
  });
}

// x as a 32h signed target of `width` characters at `decimals` (§3.3), in
// one of ERRATA E-45's spellings, as text for a raw template.
Result target_text(const Call& c, TargetSpelling spelling) {
  if (auto e = c.numbers({0, 1, 2})) return error(*e);
  const int width = c.integer(1), decimals = c.integer(2);
  if (width < 2 || width > 10 || decimals < 0 || decimals > 2)
    return error("a target is 2-10 characters with 0-2 decimals (§3.3 forms 2A, 2C, 3)");
  const double scaled = std::round(c.args[0].number * std::pow(10.0, decimals));
  const double room = std::pow(10.0, scaled < 0 ? width - 1 : width);
  if (std::abs(scaled) >= room) return error(format_number(c.args[0].number) + " does not fit " + std::to_string(width) + " characters");
  Bytes t(static_cast<std::size_t>(width));
  fields::SignedDigits{static_cast<std::size_t>(width), decimals}.encode(static_cast<std::int32_t>(scaled), t);
  respell_target(t, spelling);
  return text(std::string(t.begin(), t.end()));
}

// The hundredths digit of §3.17 bytes 49-50 after a form 2C move (ERRATA
// E-86, E-87): the digits d (0-9) for which the tenths reading `reading`
// (bytes 14-25, captured) extended by d lies within the axis's arrival
// window at 0.01 deg of `target`. The window is tolerance_deg with the
// display's 0.1 deg allowance at the hundredths' 0.01 (E-86). A positive
// reading extended is reading + d/100; a negative (or zero) one may be read
// either way the spec's "added to the rest of the position" allows (E-87):
// the magnitude extended (-12.3 and 4 is -12.34, tenths truncated) or the
// digit added (-12.4 and 6 is -12.34, tenths rounded down). A fluxgate
// heading is compared modulo 360 (§3.2 NOTE). Both readings together give
// one run of digits; when no digit fits (the tenths are already out), the
// nearest digit, so that the failure names the digit the reading wanted.
Result hundredths_bound(const Call& c, bool low) {
  return with_read_axis(c, [&](motion::Axis axis, const AxisProfile& a) {
    if (auto e = c.numbers({1, 2})) return error(*e);
    const double reading = c.args[1].number, target = c.args[2].number;
    const double window = std::max(0.01, a.tolerance_deg - kReadingSpan + 0.01);
    const bool heading = axis == motion::Axis::kAz && c.cx.profile.az_sensor == AzSensor::kFluxgate;
    auto off = [&](double full) {
      double d = full - target;
      if (heading) d -= 360.0 * std::round(d / 360.0);
      return std::abs(d);
    };
    auto miss = [&](int digit) {
      double best = off(reading + digit / 100.0);
      if (reading <= 0 && !heading) best = std::min(best, off(reading - digit / 100.0));
      return best;
    };
    int first = -1, last = -1, nearest = 0;
    for (int d = 0; d <= 9; ++d) {
      if (miss(d) < miss(nearest)) nearest = d;
      if (miss(d) > window + 1e-9) continue;
      if (first < 0) first = d;
      last = d;
    }
    if (first < 0) return number(nearest);
    return number(low ? first : last);
  });
}

// ---- LOCATE (locate_targets.hpp; §3.18, §3.17; ERRATA E-80 to E-82) -----------

// The mount's reading of the satellite at the longitude argument 1.
Result locate_reading(const Call& c, motion::Axis axis) {
  if (auto e = c.numbers({0})) return error(*e);
  const double lon = c.args[0].number;
  if (lon < -179.9 - 1e-9 || lon > 179.9 + 1e-9)
    return error(std::string(c.name) + ": " + format_number(lon) + " is not a satellite longitude -179.9 to 179.9");
  const auto to = locate::pointing(c.cx.profile, lon);
  if (!to.value) return unavailable(to.reason);
  return number(axis == motion::Axis::kAz ? to.value->azimuth_deg : to.value->elevation_deg);
}

// ---- the function table ---------------------------------------------------------

struct Function {
  ExprFunction doc;
  std::size_t arity;
  Result (*eval)(const Call&);
};

const Function kFunctions[] = {
    {{"home", "axis", "where moving vectors start: the middle of the axis's range, in tenths"}, 1,
     [](const Call& c) { return with_read_axis(c, [](motion::Axis, const AxisProfile& a) { return number(motion::home(a)); }); }},
    {{"at", "axis, fraction", "the position a fraction 0-1 of the way from min_deg to max_deg, in tenths"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({1})) return error(*e);
       return with_read_axis(c, [&](motion::Axis, const AxisProfile& a) { return number(motion::at(a, c.args[1].number)); });
     }},
    {{"reads", "axis", "1 when the axis has a position reading; unavailable with an A/D error (ad_error, E-42)"}, 1,
     [](const Call& c) { return with_read_axis(c, [](motion::Axis, const AxisProfile&) { return number(1); }); }},
    {{"stored_pol", "fraction",
      "a polarization position a fraction 0-1 along the part of the pol range inside -90.0 to 90.0 (a STORE's H/V pol, "
      "§3.19 bytes 30-39), in tenths; unavailable when that part is under 10 deg"},
     1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       AxisProfile a = c.cx.profile.pol;
       if (a.ad_error) return no_reading(motion::Axis::kPol);
       a.min_deg = std::max(a.min_deg, -90.0);
       a.max_deg = std::min(a.max_deg, 90.0);
       if (a.max_deg - a.min_deg < 10.0)
         return unavailable("a polarization range reaching 10 deg into -90.0 to 90.0 (a STORE's H/V pol positions, §3.19)");
       return number(motion::at(a, c.args[0].number));
     }},
    {{"stop_travel", "axis, F|S",
      "how far the axis travels after a stop from that speed: down its ramp (accel_dps2, E-71), 0 without one"},
     2,
     [](const Call& c) {
       const auto speed = speed_arg(c.args[1]);
       if (!speed) return error("stop_travel: argument 2 must be F or S");
       return with_axis(c, [&](motion::Axis, const AxisProfile& a) {
         const double v = motion::speed_dps(a, *speed);
         return number(a.accel_dps2 ? v * v / (2 * *a.accel_dps2) : 0.0);
       });
     }},
    {{"firmware", "", "the controller's software version the profile states, \"A.BC\" (§3.1 bytes 5-8), as text"}, 0,
     [](const Call& c) { return text(c.cx.profile.firmware); }},
    {{"agc", "", "the AGC level the profile states, 0-999 (§3.2 bytes 41-43)"}, 0,
     [](const Call& c) { return number(c.cx.profile.agc); }},
    // The power-on state the profile states (issue 32): a vector tagged
    // as-found reads it before any command could change it.
    {{"agc_channel", "", "the AGC channel the profile states: 1 SS1, 2 SS2, 3 not applicable (§3.2 byte 44 CC)"}, 0,
     [](const Call& c) { return number(c.cx.profile.agc_channel); }},
    {{"alarm_code", "", "the alarm code active at power-on, 0-63, 0 for none (§3.2 byte 39 A5..A0; alarms.code)"}, 0,
     [](const Call& c) { return number(c.cx.profile.alarms.code); }},
    {{"axis_alarm", "axis",
      "the axis's alarm active at power-on as §3.2 bytes 36-38 XXXX: 0 none, 8 off axis, 9 sensor direction, 10 runaway, "
      "11 jammed, 12 drive (alarms.az, .el, .pol)"},
     1,
     [](const Call& c) {
       const auto axis = axis_arg(c.args[0]);
       if (!axis) return error("axis_alarm: argument 1 must be an axis: az, el or pol");
       const AlarmProfile& a = c.cx.profile.alarms;
       return number(*axis == motion::Axis::kAz ? a.az : *axis == motion::Axis::kEl ? a.el : a.pol);
     }},
    {{"track_band", "", "the track band the profile states as §3.2 byte 40 BBB, 1-7 (track.band, E-70)"}, 0,
     [](const Call& c) { return number(static_cast<int>(c.cx.profile.track.band)); }},
    {{"pol_feed", "", "the polarization feed as §3.2 byte 35 XX: 0 circular, 1 single port, 2 dual port (polarization)"}, 0,
     [](const Call& c) {
       const PolType t = c.cx.profile.pol_type;
       return number(t == PolType::kCircular ? 0 : t == PolType::kSinglePort ? 1 : 2);
     }},
    {{"display_name", "", "the satellite name the controller shows at power-on, as text (§3.2 bytes 3-12; display.satellite)"}, 0,
     [](const Call& c) { return text(c.cx.profile.display.satellite); }},
    {{"count_step", "", "the position one pulse count stands for: 1 / counts_per_degree (§3.16)"}, 0,
     [](const Call& c) { return number(1.0 / c.cx.profile.counts_per_degree); }},
    {{"min_deg", "axis", "the axis's lower limit position"}, 1,
     [](const Call& c) { return with_axis(c, [](motion::Axis, const AxisProfile& a) { return number(a.min_deg); }); }},
    {{"max_deg", "axis", "the axis's upper limit position"}, 1,
     [](const Call& c) { return with_axis(c, [](motion::Axis, const AxisProfile& a) { return number(a.max_deg); }); }},
    {{"initial_deg", "axis", "the axis's position at power-on"}, 1,
     [](const Call& c) { return with_axis(c, [](motion::Axis, const AxisProfile& a) { return number(a.initial_deg); }); }},
    {{"clear_of_limits", "axis",
      "1 when the axis's power-on position (initial_deg) is more than 1 deg from its limits and its stow limit, so that no "
      "limit input is closed (§3.2 bytes 32-34 CBA clear); unavailable nearer (where a limit switch closes is the mount's)"},
     1,
     [](const Call& c) {
       return with_axis(c, [](motion::Axis axis, const AxisProfile& a) {
         constexpr double kMarginDeg = 1.0;
         const bool clear = a.initial_deg > a.min_deg + kMarginDeg && a.initial_deg < a.max_deg - kMarginDeg &&
                            (!a.has_stow_limit || std::abs(a.initial_deg - a.stow_deg) > kMarginDeg);
         return clear ? number(1)
                      : unavailable("the " + std::string(motion::name_of(axis)) +
                                    " at power-on more than 1 deg from its limits and stow limit");
       });
     }},
    {{"stow_deg", "axis", "the axis's stow limit position; unavailable without a stow limit"}, 1,
     [](const Call& c) {
       return with_axis(c, [](motion::Axis axis, const AxisProfile& a) {
         return a.has_stow_limit ? number(a.stow_deg)
                                 : unavailable("a stow limit on the " + std::string(motion::name_of(axis)));
       });
     }},
    {{"deploy_deg", "axis", "where a DEPLOY drives the axis (§3.7 'D'); unavailable when the profile does not say"}, 1,
     [](const Call& c) {
       return with_axis(c, [](motion::Axis axis, const AxisProfile& a) {
         return a.deploy_deg ? number(*a.deploy_deg)
                             : unavailable("the deploy position of the " + std::string(motion::name_of(axis)) +
                                           " in the profile (deploy_deg)");
       });
     }},
    {{"fast", "axis", "the axis's fast speed, deg/s"}, 1,
     [](const Call& c) { return with_axis(c, [](motion::Axis, const AxisProfile& a) { return number(a.fast_dps); }); }},
    {{"slow", "axis", "the axis's slow speed, deg/s"}, 1,
     [](const Call& c) { return with_axis(c, [](motion::Axis, const AxisProfile& a) { return number(a.slow_dps); }); }},
    {{"tolerance", "axis", "how close an auto move stops to its target (tolerance_deg)"}, 1,
     [](const Call& c) { return with_axis(c, [](motion::Axis, const AxisProfile& a) { return number(a.tolerance_deg); }); }},
    {{"jog_ms", "axis, F|S",
      "a jog duration that, from home, surely moves the axis a measurable distance and stays off its limits"},
     2,
     [](const Call& c) {
       const auto speed = speed_arg(c.args[1]);
       if (!speed) return error("jog_ms: argument 2 must be F or S");
       return with_read_axis(c, [&](motion::Axis axis, const AxisProfile& a) {
         return maybe(motion::measurable_jog_ms(a, *speed, motion::name_of(axis)));
       });
     }},
    {{"jog_start", "E|W|D|U|O|L, F|S, ms",
      "a start position, nearest home, from which that jog runs at least ms before it can reach a limit"},
     3,
     [](const Call& c) {
       const auto dir = c.args[0].is_number || c.args[0].text.size() != 1 ? std::nullopt
                                                                           : motion::jog_direction(c.args[0].text[0]);
       const auto speed = speed_arg(c.args[1]);
       if (!dir) return error("jog_start: argument 1 must be a jog direction E, W, D, U, O or L");
       if (!speed) return error("jog_start: argument 2 must be F or S");
       if (auto e = c.numbers({2})) return error(*e);
       const AxisProfile& a = motion::profile_of(c.cx.profile, dir->axis);
       if (a.ad_error) return no_reading(dir->axis);
       return maybe(motion::jog_start(a, dir->sign, *speed, c.integer(2), motion::name_of(dir->axis)));
     }},
    {{"move_target", "axis, from, ms",
      "a target toward the farther end of the range whose auto move from `from` lasts at least ms at fast speed"},
     3,
     [](const Call& c) {
       if (auto e = c.numbers({1, 2})) return error(*e);
       return with_read_axis(c, [&](motion::Axis axis, const AxisProfile& a) {
         return maybe(motion::move_target(a, c.args[1].number, c.integer(2), motion::name_of(axis)));
       });
     }},
    {{"away_from", "axis, to, ms",
      "a position toward the farther end of the range whose auto move to `to` lasts at least ms at fast speed, and "
      "not much more"},
     3,
     [](const Call& c) {
       if (auto e = c.numbers({1, 2})) return error(*e);
       return with_read_axis(c, [&](motion::Axis axis, const AxisProfile& a) {
         return maybe(motion::away_from(a, c.args[1].number, c.integer(2), motion::name_of(axis)));
       });
     }},
    {{"pace_ms", "", "the run's pace between commands (--pace), ms"}, 0,
     [](const Call& c) { return number(static_cast<double>(c.cx.pace.count())); }},
    {{"counts", "axis, deg", "the pulse count of a position: count_offset + deg x counts_per_degree (§3.16)"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({1})) return error(*e);
       return with_axis(c, [&](motion::Axis axis, const AxisProfile&) {
         const double n = std::round(c.cx.profile.count_offset + c.args[1].number * c.cx.profile.counts_per_degree);
         if (n < 0 || n > 99999)
           return unavailable("a 5-digit pulse count for " + std::string(motion::name_of(axis)) + " " +
                              format_number(c.args[1].number) + " deg");
         return number(n);
       });
     }},
    {{"filled", "presets|tles|signposts, index", "the index, when the profile fills that slot"}, 2, filled_slot},
    {{"first_empty", "presets|tles|signposts", "the lowest index the profile leaves empty"}, 1,
     [](const Call& c) { return slot(c, false, false); }},
    {{"last_empty", "presets|tles|signposts", "the highest index the profile leaves empty"}, 1,
     [](const Call& c) { return slot(c, false, true); }},
    {{"first_filled", "presets|tles|signposts", "the lowest index the profile fills"}, 1,
     [](const Call& c) { return slot(c, true, false); }},
    {{"last_filled", "presets|tles|signposts", "the highest index the profile fills"}, 1,
     [](const Call& c) { return slot(c, true, true); }},
    {{"second_filled", "presets|tles|signposts", "the second-lowest index the profile fills; unavailable with fewer than two"}, 1,
     second_filled_slot},
    {{"first_filled_upto", "presets|tles|signposts, max", "the lowest index up to max that the profile fills"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({1})) return error(*e);
       return slot(c, true, false, c.integer(1));
     }},
    {{"first_empty_upto", "presets|tles|signposts, max", "the lowest index up to max that the profile leaves empty"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({1})) return error(*e);
       return slot(c, false, false, c.integer(1));
     }},
    {{"store_count", "", "the number of entries of the profile's STORE list (§3.6)"}, 0,
     [](const Call& c) { return number(static_cast<double>(c.cx.profile.store.size())); }},
    {{"store_room", "n",
      "1 when the profile's STORE list (§3.6, at most 50) has room for n more names; unavailable when it has not"},
     1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const double free = 50.0 - static_cast<double>(c.cx.profile.store.size());
       if (free >= c.args[0].number) return number(1);
       return unavailable("room for " + format_number(c.args[0].number) + " more names in the STORE list: the profile's holds " +
                          std::to_string(c.cx.profile.store.size()) + " of 50");
     }},
    {{"has_navigation", "",
      "1 when the profile holds navigation data (latitude, longitude and heading, §3.22) that 46h can write back on every "
      "side of E-60 the profile leaves open (not a pole or -180 deg 00, which E-60's other side NAKs)"},
     0,
     [](const Call& c) {
       const Navigation& n = c.cx.profile.navigation;
       if (!n.latitude_min || !n.longitude_min || !n.heading_tenths)
         return unavailable("navigation data (latitude, longitude and heading) in the profile, to write back after 46h");
       const bool boundary = std::abs(*n.latitude_min) == 90 * 60 || *n.longitude_min == -180 * 60;
       if (boundary && side_pinned(c.cx.profile.readings, "E-60") != ReadingSide::kReference)
         return unavailable("navigation data off the poles and -180 deg 00 (E-60's other side NAKs them, so 46h could not write them back), or E-60 pinned to reference");
       return number(1);
     }},
    {{"negative", "axis", "a negative position inside the axis's range, in tenths; unavailable when the range has none"}, 1,
     [](const Call& c) { return position_of_sign(c, -1); }},
    {{"padded_negative", "axis",
      "a negative position inside the axis's range above -100.0, whose 32h target has a padding zero (E-45); unavailable "
      "when the range has none"},
     1, [](const Call& c) { return position_of_sign(c, -1, 99.9); }},
    {{"sign_first", "x, width, decimals", "x as a 32h target, '-' first then zero-padded digits: -5.0 in 5 at 1 is -0050 (§3.3, E-45), as text"},
     3, [](const Call& c) { return target_text(c, TargetSpelling::kSignFirst); }},
    {{"zeros_first", "x, width, decimals",
      "x as a 32h target right-justified with the zeros left of its sign: -5.0 in 5 at 1 is 00-50 (E-45's other side), as text"},
     3, [](const Call& c) { return target_text(c, TargetSpelling::kZerosFirst); }},
    {{"min", "a, b", "the smaller number"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({0, 1})) return error(*e);
       return number(std::min(c.args[0].number, c.args[1].number));
     }},
    {{"max", "a, b", "the larger number"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({0, 1})) return error(*e);
       return number(std::max(c.args[0].number, c.args[1].number));
     }},
    {{"text", "x", "x as text: a capture as the reply held it (\"0123\", \"180.0T\", where $x alone reads 123 and 180), a number as written"}, 1,
     [](const Call& c) { return text(as_read_text(c.args[0])); }},
    {{"abs", "x", "the magnitude"}, 1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       return number(std::abs(c.args[0].number));
     }},
    {{"tenths", "x", "x rounded to 0.1"}, 1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       return number(std::round(c.args[0].number * 10) / 10);
     }},
    {{"preset_flag", "index",
      "bytes 3-4 of 41h/42h with the preset flag set (§3.18/§3.19, E-29): 40h | 1 << 4 | tens, then the ones digit"},
     1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const int i = c.integer(0);
       if (i < 0 || i > 29 || i != c.args[0].number)
         return error("preset_flag: index " + format_number(c.args[0].number) + " does not fit a tens digit 0-2");
       return text(std::string{static_cast<char>(0x40 | 0x10 | i / 10), static_cast<char>('0' + i % 10)});
     }},
    {{"address", "", "the device's address byte (49-111, §1)"}, 0,
     [](const Call& c) { return number(c.cx.profile.address); }},
    {{"other_address", "step",
      "a valid address (31h-6Fh) `step` away from the device's that no controller on the line has: the one above, "
      "else the one below (at 6Fh, 6Eh)"},
     1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       // Either side serves: a vector needs another valid address, not one
       // above (§1: any of 31h-6Fh), so a device at 111 (6Fh) takes 110.
       const int step = c.integer(0);
       std::string taken;
       for (const int a : {c.cx.profile.address + step, c.cx.profile.address - step}) {
         if (a < 0x31 || a > 0x6F) continue;
         if (!on_the_line(c.cx.profile, a)) return number(a);
         if (taken.empty()) taken = std::to_string(a);
       }
       if (!taken.empty()) return unavailable("address " + taken + " free on the line: a controller there answers");
       return unavailable("a valid address " + format_number(c.args[0].number) + " away from the device's");
     }},
    {{"peer", "n", "the address of the profile's n-th bus peer (§1 multi-drop), from 1"}, 1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const int n = c.integer(0);
       const auto& peers = c.cx.profile.bus_peers;
       if (n < 1 || static_cast<std::size_t>(n) > peers.size())
         return unavailable(format_number(c.args[0].number) + " peer(s) on the line (bus_peers)");
       return number(peers[static_cast<std::size_t>(n) - 1]);
     }},
    {{"unused_address", "", "the lowest valid address (31h-6Fh) no controller on the line has"}, 0,
     [](const Call& c) {
       for (int a = 0x31; a <= 0x6F; ++a)
         if (!on_the_line(c.cx.profile, a)) return number(a);
       return unavailable("an address no controller on the line has");
     }},
    {{"foreign", "address", "the address when no controller on the line has it (a vector sends to it to be ignored)"}, 1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const int a = c.integer(0);
       if (a < 0 || a > 0x7F || a != c.args[0].number) return error("foreign: " + format_number(c.args[0].number) + " is not a 7-bit address");
       if (on_the_line(c.cx.profile, a)) return unavailable("address " + std::to_string(a) + " free on the line: a controller there answers");
       return number(a);
     }},
    {{"bitxor", "a, b", "a XOR b, of whole numbers 0 to FFFFFFFFh"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({0, 1})) return error(*e);
       const Count a = count_in(c.args[0].number, 0, kMaxBits), b = count_in(c.args[1].number, 0, kMaxBits);
       if (a.error || b.error) return error("bitxor: " + *(a.error ? a.error : b.error));
       return number(static_cast<double>(a.value ^ b.value));
     }},
    {{"bitand", "a, b", "a AND b, of whole numbers 0 to FFFFFFFFh"}, 2,
     [](const Call& c) {
       if (auto e = c.numbers({0, 1})) return error(*e);
       const Count a = count_in(c.args[0].number, 0, kMaxBits), b = count_in(c.args[1].number, 0, kMaxBits);
       if (a.error || b.error) return error("bitand: " + *(a.error ? a.error : b.error));
       return number(static_cast<double>(a.value & b.value));
     }},
    {{"char", "n", "the character with this code, as text (for raw templates)"}, 1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const double n = c.args[0].number;
       if (n < 0 || n > 0x7F || n != std::floor(n)) return error("char: " + format_number(n) + " is not a 7-bit character");
       return text(std::string(1, static_cast<char>(n)));
     }},
    {{"frame_with_check", "byte",
      "a whole frame to the device's address whose check byte is `byte` and which the device must answer (a read, or "
      "an unknown code's NAK), as text for a raw template"},
     1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const Count check = count_in(c.args[0].number, 0, 0x7F);
       if (check.error) return error("frame_with_check: " + *check.error + " (a 7-bit check byte)");
       const auto f = frame_with_check(c.cx.profile.address, static_cast<std::uint8_t>(check.value));
       if (!f) return unavailable("a frame to address " + std::to_string(c.cx.profile.address) + " with that check byte");
       return text(std::string(f->begin(), f->end()));
     }},
    {{"pad2", "n", "a whole number 0-99 as two digits: 05"}, 1,
     [](const Call& c) {
       if (auto e = c.numbers({0})) return error(*e);
       const double n = c.args[0].number;
       if (n < 0 || n > 99 || n != std::floor(n)) return error("pad2: " + format_number(n) + " is not a whole number 0-99");
       char buf[4];
       std::snprintf(buf, sizeof buf, "%02d", static_cast<int>(n));
       return text(buf);
     }},
    // ---- values the state gives: value checks of state-dependent fields --------
    {{"positive", "axis", "a positive position inside the axis's range, in tenths; unavailable when the range has none"}, 1,
     [](const Call& c) { return position_of_sign(c, 1); }},
    {{"count_low", "axis, deg",
      "the lowest pulse count a position read as deg can give: the reading's 0.1 deg and one count below; 0 where the count lies past five digits (§3.16, E-85)"},
     2, [](const Call& c) { return count_bound(c, -1); }},
    {{"count_high", "axis, deg",
      "the highest pulse count a position read as deg can give: the reading's 0.1 deg and one count above; 99999 where the count lies past five digits (§3.16, E-85)"},
     2, [](const Call& c) { return count_bound(c, +1); }},
    {{"hundredths_min", "axis, reading, target",
      "the lowest hundredths digit (§3.17 bytes 49-50) that puts the tenths reading within the arrival window of a "
      "form 2C target (E-86, E-87)"},
     3, [](const Call& c) { return hundredths_bound(c, true); }},
    {{"hundredths_max", "axis, reading, target",
      "the highest hundredths digit that puts the tenths reading within the arrival window of a form 2C target"},
     3, [](const Call& c) { return hundredths_bound(c, false); }},
    // ---- LOCATE: satellites from the profile's site, heading and ranges ----
    {{"locate_visible", "",
      "the longitude of a geostationary satellite in view and inside both axis ranges (a LOCATE that moves there, E-80)"},
     0, [](const Call& c) { return maybe(locate::visible(c.cx.profile)); }},
    {{"locate_any", "",
      "locate_visible(); on a profile without the site, where any LOCATE waits for it (E-59) and moves nowhere, 0.0: "
      "for vectors that check what a LOCATE's ACK or name shows, not where it goes"},
     0,
     [](const Call& c) {
       const auto missing = look::site_of(c.cx.profile.navigation, c.cx.profile.az_sensor, c.cx.profile.fluxgate_heading);
       return missing.site ? maybe(locate::visible(c.cx.profile)) : number(0.0);
     }},
    {{"locate_below_horizon", "",
      "the longitude of a satellite below the horizon and the elevation's lower limit, its azimuth inside the azimuth "
      "range (LOCATE_ELEVATION_RANGE_ERROR, E-81)"},
     0, [](const Call& c) { return maybe(locate::below_horizon(c.cx.profile)); }},
    {{"locate_outside_az", "",
      "the longitude of a satellite in view outside the azimuth range (LOCATE_AZIMUTH_RANGE_ERROR, E-81); unavailable "
      "when the range takes in the whole sky in view"},
     0, [](const Call& c) { return maybe(locate::outside_azimuth(c.cx.profile)); }},
    {{"locate_above_el", "",
      "the longitude of a satellite in view above the elevation's upper limit, its azimuth inside the azimuth range "
      "(LOCATE_ELEVATION_RANGE_ERROR, E-81)"},
     0, [](const Call& c) { return maybe(locate::above_elevation(c.cx.profile)); }},
    {{"locate_az", "longitude",
      "the azimuth reading of the mount pointed at the satellite at that longitude: position = true azimuth - heading, "
      "a heading on a fluxgate mount (E-80)"},
     1, [](const Call& c) { return locate_reading(c, motion::Axis::kAz); }},
    {{"locate_el", "longitude", "the elevation of the satellite at that longitude from the profile's site (E-80)"}, 1,
     [](const Call& c) { return locate_reading(c, motion::Axis::kEl); }},
    {{"locate_slack", "az|el",
      "how far a LOCATE's arrival may read from locate_az/locate_el: two controllers' earth models, tolerance_deg and "
      "the display's 0.1 deg"},
     1,
     [](const Call& c) {
       return with_axis(c, [&](motion::Axis axis, const AxisProfile&) {
         if (axis == motion::Axis::kPol) return error("locate_slack: argument 1 must be az or el");
         return number(locate::slack(c.cx.profile, axis));
       });
     }},
    {{"mode_exit", "'MODE', 'NAME'",
      "the value of an exit condition NAME of the §3.17 exit list of MODE (stow_exit_conditions for 'STOW_MODE', ...), "
      "under the profile's reading of the lost locate entry (E-28)"},
     2,
     [](const Call& c) {
       if (c.args[0].is_number || c.args[1].is_number)
         return error("mode_exit: arguments must be names in quotes: 'STOW_MODE', 'STOW_FINISHED_NORMALLY'");
       const auto mode = enums::mode_names().value_of(c.args[0].text);
       if (!mode) return error("mode_exit: " + c.args[0].text + " is not a mode of §3.17");
       const auto* exits =
           enums::exit_list_for_mode(*mode, enums::EnumReading{c.cx.profile.restore_lost_locate_exit});
       if (!exits) return error("mode_exit: " + c.args[0].text + " has no exit list");
       const auto v = exits->value_of(c.args[1].text);
       if (!v) return error("mode_exit: " + c.args[1].text + " is not an exit of " + c.args[0].text);
       return number(*v);
     }},
    {{"locate_waiting", "",
      "the §3.17 locate_states value a LOCATE waits in for what the profile's navigation data lacks: "
      "LOCATE_WAITING_FOR_LAT_LON or LOCATE_WAITING_FOR_HEADING (E-59, E-84); unavailable when it lacks nothing, "
      "or only a magnetic variation, which a controller may compute itself"},
     0,
     [](const Call& c) {
       const auto site = look::site_of(c.cx.profile.navigation, c.cx.profile.az_sensor, c.cx.profile.fluxgate_heading);
       if (site.missing == look::Missing::kNothing)
         return unavailable("navigation data a LOCATE waits for: the profile has the site, and the heading it needs");
       if (site.missing == look::Missing::kMagvar)
         return unavailable("navigation data a LOCATE surely waits for: the profile lacks only a magnetic variation, "
                            "which a controller may compute itself (E-84)");
       const auto* states = enums::state_list_for_mode(enums::Mode("LOCATE_MODE").value);
       const auto v = states ? states->value_of(look::waiting_state(site.missing)) : std::nullopt;
       if (!v) return error("locate_waiting: no such locate state");
       return number(*v);
     }},
    {{"locate_exit", "'NAME'",
      "the value of a §3.17 locate_exit_conditions name, under the profile's reading of the lost entry "
      "(errata.restore_lost_locate_exit, E-28)"},
     1,
     [](const Call& c) {
       if (c.args[0].is_number) return error("locate_exit: argument 1 must be a name in quotes: 'LOCATE_FUNCTION_COMPLETED'");
       const auto* exits = enums::exit_list_for_mode(enums::Mode("LOCATE_MODE").value,
                                                     enums::EnumReading{c.cx.profile.restore_lost_locate_exit});
       const auto v = exits ? exits->value_of(c.args[0].text) : std::nullopt;
       if (!v) return error("locate_exit: " + c.args[0].text + " is not in locate_exit_conditions");
       return number(*v);
     }},
};

const Function* find_function(std::string_view name) {
  for (const auto& f : kFunctions)
    if (f.doc.name == name) return &f;
  return nullptr;
}

// ---- the parser -----------------------------------------------------------------

bool is_name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_name_char(char c) { return is_name_start(c) || (c >= '0' && c <= '9'); }

class Parser {
 public:
  Parser(std::string_view s, const ExprContext& cx) : s_(s), cx_(cx) {}

  Result parse() {
    Result r = sum();
    if (!r.ok() && r.kind == Kind::kError) return r;
    skip_blanks();
    if (pos_ < s_.size()) return error("unexpected '" + std::string(1, s_[pos_]) + "' at character " + std::to_string(pos_ + 1));
    return r;
  }

  std::set<std::string> captures_read;

 private:
  void skip_blanks() {
    while (pos_ < s_.size() && s_[pos_] == ' ') ++pos_;
  }
  bool eat(char c) {
    skip_blanks();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  std::string name() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && is_name_char(s_[pos_])) ++pos_;
    return std::string(s_.substr(start, pos_ - start));
  }

  // An unavailable or failed operand decides the result; an error wins
  // over unavailability (it is the vector's bug).
  static std::optional<Result> first_problem(const Result& a, const Result& b) {
    if (a.kind == Kind::kError) return a;
    if (b.kind == Kind::kError) return b;
    if (!a.ok()) return a;
    if (!b.ok()) return b;
    return std::nullopt;
  }

  Result arithmetic(char op, const Result& a, const Result& b) {
    if (auto p = first_problem(a, b)) return *p;
    if (!a.value.is_number || !b.value.is_number)
      return error(std::string("'") + op + "' needs numbers, got " + (a.value.is_number ? b : a).value.text);
    switch (op) {
      case '+': return finite(a.value.number + b.value.number);
      case '-': return finite(a.value.number - b.value.number);
      case '*': return finite(a.value.number * b.value.number);
      default:
        if (b.value.number == 0) return error("division by zero");
        return finite(a.value.number / b.value.number);
    }
  }
  static Result finite(double x) { return std::isfinite(x) ? number(x) : error("a number too large (overflow)"); }

  // sum = product {('+' | '-') product}; product = unary {('*' | '/') unary}:
  // left-associative, products first.
  Result sum() { return operations('+', '-', &Parser::product); }
  Result product() { return operations('*', '/', &Parser::unary); }
  Result operations(char op1, char op2, Result (Parser::*operand)()) {
    Result r = (this->*operand)();
    while (true) {
      const char op = eat(op1) ? op1 : eat(op2) ? op2 : '\0';
      if (op == '\0') return r;
      r = arithmetic(op, r, (this->*operand)());
    }
  }
  Result unary() {
    if (eat('-')) return arithmetic('-', number(0), unary());
    return primary();
  }

  Result capture() {
    const std::string n = "$" + name();
    if (n.size() == 1) return error("'$' must be followed by a capture name");
    captures_read.insert(n);
    if (!cx_.captures) return number(0);  // static check: the value is known at run time only
    const auto it = cx_.captures->find(n);
    if (it == cx_.captures->end()) return error("no value captured as " + n);
    if (auto v = captured_number(it->second)) {
      Result r = number(*v);
      r.value.text = it->second;  // as read, for text(): only as_read_text() reads a number's text
      return r;
    }
    return text(it->second);
  }

  Result call(const std::string& fname) {
    const Function* f = find_function(fname);
    if (!f) return error("unknown function " + fname + "() (sabus vectors functions lists them)");
    std::vector<Result> results;
    if (!eat(')')) {
      do results.push_back(sum());
      while (eat(','));
      if (!eat(')')) return error("expected ')' after the arguments of " + fname + "()");
    }
    if (results.size() != f->arity)
      return error(fname + "() takes " + std::to_string(f->arity) + " argument(s) (" + std::string(f->doc.arguments) +
                   "), got " + std::to_string(results.size()));
    Args args;
    for (const auto& r : results) {
      if (r.kind == Kind::kError) return r;
    }
    for (const auto& r : results) {
      if (!r.ok()) return r;
      args.push_back(r.value);
    }
    return f->eval(Call{cx_, args, f->doc.name});
  }

  Result primary() {
    skip_blanks();
    if (pos_ >= s_.size()) return error("expected a value at the end");
    const char c = s_[pos_];
    if (c == '(') {
      ++pos_;
      Result r = sum();
      if (!eat(')')) return error("expected ')' at character " + std::to_string(pos_ + 1));
      return r;
    }
    if (c == '$') {
      ++pos_;
      return capture();
    }
    if (c == '\'') {  // a text: 'SABUS TEST'
      const std::size_t close = s_.find('\'', pos_ + 1);
      if (close == std::string_view::npos) return error("the text at character " + std::to_string(pos_ + 1) + " has no closing '");
      const std::string t(s_.substr(pos_ + 1, close - pos_ - 1));
      pos_ = close + 1;
      return text(t);
    }
    if (c == '0' && pos_ + 1 < s_.size() && (s_[pos_ + 1] == 'x' || s_[pos_ + 1] == 'X')) {  // 0x31
      unsigned v = 0;
      const auto [end, ec] = std::from_chars(s_.data() + pos_ + 2, s_.data() + s_.size(), v, 16);
      if (ec != std::errc() || end == s_.data() + pos_ + 2) return error("bad hex number at character " + std::to_string(pos_ + 1));
      pos_ = static_cast<std::size_t>(end - s_.data());
      return number(v);
    }
    if ((c >= '0' && c <= '9') || c == '.') {
      double v = 0;
      const auto [end, ec] = std::from_chars(s_.data() + pos_, s_.data() + s_.size(), v);
      if (ec != std::errc()) return error("bad number at character " + std::to_string(pos_ + 1));
      pos_ = static_cast<std::size_t>(end - s_.data());
      return number(v);
    }
    if (is_name_start(c)) {
      const std::string n = name();
      if (eat('(')) return call(n);
      return text(n);  // a symbol: az, F, presets
    }
    return error("unexpected '" + std::string(1, c) + "' at character " + std::to_string(pos_ + 1));
  }

  std::string_view s_;
  const ExprContext& cx_;
  std::size_t pos_ = 0;
};

// Calls `f` on each placeholder's expression; literal text goes to `literal`.
// Returns the first error of the template's own syntax ("{" unclosed).
template <class Literal, class Placeholder>
std::optional<std::string> scan_template(std::string_view text, Literal literal, Placeholder placeholder) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if ((c == '{' || c == '}') && i + 1 < text.size() && text[i + 1] == c) {
      literal(c);
      ++i;
    } else if (c == '{') {
      const std::size_t close = text.find('}', i);
      if (close == std::string_view::npos) return "the placeholder at character " + std::to_string(i + 1) + " has no closing '}'";
      if (auto e = placeholder(text.substr(i + 1, close - i - 1))) return e;
      i = close;
    } else if (c == '}') {
      return "a '}' at character " + std::to_string(i + 1) + " closes no placeholder (write }} for a brace)";
    } else {
      literal(c);
    }
  }
  return std::nullopt;
}

Profile& static_profile() {
  static Profile p;
  return p;
}

}  // namespace

std::string format_number(double x) {
  char buf[64];
  // Beyond any field's digits (or not finite): exponent notation, which no
  // field reads, rather than llround's unspecified result.
  if (!(std::abs(x) < 1e15)) {
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
  }
  if (std::abs(x - std::round(x)) < 1e-9) return std::to_string(std::llround(x));
  std::snprintf(buf, sizeof buf, "%.6f", x);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

std::string literal_template(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (c == '{' || c == '}') out += c;
    out += c;
  }
  return out;
}

bool has_placeholder(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{') continue;
    if (i + 1 < text.size() && text[i + 1] == '{') ++i;
    else return true;
  }
  return false;
}

Expansion expand_template(std::string_view text, const ExprContext& cx) {
  std::string out;
  Expansion problem{Kind::kValue, {}};
  auto e = scan_template(
      text, [&](char c) { out.push_back(c); },
      [&](std::string_view expr) -> std::optional<std::string> {
        if (!problem.ok()) return std::nullopt;
        Parser p(expr, cx);
        const Result r = p.parse();
        if (r.kind == Kind::kError) return "{" + std::string(expr) + "}: " + r.message;
        if (!r.ok()) problem = {r.kind, r.message};
        else out += r.value.is_number ? format_number(r.value.number) : r.value.text;
        return std::nullopt;
      });
  if (e) return {Kind::kError, *e};
  if (!problem.ok()) return problem;
  return {Kind::kValue, out};
}

Number expand_number(std::string_view text, const ExprContext& cx) {
  const Expansion e = expand_template(text, cx);
  if (!e.ok()) return {e.kind, 0, e.text};
  if (auto v = parse_double(e.text); v && e.text.find_first_not_of(" +-.0123456789eE") == std::string::npos)
    return {Kind::kValue, *v, {}};
  return {Kind::kError, 0, "\"" + std::string(text) + "\" gives \"" + e.text + "\", not a number"};
}

Count count_in(double value, long long lo, long long hi) {
  const double whole = std::trunc(value);
  if (std::isfinite(whole) && whole >= static_cast<double>(lo) && whole <= static_cast<double>(hi))
    return {static_cast<long long>(whole), std::nullopt};
  return {0, format_number(value) + " is out of range " + std::to_string(lo) + " to " + std::to_string(hi)};
}

// A bare name ("{adr}") is a symbol, which only a function takes: as a whole
// placeholder it is a typo.
bool is_bare_name(std::string_view expr) {
  while (!expr.empty() && expr.front() == ' ') expr.remove_prefix(1);
  while (!expr.empty() && expr.back() == ' ') expr.remove_suffix(1);
  return !expr.empty() && is_name_start(expr.front()) && std::all_of(expr.begin(), expr.end(), is_name_char);
}

std::optional<std::string> check_template(std::string_view text, const std::set<std::string>& captured) {
  const ExprContext cx{static_profile(), nullptr, {}};
  return scan_template(
      text, [](char) {},
      [&](std::string_view expr) -> std::optional<std::string> {
        if (is_bare_name(expr))
          return "unknown placeholder {" + std::string(expr) + "}: a name alone is not a value (sabus vectors functions lists the functions)";
        Parser p(expr, cx);
        const Result r = p.parse();
        if (r.kind == Kind::kError) return "{" + std::string(expr) + "}: " + r.message;
        for (const auto& c : p.captures_read)
          if (!captured.count(c)) return "{" + std::string(expr) + "}: " + c + " is not captured by an earlier step";
        return std::nullopt;
      });
}

std::set<std::string> template_captures(std::string_view text) {
  std::set<std::string> out;
  const ExprContext cx{static_profile(), nullptr, {}};
  (void)scan_template(
      text, [](char) {},
      [&](std::string_view expr) -> std::optional<std::string> {
        Parser p(expr, cx);
        (void)p.parse();
        out.insert(p.captures_read.begin(), p.captures_read.end());
        return std::nullopt;
      });
  return out;
}

std::vector<ExprFunction> expression_functions() {
  std::vector<ExprFunction> out;
  for (const auto& f : kFunctions) out.push_back(f.doc);
  return out;
}

}  // namespace sabus::harness
