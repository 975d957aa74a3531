// Device profiles: the shipped files, the loader's errors (line, column and
// key path of the offending key), the writer's round trip, multi_drop, and
// that no input makes the loader throw. One suite, `profile`, so that
// `ctest -R profile` selects these tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <tuple>

#include "sabus/harness/profile.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "profile_tables.hpp"  // the enumeration names, checked name by name
#include "yaml_text.hpp"

namespace sabus::harness {
namespace {

namespace fs = std::filesystem;

fs::path profiles_dir() { return fs::path(default_profile_path()).parent_path(); }

std::vector<fs::path> shipped_profiles() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(profiles_dir()))
    if (e.path().extension() == ".yaml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Profile load_ok(std::string_view yaml) {
  auto r = load_profile_text(yaml, "test.yaml");
  if (!r) ADD_FAILURE() << r.error->text() << "\n--- input:\n" << yaml;
  return r.profile.value_or(Profile{});
}

ProfileError load_bad(std::string_view yaml) {
  auto r = load_profile_text(yaml, "test.yaml");
  EXPECT_FALSE(r) << "loaded although it should not:\n" << yaml;
  EXPECT_TRUE(r.error.has_value());
  return r.error.value_or(ProfileError{});
}

// line, column, key path, and a part of the message.
void expect_error(std::string_view yaml, int line, int column, std::string_view key, std::string_view message_part) {
  ProfileError e = load_bad(yaml);
  EXPECT_EQ(e.file, "test.yaml");
  EXPECT_EQ(e.line, line) << e.text();
  EXPECT_EQ(e.column, column) << e.text();
  EXPECT_EQ(e.key, key) << e.text();
  EXPECT_NE(e.message.find(message_part), std::string::npos) << e.text() << "\n  expected to contain: " << message_part;
}

// Every field of Profile except `source` (where it was read from); on a
// difference, both profiles as YAML.
void expect_same(const Profile& a, const Profile& b) {
  Profile x = a;
  x.source = b.source;
  EXPECT_TRUE(x == b) << "--- first:\n" << to_yaml(a) << "--- second:\n" << to_yaml(b);
}

// The TLE's own mod-10 checksum: digits count their value, '-' counts 1.
int tle_checksum(std::string_view line) {
  int sum = 0;
  for (char c : line.substr(0, 68)) sum += (c >= '0' && c <= '9') ? c - '0' : (c == '-' ? 1 : 0);
  return sum % 10;
}

// ---------------------------------------------------------------------------
// Shipped profiles
// ---------------------------------------------------------------------------

TEST(profile, ShippedFilesLoadAndAreNamedAfterTheirFiles) {
  auto files = shipped_profiles();
  EXPECT_GE(files.size(), 6u);
  for (const auto& f : files) {
    auto r = load_profile_file(f.string());
    ASSERT_TRUE(r) << r.error->text();
    EXPECT_EQ(r.profile->name, f.stem().string());
    EXPECT_EQ(r.profile->source, f.string());
  }
}

TEST(profile, DefaultFileValues) {
  auto r = load_profile_file(default_profile_path());
  ASSERT_TRUE(r) << r.error->text();
  const Profile& p = *r.profile;
  EXPECT_EQ(p.name, "rc3000-1.59");
  EXPECT_EQ(p.address, '2');  // decimal 50
  EXPECT_TRUE(p.remote_enabled);
  EXPECT_EQ(p.baud, 9600);
  EXPECT_EQ(p.firmware, "1.59");
  EXPECT_EQ(p.pol_type, PolType::kSinglePort);
  EXPECT_EQ(p.az_sensor, AzSensor::kPot);
  EXPECT_FALSE(p.hundredths);
  EXPECT_TRUE(p.stow);
  EXPECT_TRUE(p.deploy);
  EXPECT_FALSE(p.dvb_receiver);
  EXPECT_EQ(p.el.min_deg, -5.0);
  EXPECT_TRUE(p.el.has_stow_limit);

  ASSERT_EQ(p.store.size(), 3u);
  EXPECT_EQ(p.store[0], (StoredSatellite{"SBS 6", -152.5, 45.6, 50.0, -40.0}));
  EXPECT_EQ(p.store[1].name, "GALAXY 19");
  EXPECT_EQ(p.store[2].name, "AMC 21");

  ASSERT_EQ(p.presets.size(), 3u);
  EXPECT_EQ(p.presets[0].index, 1);
  EXPECT_EQ(p.presets[1].index, 2);
  EXPECT_EQ(p.presets[2].index, 20);
  EXPECT_EQ(p.presets[0].data.longitude, -740);  // tenths
  EXPECT_EQ(p.presets[0].data.band, '1');        // Ku
  EXPECT_EQ(p.presets[0].data.ephemeris, '1');   // TLE
  EXPECT_EQ(p.presets[1].data.band, '2');        // C/Ku
  EXPECT_TRUE(p.presets[1].dual_band);

  ASSERT_EQ(p.tles.size(), 1u);
  EXPECT_EQ(p.tles[0].index, 1);
  for (const auto& line : {p.tles[0].line1, p.tles[0].line2}) {
    ASSERT_EQ(line.size(), 69u);
    EXPECT_EQ(tle_checksum(line), line[68] - '0') << line;  // ERRATA E-19
  }
  EXPECT_TRUE(p.signposts.empty());

  EXPECT_EQ(p.navigation.latlon_source, 7);  // remotely entered
  EXPECT_EQ(p.navigation.latitude_min, 38 * 60 + 58);
  EXPECT_EQ(p.navigation.longitude_min, -(94 * 60 + 44));
  EXPECT_EQ(p.navigation.heading_source, 7);
  EXPECT_EQ(p.navigation.heading_tenths, 1800);
  EXPECT_EQ(p.navigation.magvar_tenths, 25);
  EXPECT_FALSE(p.track.active);

  // Errata switches at the errata's decisions = the struct's defaults.
  const Profile d;
  EXPECT_EQ(p.stx_restarts_in_data, d.stx_restarts_in_data);
  EXPECT_EQ(p.unknown_command_while_offline, d.unknown_command_while_offline);
  EXPECT_EQ(p.implements_signal_strength, d.implements_signal_strength);
  EXPECT_EQ(p.implements_iess, d.implements_iess);
  EXPECT_EQ(p.nak_bad_tle_checksum, d.nak_bad_tle_checksum);
  EXPECT_EQ(p.locate_index_min, d.locate_index_min);
  EXPECT_EQ(p.locate_index_max, d.locate_index_max);
  EXPECT_EQ(p.restore_lost_locate_exit, d.restore_lost_locate_exit);
}

// The default profile writes every key: with its stored data taken out it is
// the struct's defaults, so the files that rely on defaults mean what they say.
TEST(profile, DefaultFileIsTheStructDefaultsPlusStoredData) {
  auto r = load_profile_file(default_profile_path());
  ASSERT_TRUE(r);
  Profile p = *r.profile;
  p.store.clear();
  p.presets.clear();
  p.tles.clear();
  p.navigation = Navigation{};
  // Where its DEPLOY goes is this controller's (E-90), not a default that a
  // profile leaving it out would inherit.
  EXPECT_EQ(p.el.deploy_deg, 45.0);
  p.el.deploy_deg.reset();
  expect_same(p, Profile{});
}

Profile load_shipped(const std::string& name) {
  auto r = load_profile_file((profiles_dir() / (name + ".yaml")).string());
  EXPECT_TRUE(r) << r.error->text();
  return r.profile.value_or(Profile{});
}

TEST(profile, VariantFilesChangeWhatTheySay) {
  Profile circular = load_shipped("circular-no-stow");
  EXPECT_EQ(circular.pol_type, PolType::kCircular);
  EXPECT_FALSE(circular.stow);
  EXPECT_FALSE(circular.deploy);

  Profile dvb = load_shipped("dual-port-dvb-fluxgate");
  EXPECT_EQ(dvb.pol_type, PolType::kDualPort);
  EXPECT_EQ(dvb.az_sensor, AzSensor::kFluxgate);
  EXPECT_TRUE(dvb.hundredths);
  EXPECT_TRUE(dvb.dvb_receiver);
  ASSERT_EQ(dvb.signposts.size(), 2u);
  EXPECT_EQ(dvb.signposts[0].data.fec, '3');           // 3/4
  EXPECT_EQ(dvb.signposts[1].data.fec, '9');           // AUTO
  EXPECT_EQ(dvb.signposts[1].data.polarization, 'L');  // LHCP
  EXPECT_EQ(dvb.az.max_deg, 359.9);
  EXPECT_EQ(dvb.el.max_deg, 90.0);  // an axis not written keeps its own defaults

  EXPECT_FALSE(load_shipped("remote-disabled").remote_enabled);

  Profile track = load_shipped("track-peaking");
  EXPECT_TRUE(track.track.active);
  EXPECT_EQ(track.track.activity, TrackActivity::kPeaking);
  EXPECT_EQ(track.track.band, TrackBand::kC);
  EXPECT_TRUE(track.track.dual_band);

  Profile iess = load_shipped("iess-implemented");
  EXPECT_TRUE(iess.implements_signal_strength);
  EXPECT_TRUE(iess.implements_iess);
  EXPECT_FALSE(iess.nak_bad_tle_checksum);  // the other switches keep their defaults

  Profile pulse = load_shipped("pulse-counts");  // §3.3 form 2B needs count-type sensors
  EXPECT_EQ(pulse.az_sensor, AzSensor::kPulse);
  EXPECT_EQ(pulse.counts_per_degree, 100.0);
  EXPECT_EQ(pulse.count_offset, 10000);
  EXPECT_TRUE(pulse.store.empty());
}

// ---------------------------------------------------------------------------
// Values
// ---------------------------------------------------------------------------

TEST(profile, EmptyDocumentIsTheDefaultProfile) {
  expect_same(load_ok(""), Profile{});
  expect_same(load_ok("# only a comment\n"), Profile{});
}

// READING-NOTES 4 / ERRATA E-4.
TEST(profile, AddressAsDecimalSettingOrCharacter) {
  EXPECT_EQ(load_ok("address: 50").address, '2');
  EXPECT_EQ(load_ok("address: \"2\"").address, '2');
  EXPECT_EQ(load_ok("address: '2'").address, '2');
  EXPECT_EQ(load_ok("address: 49").address, 0x31);
  EXPECT_EQ(load_ok("address: 111").address, 0x6F);
  EXPECT_EQ(load_ok("address: \"o\"").address, 0x6F);
  EXPECT_EQ(load_ok("address: 0x32").address, '2');
}

TEST(profile, TenthsMinutesAndNulls) {
  Profile p = load_ok(
      "presets:\n"
      "  - {index: 3, name: X, longitude: -0.5, pol_offset: ~, inclination: 19}\n"
      "navigation: {latitude: \"00.30 S\", longitude: \"180.00 E\", heading: 359.9, magvar: -99.9}\n");
  EXPECT_EQ(p.presets[0].data.longitude, -5);
  EXPECT_EQ(p.presets[0].data.pol_offset, std::nullopt);
  EXPECT_EQ(p.navigation.latitude_min, -30);
  EXPECT_EQ(p.navigation.longitude_min, 180 * 60);
  EXPECT_EQ(p.navigation.heading_tenths, 3599);
  EXPECT_EQ(p.navigation.magvar_tenths, -999);
}

// ---------------------------------------------------------------------------
// Errors: line and column of the offending key (1-based), its path, a message
// ---------------------------------------------------------------------------

TEST(profile, ErrorUnknownKey) {
  expect_error("name: x\nbaudrate: 9600\n", 2, 1, "baudrate", "unknown key \"baudrate\"; allowed keys: name, address");
  expect_error("axes:\n  el:\n    fast: 1\n", 3, 5, "axes.el.fast", "allowed keys: fast_dps, slow_dps");
  expect_error("errata:\n  locate_index_range: 5\n", 2, 3, "errata.locate_index_range", "unknown key");
  expect_error("store:\n  - {name: A, az: 1}\n", 2, 15, "store[0].az", "unknown key \"az\"");
}

TEST(profile, ErrorWrongType) {
  expect_error("baud: fast\n", 1, 1, "baud", "expected a whole number, got \"fast\"");
  expect_error("name: x\nbaud: \"9600\"\n", 2, 1, "baud", "got the quoted string \"9600\"");
  expect_error("remote_enabled: yes\n", 1, 1, "remote_enabled", "expected true or false");
  expect_error("axes: [1, 2]\n", 1, 1, "axes", "expected a map, got a list");
  expect_error("store: {name: A}\n", 1, 1, "store", "expected a list, got a map");
  expect_error("store:\n  - [A]\n", 2, 5, "store[0]", "expected a map, got a list");
  expect_error("presets:\n  - index: 1\n    name: [A]\n", 3, 5, "presets[0].name", "expected text, got a list");
  expect_error("polarization: linear\n", 1, 1, "polarization", "is not one of circular, single_port, dual_port");
  expect_error("agc:\n", 1, 1, "agc", "got no value");
  expect_error("navigation:\n  latitude: 38.58\n", 2, 3, "navigation.latitude", "expected \"dd.mm N\"");
}

TEST(profile, ErrorOutOfRange) {
  expect_error("baud: 1000\n", 1, 1, "baud", "not one of 300, 600, 1200, 2400, 4800, 9600");
  expect_error("axes:\n  az: {fast_dps: 0}\n", 2, 8, "axes.az.fast_dps", "greater than 0");
  expect_error("axes:\n  el: {min_deg: 10, max_deg: 5}\n", 2, 21, "axes.el.max_deg", "must be below max_deg");
  expect_error("agc: 1000\n", 1, 1, "agc", "out of range 0 to 999");
  expect_error("store:\n  - name: ABCDEFGHIJK\n", 2, 5, "store[0].name", "11 characters, expected 1 to 10");
  expect_error("store:\n  - {name: A}\n  - {name: A}\n", 3, 6, "store[1].name", "stored twice");
  expect_error("presets:\n  - {index: 21}\n", 2, 6, "presets[0].index", "out of range 1 to 20");
  expect_error("presets:\n  - {index: 2}\n  - {index: 2}\n", 3, 6, "presets[1].index", "index 2 is used twice");
  expect_error("presets:\n  - {index: 1, longitude: 12.34}\n", 2, 16, "presets[0].longitude", "more than one decimal");
  expect_error("tles:\n  - {index: 1, line1: \"1 2\", line2: \"2\"}\n", 2, 16, "tles[0].line1", "expected 69");
  expect_error("tles:\n  - {index: 11}\n", 2, 6, "tles[0].index", "out of range 1 to 10");
  expect_error("tles:\n  - {index: 1, line1: \"\"}\n", 2, 5, "tles[0]", "a TLE set needs line2");
  expect_error("navigation:\n  heading: 360\n", 2, 3, "navigation.heading", "out of range 0 to 359.9");
  expect_error("navigation:\n  latitude: \"91.00 N\"\n", 2, 3, "navigation.latitude", "beyond 90 degrees");
  expect_error("navigation:\n  longitude: \"010.60 E\"\n", 2, 3, "navigation.longitude", "minutes 60");
  expect_error("errata:\n  locate_index_min: 5\n  locate_index_max: 4\n", 3, 3, "errata.locate_index_max",
               "locate_index_min 5 is above locate_index_max 4");
  expect_error("firmware: \"1.5\"\n", 1, 1, "firmware", "\"A.BC\"");
}

// Axis rules: slow not above fast, a real mount's span, the arrival
// tolerance and the acceleration ramp (ERRATA E-71).
TEST(profile, ErrorAxisRules) {
  expect_error("axes:\n  az: {fast_dps: 1, slow_dps: 2}\n", 2, 21, "axes.az.slow_dps", "slow_dps 2 is above fast_dps 1");
  expect_error("axes:\n  el: {slow_dps: 1.5}\n", 2, 8, "axes.el.slow_dps", "above fast_dps 1");
  // fast_dps lowered below the default slow speed: the error names fast_dps.
  expect_error("axes:\n  pol: {fast_dps: 0.5}\n", 2, 9, "axes.pol.fast_dps", "slow_dps 1 is above fast_dps 0.5");
  expect_error("axes:\n  pol: {min_deg: 0, max_deg: 9.9}\n", 2, 21, "axes.pol.max_deg", "spans less than 10 degrees");
  // Exactly 10 degrees, though -61.6 - -71.6 is 9.999999999999993 in doubles.
  EXPECT_EQ(load_ok("axes:\n  el: {min_deg: -71.6, max_deg: -61.6, initial_deg: -65, stow_deg: -70}\n").el.min_deg, -71.6);
  expect_error("axes:\n  el: {min_deg: 40, max_deg: 49.9}\n", 2, 21, "axes.el.max_deg", "40 to max_deg 49.9 spans");
  load_ok("axes:\n  el: {min_deg: 40, max_deg: 50, stow_deg: 40}\n");
  expect_error("axes:\n  az: {tolerance_deg: 0.05}\n", 2, 8, "axes.az.tolerance_deg", "out of range 0.1 to 5");
  expect_error("axes:\n  az: {tolerance_deg: 5.5}\n", 2, 8, "axes.az.tolerance_deg", "out of range 0.1 to 5");
  expect_error("axes:\n  az: {accel_dps2: 0}\n", 2, 8, "axes.az.accel_dps2", "greater than 0");
  expect_error("axes:\n  az: {accel_dps2: -3}\n", 2, 8, "axes.az.accel_dps2", "greater than 0");
  // Slower than any mount: a full-range move would take longer than a
  // millisecond count holds.
  expect_error("axes:\n  az: {accel_dps2: 1e-300}\n", 2, 8, "axes.az.accel_dps2", "must be at least 0.001, got 1e-300");
  expect_error("axes:\n  el: {slow_dps: 0.0009}\n", 2, 8, "axes.el.slow_dps", "must be at least 0.001, got 9e-04");
  expect_error("axes:\n  pol: {fast_dps: 1e-300, slow_dps: 1e-300}\n", 2, 9, "axes.pol.fast_dps", "must be at least 0.001");
  EXPECT_EQ(load_ok("axes:\n  el: {fast_dps: 0.001, slow_dps: 0.001, accel_dps2: 0.001}\n").el.slow_dps, 0.001);
  expect_error("axes:\n  az: {power_on_speed: medium}\n", 2, 8, "axes.az.power_on_speed", "not one of fast, slow");
  expect_error("axes:\n  az: {ad_error: 1}\n", 2, 8, "axes.az.ad_error", "true or false");
  // §3.2: positions show -180.0 to 180.0; a fluxgate azimuth 0.0 to 359.9.
  expect_error("axes:\n  az: {max_deg: 200}\n", 2, 8, "axes.az.max_deg", "az max_deg 200 is beyond 180");
  expect_error("axes:\n  el: {max_deg: 180.1}\n", 2, 8, "axes.el.max_deg", "only a fluxgate azimuth");
  expect_error("axes:\n  az: {min_deg: 0, max_deg: 359.9}\nazimuth_sensor: pulse\n", 2, 20, "axes.az.max_deg", "beyond 180");
  load_ok("axes:\n  az: {min_deg: 0, max_deg: 359.9}\nazimuth_sensor: fluxgate\n");
  Profile p = load_ok("axes:\n  el: {accel_dps2: 2.5, tolerance_deg: 1.5, power_on_speed: slow, ad_error: true}\n");
  EXPECT_EQ(p.el.accel_dps2, 2.5);
  EXPECT_EQ(p.el.tolerance_deg, 1.5);
  EXPECT_EQ(p.el.power_on_speed, AxisSpeed::kSlow);
  EXPECT_TRUE(p.el.ad_error);
  EXPECT_EQ(p.az.accel_dps2, std::nullopt) << "another axis keeps its own defaults";
  EXPECT_EQ(load_ok("axes:\n  az: {accel_dps2: ~}\n").az.accel_dps2, std::nullopt);
}

// §3.2 byte 40: every band and submode; "K" is read as Ku, "error" as the
// track system error; the writer spells them Ku and system_error.
TEST(profile, TrackBandsAndSubmodes) {
  const std::pair<const char*, TrackBand> bands[] = {{"X", TrackBand::kX}, {"Ka", TrackBand::kKa}, {"S", TrackBand::kS},
                                                     {"C", TrackBand::kC}, {"Ku", TrackBand::kKu}, {"K", TrackBand::kKu},
                                                     {"L", TrackBand::kL}, {"none", TrackBand::kNone}};
  for (const auto& [name, band] : bands)
    EXPECT_EQ(load_ok(std::string("track: {band: ") + name + "}\n").track.band, band) << name;
  EXPECT_NE(to_yaml(load_ok("track: {band: K}\n")).find("  band: Ku\n"), std::string::npos);
  EXPECT_NE(to_yaml(load_ok("track: {band: none}\n")).find("  band: none\n"), std::string::npos);
  // Every name of the loader's table reads as its value and every value is
  // written with a name that reads back (profile_tables.hpp); the names a
  // profile writer is likely to use pinned apart.
  for (const auto& [name, activity] : profile_internal::kTrackActivities) {
    EXPECT_EQ(load_ok("track: {activity: " + std::string(name) + "}\n").track.activity, activity) << name;
    Profile p;
    p.track.activity = activity;
    EXPECT_EQ(load_ok(to_yaml(p)).track.activity, activity) << name;
  }
  const std::pair<const char*, TrackActivity> pinned[] = {
      {"idle", TrackActivity::kIdle}, {"peaking", TrackActivity::kPeaking}, {"program_track", TrackActivity::kProgramTrack}};
  for (const auto& [name, activity] : pinned)
    EXPECT_EQ(load_ok(std::string("track: {activity: ") + name + "}\n").track.activity, activity) << name;
  EXPECT_NE(to_yaml(load_ok("track: {activity: error}\n")).find("  activity: system_error\n"), std::string::npos);
  expect_error("track:\n  band: Q\n", 2, 3, "track.band", "\"Q\" is not one of X, Ka, S, C, Ku, K, L, none");
  expect_error("track:\n  activity: busy\n", 2, 3, "track.activity", "is not one of setup, auto_entry, idle");
  // ERRATA E-70: a dual-band satellite is a C/Ku one.
  expect_error("track:\n  band: X\n  dual_band: true\n", 3, 3, "track.dual_band", "C or Ku band, not X");
  EXPECT_TRUE(load_profile_text("track:\n  band: Ku\n  dual_band: true\n"));
}

// What the controller shows at power-on, and the other status fields.
TEST(profile, DisplayAndStatusFields) {
  Profile p = load_ok(
      "azimuth_sensor: fluxgate\nfluxgate_heading: M\nagc_channel: not_applicable\n"
      "display: {satellite: \"SBS 6\", pol_code: h, cursor_row: 4, cursor_column: 39, cursor_blinking: true}\n");
  EXPECT_EQ(p.fluxgate_heading, 'M');
  EXPECT_EQ(p.agc_channel, 3);
  EXPECT_EQ(p.display, (DisplayProfile{"SBS 6", 'h', 4, 39, true}));
  EXPECT_EQ(load_ok("display: {pol_code: none}\n").display.pol_code, 0);
  EXPECT_EQ(load_ok("agc_channel: SS2\n").agc_channel, 2);
  expect_error("fluxgate_heading: X\n", 1, 1, "fluxgate_heading", "not one of T, M");
  expect_error("agc_channel: SS3\n", 1, 1, "agc_channel", "not one of SS1, SS2, not_applicable");
  // ERRATA E-68: names as the controller holds and shows them, in capitals.
  expect_error("display:\n  satellite: Sbs 6\n", 2, 3, "display.satellite", "lower-case letters");
  expect_error("display:\n  satellite: \"SBS 6 \"\n", 2, 3, "display.satellite", "ends in a blank");
  expect_error("display:\n  satellite: ABCDEFGHIJK\n", 2, 3, "display.satellite", "11 characters, expected 0 to 10");
  expect_error("store:\n  - {name: amc 21}\n", 2, 6, "store[0].name", "lower-case letters");
  expect_error("display:\n  cursor_row: 5\n", 2, 3, "display.cursor_row", "out of range 1 to 4");
  expect_error("display:\n  cursor_column: 40\n", 2, 3, "display.cursor_column", "out of range 0 to 39");
  expect_error("display:\n  pol_code: x\n", 2, 3, "display.pol_code", "not one of H, h, V, v, none");
  // §3.2 byte 35: no polarization code without a rotating feed.
  expect_error("polarization: circular\ndisplay: {pol_code: V}\n", 2, 1, "display", "rotating feed");
  EXPECT_TRUE(load_profile_text("polarization: circular\ndisplay: {pol_code: none}\n"));
  // §3.2 byte 38: off axis and drive alarms are not supported for polarization.
  expect_error("alarms:\n  pol: drive\n", 2, 3, "alarms.pol", "does not report the drive alarm");
  expect_error("alarms:\n  pol: off_axis\n", 2, 3, "alarms.pol", "off_axis");
  EXPECT_EQ(load_ok("alarms:\n  pol: jammed\n  el: drive\n").alarms.el, 12);
}

TEST(profile, ErrorInitialPositionOutsideLimits) {
  // The key is absent, so the error points at the axis map.
  ProfileError e = load_bad("axes:\n  el: {min_deg: 50}\n");
  EXPECT_EQ(e.key, "axes.el");
  EXPECT_NE(e.message.find("initial_deg 45 is outside"), std::string::npos) << e.text();
}

TEST(profile, ErrorTooManyStoreEntries) {
  std::string yaml = "store:\n";
  for (int i = 0; i < 51; ++i) yaml += "  - {name: S" + std::to_string(i) + "}\n";
  expect_error(yaml, 1, 1, "store", "51 entries, at most 50");
}

TEST(profile, ErrorDuplicateKeys) {
  expect_error("address: 50\nbaud: 9600\naddress: 51\n", 3, 1, "address",
               "duplicate key \"address\" (first at line 1, column 1)");
  expect_error("errata:\n  implements_iess: true\n  implements_iess: false\n", 3, 3, "errata.implements_iess",
               "duplicate key");
  expect_error("axes:\n  az: {min_deg: 0, min_deg: 1}\n", 2, 20, "axes.az.min_deg", "first at line 2, column 8");
  expect_error("presets:\n  - index: 1\n    index: 2\n", 3, 5, "presets[0].index", "duplicate key");
  expect_error("track: {active: true}\ntrack: {active: false}\n", 2, 1, "track", "duplicate key \"track\"");
}

TEST(profile, ErrorYamlSyntax) {
  ProfileError e = load_bad("name: x\naxes: {az: {fast_dps: 1}\n");
  EXPECT_EQ(e.line, 3) << e.text();
  EXPECT_EQ(e.column, 1) << e.text();
  EXPECT_EQ(e.key, "");
  EXPECT_NE(e.message.find("YAML syntax"), std::string::npos) << e.text();

  e = load_bad("name: x\n  baud: 9600\n");
  EXPECT_EQ(e.line, 2) << e.text();
  EXPECT_NE(e.message.find("YAML syntax"), std::string::npos) << e.text();

  expect_error("name: a\n---\nname: b\n", 2, 1, "", "more than one YAML document");
  // yaml-cpp 0.7 would read this as an empty profile (Load) or never stop (LoadAll).
  expect_error(", x\n", 1, 1, "", "unexpected \",\" after the end of the document");
  expect_error("- name: x\n,\n", 2, 1, "", "unexpected \",\"");
  expect_error("name: x\nbaud: 9600\n,\n", 3, 1, "", "YAML syntax: end of map not found");
  expect_error("- name: a\n", 1, 1, "", "expected a map, got a list");
}

// §3.20 NOTE / ERRATA E-23.
TEST(profile, ErrorSignpostsWithoutDvb) {
  expect_error("name: x\nsignposts:\n  - {index: 1}\n", 2, 1, "signposts", "dvb_receiver: true");
  EXPECT_TRUE(load_profile_text("signposts: []\n"));
  EXPECT_TRUE(load_profile_text("dvb_receiver: true\nsignposts:\n  - {index: 1}\n"));
  // Order in the file does not matter.
  EXPECT_TRUE(load_profile_text("signposts:\n  - {index: 1}\ndvb_receiver: true\n"));
}

TEST(profile, ErrorBadAddress) {
  expect_error("address: 200\n", 1, 1, "address", "bad address \"200\": expected 49-111");
  expect_error("address: 48\n", 1, 1, "address", "bad address");
  expect_error("address: 5\n", 1, 1, "address", "quote it (\"5\") for the address character");
  expect_error("address: \"~\"\n", 1, 1, "address", "bad address");
  expect_error("address: [50]\n", 1, 1, "address", "expected an address");
}

TEST(profile, ErrorTextAndMissingFile) {
  ProfileError e{"p.yaml", 3, 5, "axes.az.fast_dps", "must be greater than 0, got 0"};
  EXPECT_EQ(e.text(), "p.yaml:3:5: axes.az.fast_dps: must be greater than 0, got 0");
  auto r = load_profile_file("/nonexistent/profile.yaml");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error->file, "/nonexistent/profile.yaml");
  EXPECT_EQ(r.error->line, 0);
  EXPECT_NE(r.error->message.find("cannot open"), std::string::npos);
}

