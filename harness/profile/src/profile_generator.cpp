// Random legal device profiles (profile_generator.hpp). Each draw names the
// rule of the schema (vectors/profiles/README.md) or the spec it keeps.
#include "sabus/harness/profile_generator.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "profile_tables.hpp"

namespace sabus::harness {
namespace {

using namespace profile_internal;

// Draws from one seed. The engine's output is mapped to ranges here rather
// than by the standard distributions, whose results differ between standard
// libraries: a seed means the same profile everywhere.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}

  bool chance(double p) { return unit() < p; }
  // lo..hi inclusive.
  long long integer(long long lo, long long hi) {
    const auto span = static_cast<std::uint64_t>(hi - lo) + 1;
    return lo + static_cast<long long>(rng_() % span);
  }
  double real(double lo, double hi) { return lo + unit() * (hi - lo); }
  // lo..hi on a log scale: small and large values alike.
  double log_real(double lo, double hi) { return std::exp(real(std::log(lo), std::log(hi))); }
  // A multiple of `step` in lo..hi (both multiples of it).
  double stepped(double lo, double hi, double step) {
    const auto n = static_cast<long long>(std::llround((hi - lo) / step));
    return round_to(lo + static_cast<double>(integer(0, n)) * step, step);
  }
  template <class T>
  T pick(std::initializer_list<T> items) {
    return *(items.begin() + integer(0, static_cast<long long>(items.size()) - 1));
  }
  template <class T>
  const T& pick(std::span<const T> items) {
    return items[static_cast<std::size_t>(integer(0, static_cast<long long>(items.size()) - 1))];
  }
  // How many entries of a list of at most `max`: empty, partly filled or full.
  std::size_t fill(std::size_t max) {
    switch (integer(0, 3)) {
      case 0: return 0;
      case 1: return max;
      default: return static_cast<std::size_t>(integer(1, static_cast<long long>(max)));
    }
  }
  // x to a multiple of `step` (0.1, 0.01: one over a whole number), as the
  // nearest double to the decimal, so the YAML reads "54.3".
  static double round_to(double x, double step) { return std::round(x / step) / std::round(1 / step); }

 private:
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }  // [0, 1)
  std::mt19937_64 rng_;
};

template <class T, std::size_t N>
T pick_value(Draw& d, const Named<T> (&table)[N]) {
  return table[static_cast<std::size_t>(d.integer(0, static_cast<long long>(N) - 1))].value;
}

// ---- text -------------------------------------------------------------------

// Text for a blank-padded field: printable (no 7Fh, E-18), no trailing
// blank (E-33). `alphabet` is what the field may hold.
std::string text(Draw& d, std::size_t min, std::size_t max, std::string_view alphabet) {
  const auto n = static_cast<std::size_t>(d.integer(static_cast<long long>(min), static_cast<long long>(max)));
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += alphabet[static_cast<std::size_t>(d.integer(0, static_cast<long long>(alphabet.size()) - 1))];
  while (!s.empty() && s.back() == ' ') s.back() = alphabet.front();
  return s;
}

// Names as the controller holds them in capitals (§3.2, §3.6, ERRATA E-68);
// a blank inside, rarely first (§3.6: "manually entered blank characters
// before the satellite name").
constexpr std::string_view kCapitals = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 -./&+'#";
// Any printable character, lower case included (the preset list keeps names
// as written, E-68).
std::string printable_alphabet() {
  std::string s;
  for (char c = 'A'; c <= '~'; ++c) s += c;  // starts with a letter: the padding replacement
  for (char c = ' '; c < 'A'; ++c) s += c;
  return s;
}

std::string capitals_name(Draw& d, std::size_t min) { return text(d, min, 10, kCapitals); }

// A name not yet in `taken`.
std::string unique_name(Draw& d, const std::vector<std::string>& taken) {
  for (;;) {
    std::string s = capitals_name(d, 1);
    if (std::find(taken.begin(), taken.end(), s) == taken.end()) return s;
  }
}

