// Motion expectations from the device profile (motion.hpp).
#include "sabus/harness/motion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sabus::harness::motion {
namespace {

double seconds(int ms) { return ms / 1000.0; }
int floor_tick(int ms) { return ms / kJogTick * kJogTick; }
int ceil_tick(int ms) { return (ms + kJogTick - 1) / kJogTick * kJogTick; }

// Tenths, toward the inside of [low, high] where rounding could leave it.
double tenths_down(double x) { return std::floor(x * 10 + 1e-6) / 10; }
double tenths_up(double x) { return std::ceil(x * 10 - 1e-6) / 10; }
double tenths(double x) { return std::round(x * 10) / 10; }

// Travel in `t` seconds of timer: the ramp (if any) inside the timer, or
// after it.
double travel_ramp_inside(double v, std::optional<double> accel, double t) {
  if (!accel) return v * t;
  const double a = *accel;
  return t >= 2 * v / a ? v * t - v * v / a : a * t * t / 4;
}
double travel_ramp_after(double v, std::optional<double> accel, double t) {
  if (!accel) return v * t;
  const double a = *accel;
  return t >= v / a ? v * t : a * t * t;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string speed_text(const AxisProfile& a, char speed) {
  return std::string(speed == 'F' ? "fast" : "slow") + " speed (" + number(speed_dps(a, speed)) + " deg/s)";
}

std::string range_text(const AxisProfile& a, std::string_view axis_name) {
  return "the " + std::string(axis_name) + " range (" + number(a.min_deg) + " to " + number(a.max_deg) + ")";
}

// ---- readings ------------------------------------------------------------------

// A number of display units this close to a whole one is that one: the
// representation error of a position computed in doubles (0.3 * 10 is
// 2.9999999999999996), never a distance a mount can resolve.
constexpr double kWhole = 1e-9;
// Numbers of units beyond any position (360 deg in hundredths is 36000): a
// bound from a vector's expression can be any number, and casting 1e300 to
// an integer is undefined.
constexpr double kMostUnits = 1e15;

std::int64_t whole_up(double units) { return static_cast<std::int64_t>(std::ceil(std::clamp(units, -kMostUnits, kMostUnits) - kWhole)); }
std::int64_t whole_down(double units) { return static_cast<std::int64_t>(std::floor(std::clamp(units, -kMostUnits, kMostUnits) + kWhole)); }
double snapped(double units) { return std::abs(units - std::round(units)) < kWhole ? std::round(units) : units; }

// The hundredths readings whose tenths field shows `tenths`: truncated
// toward zero (E-30, E-87's reference side), or for a negative one rounded
// down (E-87's other side: -0.2 stands for -0.20 to -0.11 too).
Readings hundredths_shown_as(std::int64_t tenths) {
  if (tenths > 0) return {tenths * 10, tenths * 10 + 9};
  if (tenths < 0) return {tenths * 10 - 9, tenths * 10 + 9};
  return {-9, 9};
}

// The positions, in display units, that a controller showing positions
// `how` reads as `r`: closed at both ends (a tie of rounding either way).
Interval positions_read_as(std::int64_t r, Shown how) {
  const double x = static_cast<double>(r);
  switch (how) {
    case Shown::kRounded: return {x - 0.5, x + 0.5};
    case Shown::kTruncated: return r > 0 ? Interval{x, x + 1} : r < 0 ? Interval{x - 1, x} : Interval{-1, 1};
    case Shown::kTruncatedDown: return {x, x + 1};
  }
  return {x - 1, x + 1};
}

// The readings of the positions in `x` (display units) shown `how`.
Readings readings_at(Interval x, Shown how) {
  switch (how) {
    case Shown::kRounded: return {whole_up(x.low - 0.5), whole_down(x.high + 0.5)};
    case Shown::kTruncated:
      return {static_cast<std::int64_t>(std::trunc(snapped(std::clamp(x.low, -kMostUnits, kMostUnits)))),
              static_cast<std::int64_t>(std::trunc(snapped(std::clamp(x.high, -kMostUnits, kMostUnits))))};
    case Shown::kTruncatedDown:
      return {static_cast<std::int64_t>(std::floor(snapped(std::clamp(x.low, -kMostUnits, kMostUnits)))),
              static_cast<std::int64_t>(std::floor(snapped(std::clamp(x.high, -kMostUnits, kMostUnits))))};
  }
  return {whole_up(x.low - 1), whole_down(x.high + 1)};
}

// A window of readings in `per_degree` units, and in tenths: the tenths
// field of a hundredths reading truncated toward zero or (a negative one,
// E-87's other side) rounded down.
PositionReadings in_tenths_and_finer(Readings r, int per_degree) {
  if (per_degree != kHundredths) return {r, std::nullopt};
  const std::int64_t low_down = r.low >= 0 ? r.low / 10 : -((-r.low + 9) / 10);
  return {{std::min(tenths_of(r.low, per_degree), low_down), tenths_of(r.high, per_degree)}, r};
}

// Stays this far inside a limit beyond the arrival tolerance: limits stop
// an axis (§3.2 bytes 32-34) and would cut a jog short.
constexpr double kLimitMargin = 0.5;

}  // namespace

const AxisProfile& profile_of(const Profile& p, Axis a) {
  return a == Axis::kAz ? p.az : a == Axis::kEl ? p.el : p.pol;
}

std::string_view name_of(Axis a) { return a == Axis::kAz ? "azimuth" : a == Axis::kEl ? "elevation" : "polarization"; }

std::optional<Axis> axis_named(std::string_view n) {
  if (n == "az") return Axis::kAz;
  if (n == "el") return Axis::kEl;
  if (n == "pol") return Axis::kPol;
  return std::nullopt;
}

std::optional<Axis> axis_of_field(std::string_view field) {
  for (Axis a : {Axis::kAz, Axis::kEl, Axis::kPol})
    if (field == name_of(a)) return a;
  return std::nullopt;
}

std::optional<JogDirection> jog_direction(char letter) {
  switch (letter) {  // §3.4 byte 3
    case 'E': return JogDirection{Axis::kAz, -1};
    case 'W': return JogDirection{Axis::kAz, +1};
    case 'D': return JogDirection{Axis::kEl, -1};
    case 'U': return JogDirection{Axis::kEl, +1};
    case 'O': return JogDirection{Axis::kPol, -1};
    case 'L': return JogDirection{Axis::kPol, +1};
    default: return std::nullopt;
  }
}

double speed_dps(const AxisProfile& a, char speed) { return speed == 'F' ? a.fast_dps : a.slow_dps; }

Interval jog_travel(const AxisProfile& a, char speed, int ms) {
  if (ms <= 0) return {0, 0};  // E-61: '0000' does not move
  const double v = speed_dps(a, speed);
  const int shortest = std::max(0, floor_tick(ms) - kJogTick), longest = ceil_tick(ms) + kJogTick;
  return {travel_ramp_inside(v, a.accel_dps2, seconds(shortest)), travel_ramp_after(v, a.accel_dps2, seconds(longest))};
}

int display_units(const Profile& p) { return p.hundredths ? kHundredths : kTenths; }

std::string_view name_of(Shown how) {
  switch (how) {
    case Shown::kRounded: return "rounded";
    case Shown::kTruncated: return "truncated";
    case Shown::kTruncatedDown: return "truncated down";
  }
  return "?";
}

std::int64_t shown(double deg, int per_degree, Shown how) {
  const double u = std::clamp(deg * per_degree, -kMostUnits, kMostUnits);
  const double nearest = std::round(u);
  if (std::abs(u - nearest) < kWhole) return static_cast<std::int64_t>(nearest);
  switch (how) {
    case Shown::kRounded: return static_cast<std::int64_t>(nearest);  // std::round: a tie away from zero
    case Shown::kTruncated: return static_cast<std::int64_t>(std::trunc(u));
    case Shown::kTruncatedDown: return static_cast<std::int64_t>(std::floor(u));
  }
  return static_cast<std::int64_t>(nearest);
}

std::int64_t tenths_of(std::int64_t reading, int per_degree) {
  return per_degree == kHundredths ? reading / 10 : reading;  // '/' truncates toward zero
}

PositionReadings near_readings(double target, double tolerance, int per_degree) {
  const double t = std::round(std::clamp(target, -kMostUnits, kMostUnits) * 100) / 100;
  const Readings r{whole_up((t - tolerance) * per_degree), whole_down((t + tolerance) * per_degree)};
  return in_tenths_and_finer(r, per_degree);
}

namespace {
// The tenths field of a hundredths display of a fluxgate heading (0.00 to
// 359.99, §3.2 NOTE) truncates the heading, which is never negative: for a
// position below 0 (a heading a turn away) that is truncation down (E-30).
Readings heading_hundredths_shown_as(std::int64_t tenths) { return {tenths * 10, tenths * 10 + 9}; }
std::int64_t floor_tenths(std::int64_t hundredths) {
  return hundredths >= 0 ? hundredths / 10 : -((-hundredths + 9) / 10);
}
}  // namespace

PositionReadings jog_readings(const AxisProfile& a, int per_degree, std::int64_t from_tenths, int sign, char speed,
                              int ms, bool heading) {
  const Interval travel = jog_travel(a, speed, ms);
  const double shortest = travel.low * per_degree, longest = travel.high * per_degree;
  const double min_units = a.min_deg * per_degree, max_units = a.max_deg * per_degree;
  // The readings the start can have been: a tenths field shows one reading
  // of a tenths display, or ten of a hundredths display (E-30).
  const Readings start = per_degree != kHundredths ? Readings{from_tenths, from_tenths}
                         : heading                  ? heading_hundredths_shown_as(from_tenths)
                                                    : hundredths_shown_as(from_tenths);
  const std::int64_t most = whole_up(longest);  // units the longest travel spans
  std::optional<Readings> all;
  for (const Shown how : kEveryWayShown) {
    const double from_low = positions_read_as(start.low, how).low, from_high = positions_read_as(start.high, how).high;
    Interval end = sign > 0 ? Interval{from_low + shortest, from_high + longest}
                            : Interval{from_low - longest, from_high - shortest};
    end.low = std::clamp(end.low, min_units, max_units);
    end.high = std::clamp(end.high, min_units, max_units);
    Readings r = readings_at(end, how);
    // The same display read twice: a reading never moves against the jog
    // (each way shown is monotonic), nor by more units than the travel spans.
    if (sign > 0) {
      r.low = std::max(r.low, start.low);
      r.high = std::min(r.high, start.high + most);
    } else {
      r.high = std::min(r.high, start.high);
      r.low = std::max(r.low, start.low - most);
    }
    all = all ? Readings{std::min(all->low, r.low), std::max(all->high, r.high)} : r;
  }
  if (heading && per_degree == kHundredths) return {{floor_tenths(all->low), floor_tenths(all->high)}, *all};
  return in_tenths_and_finer(*all, per_degree);
}

Readings readings_between(double low, double high, int per_degree) {
  return {whole_up(low * per_degree), whole_down(high * per_degree)};
}

double home(const AxisProfile& a) { return at(a, 0.5); }

double at(const AxisProfile& a, double fraction) {
  return std::clamp(tenths(a.min_deg + fraction * (a.max_deg - a.min_deg)), tenths_up(a.min_deg), tenths_down(a.max_deg));
}

Maybe<int> measurable_jog_ms(const AxisProfile& a, char speed, std::string_view axis_name) {
  const double h = home(a);
  const double room = std::min(h - a.min_deg, a.max_deg - h) - a.tolerance_deg - kLimitMargin;
  for (int ms = kJogTick; ms <= floor_tick(kMaxJogMs); ms += kJogTick) {
    const Interval t = jog_travel(a, speed, ms);
    if (t.high + kDisplayResolution > room) break;  // longer jogs only travel farther
    if (t.low - kDisplayResolution >= 0.5) return {ms, ""};
  }
  return {std::nullopt, "no jog of 50-9950 ms at " + speed_text(a, speed) + " surely moves the " +
                            std::string(axis_name) + " a measurable 0.5 deg and stays off the limits of " +
                            range_text(a, axis_name)};
}

Maybe<double> jog_start(const AxisProfile& a, int sign, char speed, int ms, std::string_view axis_name) {
  // Elapsed time, whatever the timer: the axis covers at most v * t.
  const double need = speed_dps(a, speed) * seconds(ms) + a.tolerance_deg + kLimitMargin;
  const double inner = a.tolerance_deg + kLimitMargin;
  const double h = home(a);
  const double start = sign > 0 ? tenths_down(std::min(h, a.max_deg - need)) : tenths_up(std::max(h, a.min_deg + need));
  if (start >= a.min_deg + inner && start <= a.max_deg - inner) return {start, ""};
  return {std::nullopt, range_text(a, axis_name) + " is too short for a jog at " + speed_text(a, speed) + " to run " +
                            std::to_string(ms) + " ms"};
}

Maybe<double> move_target(const AxisProfile& a, double from, int ms, std::string_view axis_name) {
  const double inset = 0.05 * (a.max_deg - a.min_deg);
  const double target = a.max_deg - from >= from - a.min_deg ? tenths_down(a.max_deg - inset) : tenths_up(a.min_deg + inset);
  const double fastest_ms = std::abs(target - from) / a.fast_dps * 1000;
  if (fastest_ms >= ms) return {target, ""};
  return {std::nullopt, "an auto move across " + range_text(a, axis_name) + " at " + speed_text(a, 'F') +
                            " can end in " + number(std::round(fastest_ms)) + " ms, before " + std::to_string(ms) + " ms"};
}

Maybe<double> away_from(const AxisProfile& a, double to, int ms, std::string_view axis_name) {
  const double inset = a.tolerance_deg + kLimitMargin;  // clear of the limit switches, as a jog's start
  // A move ends within tolerance_deg of its target, twice: the move that
  // puts the axis here may stop that much short of `from` (nearer `to`), and
  // the move to `to` that much short of it. Neither is travelled.
  const double travel = a.fast_dps * seconds(ms) * 1.1 + 2 * a.tolerance_deg;
  const bool up = a.max_deg - to >= to - a.min_deg;
  const double from = up ? tenths_up(to + travel) : tenths_down(to - travel);
  if (from >= a.min_deg + inset && from <= a.max_deg - inset) return {from, ""};
  return {std::nullopt, range_text(a, axis_name) + " has no room for a move of " + std::to_string(ms) + " ms at " +
                            speed_text(a, 'F') + " to " + number(to)};
}

std::chrono::milliseconds longest_move(const AxisProfile& a, double distance) {
  double ms = std::abs(distance) / a.slow_dps * 1000;
  if (a.accel_dps2) ms += 2 * a.fast_dps / *a.accel_dps2 * 1000;
  if (!(ms < static_cast<double>(kLongestMoveMs))) return std::chrono::milliseconds(kLongestMoveMs);
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(ms)));
}

}  // namespace sabus::harness::motion
