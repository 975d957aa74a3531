// Device profiles in YAML (vectors/profiles/README.md is the schema): the
// loader, which rejects a bad file with the key's line and column. The
// writer (to_yaml, profile_writer.cpp) writes what it reads back to an equal
// profile; the names both spell enumerations with are profile_tables.hpp.
//
// The strict reading itself (marks, duplicate keys, scalars without as<T>(),
// the stray-',' guard) is yaml_reader.hpp, shared with the vector loader.
#include "sabus/harness/profile_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <span>
#include <tuple>

#include "profile_tables.hpp"
#include "sabus/harness/data_dir.hpp"
#include "sabus/harness/yaml_reader.hpp"
#include "sabus/protocol/frame.hpp"

namespace sabus::harness {
namespace {

using namespace yaml_reader;
using namespace profile_internal;

// ---------------------------------------------------------------------------
// Limits
// ---------------------------------------------------------------------------

// A profile is a few kilobytes; anything near this is not a profile, and the
// cap bounds what yaml-cpp allocates for a hostile input.
constexpr std::size_t kMaxProfileBytes = 1 << 20;
constexpr std::size_t kMaxProfileName = 100;
constexpr std::size_t kMaxStore = 50;      // §3.6 "A maximum of 50 satellites"
constexpr std::size_t kMaxPresets = 20;    // §3.10 index 1-20
constexpr std::size_t kMaxTles = 10;       // §3.12 index 1-10
constexpr std::size_t kMaxSignposts = 20;  // §3.20 index 1-20
constexpr std::size_t kTleLine = 69;       // §3.12 "69 characters (including checksum)", E-19
// Positions as the 6-character fields of §3.2 carry them (E-12), with room for
// a fluxgate azimuth of 0.0-359.9 (§3.2 NOTE).
constexpr double kPositionMin = -180.0, kPositionMax = 360.0;
// A real mount's axis moves through at least this many degrees.
constexpr double kMinAxisSpan = 10.0;
constexpr double kMaxSpeed = 1000.0;      // deg/s
constexpr double kMaxAccel = 10000.0;     // deg/s^2
// Slower is no mount's; and the times derived from a speed or a ramp (a
// full-range move at the slow speed, motion::longest_move) must stay finite
// and fit in milliseconds.
constexpr double kMinSpeed = 0.001, kMinAccel = 0.001;
// How close an auto move stops to its target, the display's 0.1 deg included.
constexpr double kToleranceMin = 0.1, kToleranceMax = 5.0;
constexpr std::size_t kDisplayRows = 4, kDisplayColumns = 40;  // §3.8 the 4x40 LCD

// ---------------------------------------------------------------------------
// Scalars
// ---------------------------------------------------------------------------

double to_number_in(const YAML::Node& v, const At& at, double lo, double hi) {
  double d = to_number(v, at);
  if (d < lo || d > hi) fail(at, number_text(d) + " is out of range " + number_text(lo) + " to " + number_text(hi));
  return d;
}

// Greater than 0, and at least `least` when that is given.
double to_positive(const YAML::Node& v, const At& at, double hi, double least = 0) {
  double d = to_number(v, at);
  if (d <= 0) fail(at, "must be greater than 0, got " + number_text(d));
  if (d < least) fail(at, "must be at least " + number_text(least) + ", got " + number_text(d));
  if (d > hi) fail(at, number_text(d) + " is out of range: at most " + number_text(hi));
  return d;
}

// Fields carried in tenths on the wire (§3.10 "-179.9", §3.22 "ddd.d"): a
// second decimal would be lost, so it is an error rather than rounded away.
std::int32_t to_tenths(const YAML::Node& v, const At& at, double lo, double hi) {
  double d = to_number_in(v, at, lo, hi);
  double t = d * 10;
  double r = std::round(t);
  if (std::fabs(t - r) > 1e-6) fail(at, number_text(d) + " has more than one decimal place (the field holds tenths)");
  return static_cast<std::int32_t>(r);
}

// Optional wire fields (a blank field in the reply): YAML null is "no value".
std::optional<std::int32_t> to_opt_tenths(const YAML::Node& v, const At& at, double lo, double hi) {
  if (v.IsNull()) return std::nullopt;
  return to_tenths(v, at, lo, hi);
}
std::optional<std::int32_t> to_opt_integer(const YAML::Node& v, const At& at, long long lo, long long hi) {
  if (v.IsNull()) return std::nullopt;
  return static_cast<std::int32_t>(to_integer_in(v, at, lo, hi));
}

bool is_field_char(char c) { return c >= 0x20 && c <= 0x7E; }  // §1 Data Format, 7Fh excluded (E-18 marker)

// Text for a left-justified, blank-padded field (§3.6, E-33): printable, at
// most `max` characters, and no trailing blank (the padding would swallow it).
std::string to_field_text(const YAML::Node& v, const At& at, std::size_t min, std::size_t max) {
  const std::string& s = scalar(v, at, "text");
  if (s.size() < min || s.size() > max)
    fail(at, quoted_clip(s) + " has " + std::to_string(s.size()) + " characters, expected " +
                 (min == max ? std::to_string(min) : std::to_string(min) + " to " + std::to_string(max)));
  if (!std::all_of(s.begin(), s.end(), is_field_char))
    fail(at, quoted_clip(s) + " has a character outside printable ASCII 0x20-0x7e");
  if (min != max && !s.empty() && s.back() == ' ') fail(at, quoted_clip(s) + " ends in a blank (the field is blank-padded)");
  return s;
}

// A satellite name as the controller holds and shows it: §3.2 "in upper
// case letters", §3.6 "in capital letters" (ERRATA E-68).
std::string to_capitals_name(const YAML::Node& v, const At& at, std::size_t min) {
  std::string s = to_field_text(v, at, min, 10);
  if (std::any_of(s.begin(), s.end(), [](char c) { return c >= 'a' && c <= 'z'; }))
    fail(at, quoted_clip(s) + " has lower-case letters; the controller holds names in capitals (§3.2, §3.6, ERRATA E-68)");
  return s;
}

template <class T, std::size_t N>
T to_choice(const YAML::Node& v, const At& at, const Named<T> (&table)[N]) {
  const std::string& s = scalar(v, at, "one of " + names_of(table));
  for (const auto& n : table)
    if (n.name == s) return n.value;
  fail(at, quoted_clip(s) + " is not one of " + names_of(table));
}

// The protocol's own tables of one-character fields (messages.hpp), read by
// their meaning ("Ku", "TLE", "7/8") or by the character itself ("H").
std::string meanings_of(std::span<const fields::ChoiceItem> items, bool by_char) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + (by_char ? std::string(1, i.ch) : std::string(i.meaning));
  return out;
}
char to_item(const YAML::Node& v, const At& at, std::span<const fields::ChoiceItem> items, bool by_char) {
  const std::string& s = scalar(v, at, "one of " + meanings_of(items, by_char));
  for (const auto& i : items)
    if (by_char ? s == std::string_view(&i.ch, 1) : s == i.meaning) return i.ch;
  fail(at, quoted_clip(s) + " is not one of " + meanings_of(items, by_char));
}

int to_baud(const YAML::Node& v, const At& at) {
  auto n = to_integer_in(v, at, 0, 1'000'000);
  if (std::find(std::begin(kBauds), std::end(kBauds), n) == std::end(kBauds))
    fail(at, std::to_string(n) + " is not one of 300, 600, 1200, 2400, 4800, 9600 (ERRATA E-2)");
  return static_cast<int>(n);
}

// §3.1 "A.BC".
std::string to_firmware(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a version \"A.BC\"");
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (s.size() != 4 || !digit(s[0]) || s[1] != '.' || !digit(s[2]) || !digit(s[3]))
    fail(at, "expected a version \"A.BC\" (§3.1), got " + quoted_clip(s));
  return s;
}

