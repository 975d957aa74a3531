// A controller that moves exactly as its profile says passes the jogged
// matcher, whatever speeds, ramp, duration, limits and start it has, and
// however it shows a position: rounded or truncated (ERRATA E-76), in tenths
// or, with 0.01 deg feedback, in hundredths (§3.17 bytes 49-50, E-30). The
// reading is compared as a whole number of display units (motion.hpp), so a
// reading at the edge of its window is never lost to a bound computed in
// doubles (sweep seeds 3226426560851818593, 463807582702990695,
// 13220031529678979844 failed so before).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sabus/harness/motion.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/messages.hpp"

namespace sabus::harness {
namespace {

// A number of hundredths of a degree between `low` and `high`, in degrees.
double hundredths_between(int low, int high) { return *rc::gen::inRange(low, high + 1) / 100.0; }

// A tenths reading as a capture holds it ("-0.4", "359.6").
std::string tenths_text(std::int64_t tenths) {
  const std::int64_t m = std::llabs(tenths);
  return (tenths < 0 ? "-" : "") + std::to_string(m / 10) + "." + std::to_string(m % 10);
}

// The 40h reply (§3.17) showing an azimuth reading in `per` units: its
// tenths (truncated toward zero, E-30) in bytes 14-19, its hundredths digit
// in byte 49 ('0' on a tenths display).
FrameDescription extended_status(std::int64_t reading, int per) {
  ExtendedStatusReply r;
  r.status.azimuth = {fields::AzimuthReading::Kind::kPosition,
                      static_cast<std::int32_t>(motion::tenths_of(reading, per)), 0};
  r.az_hundredths = per == motion::kHundredths ? static_cast<std::int32_t>(std::llabs(reading) % 10) : 0;
  return describe_frame(encode_reply(r, '2', 0x40).value());
}

RC_GTEST_PROP(MotionReadings, AJogAsTheProfileSaysPassesJoggedHoweverTheDisplayShowsIt, ()) {
  Profile p;
  p.hundredths = *rc::gen::arbitrary<bool>();
  const int per = motion::display_units(p);
  const motion::Shown how = *rc::gen::elementOf(motion::kEveryWayShown);
  AxisProfile& a = p.az;
  a.min_deg = hundredths_between(-18000, 0);
  a.max_deg = hundredths_between(static_cast<int>(std::lround(a.min_deg * 100)) + 100, 18000);
  a.fast_dps = hundredths_between(1, 2000);
  a.slow_dps = hundredths_between(1, static_cast<int>(std::lround(a.fast_dps * 100)));
  if (*rc::gen::arbitrary<bool>()) a.accel_dps2 = hundredths_between(10, 5000);
  const char speed = *rc::gen::element('F', 'S');
  const char jog = *rc::gen::element('E', 'W');  // §3.4 byte 3: the azimuth's two directions
  const int ms = *rc::gen::inRange(0, motion::kMaxJogMs + 1);
  // The mount's start and its travel: anywhere the profile allows, to the
  // millionth of a degree (a position is not a display unit).
  const double start = a.min_deg + (a.max_deg - a.min_deg) * *rc::gen::inRange(0, 1'000'001) / 1e6;
  const motion::Interval travel = motion::jog_travel(a, speed, ms);
  const double moved = travel.low + (travel.high - travel.low) * *rc::gen::inRange(0, 1'000'001) / 1e6;
  const int sign = motion::jog_direction(jog)->sign;
  const double end = std::clamp(start + sign * moved, a.min_deg, a.max_deg);  // limits stop it (§3.2 bytes 32-34)

  const std::int64_t start_reading = motion::shown(start, per, how);
  const std::int64_t end_reading = motion::shown(end, per, how);
  FieldMatcher m;
  m.field = "azimuth";
  m.kind = FieldMatcher::Kind::kJogged;
  m.jog = jog;
  m.speed = speed;
  m.values = {tenths_text(motion::tenths_of(start_reading, per)), std::to_string(ms)};
  const ResolvedMatcher r = resolve_matcher(m, ExprContext{p});
  RC_ASSERT(r.kind == Expansion::Kind::kValue);
  Captures captures;
  const auto failure = check_field(extended_status(end_reading, per), r.matcher, captures);
  RC_LOG() << motion::name_of(how) << " in 1/" << per << " deg: from " << start << " (read " << start_reading
           << ") by " << moved << " to " << end << " (read " << end_reading << ")\n";
  RC_ASSERT(!failure);
}

}  // namespace
}  // namespace sabus::harness