// ---------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------

TEST(profile, ToYamlRoundTripOfEveryShippedFile) {
  for (const auto& f : shipped_profiles()) {
    SCOPED_TRACE(f.string());
    auto r = load_profile_file(f.string());
    ASSERT_TRUE(r) << r.error->text();
    std::string yaml = to_yaml(*r.profile);
    auto back = load_profile_text(yaml);
    ASSERT_TRUE(back) << back.error->text() << "\n" << yaml;
    expect_same(*back.profile, *r.profile);
    EXPECT_EQ(to_yaml(*back.profile), yaml);
  }
}

// Every field away from its default, and the awkward values: negative tenths
// below one, null optionals, quotes in names, a raw source code.
Profile every_field_set() {
  Profile p;
  p.name = "bench \"A\" \\ #1";
  p.address = 'o';
  p.remote_enabled = false;
  p.baud = 300;
  p.firmware = "2.07";
  p.pol_type = PolType::kDualPort;
  p.az_sensor = AzSensor::kResolver;
  p.hundredths = true;
  p.stow = false;
  p.deploy = false;
  p.dvb_receiver = true;
  p.counts_per_degree = 123.456;
  p.count_offset = 99999;
  p.fluxgate_heading = 'M';
  p.az = {3.3, 0.1, -170.5, 179.25, 12.125, true, 0.1, 5, 0.25, AxisSpeed::kSlow, true, 120.75};
  p.el = {0.7, 0.05, 0, 89.5, 1e-3, false, 0, 0.1, 1000, AxisSpeed::kFast, false, std::nullopt};
  p.pol = {9, 3, -45, 45, -44.9, true, 44.9, 2.5, std::nullopt, AxisSpeed::kSlow, false, -12.5};
  p.turnaround_ms = 0.25;
  p.agc = 0;
  p.agc_channel = 3;
  p.display = {" \"Q\" 1", 'v', 4, 39, true};
  p.store = {{"A: #B", 1.5, -2.25, 0.1, -0.1}, {"'Q'", -180, 360, 0, 0}};
  p.presets = {{20, {"P20", -5, 19, '6', '2', std::nullopt}, true}, {7, {"", std::nullopt, std::nullopt, '3', '0', -900}, false}};
  p.tles = {{10, std::string(69, 'x'), std::string(68, ' ') + "9"}};
  SignpostData sp;
  sp.longitude = 1800;
  sp.frequency = std::nullopt;
  sp.symbol_rate = 30000;
  sp.fec = '7';
  sp.polarization = 'R';
  sp.id = "ID 6";
  sp.priority = 9;
  p.signposts = {{20, sp}, {1, SignpostData{}}};
  p.navigation = {6, -(90 * 60), 179 * 60 + 59, 6, 0, -1};
  p.track = {true, TrackActivity::kChecksumError, TrackBand::kKu, true};
  p.stx_restarts_in_data = false;
  p.unknown_command_while_offline = OfflineUnknown::kOffline;
  p.implements_signal_strength = true;
  p.implements_iess = true;
  p.nak_bad_tle_checksum = true;
  p.locate_index_min = 0;
  p.locate_index_max = 19;
  p.restore_lost_locate_exit = false;
  return p;
}