// §3.22 "dd.mm(N/S)" / "ddd.mm(E/W)": degrees, two-digit minutes, a blank
// and the hemisphere, as the controller displays them. Stored as signed
// minutes, south and west negative (§3.23 sddmm).
std::optional<std::int32_t> to_minutes(const YAML::Node& v, const At& at, int max_deg, char pos, char neg) {
  if (v.IsNull()) return std::nullopt;
  std::string form = max_deg == 90 ? "\"dd.mm N\" or \"dd.mm S\"" : "\"ddd.mm E\" or \"ddd.mm W\"";
  const std::string& s = scalar(v, at, form);
  auto bad = [&] { fail(at, "expected " + form + " (degrees.minutes, §3.22), got " + quoted_clip(s)); };
  std::size_t dot = s.find('.');
  if (dot == std::string::npos || dot == 0 || dot > 3 || s.size() != dot + 5 || s[dot + 3] != ' ') bad();
  int deg = 0, min = 0;
  if (!parse_whole(std::string_view(s).substr(0, dot), deg) || !parse_whole(std::string_view(s).substr(dot + 1, 2), min))
    bad();
  char hemi = s.back();
  if ((hemi != pos && hemi != neg) || s[0] == '-' || s[0] == '+' || s[dot + 1] == '-' || s[dot + 1] == '+') bad();
  if (min > 59) fail(at, "minutes " + std::to_string(min) + " are out of range 0 to 59");
  if (deg * 60 + min > max_deg * 60) fail(at, quoted_clip(s) + " is beyond " + std::to_string(max_deg) + " degrees");
  return hemi == neg ? -(deg * 60 + min) : deg * 60 + min;
}

