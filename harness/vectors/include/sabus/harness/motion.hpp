// What a device profile lets a vector expect of motion: where moving vectors
// start, how far a jog of a given duration and speed can take an axis, how
// long a move can last, and where a jog or move must start to last long
// enough to be watched. One place for the tolerances every motion check
// shares:
//   - the jog timer: "a multiple of approx. 50 milliseconds" (§3.4, E-61):
//     a duration counts from one 50 ms tick below its multiple of 50 to one
//     tick above it; '0000' does not move;
//   - acceleration (AxisProfile::accel_dps2, optional): the ramp may be
//     inside the timer or after it, so the shortest travel ramps up and down
//     within the duration and the longest ramps down after it;
//   - the display: a controller reads its position in whole display units,
//     tenths (§3.2 bytes 14-31) or, with 0.01 deg feedback (`hundredths`),
//     hundredths (§3.17 bytes 49-50, whose tenths are those digits
//     truncated, E-30); whether it rounds or truncates is not said (E-76),
//     so a window of readings holds for each way (Shown) and is compared
//     with a reading as a whole number, never as degrees;
//   - limits: an axis stops at its limit positions (§3.2 bytes 32-34).
// Pure functions of the profile (vectors/README.md, "Profile expressions").
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sabus/harness/profile.hpp"