TEST(profile, ToYamlRoundTripWithEveryFieldSet) {
  const Profile p = every_field_set();
  std::string yaml = to_yaml(p);
  auto back = load_profile_text(yaml);
  ASSERT_TRUE(back) << back.error->text() << "\n" << yaml;
  expect_same(*back.profile, p);
  EXPECT_EQ(to_yaml(*back.profile), yaml);
}

// Text a profile may hold that YAML would read as something else, or that
// ends a value, a line or a document: written exactly, read back exactly.
TEST(profile, ToYamlWritesTextThatLooksLikeYamlExactly) {
  const std::string hostile[] = {"\"", "\\", "\\\"", "#", " # x", "a: b", "- x", "~", "null", "NULL", "true", "no",
                                 "0x32", "1e3", ".5", "'", "''", "{a}", "[a]", "&A", "*A", "!T", "%", "@", "`", "|",
                                 ">", "? x", "---", "...", " lead", "{{x}}", "\\x41", "\\n"};
  for (const std::string& text : hostile) {
    SCOPED_TRACE(text);
    std::string capitals = text;  // the displayed and stored names are in capitals (E-68)
    for (char& c : capitals) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    Profile p = every_field_set();
    p.name = text;
    p.display.satellite = capitals;
    p.store[0].name = capitals;
    p.presets[0].data.name = text;
    p.signposts[0].data.id = text.substr(0, 4);
    p.tles[0].line1 = (text + std::string(69, 'x')).substr(0, 69);
    const std::string yaml = to_yaml(p);
    EXPECT_EQ(test::yaml_text_problem(yaml), "") << yaml;
    auto back = load_profile_text(yaml);
    ASSERT_TRUE(back) << back.error->text() << "\n" << yaml;
    expect_same(*back.profile, p);
    EXPECT_EQ(to_yaml(*back.profile), yaml);
  }
}