// ---- the mount ----------------------------------------------------------------

// Positions in the loader's range (-180 to 360, E-12), spans of at least 10
// degrees (a real mount's axis).
struct Range {
  double min, max;
};

// §3.2 bytes 14-31 show -180.0 to 180.0; a fluxgate azimuth 0.0 to 359.9
// (NOTE).
Range az_range(Draw& d, AzSensor sensor) {
  const double top = sensor == AzSensor::kFluxgate ? 360 : 180;
  switch (d.integer(0, 2)) {
    case 0: return {-180, 180};
    case 1: return sensor == AzSensor::kFluxgate ? Range{0, 359.9} : Range{-90, 90};
    default: {
      const double lo = d.stepped(-180, top - 10, 0.1);
      return {lo, d.stepped(lo + 10, top, 0.1)};
    }
  }
}

// Elevation with and without negative positions; an upper limit past the
// zenith, near it, or short of it (a mount that leaves the high sky out of
// reach: a LOCATE there is a range error, ERRATA E-81).
Range el_range(Draw& d) {
  const double lo = d.chance(0.5) ? d.stepped(-15, -0.1, 0.1) : d.stepped(0, 30, 0.1);
  const double roll = d.real(0, 1);
  const double hi = roll < 0.6   ? d.stepped(std::max(lo + 10, 60.0), 90, 0.1)
                    : roll < 0.8 ? d.stepped(90, 180, 0.1)
                                 : d.stepped(lo + 10, 60, 0.1);
  return {lo, hi};
}

Range pol_range(Draw& d) {
  if (d.chance(0.5)) return {-90, 90};
  const double lo = d.stepped(-180, 0, 0.1);
  return {lo, d.stepped(lo + 10, 180, 0.1)};
}

double inside(Draw& d, Range r) {
  if (d.chance(0.1)) return d.chance(0.5) ? r.min : r.max;  // at a limit at power-on (§3.2 bytes 32-34)
  return std::clamp(d.stepped(std::ceil(r.min * 10) / 10, std::floor(r.max * 10) / 10, 0.1), r.min, r.max);
}

AxisProfile axis(Draw& d, Range r) {
  AxisProfile a;
  a.fast_dps = std::max(0.1, Draw::round_to(d.log_real(0.1, 50), 0.01));
  a.slow_dps = std::clamp(Draw::round_to(a.fast_dps * d.real(0.05, 1), 0.01), 0.1, a.fast_dps);
  a.min_deg = r.min;
  a.max_deg = r.max;
  a.initial_deg = inside(d, r);
  a.has_stow_limit = d.chance(0.5);
  a.stow_deg = a.has_stow_limit ? (d.chance(0.5) ? r.min : inside(d, r)) : 0.0;
  a.tolerance_deg = d.chance(0.5) ? 0.1 : d.stepped(0.1, 5, 0.1);
  if (d.chance(0.5)) a.accel_dps2 = std::max(0.5, Draw::round_to(d.log_real(0.5, 500), 0.1));
  a.power_on_speed = d.chance(0.75) ? AxisSpeed::kFast : AxisSpeed::kSlow;
  a.ad_error = d.chance(1.0 / 12);
  return a;
}

// ---- stored data ----------------------------------------------------------------

void store(Draw& d, Profile& p) {
  std::vector<std::string> names;
  const std::size_t n = d.fill(50);  // §3.6 "A maximum of 50 satellites"
  for (std::size_t i = 0; i < n; ++i) {
    StoredSatellite s;
    s.name = unique_name(d, names);
    names.push_back(s.name);
    // Positions the mount stored them at: inside its ranges.
    s.az_deg = inside(d, {p.az.min_deg, p.az.max_deg});
    s.el_deg = inside(d, {p.el.min_deg, p.el.max_deg});
    s.h_pol_deg = inside(d, {p.pol.min_deg, p.pol.max_deg});
    s.v_pol_deg = inside(d, {p.pol.min_deg, p.pol.max_deg});
    p.store.push_back(std::move(s));
  }
}