// §3.22 sources: a name, or the raw 3-bit code 1-7.
template <std::size_t N>
std::uint8_t to_source(const YAML::Node& v, const At& at, const Named<std::uint8_t> (&table)[N]) {
  const std::string& s = scalar(v, at, "a source");
  long long n = 0;
  if (v.Tag() != "!" && parse_whole(s, n)) return static_cast<std::uint8_t>(to_integer_in(v, at, 1, 7));
  return to_choice(v, at, table);
}

// ---------------------------------------------------------------------------
// Maps and lists
// ---------------------------------------------------------------------------

// Index keys of the indexed lists: in range and unique within the list.
class IndexSet {
 public:
  IndexSet(int lo, int hi) : lo_(lo), hi_(hi) {}
  std::uint8_t take(const YAML::Node& v, const At& at) {
    auto n = static_cast<int>(to_integer_in(v, at, lo_, hi_));
    if (seen_[static_cast<std::size_t>(n)]) fail(at, "index " + std::to_string(n) + " is used twice");
    seen_[static_cast<std::size_t>(n)] = true;
    return static_cast<std::uint8_t>(n);
  }

 private:
  int lo_, hi_;
  std::array<bool, 256> seen_{};
};

// ---------------------------------------------------------------------------
// Sections
// ---------------------------------------------------------------------------

// Where each axis's range was given, for the rules that need other keys.
struct AxisRanges {
  std::optional<At> az, el, pol;
};

// Reads into `axis` so that an absent key keeps that axis's own default;
// `range` is where its range was given.
void read_axis(const YAML::Node& v, const At& at, AxisProfile& axis, std::optional<At>& range_at) {
  MapReader r(v, at,
              {"fast_dps", "slow_dps", "min_deg", "max_deg", "initial_deg", "has_stow_limit", "stow_deg", "deploy_deg",
               "tolerance_deg", "accel_dps2", "power_on_speed", "ad_error"});
  auto position = [](const YAML::Node& n, const At& a) { return to_number_in(n, a, kPositionMin, kPositionMax); };
  auto speed = [](const YAML::Node& n, const At& a) { return to_positive(n, a, kMaxSpeed, kMinSpeed); };
  r.read("fast_dps", axis.fast_dps, speed);
  r.read("slow_dps", axis.slow_dps, speed);
  r.read("min_deg", axis.min_deg, position);
  r.read("max_deg", axis.max_deg, position);
  r.read("initial_deg", axis.initial_deg, position);
  r.read("has_stow_limit", axis.has_stow_limit, to_bool);
  r.read("stow_deg", axis.stow_deg, position);
  r.read("deploy_deg", axis.deploy_deg, [&](const YAML::Node& n, const At& a) -> std::optional<double> {
    if (n.IsNull()) return std::nullopt;  // not stated
    return position(n, a);
  });
  r.read("tolerance_deg", axis.tolerance_deg,
         [](const YAML::Node& n, const At& a) { return to_number_in(n, a, kToleranceMin, kToleranceMax); });
  r.read("accel_dps2", axis.accel_dps2, [](const YAML::Node& n, const At& a) -> std::optional<double> {
    if (n.IsNull()) return std::nullopt;  // none: the axis reaches its speed at once
    return to_positive(n, a, kMaxAccel, kMinAccel);
  });
  r.read("power_on_speed", axis.power_on_speed, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kAxisSpeeds); });
  r.read("ad_error", axis.ad_error, to_bool);
  if (axis.slow_dps > axis.fast_dps)
    fail(r.at(r.has("slow_dps") ? "slow_dps" : "fast_dps"),
         "slow_dps " + number_text(axis.slow_dps) + " is above fast_dps " + number_text(axis.fast_dps));
  // Reaching a limit asserts its limit bit (§3.2 bytes 32-34): min below max,
  // and the power-on and stow positions between them.
  const At range = r.at(r.has("max_deg") ? "max_deg" : "min_deg");
  range_at = range;
  if (axis.min_deg >= axis.max_deg)
    fail(range, "min_deg " + number_text(axis.min_deg) + " must be below max_deg " + number_text(axis.max_deg));
  // 1e-9: -61.6 - -71.6 is 9.999999999999993 in doubles, a span of 10.
  if (axis.max_deg - axis.min_deg < kMinAxisSpan - 1e-9)
    fail(range, "min_deg " + number_text(axis.min_deg) + " to max_deg " + number_text(axis.max_deg) + " spans less than " +
                    number_text(kMinAxisSpan) + " degrees (a real mount's axis)");
  auto inside = [&](double d) { return d >= axis.min_deg && d <= axis.max_deg; };
  if (!inside(axis.initial_deg))
    fail(r.at("initial_deg"), "initial_deg " + number_text(axis.initial_deg) + " is outside min_deg..max_deg");
  if (axis.has_stow_limit && !inside(axis.stow_deg))
    fail(r.at("stow_deg"), "stow_deg " + number_text(axis.stow_deg) + " is outside min_deg..max_deg");
  if (axis.deploy_deg && !inside(*axis.deploy_deg))
    fail(r.at("deploy_deg"), "deploy_deg " + number_text(*axis.deploy_deg) + " is outside min_deg..max_deg");
}