// A profile made in code may hold what no profile file can (a control
// character, DEL, a byte that is not UTF-8): the text is escaped, the file
// stays valid YAML and the loader names the field.
TEST(profile, ToYamlEscapesTextNoProfileHoldsAndTheLoaderNamesIt) {
  for (int b = 0; b < 256; ++b) {
    if (b >= 0x20 && b <= 0x7E) continue;
    SCOPED_TRACE(b);
    Profile p;
    p.name = std::string("A") + static_cast<char>(b) + "Z";
    const std::string yaml = to_yaml(p);
    EXPECT_EQ(test::yaml_text_problem(yaml), "") << yaml;
    const ProfileError e = load_bad(yaml);
    EXPECT_EQ(e.key, "name") << e.text();
    EXPECT_NE(e.message.find("printable ASCII"), std::string::npos) << e.text();
  }
}

// A code that is not in its table (a preset's band, a signpost's FEC) is
// written quoted as it is, for the loader to name.
TEST(profile, ToYamlWritesACodeNotInItsTableForTheLoaderToName) {
  Profile p = every_field_set();
  p.presets[0].data.band = '\x01';
  std::string yaml = to_yaml(p);
  EXPECT_EQ(test::yaml_text_problem(yaml), "") << yaml;
  EXPECT_EQ(load_bad(yaml).key, "presets[0].band");
  p = every_field_set();
  p.signposts[0].data.fec = '"';
  yaml = to_yaml(p);
  EXPECT_NE(yaml.find("fec: \"\\\"\""), std::string::npos) << yaml;
  EXPECT_EQ(load_bad(yaml).key, "signposts[0].fec");
}

