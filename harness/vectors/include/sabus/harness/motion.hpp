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
//   - the display: positions are shown in tenths (§3.2 bytes 14-31), each
//     reading off by up to kDisplayResolution / 2;
//   - limits: an axis stops at its limit positions (§3.2 bytes 32-34).
// Pure functions of the profile (vectors/README.md, "Profile expressions").
#pragma once

#include <chrono>
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

inline constexpr double kDisplayResolution = 0.1;  // degrees: positions are shown in tenths
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

// Where a jog of `ms` from `from` in direction `sign` can leave the axis, as
// read on the display: jog_travel clipped at the limits, widened by one
// display resolution (two readings).
Interval jog_end(const AxisProfile& a, double from, int sign, char speed, int ms);

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

// The longest an auto move of `distance` degrees can take: at slow speed
// (a controller may approach at slow speed), with both ramps. At most
// kLongestMoveMs: a distance from a vector's matcher can be any number.
inline constexpr std::int64_t kLongestMoveMs = 3'600'000;
std::chrono::milliseconds longest_move(const AxisProfile& a, double distance);

}  // namespace sabus::harness::motion