// Indexes 1..max, `count` of them, in a drawn order.
std::vector<std::uint8_t> indexes(Draw& d, std::size_t count, std::size_t max) {
  std::vector<std::uint8_t> all;
  for (std::size_t i = 1; i <= max; ++i) all.push_back(static_cast<std::uint8_t>(i));
  for (std::size_t i = all.size(); i > 1; --i)
    std::swap(all[i - 1], all[static_cast<std::size_t>(d.integer(0, static_cast<long long>(i) - 1))]);
  all.resize(count);
  return all;
}

void presets(Draw& d, Profile& p) {
  const std::string alphabet = printable_alphabet();
  for (std::uint8_t index : indexes(d, d.fill(20), 20)) {  // §3.10 index 1-20
    PresetSatellite s;
    s.index = index;
    SatelliteData& sat = s.data;
    sat.name = text(d, 0, 10, alphabet);
    sat.longitude = static_cast<std::int32_t>(d.integer(-1799, 1799));
    sat.inclination = static_cast<std::int32_t>(d.integer(0, 19));
    sat.band = d.pick(std::span<const fields::ChoiceItem>(layouts::kBands)).ch;
    // E-51: ephemeris data for the first 10 sets only.
    sat.ephemeris = index <= 10 ? d.pick(std::span<const fields::ChoiceItem>(layouts::kEphemeris)).ch : '0';
    sat.pol_offset = static_cast<std::int32_t>(d.integer(-900, 900));
    s.dual_band = sat.band == '2' && d.chance(0.5);  // C/Ku (§3.7 'T', E-70)
    p.presets.push_back(std::move(s));
  }
}

// A TLE line of 69 characters with the right mod-10 checksum (E-19): the
// shipped profile's ISS set under a drawn catalog number.
std::string tle_line(std::string line, const std::string& number) {
  line.replace(2, 5, number);
  int sum = 0;
  for (std::size_t i = 0; i < 68; ++i) sum += line[i] >= '0' && line[i] <= '9' ? line[i] - '0' : line[i] == '-' ? 1 : 0;
  line[68] = static_cast<char>('0' + sum % 10);
  return line;
}

void tles(Draw& d, Profile& p) {
  static const std::string kLine1 = "1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927";
  static const std::string kLine2 = "2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537";
  for (std::uint8_t index : indexes(d, d.fill(10), 10)) {  // §3.12 index 1-10
    const std::string number = std::to_string(d.integer(10000, 99999));
    p.tles.push_back(TleSet{index, tle_line(kLine1, number), tle_line(kLine2, number)});
  }
}

void signposts(Draw& d, Profile& p) {
  if (!p.dvb_receiver) return;  // §3.20 NOTE, E-23
  const std::string alphabet = printable_alphabet();
  for (std::uint8_t index : indexes(d, d.fill(20), 20)) {
    Signpost s;
    s.index = index;
    SignpostData& sp = s.data;
    sp.longitude = static_cast<std::int32_t>(d.integer(-1799, 1800));
    sp.frequency = static_cast<std::int32_t>(d.integer(10700, 12750));
    sp.symbol_rate = static_cast<std::int32_t>(d.integer(1000, 30000));
    sp.fec = d.pick(std::span<const fields::ChoiceItem>(layouts::kFec)).ch;
    sp.polarization = d.pick(std::span<const fields::ChoiceItem>(layouts::kSignpostPol)).ch;
    sp.id = text(d, 0, 6, alphabet);
    sp.priority = static_cast<std::uint32_t>(d.integer(0, 9));
    p.signposts.push_back(std::move(s));
  }
}