// The sweep writes a failing profile with the failures, which hold what the
// vectors and the controller said, as a comment above it (to_yaml with a
// comment): whatever they hold, the profile reads back equal.
TEST(profile, ToYamlWithACommentOfAnyTextReadsBackEqual) {
  const std::string comment =
      "A random legal profile on which vectors failed:\n"
      "  3.2-x: expected x\ny: 1\r\"q\" \\ \x01\x7f\xc2\x85\xe2\x80\xa8\xef\xbb\xbf \xc3\xa9 # z, got L0\n"
      "  run aborted: \xff\xfe name: \"injected\"\r\n---\n...\n"
      "Reproduce: sabus vectors sweep --profile-seed 5";
  const Profile p = every_field_set();
  const std::string yaml = to_yaml(p, comment);
  EXPECT_EQ(test::yaml_text_problem(yaml), "") << yaml;
  ASSERT_EQ(yaml.rfind(to_yaml(p)), yaml.size() - to_yaml(p).size()) << "the profile after the comment:\n" << yaml;
  const std::string head = yaml.substr(0, yaml.size() - to_yaml(p).size());
  std::istringstream lines(head);
  std::size_t n = 0;
  for (std::string line; std::getline(lines, line); ++n) EXPECT_EQ(line.rfind("# ", 0), 0u) << "line " << n << ": " << line;
  EXPECT_EQ(n, 7u) << head;
  EXPECT_NE(head.find("#   3.2-x: expected x\n# y: 1\\x0d\"q\" \\ \\x01\\x7f"), std::string::npos) << head;
  EXPECT_NE(head.find("\\xff\\xfe name"), std::string::npos) << head;
  auto back = load_profile_text(yaml);
  ASSERT_TRUE(back) << back.error->text() << "\n" << yaml;
  expect_same(*back.profile, p);
}

