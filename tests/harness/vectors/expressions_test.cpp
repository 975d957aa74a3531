// Profile expressions and the motion expectations behind them: values from
// the profile, capabilities a profile lacks, errors a vector makes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/expressions.hpp"
#include "sabus/harness/motion.hpp"

namespace sabus::harness {
namespace {

using Kind = Expansion::Kind;

Profile profile_with_el(double min, double max, double fast, double slow) {
  Profile p;
  p.el.min_deg = min;
  p.el.max_deg = max;
  p.el.fast_dps = fast;
  p.el.slow_dps = slow;
  return p;
}

Expansion expand(std::string_view t, const Profile& p, const std::map<std::string, std::string>* captures = nullptr) {
  return expand_template(t, ExprContext{p, captures, std::chrono::milliseconds(1000)});
}

TEST(Expressions, TextOutsideBracesIsKeptAndBracesEscape) {
  const Profile p;
  EXPECT_EQ(expand("plain", p).text, "plain");
  EXPECT_EQ(expand("a {{b}} c", p).text, "a {b} c");
  EXPECT_FALSE(has_placeholder("a {{b}}"));
  EXPECT_TRUE(has_placeholder("{home(az)}"));
}

TEST(Expressions, ALiteralTemplateExpandsToItsText) {
  const Profile p;
  for (std::string_view text : {"", "plain", "{x}", "}{", "{{", "a}}b", "{home(az)}", "{$t} {", "q\"\\'{x} #-"}) {
    const std::string t = literal_template(text);
    EXPECT_FALSE(has_placeholder(t)) << t;
    EXPECT_EQ(check_template(t, {}), std::nullopt) << t;
    const Expansion e = expand(t, p);
    EXPECT_TRUE(e.ok()) << t << ": " << e.text;
    EXPECT_EQ(e.text, text) << t;
  }
}

TEST(Expressions, PositionsComeFromTheProfile) {
  const Profile p = profile_with_el(0, 90, 20, 5);
  EXPECT_EQ(expand("{home(el)}", p).text, "45");
  EXPECT_EQ(expand("{at(el, 0.25)}", p).text, "22.5");
  EXPECT_EQ(expand("{min_deg(el)} to {max_deg(el)}", p).text, "0 to 90");
  EXPECT_EQ(expand("{home(el) + 1.5}", p).text, "46.5");
  EXPECT_EQ(expand("{-(home(el) - 50) * 2}", p).text, "10");
  EXPECT_EQ(expand("{pace_ms()}", p).text, "1000");
}

// ERRATA E-80, E-81: LOCATE satellites from the site, heading and ranges. A
// site at 33 52' S 151 12' E, mount azimuth 0.0 heading 030.0, azimuth -170
// to 20 (true 200 to 50 through north), elevation 0 to 45.
Profile southern_site() {
  Profile p;
  p.navigation.latitude_min = -(33 * 60 + 52);
  p.navigation.longitude_min = 151 * 60 + 12;
  p.navigation.heading_tenths = 300;
  p.az.min_deg = -170;
  p.az.max_deg = 20;
  p.el.min_deg = 0;
  p.el.max_deg = 45;
  return p;
}

double number_of(std::string_view t, const Profile& p) {
  const Expansion e = expand(t, p);
  EXPECT_EQ(e.kind, Kind::kValue) << t << ": " << e.text;
  return std::stod(e.text);
}

TEST(Expressions, LocateSatellitesComeFromTheSiteHeadingAndRanges) {
  const Profile p = southern_site();
  const double visible = number_of("{locate_visible()}", p);
  const double el = number_of("{locate_el(locate_visible())}", p);
  const double az = number_of("{locate_az(locate_visible())}", p);
  EXPECT_GE(el, 5.0);
  EXPECT_LE(el, 43.0) << "2 deg inside the upper limit";
  EXPECT_GE(az, -168.0);
  EXPECT_LE(az, 18.0);
  EXPECT_EQ(number_of("{locate_any()}", p), visible);
  EXPECT_LT(number_of("{locate_el(locate_below_horizon())}", p), -3.0);
  const double wide = number_of("{locate_az(locate_outside_az())}", p);
  EXPECT_TRUE(wide > 23.0 && wide < 190.0) << wide;
  EXPECT_GT(number_of("{locate_el(locate_above_el())}", p), 48.0);
  // 97.0 W, issue 22's fixed longitude, is below the horizon here.
  EXPECT_LT(number_of("{locate_el(-97.0)}", p), 0.0);
  // The heading turns the mount: true azimuth less 030.0.
  Profile north = p;
  north.navigation.heading_tenths = 0;
  EXPECT_NEAR(number_of("{locate_az(150)}", north) - 30.0, number_of("{locate_az(150)}", p), 1e-6);

  // A mount that sees the whole sky has no satellite outside its ranges.
  Profile whole = p;
  whole.az.min_deg = -180;
  whole.az.max_deg = 180;
  whole.el.max_deg = 90;
  EXPECT_EQ(expand("{locate_outside_az()}", whole).kind, Kind::kUnavailable);
  EXPECT_EQ(expand("{locate_above_el()}", whole).kind, Kind::kUnavailable);
  // Without the site nothing can be chosen, but locate_any() still sends one.
  Profile lost = p;
  lost.navigation.latitude_min.reset();
  EXPECT_EQ(expand("{locate_visible()}", lost).kind, Kind::kUnavailable);
  EXPECT_EQ(expand("{locate_any()}", lost).text, "0");
  EXPECT_EQ(expand("{locate_az(100.0)}", lost).kind, Kind::kUnavailable);
  EXPECT_EQ(expand("{locate_az(180.1)}", p).kind, Kind::kError);
}

// The LOCATE targets are kept per thread, keyed by what their search reads
// (locate_targets.cpp): whatever was asked before, each answer is the one a
// thread that never searched gives (a new thread starts with nothing kept).
TEST(Expressions, LocateTargetsFollowEveryChangeOfTheProfile) {
  const char* const kTargets[] = {"{locate_visible()}", "{locate_below_horizon()}", "{locate_outside_az()}",
                                  "{locate_above_el()}"};
  auto answers = [&](const Profile& p) {
    std::vector<std::string> out;
    for (const char* t : kTargets) out.push_back(expand(t, p).text);
    return out;
  };
  auto on_a_new_thread = [&](const Profile& p) {
    std::vector<std::string> out;
    std::thread([&] { out = answers(p); }).join();
    return out;
  };
  const Profile base = southern_site();
  std::vector<Profile> changed(8, base);
  changed[0].navigation.latitude_min = *base.navigation.latitude_min + 600;
  changed[1].navigation.longitude_min = *base.navigation.longitude_min - 1200;
  changed[2].navigation.heading_tenths = 900;
  changed[3].az.min_deg = base.az.min_deg + 40;
  changed[4].az.max_deg = base.az.max_deg - 10;
  changed[5].el.min_deg = 20;
  changed[6].el.max_deg = 30;
  changed[7].navigation.latitude_min.reset();
  const auto first = answers(base);
  EXPECT_EQ(first, on_a_new_thread(base));
  for (const Profile& p : changed) {
    const auto got = answers(p);
    EXPECT_EQ(got, on_a_new_thread(p));
    EXPECT_EQ(answers(base), first) << "asked again after another profile";
  }
  EXPECT_NE(answers(changed[6]), first) << "a lower elevation limit moves the targets";
}

TEST(Expressions, CapturesAreNumbersWhenTheyReadAsNumbers) {
  const Profile p;
  const std::map<std::string, std::string> captures{{"$az0", "  30.0"}, {"$name", "SBS 6"}};
  EXPECT_EQ(expand("{$az0 + 0.5}", p, &captures).text, "30.5");
  EXPECT_EQ(expand("{$name}", p, &captures).text, "SBS 6");
  EXPECT_EQ(expand("{$name + 1}", p, &captures).kind, Kind::kError);
  EXPECT_EQ(expand("{$other}", p, &captures).kind, Kind::kError);
}

// text(): a capture as the reply held it, for a matcher that compares two
// readings character for character (a name "0123", a heading "180.0T", a
// right-justified position), where $x alone is read as a number.
TEST(Expressions, TextGivesACaptureAsItWasRead) {
  const Profile p;
  const std::map<std::string, std::string> captures{
      {"$name", "0123"}, {"$heading", "180.0T"}, {"$az", "   0.0"}, {"$byte", "0x47"}, {"$sat", "SBS 6"}};
  EXPECT_EQ(expand("{$name}", p, &captures).text, "123");
  EXPECT_EQ(expand("{text($name)}", p, &captures).text, "0123");
  EXPECT_EQ(expand("{text($heading)}", p, &captures).text, "180.0T");
  EXPECT_EQ(expand("{text($az)}", p, &captures).text, "   0.0");
  EXPECT_EQ(expand("{text($byte)}", p, &captures).text, "0x47");
  EXPECT_EQ(expand("{text($sat)}", p, &captures).text, "SBS 6");
  EXPECT_EQ(expand("{text($name + 1)}", p, &captures).text, "124") << "a computed number has no text of its own";
  EXPECT_EQ(expand("{text(2.50)}", p, &captures).text, "2.5");
}

TEST(Expressions, ACaptureIsANumberOnlyWhenAllOfItIsOne) {
  const Profile p;
  const std::map<std::string, std::string> captures{
      {"$heading", "180.0T"}, {"$magnetic", " 90.5M"}, {"$prefix", "12abc"}, {"$nan", "nan"},
      {"$inf", "inf"},        {"$letter", "T"},        {"$sum", "1-2"},      {"$plus", "+7"},
      {"$byte", "0x57"},      {"$hex_tail", "0x5g"}};
  // A one-byte field's text is its 0xNN.
  EXPECT_EQ(expand("{bitand($byte, 0x0f)}", p, &captures).text, "7");
  // A fluxgate heading keeps its reference letter (§3.2, E-12).
  EXPECT_EQ(expand("{$heading + 0.1}", p, &captures).text, "180.1");
  EXPECT_EQ(expand("{$magnetic}", p, &captures).text, "90.5");
  EXPECT_EQ(expand("{$plus + 1}", p, &captures).text, "8");
  for (const std::string name : {"$prefix", "$nan", "$inf", "$letter", "$sum", "$hex_tail"}) {
    EXPECT_EQ(expand(std::string(1, '{').append(name).append("}"), p, &captures).text, captures.at(name)) << name;
    EXPECT_EQ(expand(std::string(1, '{').append(name).append(" + 1}"), p, &captures).kind, Kind::kError) << name;
  }
  EXPECT_EQ(expand_number("{$prefix}", ExprContext{p, &captures}).kind, Kind::kError);
}

// Any number a vector writes is handled: out-of-range arguments and results
// are errors or unavailable, never a conversion out of an integer's range.
TEST(Expressions, HugeNumbersAreErrorsNotConversions) {
  Profile p;
  for (int i = 1; i <= 5; ++i) p.presets.push_back({static_cast<std::uint8_t>(i), {}, false});
  struct Case {
    const char* expression;
    Kind kind;
    const char* text;  // the whole text, or "" when only the kind is checked
  };
  const Case cases[] = {
      {"{1e300 * 1e300}", Kind::kError, "{1e300 * 1e300}: a number too large (overflow)"},
      {"{-1e308 - 1e308}", Kind::kError, "{-1e308 - 1e308}: a number too large (overflow)"},
      {"{1e300 / 1e-300}", Kind::kError, "{1e300 / 1e-300}: a number too large (overflow)"},
      {"{filled(presets, 1e20)}", Kind::kError, "{filled(presets, 1e20)}: filled: 1e+20 is not an index of presets"},
      {"{filled(presets, 2.5)}", Kind::kError, "{filled(presets, 2.5)}: filled: 2.5 is not an index of presets"},
      {"{filled(presets, 2)}", Kind::kValue, "2"},
      {"{preset_flag(-1e12)}", Kind::kError, ""},
      {"{peer(-1)}", Kind::kUnavailable, ""},
      {"{peer(1e30)}", Kind::kUnavailable, ""},
      {"{other_address(1e15)}", Kind::kUnavailable, ""},
      {"{foreign(1e15)}", Kind::kError, "{foreign(1e15)}: foreign: 1e+15 is not a 7-bit address"},
      {"{foreign(0x12)}", Kind::kValue, "18"},
      {"{first_empty_upto(presets, 1e20)}", Kind::kValue, "6"},
      {"{first_filled_upto(presets, -1e20)}", Kind::kUnavailable, ""},
      {"{jog_start(E, F, 1e20)}", Kind::kUnavailable, ""},
      {"{move_target(az, 0, 1e20)}", Kind::kUnavailable, ""},
      {"{bitxor(1e20, 1)}", Kind::kError, "{bitxor(1e20, 1)}: bitxor: 1e+20 is out of range 0 to 4294967295"},
      {"{bitand(-1, 1)}", Kind::kError, "{bitand(-1, 1)}: bitand: -1 is out of range 0 to 4294967295"},
      {"{bitxor(0x32, 0x20)}", Kind::kValue, "18"},
      {"{frame_with_check(300)}", Kind::kError,
       "{frame_with_check(300)}: frame_with_check: 300 is out of range 0 to 127 (a 7-bit check byte)"},
  };
  for (const Case& c : cases) {
    const Expansion e = expand(c.expression, p);
    EXPECT_EQ(e.kind, c.kind) << c.expression << ": " << e.text;
    if (*c.text) {
      EXPECT_EQ(e.text, c.text) << c.expression;
    }
  }
  EXPECT_EQ(format_number(1e20), "1e+20");
  EXPECT_EQ(format_number(-1e15), "-1e+15");
  EXPECT_EQ(format_number(999999999999999.0), "999999999999999");
}

// §3.16, ERRATA E-85: a reading's counts, one count either way; a position
// whose count lies past five digits may show any count (held at an end or
// wrapped), so its bounds widen to 0 and 99999.
TEST(Expressions, CountBoundsAreTheReadingsCountsOrAnyPastFiveDigits) {
  Profile p = profile_with_el(-10, 80, 2, 1);
  p.count_offset = 10000;
  p.counts_per_degree = 1000;
  EXPECT_EQ(expand("{count_low(el, 20)}", p).text, "29899");
  EXPECT_EQ(expand("{count_high(el, 20)}", p).text, "30101");
  EXPECT_EQ(expand("{count_low(el, 89.95)}", p).text, "0");  // 99850 to 100050
  EXPECT_EQ(expand("{count_high(el, 89.95)}", p).text, "99999");
  EXPECT_EQ(expand("{count_low(el, -9.95)}", p).text, "0");  // -50 to 150
  EXPECT_EQ(expand("{count_high(el, -9.95)}", p).text, "99999");
}

TEST(Expressions, ACountIsWholeAndInRange) {
  EXPECT_EQ(count_in(12.9, 1, 20).value, 12);
  EXPECT_EQ(count_in(12.9, 1, 20).error, std::nullopt);
  EXPECT_EQ(count_in(20, 1, 20).value, 20);
  EXPECT_EQ(count_in(21, 1, 20).error, "21 is out of range 1 to 20");
  EXPECT_EQ(count_in(0.5, 1, 20).error, "0.5 is out of range 1 to 20");
  EXPECT_EQ(count_in(1e19, 0, 3600000).error, "1e+19 is out of range 0 to 3600000");
  EXPECT_TRUE(count_in(std::numeric_limits<double>::quiet_NaN(), 0, 1).error.has_value());
  EXPECT_TRUE(count_in(-std::numeric_limits<double>::infinity(), 0, 1).error.has_value());
}

TEST(Expressions, AMissingCapabilityIsUnavailableWithItsReason) {
  Profile p;
  p.az.has_stow_limit = false;
  const Expansion e = expand("{stow_deg(az)}", p);
  EXPECT_EQ(e.kind, Kind::kUnavailable);
  EXPECT_NE(e.text.find("stow limit on the azimuth"), std::string::npos) << e.text;

  p.presets.clear();
  EXPECT_EQ(expand("{first_empty(presets)}", p).text, "1");
  EXPECT_EQ(expand("{last_empty(presets)}", p).text, "20");
  EXPECT_EQ(expand("{first_filled(presets)}", p).kind, Kind::kUnavailable);
  for (int i = 1; i <= 20; ++i) p.presets.push_back({static_cast<std::uint8_t>(i), {}, false});
  const Expansion full = expand("{first_empty(presets)}", p);
  EXPECT_EQ(full.kind, Kind::kUnavailable);
  EXPECT_NE(full.text.find("every one filled"), std::string::npos) << full.text;
  EXPECT_EQ(expand("{last_filled(presets)}", p).text, "20");
  EXPECT_EQ(expand("{filled(presets, 7)}", p).text, "7");
  p.presets.pop_back();  // slot 20
  EXPECT_EQ(expand("{filled(presets, 20)}", p).kind, Kind::kUnavailable);
  EXPECT_EQ(expand("{first_filled_upto(presets, 10)}", p).text, "1");
}

// second_filled: the second slot a profile fills, for a write of two slots
// read back each to its own record (issue 32); unavailable below two.
TEST(Expressions, SecondFilledSlotNeedsTwo) {
  Profile p;
  p.tles.clear();
  EXPECT_EQ(expand("{second_filled(tles)}", p).kind, Kind::kUnavailable);
  p.tles.push_back({4, "", ""});
  const Expansion one = expand("{second_filled(tles)}", p);
  EXPECT_EQ(one.kind, Kind::kUnavailable);
  EXPECT_NE(one.text.find("two filled TLE slots"), std::string::npos) << one.text;
  p.tles.push_back({9, "", ""});
  EXPECT_EQ(expand("{second_filled(tles)}", p).text, "9");
  EXPECT_EQ(expand("{first_filled(tles)}", p).text, "4");
}

// firmware(): the version §3.1 bytes 5-8 report, as the profile states it.
TEST(Expressions, FirmwareIsTheProfilesVersionAsText) {
  Profile p;
  p.firmware = "2.07";
  EXPECT_EQ(expand("{firmware()}", p).text, "2.07");
}

// other_address: another valid address (§1: 31h-6Fh) on either side of the
// device's, one no controller on the line has (issue 22: at 111 it is 110).
TEST(Expressions, AnotherAddressIsTakenOnEitherSide) {
  Profile p;
  p.address = 50;
  EXPECT_EQ(expand("{other_address(1)}", p).text, "51");
  p.address = 0x6F;
  EXPECT_EQ(expand("{other_address(1)}", p).text, "110") << "the one below at the highest address";
  p.address = 0x31;
  EXPECT_EQ(expand("{other_address(1)}", p).text, "50");
  p.address = 50;
  p.bus_peers = {51};
  EXPECT_EQ(expand("{other_address(1)}", p).text, "49") << "the one above answers: the one below";
  p.bus_peers = {49, 51};
  const Expansion both = expand("{other_address(1)}", p);
  EXPECT_EQ(both.kind, Kind::kUnavailable);
  EXPECT_NE(both.text.find("address 51 free on the line"), std::string::npos) << both.text;
  p.address = 0x31;
  p.bus_peers = {0x32};
  const Expansion edge = expand("{other_address(1)}", p);
  EXPECT_EQ(edge.kind, Kind::kUnavailable);
  EXPECT_NE(edge.text.find("address 50 free on the line"), std::string::npos) << edge.text;
}

TEST(Expressions, ErrorsNameTheProblem) {
  const Profile p;
  EXPECT_NE(expand("{nope(az)}", p).text.find("unknown function nope()"), std::string::npos);
  EXPECT_NE(expand("{home(az, el)}", p).text.find("takes 1 argument"), std::string::npos);
  EXPECT_NE(expand("{home(x)}", p).text.find("must be an axis"), std::string::npos);
  EXPECT_NE(expand("{home(az)", p).text.find("no closing"), std::string::npos);
  EXPECT_NE(expand("a}b", p).text.find("closes no placeholder"), std::string::npos);
  EXPECT_NE(expand("{1 +}", p).text.find("expected a value"), std::string::npos);
  EXPECT_EQ(expand("{1 / 0}", p).kind, Kind::kError);
}

TEST(Expressions, LoadTimeCheckNeedsEveryCaptureFromAnEarlierStep) {
  EXPECT_EQ(check_template("{home(az)}", {}), std::nullopt);
  EXPECT_NE(check_template("{$az0 + 1}", {}), std::nullopt);
  EXPECT_EQ(check_template("{$az0 + 1}", {"$az0"}), std::nullopt);
  EXPECT_NE(check_template("{jog_ms(az)}", {}), std::nullopt);
  EXPECT_EQ(template_captures("{$a} and {$b + home(el)}"), (std::set<std::string>{"$a", "$b"}));
}

TEST(Expressions, NumbersAreWrittenWithTheDigitsTheyNeed) {
  EXPECT_EQ(format_number(30), "30");
  EXPECT_EQ(format_number(-2.5), "-2.5");
  EXPECT_EQ(format_number(12.25), "12.25");
  EXPECT_EQ(format_number(-0.0), "0");
  const Profile p;
  EXPECT_EQ(expand_number("{home(el)}", ExprContext{p}).value, 42.5);
  EXPECT_EQ(expand_number("abc", ExprContext{p}).kind, Kind::kError);
}

// away_from promises a move of at least `ms` to `to` however the move that
// put the axis there ended within its tolerance: seen on the reference
// controller, approaching from either end, with tolerances up to 5 deg
// (sweep seed 12383529513502669763: a tolerance of 1.4 deg at 0.27 deg/s
// left a DEPLOY no move at all when only one tolerance was allowed for).
TEST(Motion, AwayFromLeavesAMoveOfAtLeastItsTimeWhereverTheSetupStopped) {
  for (const double tolerance : {0.1, 1.4, 5.0})
    for (const double start : {-3.8, 81.3}) {
      Profile p;
      p.el.min_deg = -3.8;
      p.el.max_deg = 81.3;
      p.el.fast_dps = 0.27;
      p.el.tolerance_deg = tolerance;
      p.el.initial_deg = start;
      VirtualClock clock;
      Controller c(p, clock);
      const double to = 36;
      const auto from = motion::away_from(p.el, to, 3000, "elevation");
      ASSERT_TRUE(from.value) << from.reason;
      auto move_el = [&](double deg) {
        const auto tenths = static_cast<std::int32_t>(std::lround(deg * 10));
        c.execute(request_frame(AutoMove{AutoMoveAzEl{0, tenths}}, p.address));
        for (int i = 0; i < 100000 && c.state().el.motion != AxisState::Motion::kIdle; ++i) {
          clock.advance(std::chrono::milliseconds(10));
          c.update();
        }
      };
      move_el(*from.value);
      const auto t0 = clock.now();
      move_el(to);
      EXPECT_GE(clock.now() - t0, std::chrono::milliseconds(3000))
          << "tolerance " << tolerance << ", from " << start << " via " << *from.value;
    }
}

TEST(Motion, AJogTravelsSpeedTimesTheTimerWithinOneTickEitherWay) {
  AxisProfile a;
  a.fast_dps = 2;
  const auto t = motion::jog_travel(a, 'F', 1000);
  EXPECT_DOUBLE_EQ(t.low, 2 * 0.95);
  EXPECT_DOUBLE_EQ(t.high, 2 * 1.05);
  const auto odd = motion::jog_travel(a, 'F', 1020);  // "approx." a multiple of 50: 1000 or 1050
  EXPECT_DOUBLE_EQ(odd.low, 2 * 0.95);
  EXPECT_DOUBLE_EQ(odd.high, 2 * 1.10);
  EXPECT_EQ(motion::jog_travel(a, 'F', 0).high, 0) << "E-61: 0000 does not move";
}

TEST(Motion, ARampShortensTheShortestTravelAndNeverTheLongest) {
  AxisProfile a;
  a.fast_dps = 10;
  a.accel_dps2 = 40;  // 0.25 s to full speed
  const auto t = motion::jog_travel(a, 'F', 1000);
  EXPECT_DOUBLE_EQ(t.low, 10 * 0.95 - 10 * 10 / 40.0);  // ramps up and down inside the timer
  EXPECT_DOUBLE_EQ(t.high, 10 * 1.05);                  // ramps down after it
  a.accel_dps2 = 20;  // 0.5 s up, 0.5 s down: full speed never reached inside 0.95 s
  EXPECT_DOUBLE_EQ(motion::jog_travel(a, 'F', 1000).low, 20 * 0.95 * 0.95 / 4);
  const auto short_jog = motion::jog_travel(a, 'F', 200);
  EXPECT_DOUBLE_EQ(short_jog.low, 20 * 0.15 * 0.15 / 4);
  EXPECT_DOUBLE_EQ(short_jog.high, 20 * 0.25 * 0.25);
}

TEST(Motion, AJogEndsWithinTheLimitsAsReadRoundedOrTruncated) {
  AxisProfile a;
  a.min_deg = 0;
  a.max_deg = 90;
  a.fast_dps = 20;
  // 19-21 deg down from a reading of 10.0: the limit at 0, read 0.0 however shown.
  EXPECT_EQ(motion::jog_readings(a, motion::kTenths, 100, -1, 'F', 1000).tenths, (motion::Readings{0, 0}));
  // 1-3 deg up from a reading of 45.0, a position of 44.95 to 45.1: a
  // reading of 45.9 (44.95 + 1 rounded down at the tie) to 48.0 (the start's
  // reading and the 30 tenths of the longest travel).
  EXPECT_EQ(motion::jog_readings(a, motion::kTenths, 450, +1, 'F', 100).tenths, (motion::Readings{459, 480}));
  // '0000' does not move: the start's reading, whatever way it is shown.
  EXPECT_EQ(motion::jog_readings(a, motion::kTenths, 450, +1, 'F', 0).tenths, (motion::Readings{450, 450}));
  EXPECT_EQ(motion::jog_readings(a, motion::kHundredths, 450, +1, 'F', 0),
            (motion::PositionReadings{{450, 450}, motion::Readings{4500, 4509}}))
      << "45.0 on a hundredths display is 45.00 to 45.09 (E-30)";
}

TEST(Motion, AReadingAcrossZeroAllowsTheTruncationOfBothEnds) {
  // The profile of sweep seed 463807582702990695: a 1750 ms 'W' jog at
  // 0.36 deg/s from a reading of -0.4 on a hundredths display. The start
  // can be -0.49 (truncated toward zero, E-30) and the end 0.19 after
  // 0.612-0.648 deg: a reading of 0.1, which a bound of -0.4 + 0.612 - 0.1
  // in doubles (0.112) failed.
  AxisProfile a;
  a.min_deg = -10;
  a.max_deg = 10;
  a.fast_dps = 0.36;
  const auto r = motion::jog_readings(a, motion::kHundredths, -4, +1, 'F', 1750);
  EXPECT_TRUE(r.tenths.contains(1)) << r.tenths.low << " to " << r.tenths.high;
  EXPECT_FALSE(r.tenths.contains(-1)) << "0.612 deg at least: never still below zero";
  ASSERT_TRUE(r.hundredths);
  EXPECT_TRUE(r.hundredths->contains(12)) << "-0.49 + 0.612, truncated";
  EXPECT_FALSE(r.hundredths->contains(10));
}

TEST(Motion, AFluxgateHeadingOnAHundredthsDisplayIsTruncatedAsAHeading) {
  // The profile of sweep seed 1572771045374231305: a 500 ms 'E' jog at 1.42
  // deg/s from a heading of 0.5 (0.50 to 0.59, a fluxgate azimuth with
  // hundredths) ends 0.64 to 0.78 deg lower, at -0.28 to -0.05: a heading of
  // 359.72 to 359.95, whose tenths field truncates the heading to 359.7 to
  // 359.9, that is -0.3 to -0.1 (truncation toward zero of the position
  // would give -0.2 to 0.0, and 359.7M was read).
  AxisProfile a;
  a.min_deg = -180;
  a.max_deg = 180;
  a.fast_dps = 1.42;
  const auto heading = motion::jog_readings(a, motion::kHundredths, 5, -1, 'F', 500, true);
  EXPECT_TRUE(heading.tenths.contains(-3)) << heading.tenths.low << " to " << heading.tenths.high;
  EXPECT_FALSE(heading.tenths.contains(1)) << "0.64 deg at least below 0.59";
  const auto position = motion::jog_readings(a, motion::kHundredths, 5, -1, 'F', 500);
  EXPECT_TRUE(position.tenths.contains(-3)) << "a negative position's tenths rounded down (E-87's other side)";
  EXPECT_FALSE(position.tenths.contains(-4)) << "-0.28 at most: -0.2 truncated toward zero (E-30), -0.3 rounded down";
  // A heading of 359.7 read where the range says -0.3: 359.70 to 359.79, so
  // -0.30 to -0.21, not the -0.39 to -0.30 of a negative position.
  const auto from_negative = motion::jog_readings(a, motion::kHundredths, -3, +1, 'F', 0, true);
  ASSERT_TRUE(from_negative.hundredths);
  EXPECT_EQ(*from_negative.hundredths, (motion::Readings{-30, -21}));
}

TEST(Motion, AReadingIsShownRoundedOrTruncatedAndItsTenthsAreTruncated) {
  using motion::Shown;
  EXPECT_EQ(motion::shown(-0.47, 100, Shown::kRounded), -47);
  EXPECT_EQ(motion::shown(-0.47, 10, Shown::kRounded), -5);
  EXPECT_EQ(motion::shown(-0.47, 10, Shown::kTruncated), -4);
  EXPECT_EQ(motion::shown(-0.47, 10, Shown::kTruncatedDown), -5);
  EXPECT_EQ(motion::shown(0.3, 10, Shown::kTruncated), 3) << "0.3 * 10 is 2.9999999999999996 in doubles";
  EXPECT_EQ(motion::shown(0.25, 10, Shown::kRounded), 3) << "a tie away from zero";
  EXPECT_EQ(motion::tenths_of(-47, 100), -4) << "E-30: the hundredths digit extends the magnitude";
  EXPECT_EQ(motion::tenths_of(47, 100), 4);
  EXPECT_EQ(motion::tenths_of(-47, 10), -47);
}

TEST(Motion, NearIsAReadingWithinTheToleranceInTheDisplaysUnits) {
  // Form 2C to 12.25 with a tolerance of 0.1: 12.15 to 12.35 as read.
  EXPECT_EQ(motion::near_readings(12.25, 0.1, motion::kHundredths),
            (motion::PositionReadings{{121, 123}, motion::Readings{1215, 1235}}));
  // -12.35 has the tenths field -12.3 (toward zero, E-30) or -12.4 (rounded
  // down, E-87's other side).
  EXPECT_EQ(motion::near_readings(-12.25, 0.1, motion::kHundredths),
            (motion::PositionReadings{{-124, -121}, motion::Readings{-1235, -1215}}));
  // In doubles -0.4 + 0.1 is -0.30000000000000004: still 3 tenths.
  EXPECT_EQ(motion::near_readings(-0.4, 0.1, motion::kTenths), (motion::PositionReadings{{-5, -3}, std::nullopt}));
  EXPECT_EQ(motion::readings_between(-0.4 + 0.1, 0.3, motion::kTenths), (motion::Readings{-3, 3}));
  EXPECT_EQ(motion::readings_between(1e300, -1e300, motion::kTenths).low > 0, true) << "an empty window, not an overflow";
}

TEST(Motion, AMeasurableJogMovesAtLeastHalfADegreeAndStaysOffTheLimits) {
  AxisProfile a;
  a.min_deg = 0;
  a.max_deg = 90;
  for (double v : {0.1, 0.5, 5.0, 20.0, 50.0}) {
    a.fast_dps = v;
    const auto ms = motion::measurable_jog_ms(a, 'F', "elevation");
    ASSERT_TRUE(ms.value) << v << ": " << ms.reason;
    const auto t = motion::jog_travel(a, 'F', *ms.value);
    EXPECT_GE(t.low - motion::kDisplayResolution, 0.5) << v;
    EXPECT_LE(t.high, 45.0) << v;
  }
  a.min_deg = 0;
  a.max_deg = 10;
  a.fast_dps = 50;
  const auto none = motion::measurable_jog_ms(a, 'F', "elevation");
  EXPECT_FALSE(none.value);
  EXPECT_NE(none.reason.find("elevation"), std::string::npos) << none.reason;
}

TEST(Motion, AJogStartLeavesRoomForTheWholeDuration) {
  AxisProfile a;
  a.min_deg = 0;
  a.max_deg = 90;
  a.slow_dps = 5;
  const auto up = motion::jog_start(a, +1, 'S', 4000, "elevation");  // 20 deg of room above
  ASSERT_TRUE(up.value);
  EXPECT_LE(*up.value + 20.0, 90.0);
  EXPECT_EQ(*up.value, 45.0) << "home leaves room enough";
  const auto far = motion::jog_start(a, +1, 'S', 12000, "elevation");  // 60 deg
  ASSERT_TRUE(far.value);
  EXPECT_LE(*far.value + 60.0, 90.0);
  EXPECT_FALSE(motion::jog_start(a, +1, 'S', 20000, "elevation").value) << "100 deg do not fit in 90";
}

TEST(Motion, AMoveTargetLastsLongEnoughOrSaysWhyNot) {
  AxisProfile a;
  a.min_deg = -180;
  a.max_deg = 180;
  a.fast_dps = 2;
  const auto t = motion::move_target(a, -170.0, 3000, "azimuth");
  ASSERT_TRUE(t.value);
  EXPECT_EQ(*t.value, 162.0);
  a.fast_dps = 500;
  EXPECT_FALSE(motion::move_target(a, 0.0, 3000, "azimuth").value);
}

}  // namespace
}  // namespace sabus::harness