void read_axes(const YAML::Node& v, const At& at, Profile& p, AxisRanges& ranges) {
  MapReader r(v, at, {"az", "el", "pol"});
  r.with("az", [&](const YAML::Node& n, const At& a) { read_axis(n, a, p.az, ranges.az); });
  r.with("el", [&](const YAML::Node& n, const At& a) { read_axis(n, a, p.el, ranges.el); });
  r.with("pol", [&](const YAML::Node& n, const At& a) { read_axis(n, a, p.pol, ranges.pol); });
}

// §3.2 bytes 14-31: a position field shows -180.0 to 180.0; only an azimuth
// read from the fluxgate compass shows 0.0-359.9 (§3.2 NOTE).
void check_shown_ranges(const Profile& p, const AxisRanges& ranges, const At& axes) {
  const std::tuple<const char*, const AxisProfile*, const std::optional<At>*> all[] = {
      {"az", &p.az, &ranges.az}, {"el", &p.el, &ranges.el}, {"pol", &p.pol, &ranges.pol}};
  for (const auto& [name, axis, at] : all) {
    const bool heading = axis == &p.az && p.az_sensor == AzSensor::kFluxgate;
    if (axis->max_deg > 180.0 && !heading)
      fail(at->value_or(axes), std::string(name) + " max_deg " + number_text(axis->max_deg) +
                                   " is beyond 180, the most a position field shows (§3.2); only a fluxgate "
                                   "azimuth (azimuth_sensor: fluxgate) reads up to 359.9");
  }
}

// §3.6: names are unique (a STORE of an existing name overwrites it, §3.19).
void read_store(const YAML::Node& v, const At& at, Profile& p) {
  p.store.clear();
  for_each_element(v, at, kMaxStore, [&](const YAML::Node& e, const At& ea) {
    MapReader r(e, ea, {"name", "az_deg", "el_deg", "h_pol_deg", "v_pol_deg"});
    StoredSatellite s;
    auto position = [](const YAML::Node& n, const At& a) { return to_number_in(n, a, kPositionMin, kPositionMax); };
    if (!r.has("name")) fail(ea, "a STORE entry needs a name");
    r.read("name", s.name, [](const YAML::Node& n, const At& a) { return to_capitals_name(n, a, 1); });
    r.read("az_deg", s.az_deg, position);
    r.read("el_deg", s.el_deg, position);
    r.read("h_pol_deg", s.h_pol_deg, position);
    r.read("v_pol_deg", s.v_pol_deg, position);
    for (const auto& other : p.store)
      if (other.name == s.name) fail(r.at("name"), "name " + quoted_clip(s.name) + " is stored twice");
    p.store.push_back(std::move(s));
  });
}