// ---------------------------------------------------------------------------
// multi_drop
// ---------------------------------------------------------------------------

TEST(profile, MultiDropOneProfilePerAddressRestShared) {
  Profile base = every_field_set();
  auto bus = multi_drop(base, {50, 51, 60});
  ASSERT_EQ(bus.size(), 3u);
  const std::uint8_t addresses[] = {50, 51, 60};
  for (std::size_t i = 0; i < bus.size(); ++i) {
    EXPECT_EQ(bus[i].address, addresses[i]);
    EXPECT_EQ(bus[i].name, base.name + "-" + std::to_string(addresses[i]));
    Profile same = bus[i];
    same.address = base.address;
    same.name = base.name;
    expect_same(same, base);
  }
  EXPECT_TRUE(multi_drop(base, {}).empty());
}

// ---------------------------------------------------------------------------
// Robustness: no input makes the loader throw
// ---------------------------------------------------------------------------

TEST(profile, NeverThrowsOnTruncatedShippedFiles) {
  std::size_t loads = 0, errors = 0;
  for (const auto& f : shipped_profiles()) {
    const std::string text = read_text(f);
    for (std::size_t n = 0; n <= text.size(); ++n) {
      ProfileResult r;
      ASSERT_NO_THROW(r = load_profile_text(std::string_view(text).substr(0, n), f.string())) << "prefix " << n;
      ASSERT_NE(r.profile.has_value(), r.error.has_value()) << "prefix " << n;
      if (r.error) {
        ++errors;
        EXPECT_FALSE(r.error->message.empty());
      }
      ++loads;
    }
  }
  EXPECT_GT(errors, 0u);
  EXPECT_GT(loads, errors);
}