namespace sabus::harness::motion {

enum class Axis : std::uint8_t { kAz, kEl, kPol };
const AxisProfile& profile_of(const Profile& p, Axis a);
std::string_view name_of(Axis a);        // "azimuth", "elevation", "polarization"
std::optional<Axis> axis_named(std::string_view short_name);  // "az", "el", "pol"
// The axis whose position a reply field holds ("azimuth", "elevation",
// "polarization"), or nullopt for any other field.
std::optional<Axis> axis_of_field(std::string_view field);

// A jog direction letter of §3.4 (E W D U O L): its axis and sign (+1
// clockwise/up, -1 counterclockwise/down); nullopt for 'X' and others.
struct JogDirection {
  Axis axis;
  int sign;
};
std::optional<JogDirection> jog_direction(char letter);

inline constexpr double kDisplayResolution = 0.1;  // degrees: positions are shown in tenths (§3.2 bytes 14-31)
inline constexpr int kJogTick = 50;                // ms: the jog timer's resolution (E-61)
inline constexpr int kMaxJogMs = 9999;             // §3.4 bytes 5-8

struct Interval {
  double low = 0, high = 0;
  bool contains(double x) const { return x >= low - 1e-9 && x <= high + 1e-9; }
};

// The speed of a jog: 'F' fast, 'S' slow (§3.4 byte 4).
double speed_dps(const AxisProfile& a, char speed);

// How far the axis travels on a jog of `ms` (E-61 ticks, the ramp), without
// limits; both bounds >= 0.
Interval jog_travel(const AxisProfile& a, char speed, int ms);

// ---- readings at the display's resolution ------------------------------------

// Display units per degree: tenths (§3.2 bytes 14-31) and hundredths (§3.17
// bytes 49-50 with a mount's 0.01 deg feedback, E-30).
inline constexpr int kTenths = 10, kHundredths = 100;
// The units a controller with this profile reads its positions in.
int display_units(const Profile& p);

// How a controller turns a position into its reading: the spec does not say
// (ERRATA E-76), so each of these is legal. Rounded: to the nearest unit
// (a tie either way). Truncated: the digits of a signed position dropped
// (toward zero). Truncated down: toward minus infinity, as the digits of a
// heading 0.0-359.9 dropped (§3.2 NOTE) read on the signed axis.
enum class Shown : std::uint8_t { kRounded, kTruncated, kTruncatedDown };
inline constexpr std::array<Shown, 3> kEveryWayShown = {Shown::kRounded, Shown::kTruncated, Shown::kTruncatedDown};
std::string_view name_of(Shown how);  // "rounded", "truncated", "truncated down"

// The reading of the position `deg` in units of 1/`per_degree`, shown `how`
// (a tie rounds away from zero): what a controller that shows it that way
// says. Nearest the representation of a position that is a whole number of
// units already.
std::int64_t shown(double deg, int per_degree, Shown how);
// The tenths field that shows a reading in `per_degree` units: the same
// reading in tenths; a reading in hundredths truncated toward zero, its
// hundredths digit extending the magnitude (§3.17 bytes 49-50, E-30).
std::int64_t tenths_of(std::int64_t reading, int per_degree);

// Whole display units, inclusive.
struct Readings {
  std::int64_t low = 0, high = 0;
  bool contains(std::int64_t r) const { return r >= low && r <= high; }
  bool operator==(const Readings&) const = default;
};

// The readings of one position matcher: of a field in tenths, and, on a
// mount with 0.01 deg feedback, of a 40h position with its hundredths digit.
struct PositionReadings {
  Readings tenths;
  std::optional<Readings> hundredths;
  bool operator==(const PositionReadings&) const = default;
};

// The readings of a position within `tolerance` of `target` (degrees) on a
// display of `per_degree` units: a reading within the tolerance (E-71, "as
// read on the display"); in tenths, those readings' tenths (E-30). The
// target is taken to hundredths, the finest a command carries (§3.3 form 2C).
PositionReadings near_readings(double target, double tolerance, int per_degree);

// Where a jog of `ms` in direction `sign` at `speed` can leave the axis, as
// read: from a start read as `from_tenths` (a tenths field), for each way a
// controller may show a position (Shown), the positions that reading can
// stand for, moved by jog_travel, clipped at the limits, read again the same
// way; a reading never moves against the jog, nor by more units than the
// longest travel spans. The union of the windows of every way shown.
PositionReadings jog_readings(const AxisProfile& a, int per_degree, std::int64_t from_tenths, int sign, char speed, int ms,
                              bool heading = false);

// The readings in `per_degree` units of a reading written [low, high] in
// degrees, inclusive (a range matcher): the whole units between them.
Readings readings_between(double low, double high, int per_degree);

// Where moving vectors start: the middle of the axis's range, in tenths.
double home(const AxisProfile& a);
// A position `fraction` (0..1) of the way from min_deg to max_deg, in tenths.
double at(const AxisProfile& a, double fraction);

// A value, or the capability the profile lacks for it.
template <class T>
struct Maybe {
  std::optional<T> value;
  std::string reason;  // why not, when there is no value
};

// A jog duration (a multiple of 50 ms, 50-9950) that, from home, surely
// moves the axis a measurable distance (its shortest travel >= 0.5 deg beyond
// the display's resolution) and surely stays off the limits; the shortest
// such duration.
Maybe<int> measurable_jog_ms(const AxisProfile& a, char speed, std::string_view axis_name);

// A start position, nearest home in tenths, from which a jog in direction
// `sign` at `speed` runs at least `ms` before it can reach the limit.
Maybe<double> jog_start(const AxisProfile& a, int sign, char speed, int ms, std::string_view axis_name);

// A target for an auto move from `from` whose travel at fast speed lasts at
// least `ms`: the farther end of the range, held 5% of the span inside it.
Maybe<double> move_target(const AxisProfile& a, double from, int ms, std::string_view axis_name);
// A position, toward the farther end of the range, whose auto move to `to`
// lasts at least ms at fast speed and no more than that by much: `to` plus
// the fast speed's travel in ms (and 10 % more) and the axis's arrival
// tolerance, in tenths; unavailable when the range has no room for it.
Maybe<double> away_from(const AxisProfile& a, double to, int ms, std::string_view axis_name);

// The longest an auto move of `distance` degrees can take: at slow speed
// (a controller may approach at slow speed), with both ramps. At most
// kLongestMoveMs: a distance from a vector's matcher can be any number.
inline constexpr std::int64_t kLongestMoveMs = 3'600'000;
std::chrono::milliseconds longest_move(const AxisProfile& a, double distance);

}  // namespace sabus::harness::motion