// §3.10 field ranges.
void read_presets(const YAML::Node& v, const At& at, Profile& p) {
  p.presets.clear();
  IndexSet indexes(1, static_cast<int>(kMaxPresets));
  for_each_element(v, at, kMaxPresets, [&](const YAML::Node& e, const At& ea) {
    MapReader r(e, ea, {"index", "name", "longitude", "inclination", "band", "ephemeris", "pol_offset", "dual_band"});
    if (!r.has("index")) fail(ea, "a preset needs an index (1-20)");
    PresetSatellite s;
    SatelliteData& d = s.data;
    r.with("index", [&](const YAML::Node& n, const At& a) { s.index = indexes.take(n, a); });
    r.read("name", d.name, [](const YAML::Node& n, const At& a) { return to_field_text(n, a, 0, 10); });
    r.read("longitude", d.longitude, [](const YAML::Node& n, const At& a) { return to_opt_tenths(n, a, -179.9, 179.9); });
    r.read("inclination", d.inclination, [](const YAML::Node& n, const At& a) { return to_opt_integer(n, a, 0, 19); });
    r.read("band", d.band, [](const YAML::Node& n, const At& a) { return to_item(n, a, layouts::kBands, false); });
    r.read("ephemeris", d.ephemeris,
           [](const YAML::Node& n, const At& a) { return to_item(n, a, layouts::kEphemeris, false); });
    r.read("pol_offset", d.pol_offset, [](const YAML::Node& n, const At& a) { return to_opt_tenths(n, a, -90, 90); });
    r.read("dual_band", s.dual_band, to_bool);
    p.presets.push_back(std::move(s));
  });
}

// §3.12: two lines of 69 characters each; the checksum digit is not checked
// here, a profile may hold a bad one on purpose (ERRATA E-19).
void read_tles(const YAML::Node& v, const At& at, Profile& p) {
  p.tles.clear();
  IndexSet indexes(1, static_cast<int>(kMaxTles));
  for_each_element(v, at, kMaxTles, [&](const YAML::Node& e, const At& ea) {
    MapReader r(e, ea, {"index", "line1", "line2"});
    TleSet t;
    r.with("index", [&](const YAML::Node& n, const At& a) { t.index = indexes.take(n, a); });
    for (auto key : {"index", "line1", "line2"})
      if (!r.has(key)) fail(ea, std::string("a TLE set needs ") + key);
    auto line = [](const YAML::Node& n, const At& a) { return to_field_text(n, a, kTleLine, kTleLine); };
    r.read("line1", t.line1, line);
    r.read("line2", t.line2, line);
    p.tles.push_back(std::move(t));
  });
}

// §3.20 field ranges; priority 0-9 (ERRATA E-23).
void read_signposts(const YAML::Node& v, const At& at, Profile& p) {
  p.signposts.clear();
  IndexSet indexes(1, static_cast<int>(kMaxSignposts));
  for_each_element(v, at, kMaxSignposts, [&](const YAML::Node& e, const At& ea) {
    MapReader r(e, ea, {"index", "longitude", "frequency", "symbol_rate", "fec", "polarization", "id", "priority"});
    if (!r.has("index")) fail(ea, "a signpost needs an index (1-20)");
    Signpost s;
    SignpostData& d = s.data;
    r.with("index", [&](const YAML::Node& n, const At& a) { s.index = indexes.take(n, a); });
    r.read("longitude", d.longitude, [](const YAML::Node& n, const At& a) { return to_opt_tenths(n, a, -179.9, 180); });
    r.read("frequency", d.frequency, [](const YAML::Node& n, const At& a) { return to_opt_integer(n, a, 10700, 12750); });
    r.read("symbol_rate", d.symbol_rate,
           [](const YAML::Node& n, const At& a) { return to_opt_integer(n, a, 1000, 30000); });
    r.read("fec", d.fec, [](const YAML::Node& n, const At& a) { return to_item(n, a, layouts::kFec, false); });
    r.read("polarization", d.polarization,
           [](const YAML::Node& n, const At& a) { return to_item(n, a, layouts::kSignpostPol, true); });
    r.read("id", d.id, [](const YAML::Node& n, const At& a) { return to_field_text(n, a, 0, 6); });
    r.read("priority", d.priority,
           [](const YAML::Node& n, const At& a) { return static_cast<std::uint32_t>(to_integer_in(n, a, 0, 9)); });
    p.signposts.push_back(std::move(s));
  });
}