// Absent, or from any source of §3.22 byte 3 / byte 29.
Navigation navigation(Draw& d) {
  Navigation n;
  n.latlon_source = d.pick<std::uint8_t>({1, 2, 3, 4, 5, 7});
  if (n.latlon_source != 1) {
    n.latitude_min = static_cast<std::int32_t>(d.integer(-90 * 60, 90 * 60));
    n.longitude_min = static_cast<std::int32_t>(d.integer(-180 * 60, 180 * 60));
  }
  n.heading_source = static_cast<std::uint8_t>(d.integer(1, 7));
  if (n.heading_source != 1) n.heading_tenths = static_cast<std::int32_t>(d.integer(0, 3599));
  if (d.chance(0.7)) n.magvar_tenths = static_cast<std::int32_t>(d.integer(-999, 999));
  return n;
}

// ---- the rest ------------------------------------------------------------------

void line_settings(Draw& d, Profile& p) {
  p.address = static_cast<std::uint8_t>(d.integer(49, 111));
  if (d.chance(0.125)) {  // §1 multi-drop
    const auto peers = d.integer(1, 3);
    while (static_cast<long long>(p.bus_peers.size()) < peers) {
      const auto a = static_cast<std::uint8_t>(d.integer(49, 111));
      if (a != p.address && std::find(p.bus_peers.begin(), p.bus_peers.end(), a) == p.bus_peers.end())
        p.bus_peers.push_back(a);
    }
  }
  // 1 in 20 with remote control disabled: such a profile runs only the 31
  // offline vectors (every other one requires remote_enabled), so a quarter
  // of the sweep spent there explored little; at 1 in 20 a sweep of 200
  // still draws about ten (none with odds 0.95^200, 4e-5) and 10,000 draw 500.
  p.remote_enabled = !d.chance(0.05);
  p.baud = kBauds[static_cast<std::size_t>(d.integer(0, static_cast<long long>(std::size(kBauds)) - 1))];
}

void mount(Draw& d, Profile& p) {
  p.firmware = std::to_string(d.integer(0, 9)) + "." + std::to_string(d.integer(0, 9)) + std::to_string(d.integer(0, 9));
  p.pol_type = pick_value(d, kPolTypes);
  p.az_sensor = pick_value(d, kAzSensors);
  p.fluxgate_heading = pick_value(d, kHeadingReferences);
  p.hundredths = d.chance(0.5);
  p.stow = d.chance(0.5);
  p.deploy = d.chance(0.5);
  p.dvb_receiver = d.chance(0.5);
  p.counts_per_degree = std::max(0.01, Draw::round_to(d.log_real(1, 10000), 0.01));
  p.count_offset = static_cast<std::int32_t>(d.integer(0, 99999));
  p.az = axis(d, az_range(d, p.az_sensor));
  p.el = axis(d, el_range(d));
  p.pol = axis(d, pol_range(d));
  p.turnaround_ms = d.chance(0.5) ? d.stepped(0, 10, 0.1) : d.stepped(0, kRandomMaxTurnaroundMs, 0.1);
  p.agc = static_cast<std::uint16_t>(d.integer(0, 999));
  p.agc_channel = pick_value(d, kAgcChannels);
}

void display(Draw& d, Profile& p) {
  DisplayProfile& s = p.display;
  if (d.chance(0.5)) s.satellite = !p.store.empty() && d.chance(0.5) ? d.pick(std::span<const StoredSatellite>(p.store)).name
                                                                       : capitals_name(d, 0);
  // §3.2 byte 35: a code only with a rotating feed.
  if (p.pol_type != PolType::kCircular && d.chance(0.5)) s.pol_code = d.pick({'H', 'h', 'V', 'v'});
  s.cursor_row = static_cast<std::uint8_t>(d.integer(1, 4));
  s.cursor_column = static_cast<std::uint8_t>(d.integer(0, 39));
  s.cursor_blinking = d.chance(0.5);
}