TEST(profile, NeverThrowsOnMutatedFiles) {
  const std::string text = read_text(default_profile_path());
  std::mt19937 rng(12345);
  const std::string alphabet = "-:{}[],#&*!|>'\"%@`? \n\t.0123456789aZ\x7f\x80\xff";
  for (int i = 0; i < 2000; ++i) {
    std::string s = text;
    for (int k = 0; k < 3; ++k) {
      std::size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0: s[at] = alphabet[rng() % alphabet.size()]; break;
        case 1: s.erase(at, 1 + rng() % 8); break;
        default: s.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
      }
    }
    ProfileResult r;
    ASSERT_NO_THROW(r = load_profile_text(s)) << s;
    ASSERT_NE(r.profile.has_value(), r.error.has_value());
  }
}

TEST(profile, NeverThrowsOnHostileInputs) {
  // Deep nesting: yaml-cpp's depth guard, reported as a syntax error.
  EXPECT_FALSE(load_profile_text(std::string(100000, '[')));
  // Aliases: a list is bounded before it is walked.
  std::string laughs = "store: [&a {name: A}";
  for (int i = 0; i < 60; ++i) laughs += ", *a";
  laughs += "]\n";
  expect_error(laughs, 1, 1, "store", "61 entries, at most 50");
  EXPECT_FALSE(load_profile_text(std::string(2 << 20, ' ')));  // over the size cap
  EXPECT_NO_THROW(load_profile_text(std::string("name: \0x", 8)));
}

}  // namespace
}  // namespace sabus::harness