// §3.22 fields.
void read_navigation(const YAML::Node& v, const At& at, Navigation& nav) {
  MapReader r(v, at, {"latlon_source", "latitude", "longitude", "heading_source", "heading", "magvar"});
  r.read("latlon_source", nav.latlon_source, [](const YAML::Node& n, const At& a) { return to_source(n, a, kLatLonSources); });
  r.read("latitude", nav.latitude_min, [](const YAML::Node& n, const At& a) { return to_minutes(n, a, 90, 'N', 'S'); });
  r.read("longitude", nav.longitude_min, [](const YAML::Node& n, const At& a) { return to_minutes(n, a, 180, 'E', 'W'); });
  r.read("heading_source", nav.heading_source,
         [](const YAML::Node& n, const At& a) { return to_source(n, a, kHeadingSources); });
  r.read("heading", nav.heading_tenths, [](const YAML::Node& n, const At& a) { return to_opt_tenths(n, a, 0, 359.9); });
  r.read("magvar", nav.magvar_tenths, [](const YAML::Node& n, const At& a) { return to_opt_tenths(n, a, -99.9, 99.9); });
}

void read_track(const YAML::Node& v, const At& at, TrackProfile& track) {
  MapReader r(v, at, {"active", "activity", "band", "dual_band"});
  r.read("active", track.active, to_bool);
  r.read("activity", track.activity, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kTrackActivities); });
  r.read("band", track.band, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kTrackBands); });
  r.read("dual_band", track.dual_band, to_bool);
  // ERRATA E-70: a dual-band satellite is a C/Ku one (§3.10 band 2); the
  // 'T' band change of §3.7 switches between C and K(u).
  if (track.dual_band && track.band != TrackBand::kC && track.band != TrackBand::kKu)
    fail(r.at(r.has("dual_band") ? "dual_band" : "band"),
         "a dual-band satellite is tracked in C or Ku band, not " + std::string(name_of(kTrackBands, track.band)) + " (ERRATA E-70)");
}

// §3.2 bytes 3-12 and 35 ZZZ; §3.8 bytes 163-166.
void read_display(const YAML::Node& v, const At& at, DisplayProfile& d) {
  MapReader r(v, at, {"satellite", "pol_code", "cursor_row", "cursor_column", "cursor_blinking"});
  r.read("satellite", d.satellite, [](const YAML::Node& n, const At& a) { return to_capitals_name(n, a, 0); });
  r.read("pol_code", d.pol_code, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kPolCodes); });
  r.read("cursor_row", d.cursor_row, [](const YAML::Node& n, const At& a) {
    return static_cast<std::uint8_t>(to_integer_in(n, a, 1, kDisplayRows));
  });
  r.read("cursor_column", d.cursor_column, [](const YAML::Node& n, const At& a) {
    return static_cast<std::uint8_t>(to_integer_in(n, a, 0, kDisplayColumns - 1));
  });
  r.read("cursor_blinking", d.cursor_blinking, to_bool);
}

void read_alarms(const YAML::Node& v, const At& at, AlarmProfile& alarms) {
  MapReader r(v, at, {"az", "el", "pol", "code"});
  auto axis = [](const YAML::Node& n, const At& a) { return to_choice(n, a, kAxisAlarms); };
  r.read("az", alarms.az, axis);
  r.read("el", alarms.el, axis);
  r.read("pol", alarms.pol, axis);
  // §3.2 byte 38: off axis and drive alarms are "not currently supported" for polarization.
  if (alarms.pol == 8 || alarms.pol == 12)
    fail(r.at("pol"), "a polarization axis does not report the " + std::string(name_of(kAxisAlarms, alarms.pol)) +
                          " alarm (§3.2 byte 38: not currently supported)");
  // §3.2 byte 39: A5..A0.
  r.read("code", alarms.code, [](const YAML::Node& n, const At& a) { return static_cast<std::uint8_t>(to_integer_in(n, a, 0, 63)); });
}

// The *profile* switches of protocol/ERRATA.md.
void read_errata(const YAML::Node& v, const At& at, Profile& p) {
  MapReader r(v, at,
              {"stx_restarts_in_data", "unknown_command_while_offline", "implements_signal_strength", "implements_iess",
               "nak_bad_tle_checksum", "locate_index_min", "locate_index_max", "restore_lost_locate_exit"});
  // E-22: the locate text says 0-19, the rest 1-20; a profile may take either.
  auto locate_index = [](const YAML::Node& n, const At& a) { return static_cast<std::uint8_t>(to_integer_in(n, a, 0, 20)); };
  r.read("stx_restarts_in_data", p.stx_restarts_in_data, to_bool);  // E-7
  r.read("unknown_command_while_offline", p.unknown_command_while_offline,
         [](const YAML::Node& n, const At& a) { return to_choice(n, a, kOfflineUnknown); });  // E-10
  r.read("implements_signal_strength", p.implements_signal_strength, to_bool);  // E-16, E-36
  r.read("implements_iess", p.implements_iess, to_bool);                        // E-16, E-37
  r.read("nak_bad_tle_checksum", p.nak_bad_tle_checksum, to_bool);              // E-19
  r.read("locate_index_min", p.locate_index_min, locate_index);
  r.read("locate_index_max", p.locate_index_max, locate_index);
  r.read("restore_lost_locate_exit", p.restore_lost_locate_exit, to_bool);  // E-28
  if (p.locate_index_min > p.locate_index_max)
    fail(r.at(r.has("locate_index_max") ? "locate_index_max" : "locate_index_min"),
         "locate_index_min " + std::to_string(p.locate_index_min) + " is above locate_index_max " +
             std::to_string(p.locate_index_max));
}

