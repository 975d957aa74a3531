// Random legal device profiles (profile_generator.hpp): every one passes the
// loader after to_yaml and reads back equal, a seed always gives the same
// profile, the draws stay inside their stated ranges, and over many seeds
// every value of every enumeration and every shape of the stored lists
// turns up.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <set>
#include <string>

#include "sabus/harness/profile_generator.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "yaml_text.hpp"

namespace sabus::harness {
namespace {

RC_GTEST_PROP(ProfileGenerator, EveryProfileLoadsBackEqualAfterToYaml, (std::uint64_t seed)) {
  const Profile p = random_profile(seed);
  const std::string yaml = to_yaml(p);
  const ProfileResult back = load_profile_text(yaml, "random.yaml");
  if (!back) RC_FAIL(back.error->text() + "\n" + yaml);
  Profile loaded = *back.profile;
  loaded.source = p.source;
  RC_ASSERT(loaded == p);
  RC_ASSERT(to_yaml(loaded) == yaml);
}

// As `sabus vectors sweep` writes a failing profile: under a comment of its
// failures, which may hold anything a vector or a controller said. Any
// bytes at all: the profile reads back equal and the file stays valid.
RC_GTEST_PROP(ProfileGenerator, EveryProfileLoadsBackEqualUnderAnyComment, (std::uint64_t seed)) {
  const std::string comment =
      *rc::gen::container<std::string>(rc::gen::map(rc::gen::inRange(0, 256), [](int b) { return static_cast<char>(b); }));
  const Profile p = random_profile(seed);
  const std::string yaml = to_yaml(p, comment);
  RC_ASSERT(test::yaml_text_problem(yaml).empty());
  const ProfileResult back = load_profile_text(yaml, "random.yaml");
  if (!back) RC_FAIL(back.error->text() + "\n" + yaml);
  Profile loaded = *back.profile;
  loaded.source = p.source;
  RC_ASSERT(loaded == p);
}

RC_GTEST_PROP(ProfileGenerator, ASeedAlwaysGivesTheSameProfile, (std::uint64_t seed)) {
  RC_ASSERT(random_profile(seed) == random_profile(seed));
  RC_ASSERT(random_profile(seed).name == "random-" + std::to_string(seed));
}

void check_axis(const AxisProfile& a) {
  RC_ASSERT(a.fast_dps >= 0.1);
  RC_ASSERT(a.fast_dps <= 50.0);
  RC_ASSERT(a.slow_dps >= 0.1);
  RC_ASSERT(a.slow_dps <= a.fast_dps);
  RC_ASSERT(a.max_deg - a.min_deg >= 10.0 - 1e-9);  // as the loader compares: -61.6 - -71.6 is 9.999999999999993
  RC_ASSERT(a.tolerance_deg >= 0.1);
  RC_ASSERT(a.tolerance_deg <= 5.0);
  if (a.accel_dps2) {
    RC_ASSERT(*a.accel_dps2 >= 0.5);
    RC_ASSERT(*a.accel_dps2 <= 500.0);
  }
}

bool inside(const AxisProfile& a, double x) { return x >= a.min_deg && x <= a.max_deg; }

RC_GTEST_PROP(ProfileGenerator, DrawsStayInsideTheirStatedRanges, (std::uint64_t seed)) {
  const Profile p = random_profile(seed);
  for (const AxisProfile* a : {&p.az, &p.el, &p.pol}) check_axis(*a);
  RC_ASSERT(p.turnaround_ms >= 0.0);
  RC_ASSERT(p.turnaround_ms <= kRandomMaxTurnaroundMs);
  for (const auto& s : p.store) {
    RC_ASSERT(inside(p.az, s.az_deg));
    RC_ASSERT(inside(p.el, s.el_deg));
    RC_ASSERT(inside(p.pol, s.h_pol_deg));
    RC_ASSERT(inside(p.pol, s.v_pol_deg));
  }
  for (const auto& s : p.presets) {
    if (s.index > 10) RC_ASSERT(s.data.ephemeris == '0');  // E-51
    if (s.dual_band) RC_ASSERT(s.data.band == '2');        // C/Ku
  }
  RC_ASSERT(p.signposts.empty() || p.dvb_receiver);
  RC_ASSERT((p.locate_index_min == 1 && p.locate_index_max == 20) ||
            (p.locate_index_min == 0 && p.locate_index_max == 19));  // E-22's two readings
}

// Over many seeds: each value of each enumeration, and each shape of each
// list, at least once.
TEST(ProfileGenerator, ManySeedsCoverEveryValueAndShape) {
  std::set<std::string> seen;
  auto mark = [&](const std::string& what) { seen.insert(what); };
  auto size_shape = [](std::size_t n, std::size_t max) { return n == 0 ? "empty" : n == max ? "full" : "partly filled"; };
  for (std::uint64_t seed = 0; seed < 2000; ++seed) {
    const Profile p = random_profile(seed);
    mark("track.activity " + std::to_string(static_cast<int>(p.track.activity)));
    mark("track.band " + std::to_string(static_cast<int>(p.track.band)));
    mark(std::string("track.active ") + (p.track.active ? "on" : "off"));
    mark(std::string("track.dual_band ") + (p.track.dual_band ? "on" : "off"));
    mark("polarization " + std::to_string(static_cast<int>(p.pol_type)));
    mark("azimuth_sensor " + std::to_string(static_cast<int>(p.az_sensor)));
    mark(std::string("fluxgate_heading ") + p.fluxgate_heading);
    mark("agc_channel " + std::to_string(p.agc_channel));
    mark("baud " + std::to_string(p.baud));
    mark(std::string("display.pol_code ") + (p.display.pol_code ? std::string(1, p.display.pol_code) : "none"));
    mark(std::string("display.satellite ") + (p.display.satellite.empty() ? "blank" : "named"));
    for (const auto& [name, on] : std::initializer_list<std::pair<const char*, bool>>{{"remote_enabled", p.remote_enabled},
                                   {"hundredths", p.hundredths},
                                   {"stow", p.stow},
                                   {"deploy", p.deploy},
                                   {"dvb_receiver", p.dvb_receiver},
                                   {"bus_peers", !p.bus_peers.empty()},
                                   {"stx_restarts_in_data", p.stx_restarts_in_data},
                                   {"implements_signal_strength", p.implements_signal_strength},
                                   {"implements_iess", p.implements_iess},
                                   {"nak_bad_tle_checksum", p.nak_bad_tle_checksum},
                                   {"restore_lost_locate_exit", p.restore_lost_locate_exit},
                                   {"locate_index_min 0", p.locate_index_min == 0},
                                   {"unknown_command_while_offline offline",
                                    p.unknown_command_while_offline == OfflineUnknown::kOffline}})
      mark(std::string(name) + (on ? " on" : " off"));
    for (const AxisProfile* a : {&p.az, &p.el, &p.pol}) {
      mark(std::string("accel ") + (a->accel_dps2 ? "on" : "off"));
      mark(std::string("tolerance ") + (a->tolerance_deg > 0.1 ? "wide" : "0.1"));
      mark(std::string("power_on_speed ") + (a->power_on_speed == AxisSpeed::kFast ? "fast" : "slow"));
      mark(std::string("ad_error ") + (a->ad_error ? "on" : "off"));
      mark(std::string("stow limit ") + (a->has_stow_limit ? "on" : "off"));
      if (a->initial_deg == a->min_deg || a->initial_deg == a->max_deg) mark("initial at a limit");
    }
    mark(std::string("elevation ") + (p.el.min_deg < 0 ? "below 0" : "not below 0"));
    // LOCATE geometry (E-80, E-81): sites in every quarter of the globe and
    // mounts that leave part of the sky out of reach.
    if (p.el.max_deg < 60) mark("elevation short of the high sky");
    if (p.az.max_deg - p.az.min_deg < 180) mark("azimuth under half a turn");
    if (p.navigation.latitude_min && p.navigation.longitude_min)
      mark(std::string("site ") + (*p.navigation.latitude_min < 0 ? "south" : "north") +
           (*p.navigation.longitude_min < 0 ? " west" : " east"));
    mark(std::string("store ") + size_shape(p.store.size(), 50));
    mark(std::string("presets ") + size_shape(p.presets.size(), 20));
    mark(std::string("tles ") + size_shape(p.tles.size(), 10));
    if (p.dvb_receiver) mark(std::string("signposts ") + size_shape(p.signposts.size(), 20));
    mark("navigation latlon_source " + std::to_string(p.navigation.latlon_source));
    mark("navigation heading_source " + std::to_string(p.navigation.heading_source));
    mark(std::string("magvar ") + (p.navigation.magvar_tenths ? "ready" : "not ready"));
    if (p.alarms.az || p.alarms.el || p.alarms.pol) mark("axis alarm");
    if (p.alarms.code) mark("alarm code");
  }
  std::set<std::string> want;
  for (int i = 0; i < 14; ++i) want.insert("track.activity " + std::to_string(i));
  for (int i = 1; i <= 7; ++i) want.insert("track.band " + std::to_string(i));
  for (int i = 0; i < 3; ++i) want.insert("polarization " + std::to_string(i));
  for (int i = 0; i < 4; ++i) want.insert("azimuth_sensor " + std::to_string(i));
  for (int i = 1; i <= 3; ++i) want.insert("agc_channel " + std::to_string(i));
  for (int b : {300, 600, 1200, 2400, 4800, 9600}) want.insert("baud " + std::to_string(b));
  for (const char* v : {"H", "h", "V", "v", "none"}) want.insert(std::string("display.pol_code ") + v);
  for (const char* v : {"T", "M"}) want.insert(std::string("fluxgate_heading ") + v);
  for (const char* k : {"track.active", "track.dual_band", "remote_enabled", "hundredths", "stow", "deploy", "dvb_receiver",
                        "bus_peers", "stx_restarts_in_data", "implements_signal_strength", "implements_iess",
                        "nak_bad_tle_checksum", "restore_lost_locate_exit", "locate_index_min 0",
                        "unknown_command_while_offline offline", "accel", "ad_error", "stow limit"})
    for (const char* v : {" on", " off"}) want.insert(std::string(k) + v);
  for (const char* k : {"store", "presets", "tles", "signposts"})
    for (const char* v : {" empty", " partly filled", " full"}) want.insert(std::string(k) + v);
  for (int s : {1, 2, 3, 4, 5, 7}) want.insert("navigation latlon_source " + std::to_string(s));
  for (int s = 1; s <= 7; ++s) want.insert("navigation heading_source " + std::to_string(s));
  for (const char* w : {"tolerance wide", "tolerance 0.1", "power_on_speed fast", "power_on_speed slow",
                        "elevation short of the high sky", "azimuth under half a turn", "site north east",
                        "site north west", "site south east", "site south west",
                        "initial at a limit", "elevation below 0", "elevation not below 0", "magvar ready",
                        "magvar not ready", "axis alarm", "alarm code", "display.satellite blank",
                        "display.satellite named"})
    want.insert(w);
  for (const auto& w : want) EXPECT_TRUE(seen.count(w)) << "never drawn: " << w;
}

}  // namespace
}  // namespace sabus::harness