void track_and_alarms(Draw& d, Profile& p) {
  p.track.active = d.chance(1.0 / 3);
  p.track.activity = pick_value(d, kTrackActivities);
  p.track.band = pick_value(d, kTrackBands);
  p.track.dual_band = (p.track.band == TrackBand::kC || p.track.band == TrackBand::kKu) && d.chance(0.5);  // E-70
  auto alarm = [&] { return d.chance(0.2) ? pick_value(d, kAxisAlarms) : std::uint8_t{0}; };
  p.alarms.az = alarm();
  p.alarms.el = alarm();
  // §3.2 byte 38: no off axis (1000) or drive (1100) alarm for polarization.
  do p.alarms.pol = alarm();
  while (p.alarms.pol == 8 || p.alarms.pol == 12);
  p.alarms.code = d.chance(0.25) ? static_cast<std::uint8_t>(d.integer(0, 63)) : 0;
}

void errata(Draw& d, Profile& p) {
  p.stx_restarts_in_data = d.chance(0.5);                               // E-7
  p.unknown_command_while_offline = pick_value(d, kOfflineUnknown);     // E-10
  p.implements_signal_strength = d.chance(0.5);                         // E-16
  p.implements_iess = d.chance(0.5);                                    // E-16
  p.nak_bad_tle_checksum = d.chance(0.5);                               // E-19
  const bool zero_based = d.chance(0.5);                                // E-22
  p.locate_index_min = zero_based ? 0 : 1;
  p.locate_index_max = zero_based ? 19 : 20;
  p.restore_lost_locate_exit = d.chance(0.5);                           // E-28
}

// §3.7 'D' (ERRATA E-90): a mount with a deploy function states where a
// DEPLOY drives the elevation, and sometimes the azimuth; or says nothing.
void deploy_positions(Draw& d, Profile& p) {
  if (!p.deploy || d.chance(0.25)) return;
  p.el.deploy_deg = inside(d, {p.el.min_deg, p.el.max_deg});
  if (d.chance(0.5)) p.az.deploy_deg = inside(d, {p.az.min_deg, p.az.max_deg});
}

// The spec's open points (readings.hpp): most are left open, as a profile
// that knows nothing of its firmware's reading would; one in four is pinned
// to a side, which the controller then takes and the vectors hold it to.
void readings(Draw& d, Profile& p) {
  for (const ReadingPoint& point : reading_points()) {
    if (!d.chance(0.25)) continue;
    if (point.other_2.empty()) {
      p.readings[std::string(point.id)] = d.chance(0.5) ? ReadingSide::kOther : ReadingSide::kReference;
    } else {
      const auto sides = sides_of(point);
      p.readings[std::string(point.id)] = sides[static_cast<std::size_t>(d.integer(0, static_cast<int>(sides.size()) - 1))];
    }
  }
}

}  // namespace

void hold_only_what_sides_allow(Profile& p, const ReadingPins& sides) {
  // ERRATA E-23 other-2 NAKs priority 0 (as 44h's "1 - 9" reads).
  if (side_taken(sides, "E-23") == ReadingSide::kOther2)
    for (Signpost& s : p.signposts) s.data.priority = std::max<std::uint32_t>(s.data.priority, 1);
}

Profile random_profile(std::uint64_t seed) {
  Draw d(seed);
  Profile p;
  p.name = "random-" + std::to_string(seed);
  line_settings(d, p);
  mount(d, p);
  store(d, p);
  presets(d, p);
  tles(d, p);
  signposts(d, p);
  p.navigation = d.chance(0.25) ? Navigation{} : navigation(d);
  display(d, p);
  track_and_alarms(d, p);
  errata(d, p);
  deploy_positions(d, p);
  readings(d, p);  // drawn last: the fields before keep their draws
  hold_only_what_sides_allow(p, p.readings);
  return p;
}

}  // namespace sabus::harness