// The sides of the spec's open points this device is pinned to (readings.hpp,
// ERRATA entries of class reading): `E-90: other`.
void read_readings(const YAML::Node& v, const At& at, Profile& p) {
  std::vector<std::string_view> ids;
  for (const ReadingPoint& point : reading_points()) ids.push_back(point.id);
  MapReader r(v, at, ids);
  for (const ReadingPoint& point : reading_points())
    r.with(point.id, [&](const YAML::Node& n, const At& a) {
      const std::string& name = scalar(n, a, sides_named(point));
      const auto side = reading_side_named(name);
      if (!side || !has_side(point, *side)) {
        std::string listed;
        for (ReadingSide s : sides_of(point))
          listed += (listed.empty() ? "" : ", ") + std::string(to_string(s)) + " (" + std::string(side_text(point, s)) + ")";
        fail(a, quoted_clip(name) + " is not a side of " + std::string(point.id) + ": " + listed);
      }
      p.readings[std::string(point.id)] = *side;
    });
}

// §1 multi-drop: the other addresses on the line, one address or a list;
// each distinct and not the profile's own.
void read_bus_peers(const YAML::Node& v, const At& at, Profile& p) {
  auto one = [&](const YAML::Node& n, const At& a) {
    const std::uint8_t peer = to_address(n, a);
    if (peer == p.address) fail(a, "a bus peer cannot have the profile's own address " + std::to_string(peer));
    if (std::find(p.bus_peers.begin(), p.bus_peers.end(), peer) != p.bus_peers.end())
      fail(a, "address " + std::to_string(peer) + " is listed twice");
    p.bus_peers.push_back(peer);
  };
  if (v.IsScalar()) return one(v, at);
  for_each_element(v, at, 62, one);
}

Profile read_profile(const YAML::Node& root) {
  Profile p;
  if (root.IsNull()) return p;  // an empty document: every key at its default
  MapReader r(root, At{"", root.Mark()},
              {"name", "address", "bus_peers", "remote_enabled", "baud", "firmware", "polarization", "azimuth_sensor",
               "fluxgate_heading", "hundredths", "stow", "deploy", "dvb_receiver", "counts_per_degree", "count_offset", "axes",
               "turnaround_ms", "agc", "agc_channel", "display", "store", "presets", "tles", "signposts", "navigation",
               "track", "alarms", "errata", "readings"});
  r.read("name", p.name, [](const YAML::Node& n, const At& a) { return to_field_text(n, a, 1, kMaxProfileName); });
  r.read("address", p.address, to_address);
  r.with("bus_peers", [&](const YAML::Node& n, const At& a) { read_bus_peers(n, a, p); });
  r.read("remote_enabled", p.remote_enabled, to_bool);
  r.read("baud", p.baud, to_baud);
  r.read("firmware", p.firmware, to_firmware);
  r.read("polarization", p.pol_type, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kPolTypes); });
  r.read("azimuth_sensor", p.az_sensor, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kAzSensors); });
  r.read("fluxgate_heading", p.fluxgate_heading,
         [](const YAML::Node& n, const At& a) { return to_choice(n, a, kHeadingReferences); });
  r.read("hundredths", p.hundredths, to_bool);
  r.read("stow", p.stow, to_bool);
  r.read("deploy", p.deploy, to_bool);
  r.read("dvb_receiver", p.dvb_receiver, to_bool);
  r.read("counts_per_degree", p.counts_per_degree, [](const YAML::Node& n, const At& a) { return to_positive(n, a, 99999); });
  // §3.16: five-digit counts.
  r.read("count_offset", p.count_offset,
         [](const YAML::Node& n, const At& a) { return static_cast<std::int32_t>(to_integer_in(n, a, 0, 99999)); });
  AxisRanges ranges;
  r.with("axes", [&](const YAML::Node& n, const At& a) { read_axes(n, a, p, ranges); });
  r.read("turnaround_ms", p.turnaround_ms, [](const YAML::Node& n, const At& a) { return to_number_in(n, a, 0, 60000); });
  // §3.2 bytes 41-43.
  r.read("agc", p.agc, [](const YAML::Node& n, const At& a) { return static_cast<std::uint16_t>(to_integer_in(n, a, 0, 999)); });
  r.read("agc_channel", p.agc_channel, [](const YAML::Node& n, const At& a) { return to_choice(n, a, kAgcChannels); });
  r.with("display", [&](const YAML::Node& n, const At& a) { read_display(n, a, p.display); });
  r.with("store", [&](const YAML::Node& n, const At& a) { read_store(n, a, p); });
  r.with("presets", [&](const YAML::Node& n, const At& a) { read_presets(n, a, p); });
  r.with("tles", [&](const YAML::Node& n, const At& a) { read_tles(n, a, p); });
  r.with("signposts", [&](const YAML::Node& n, const At& a) { read_signposts(n, a, p); });
  r.with("navigation", [&](const YAML::Node& n, const At& a) { read_navigation(n, a, p.navigation); });
  r.with("track", [&](const YAML::Node& n, const At& a) { read_track(n, a, p.track); });
  r.with("alarms", [&](const YAML::Node& n, const At& a) { read_alarms(n, a, p.alarms); });
  r.with("errata", [&](const YAML::Node& n, const At& a) { read_errata(n, a, p); });
  r.with("readings", [&](const YAML::Node& n, const At& a) { read_readings(n, a, p); });
  // §3.20 NOTE / ERRATA E-23: signposts exist only with the DVB receiver option.
  if (!p.signposts.empty() && !p.dvb_receiver)
    fail(r.at("signposts"), "signposts need the DVB receiver option (dvb_receiver: true; §3.20, ERRATA E-23)");
  // ERRATA E-23 other-2: a controller that NAKs priority 0 holds none (what
  // it holds is written back after a vector changes it).
  if (side_pinned(p.readings, "E-23") == ReadingSide::kOther2 &&
      std::any_of(p.signposts.begin(), p.signposts.end(), [](const Signpost& s) { return s.data.priority == 0; }))
    fail(r.at("signposts"), "a signpost of priority 0 on a controller pinned to E-23 other-2, which NAKs priority 0 (§3.20, §3.21)");
  check_shown_ranges(p, ranges, r.at("axes"));
  // §3.2 byte 35: without a rotating feed there is no polarization to show.
  if (p.display.pol_code != 0 && p.pol_type == PolType::kCircular)
    fail(r.at("display"), "a polarization code is displayed only with a rotating feed (polarization: single_port or dual_port)");
  return p;
}

ProfileError make_error(const std::string& file, int line, int column, std::string key, std::string message) {
  return ProfileError{file, line, column, std::move(key), std::move(message)};
}

}  // namespace

std::string ProfileError::text() const {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line) + ":" + std::to_string(column);
  out += ": ";
  if (!key.empty()) out += key + ": ";
  return out + message;
}

ProfileResult load_profile_text(std::string_view yaml, const std::string& name) {
  ProfileResult result;
  if (yaml.size() > kMaxProfileBytes) {
    result.error = make_error(name, 0, 0, "", "larger than " + std::to_string(kMaxProfileBytes) + " bytes");
    return result;
  }
  try {
    const std::string text(yaml);
    require_single_document(text, "a profile");
    result.profile = read_profile(YAML::Load(text));
    result.profile->source = name;
  } catch (const Failure& f) {
    result.error = make_error(name, one_based(f.at.mark.line), one_based(f.at.mark.column), f.at.path, f.message);
  } catch (const YAML::Exception& e) {  // syntax errors, including DeepRecursion
    result.error = make_error(name, one_based(e.mark.line), one_based(e.mark.column), "", "YAML syntax: " + e.msg);
  } catch (const std::exception& e) {  // bad_alloc and anything else: never out of the loader
    result.error = make_error(name, 0, 0, "", std::string("cannot read the profile: ") + e.what());
  }
  return result;
}

ProfileResult load_profile_file(const std::string& path) {
  ProfileResult result;
  std::string error;
  auto text = read_capped(path, kMaxProfileBytes, error);
  if (!text) {
    result.error = make_error(path, 0, 0, "", error);
    return result;
  }
  return load_profile_text(*text, path);
}

std::string default_profile_path() { return data_path("vectors/profiles/rc3000-1.59.yaml"); }

}  // namespace sabus::harness
