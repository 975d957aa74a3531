// The reference controller: every command handler, every NAK rule, motion on
// a virtual clock, and the faults' effect on the wire.
#include <gtest/gtest.h>

#include <functional>
#include <set>

#include "sabus/harness/controller.hpp"
#include "controller_internal.hpp"
#include "controller_rig.hpp"  // the submode table, checked row by row

namespace sabus::harness {
namespace {

using namespace std::chrono_literals;

Profile test_profile() {
  Profile p;
  p.store = {{"SBS 6", -74.0, 40.0, 10.0, -80.0}, {"GALAXY 19", -97.0, 35.0, 20.0, -70.0}};
  PresetSatellite g19;
  g19.index = 1;
  g19.data = {"GALAXY 19", -971, 0, '1', '0', -125};
  p.presets = {g19};
  p.navigation.latlon_source = 7;
  p.navigation.latitude_min = 40 * 60;
  p.navigation.longitude_min = -75 * 60;
  // Mount azimuth 0.0 points true north (§3.23), so a LOCATE's azimuth is
  // its true azimuth (ERRATA E-80).
  p.navigation.heading_source = 7;
  p.navigation.heading_tenths = 0;
  return p;
}

// A LOCATE (§3.18) of a satellite given by its name and longitude in tenths,
// west negative: not a preset.
RemoteLocate locate_satellite(std::string name, std::int32_t longitude_tenths) {
  RemoteLocate l;
  l.preset.preset = false;
  l.sat = {std::move(name), longitude_tenths, 0, '1', '0', 0};
  return l;
}

struct Rig : ControllerRig {
  explicit Rig(Profile p = test_profile(), FaultSet f = {}) : ControllerRig(std::move(p), f) {}
};

// ---- §3.1 / §3.2 ------------------------------------------------------------------

TEST(Controller, DeviceTypeIs3KAndTheFirmware) {
  Rig r;
  auto d = r.reply<DeviceTypeReply>(DeviceTypeQuery{});
  EXPECT_EQ(d.controller, "3K");
  EXPECT_EQ(d.version, "1.59");
}

TEST(Controller, StatusReflectsThePositions) {
  Rig r;
  auto s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 0);
  EXPECT_EQ(s.elevation, 450);
  EXPECT_EQ(s.polarization, 0);
  EXPECT_EQ(s.az_status & 0x0F, 0);
  EXPECT_EQ(s.pol_equipment >> 4, 1) << "single-port feed";
  EXPECT_NE(s.track >> 4, 0) << "BBB is never 000";
}

TEST(Controller, StatusPollDoesNotForceRemoteMode) {
  Rig r;
  r.status();
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "MANUAL_MODE");
  Rig faulty(test_profile(), {Fault::kStatusForcesRemote});
  faulty.status();
  EXPECT_EQ(meanings::mode_name(faulty.extended().mode), "REMOTE_MODE");
}

// ---- §3.3 auto move ------------------------------------------------------------------

TEST(Controller, AutoMoveForm2AMovesAndReportsRemoteAutoMove) {
  Rig r;
  auto s = r.reply<StatusReply>(AutoMove{AutoMoveAzEl{-1525, 456}}).status;
  EXPECT_EQ(s.az_status & 0x0F, 0x7) << "remotely commanded auto move in progress";
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "REMOTE_MODE");
  r.wait(200s);
  s = r.status();
  EXPECT_EQ(s.azimuth.tenths, -1525);
  EXPECT_EQ(s.elevation, 456);
  EXPECT_EQ(s.az_status & 0x0F, 0);
}

TEST(Controller, AutoMoveForm1ToAStoredSatelliteWithPolarization) {
  Rig r;
  auto s = r.reply<StatusReply>(AutoMove{AutoMoveStored{'V', "SBS 6"}}).status;
  EXPECT_EQ(s.sat_name, "SBS 6");
  r.wait(200s);
  s = r.status();
  EXPECT_EQ(s.azimuth.tenths, -740);
  EXPECT_EQ(s.elevation, 400);
  EXPECT_EQ(s.polarization, -800);
  EXPECT_EQ(s.pol_equipment & 7, 2) << "'V' displayed";
}

TEST(Controller, AutoMoveNameThatParsesAsNumbersIsForm1WhenStored) {
  Profile p = test_profile();
  p.store.push_back({"0100000200", 12.0, 34.0, 0, 0});
  Rig r(p);
  r.send_raw(0x32, " 0100000200");
  r.wait(200s);
  EXPECT_EQ(r.status().azimuth.tenths, 120) << "READING-NOTES 31: the stored name wins";
}

TEST(Controller, AutoMoveForm2BAnd2CNeedTheirSensors) {
  Profile p = test_profile();
  p.az_sensor = AzSensor::kPulse;
  p.hundredths = true;
  Rig r(p);
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveCounts{11050, 12152}})));
  r.wait(300s);
  auto pulses = r.reply<PulseCountReply>(PulseCountQuery{});
  EXPECT_EQ(pulses.az, 11050u);
  EXPECT_EQ(pulses.el, 12152u);
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveAxis{'A', -12345}})));
  r.wait(300s);
  auto x = r.extended();
  EXPECT_EQ(x.status.azimuth.tenths, -1234);
  EXPECT_EQ(x.az_hundredths, 5) << "READING-NOTES 30";
}

TEST(Controller, AutoMoveForm3MovesPolarization) {
  Rig r;
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMovePol{500}})));
  r.wait(60s);
  EXPECT_EQ(r.status().polarization, 500);
}

// ---- §3.4 / §3.24 jog ------------------------------------------------------------------

TEST(Controller, JogLastsItsDurationInFiftyMillisecondSteps) {
  Rig r;  // az slow speed 0.5 deg/s
  ASSERT_FALSE(is_nak(r.send(Jog{{'W', 'S', 1000}})));
  EXPECT_EQ(r.status().az_status & 0x0F, 0x5);
  r.wait(5s);
  EXPECT_EQ(r.status().azimuth.tenths, 5) << "1 s at 0.5 deg/s";
  EXPECT_EQ(r.status().az_status & 0x0F, 0);
  ASSERT_FALSE(is_nak(r.send(Jog{{'W', 'F', 1}})));  // 1 ms rounds up to 50 ms
  r.wait(1s);
  EXPECT_EQ(r.status().azimuth.tenths, 6) << "0.05 s at 2 deg/s";
  ASSERT_FALSE(is_nak(r.send(Jog{{'W', 'F', 0}})));
  r.wait(1s);
  EXPECT_EQ(r.status().azimuth.tenths, 6) << "0000 does not move";
}

TEST(Controller, SecondAxisJogEndsTheFirst) {
  Rig r;
  r.send(Jog{{'W', 'S', 9999}});
  r.wait(1s);
  r.send(Jog{{'U', 'S', 9999}});
  auto s = r.status();
  EXPECT_EQ(s.az_status & 0x0F, 0) << "the azimuth jog terminated";
  EXPECT_EQ(s.el_status & 0x0F, 0x5);
  Rig faulty(test_profile(), {Fault::kSecondAxisJogKeepsFirst});
  faulty.send(Jog{{'W', 'S', 9999}});
  faulty.send(Jog{{'U', 'S', 9999}});
  EXPECT_EQ(faulty.status().az_status & 0x0F, 0x5);
}

TEST(Controller, XStopsEverything) {
  Rig r;
  r.send(AutoMove{AutoMoveAzEl{-1525, 456}});
  r.wait(1s);
  ASSERT_FALSE(is_nak(r.send(Jog{{'X', 'S', 0}})));
  const auto s = r.status();
  EXPECT_EQ(s.az_status & 0x0F, 0);
  EXPECT_EQ(s.el_status & 0x0F, 0);
  const auto az = s.azimuth.tenths;
  r.wait(10s);
  EXPECT_EQ(r.status().azimuth.tenths, az);
}

TEST(Controller, JogMinimalRepliesWithThePositionOfTheJoggedAxis) {
  Rig r;
  auto j = r.reply<JogPositionReply>(JogMinimal{{'D', 'F', 500}});
  EXPECT_EQ(j.axis, 'E');
  EXPECT_EQ(j.position, 450) << "position when the command was received";
  EXPECT_EQ(r.reply<JogPositionReply>(JogMinimal{{'O', 'F', 500}}).axis, 'P');
  EXPECT_EQ(r.reply<JogPositionReply>(JogMinimal{{'X', 'F', 0}}).axis, 'A');  // ERRATA E-46
}

TEST(Controller, JogStopsAtTheLimitAndThenNaks) {
  Rig r;  // el max 90, fast 1 deg/s, from 45: five 10 s jogs reach the limit
  for (int i = 0; i < 5; ++i) {
    r.send(Jog{{'U', 'F', 9999}});
    r.wait(10s);
  }
  auto s = r.status();
  EXPECT_EQ(s.elevation, 900);
  EXPECT_EQ(s.el_limits & 4, 4) << "elevation up limit";
  auto o = r.send(Jog{{'U', 'F', 100}});
  ASSERT_TRUE(is_nak(o));
  EXPECT_EQ(o.nak, NakRule::kJogIntoLimit);
  EXPECT_FALSE(is_nak(r.send(Jog{{'D', 'F', 100}}))) << "away from the limit is fine";
}

// ---- acceleration ramps and arrival tolerance (ERRATA E-71) -------------------------

Profile ramped_profile(double accel, double tolerance = 0.1) {
  Profile p = test_profile();
  p.az.accel_dps2 = accel;  // fast 2 deg/s, slow 0.5 deg/s
  p.az.tolerance_deg = tolerance;
  return p;
}

TEST(Controller, RampedJogRampsUpInTheTimerAndDownAfterIt) {
  Rig r(ramped_profile(1.0));  // 2 s to reach 2 deg/s, 2 s to stop
  ASSERT_FALSE(is_nak(r.send(Jog{{'W', 'F', 2000}})));
  r.wait(1s);
  EXPECT_EQ(r.status().azimuth.tenths, 5) << "a t^2 / 2 after 1 s";
  r.wait(1s);
  auto s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 20) << "at the end of the timer";
  EXPECT_EQ(s.az_status & 0x0F, 0x5) << "still moving: ramping down after the timer";
  r.wait(1s);
  EXPECT_EQ(r.status().azimuth.tenths, 35);
  r.wait(5s);
  s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 40) << "v * t: the ramp down makes up for the ramp up";
  EXPECT_EQ(s.az_status & 0x0F, 0);
}

TEST(Controller, RampedShortJogNeverReachesItsSpeed) {
  Rig r(ramped_profile(1.0));
  ASSERT_FALSE(is_nak(r.send(Jog{{'E', 'F', 1000}})));  // up to 1 deg/s in 1 s, then 1 s down
  r.wait(10s);
  EXPECT_EQ(r.status().azimuth.tenths, -10) << "a t^2";
}

TEST(Controller, RampedMotionDoesNotDependOnHowTimeIsCut) {
  Rig whole(ramped_profile(3.7)), steps(ramped_profile(3.7));
  for (Rig* r : {&whole, &steps}) {
    r->send(Jog{{'W', 'F', 1730}});
    r->send(AutoMove{AutoMoveAzEl{-453, 300}});  // turns the running jog round
  }
  whole.wait(40s);
  for (int i = 0; i < 40000; i += 7) steps.wait(7ms);
  steps.wait(40s);
  EXPECT_NEAR(whole.c.state().az.position, steps.c.state().az.position, 1e-6);
  EXPECT_NEAR(whole.c.state().az.position, -45.3, 1e-6);
  EXPECT_EQ(whole.c.state().az.motion, AxisState::Motion::kIdle);
}

TEST(Controller, RampedAutoMoveSlowsDownToItsTarget) {
  Rig r(ramped_profile(0.5));  // 4 s to reach 2 deg/s over 4 deg
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveAzEl{300, 450}})));
  r.wait(2s);
  EXPECT_EQ(r.status().azimuth.tenths, 10) << "0.5 * 0.5 * 2^2";
  r.wait(15s);
  EXPECT_EQ(r.status().az_status & 0x0F, 0x7) << "cruising";
  r.wait(60s);
  auto s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 300);
  EXPECT_EQ(s.az_status & 0x0F, 0);
}

TEST(Controller, RampedStopRampsDown) {
  Rig r(ramped_profile(1.0));
  r.send(Jog{{'W', 'F', 9999}});
  r.wait(5s);  // at 2 deg/s, 8 deg out
  ASSERT_FALSE(is_nak(r.send(Jog{{'X', 'S', 0}})));
  auto s = r.status();
  EXPECT_EQ(s.az_status & 0x0F, 0x5) << "slowing down";
  r.wait(10s);
  s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 100) << "8 deg, then 2 deg ramping down";
  EXPECT_EQ(s.az_status & 0x0F, 0);
}

TEST(Controller, AutoMoveStopsWithinTheTolerance) {
  Rig r(ramped_profile(2.0, 2.0));  // stops up to 1.9 deg short, read within 2
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveAzEl{500, 450}})));
  r.wait(60s);
  EXPECT_EQ(r.status().azimuth.tenths, 481);
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveAzEl{490, 450}})));
  r.wait(60s);
  EXPECT_EQ(r.status().azimuth.tenths, 481) << "already within the tolerance: no move";
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveAzEl{1800, 450}})));
  r.wait(200s);
  auto s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 1800) << "a move to a limit ends on its switch";
  EXPECT_EQ(s.az_limits & 4, 4);
  Profile no_ramp = test_profile();
  no_ramp.el.tolerance_deg = 1.0;
  Rig q(no_ramp);
  ASSERT_FALSE(is_nak(q.send(AutoMove{AutoMoveAzEl{0, 300}})));
  q.wait(60s);
  EXPECT_EQ(q.status().elevation, 309) << "0.9 deg short without a ramp too";
}

// ---- §3.5 - §3.7 ------------------------------------------------------------------------

TEST(Controller, PolPresetUsesTheLastAutoMoveTarget) {
  Rig r;
  r.send(AutoMove{AutoMoveStored{' ', "GALAXY 19"}});
  r.send(PolPreset{'V'});
  r.wait(100s);
  EXPECT_EQ(r.status().polarization, -700);
  Profile dual = test_profile();
  dual.pol_type = PolType::kDualPort;
  Rig d(dual);
  d.send(AutoMove{AutoMoveStored{' ', "GALAXY 19"}});
  d.send(PolPreset{'V'});
  d.wait(100s);
  EXPECT_EQ(d.status().polarization, 200) << "§3.5: a dual-port feed has one position";
}

TEST(Controller, QueryNameFirstLastAndOnePastLast) {
  Rig r;
  auto first = r.reply<QueryNameReply>(QueryName{{1}});
  EXPECT_EQ(first.index, 1u);
  EXPECT_EQ(first.total, 2u);
  EXPECT_EQ(first.name, "SBS 6");
  EXPECT_EQ(r.reply<QueryNameReply>(QueryName{{2}}).name, "GALAXY 19");
  EXPECT_EQ(r.send(QueryName{{3}}).nak, NakRule::kQueryNameIndex);
  EXPECT_EQ(r.send(QueryName{{0}}).nak, NakRule::kQueryNameIndex);
}

TEST(Controller, DriveResetClearsTheAlarm) {
  Rig r;
  r.c.mutable_state().az.alarm = 0xB;
  r.c.mutable_state().alarm_code = 2;  // azimuth jammed
  EXPECT_EQ(r.status().az_status & 0x0F, 0xB);
  ASSERT_FALSE(is_nak(r.send(Misc{'R', 'A'})));
  auto s = r.status();
  EXPECT_EQ(s.az_status & 0x0F, 0);
  EXPECT_EQ(s.alarm_code, 0);
}

TEST(Controller, StowDeployAndSearchChangeTheMode) {
  Rig r;
  r.send(Misc{'S', ' '});
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "STOW_MODE");
  r.wait(300s);
  auto x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.mode), "MANUAL_MODE");
  EXPECT_EQ(meanings::mode_name(x.last_mode), "STOW_MODE");
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "STOW_FINISHED_NORMALLY");
  EXPECT_EQ(x.status.el_limits & 1, 1) << "elevation stow";
  r.send(Misc{'D', ' '});
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "DEPLOY_MODE");
  r.send(Misc{'A', 'E'});
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "SPIRAL_REMOTE_MODE");
}

// ERRATA E-99: a STOW drives every axis with a stow limit to it, so §3.2
// bytes 32-34 show bit C on each; a move away clears it.
TEST(Controller, StowReachesEveryStowLimit) {
  Profile p = test_profile();
  p.az.has_stow_limit = true;
  p.az.stow_deg = 35.0;
  p.pol.has_stow_limit = true;
  p.pol.stow_deg = -20.0;
  Rig r(p);
  r.send(Misc{'S', ' '});
  r.wait(600s);
  auto x = r.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "STOW_FINISHED_NORMALLY");
  EXPECT_EQ(x.status.az_limits & 1, 1) << "azimuth stow";
  EXPECT_EQ(x.status.el_limits & 1, 1) << "elevation stow";
  EXPECT_EQ(x.status.pol_limits & 1, 1) << "polarization stow";
  r.send(AutoMove{AutoMoveAzEl{0, 300}});
  r.wait(600s);
  auto s = r.status();
  EXPECT_EQ(s.az_limits & 1, 0) << "azimuth away from its stow position";
  EXPECT_EQ(s.el_limits & 1, 0) << "elevation away from its stow position";
}

// A STOW from the stow position has nothing to move: it finishes at once
// instead of staying in STOW_MODE.
TEST(Controller, StowFromTheStowPositionFinishes) {
  Profile p = test_profile();
  p.az.initial_deg = 0.0;
  p.el.has_stow_limit = true;
  p.el.stow_deg = p.el.initial_deg;
  Rig r(p);
  r.send(Misc{'S', ' '});
  r.wait(1s);
  auto x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.mode), "MANUAL_MODE");
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "STOW_FINISHED_NORMALLY");
}

// ERRATA E-90: the reference search moves leg by leg about where it began,
// then returns there and exits with no peak found.
TEST(Controller, ASearchMovesAboutWhereItBeganAndReturns) {
  Rig r;
  const double az0 = r.c.state().az.position, el0 = r.c.state().el.position;
  ASSERT_FALSE(is_nak(r.send(Misc{'A', 'E'})));
  double farthest = 0;
  for (int i = 0; i < 150; ++i) {  // 15 s in 100 ms steps
    r.wait(100ms);
    farthest = std::max({farthest, std::abs(r.c.state().az.position - az0), std::abs(r.c.state().el.position - el0)});
  }
  EXPECT_GE(farthest, 2.0) << "an expanding spiral's legs grow";
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "SPIRAL_REMOTE_MODE");
  r.wait(300s);
  auto x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.mode), "MANUAL_MODE");
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "SPIRAL_NO_PEAK_FOUND");
  EXPECT_NEAR(r.c.state().az.position, az0, 0.11);
  EXPECT_NEAR(r.c.state().el.position, el0, 0.11);
}

TEST(Controller, TheStopKeyEndsASearchWithTheStopEntryOfItsMovement) {
  Rig r;
  ASSERT_FALSE(is_nak(r.send(Misc{'A', 'E'})));
  r.wait(1500ms);
  ASSERT_TRUE(r.c.state().az.motion != AxisState::Motion::kIdle || r.c.state().el.motion != AxisState::Motion::kIdle);
  ASSERT_FALSE(is_nak(r.send(Misc{'K', 'A'})));
  r.wait(100ms);
  const double az = r.c.state().az.position, el = r.c.state().el.position;
  r.wait(30s);
  EXPECT_EQ(r.c.state().az.position, az);
  EXPECT_EQ(r.c.state().el.position, el);
  auto x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.mode), "MANUAL_MODE");
  const std::string exit = meanings::exit_name(x.last_mode, x.exit_status);
  EXPECT_TRUE(exit.starts_with("SPIRAL_") && exit.ends_with("_STOP_KEY")) << exit;
  // 'X' likewise, into REMOTE.
  ASSERT_FALSE(is_nak(r.send(Misc{'A', 'F'})));
  r.wait(1500ms);
  ASSERT_FALSE(is_nak(r.send(Jog{{'X', 'F', 0}})));
  x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.mode), "REMOTE_MODE");
  EXPECT_EQ(meanings::mode_name(x.last_mode), "SPIRAL_REMOTE_MODE");
  EXPECT_TRUE(meanings::exit_name(x.last_mode, x.exit_status).ends_with("_STOP_KEY"));
}

// ERRATA E-90: a DEPLOY drives the elevation to the profile's deploy_deg,
// then the azimuth to its own when the profile states one.
TEST(Controller, ADeployGoesWhereTheProfileSays) {
  Profile p = test_profile();
  p.el.deploy_deg = 30.0;
  p.az.deploy_deg = -20.0;
  Rig r(p);
  ASSERT_FALSE(is_nak(r.send(Misc{'D', ' '})));
  r.wait(300s);
  auto x = r.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "DEPLOY_FINISHED_NORMALLY");
  EXPECT_NEAR(r.c.state().el.position, 30.0, 0.11);
  EXPECT_NEAR(r.c.state().az.position, -20.0, 0.11);
  // Stopped on its way: the MOVE_STOPPED entry of the movement it is in.
  ASSERT_FALSE(is_nak(r.send(AutoMove{AutoMoveAzEl{0, 600}})));
  r.wait(300s);
  ASSERT_FALSE(is_nak(r.send(Misc{'D', ' '})));
  r.wait(2s);
  ASSERT_FALSE(is_nak(r.send(Misc{'K', 'A'})));
  x = r.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "DEPLOY_MOVING_ELEVATION_MOVE_STOPPED");
}

TEST(Controller, TrackBandChangeAndErrorReset) {
  Profile p = test_profile();
  p.track = {true, TrackActivity::kIdle, TrackBand::kC, true};
  Rig r(p);
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "TRACK_MODE");
  ASSERT_FALSE(is_nak(r.send(Misc{'T', 'K'})));
  EXPECT_EQ(r.status().track >> 4, 0b101) << "Ku band";
  ASSERT_FALSE(is_nak(r.send(Misc{'T', 'R'})));
}

// §3.2 byte 40: BBB from the profile's band, "band not defined" included.
TEST(Controller, TrackByteCarriesEveryBand) {
  const std::pair<TrackBand, std::uint8_t> bands[] = {{TrackBand::kX, 0b001}, {TrackBand::kKa, 0b010},
                                                      {TrackBand::kS, 0b011}, {TrackBand::kC, 0b100},
                                                      {TrackBand::kKu, 0b101}, {TrackBand::kNone, 0b110},
                                                      {TrackBand::kL, 0b111}};
  for (const auto& [band, bbb] : bands) {
    Profile p = test_profile();
    p.track.band = band;
    Rig r(p);
    EXPECT_EQ(r.status().track, bbb << 4) << "TRACK not active: SSSS 0000";
  }
}

// §3.2 byte 40 SSSS and byte 35 'Y', §3.17 byte 46, and the TRACK rules of
// §3.4 for each submode (ERRATA E-69).
TEST(Controller, EachTrackSubmodeHasItsByteStateAndRules) {
  // The controller's one table of submodes (controller_internal.hpp), pinned
  // to the spec where its rows differ in kind: a setup code, the two codes
  // 0011 shares, a search and the first and last error codes.
  auto pin = [](TrackActivity a, std::uint8_t ssss, std::string_view state, bool peaking_or_search) {
    const TrackSubmode& row = track_submode(a);
    EXPECT_EQ(row.ssss, ssss) << state;
    EXPECT_EQ(row.state, state);
    EXPECT_EQ(row.peaking_or_search, peaking_or_search) << state;
  };
  pin(TrackActivity::kSetup, 0b0001, "TRACK_INITIALIZING_PARAMETERS", false);
  pin(TrackActivity::kIdle, 0b0011, "TRACK_STEP_IDLE", false);
  pin(TrackActivity::kPeaking, 0b0011, "TRACK_STEP_PEAKING", true);
  pin(TrackActivity::kSearching, 0b0100, "TRACK_SEARCH_PERFORMING_SEARCH_PATTERN", true);
  pin(TrackActivity::kJammedError, 0b1000, "TRACK_ERROR_CREEP_JAMMED", false);
  pin(TrackActivity::kChecksumError, 0b1110, "TRACK_ERROR_TRACK_CHECKSUM", false);
  // One row per submode, kSetup through kChecksumError in order.
  ASSERT_EQ(std::size(kTrackSubmodes), static_cast<std::size_t>(TrackActivity::kChecksumError) + 1);
  for (std::size_t i = 0; i < std::size(kTrackSubmodes); ++i)
    EXPECT_EQ(kTrackSubmodes[i].activity, static_cast<TrackActivity>(i)) << kTrackSubmodes[i].state;
  for (const TrackSubmode& row : kTrackSubmodes) {
    SCOPED_TRACE(row.state);
    Profile p = test_profile();
    p.track = {true, row.activity, TrackBand::kKu, true};
    Rig r(p);
    auto x = r.extended();
    EXPECT_EQ(x.status.track, 0b101 << 4 | row.ssss);
    EXPECT_EQ(meanings::mode_name(x.mode), "TRACK_MODE");
    EXPECT_EQ(meanings::state_name(x.mode, x.state), row.state);
    EXPECT_EQ((x.status.pol_equipment >> 3) & 1, row.peaking_or_search ? 0 : 1) << "byte 35 'Y'";
    const auto band_change = r.send(Misc{'T', 'C'});
    EXPECT_EQ(band_change.nak, row.peaking_or_search ? std::optional(NakRule::kMiscTrackPolNotAllowed) : std::nullopt);
    const auto jog = r.send(Jog{{'O', 'S', 100}});
    EXPECT_EQ(jog.nak, row.peaking_or_search ? std::optional(NakRule::kTrackPeaking) : std::nullopt);
    ASSERT_FALSE(is_nak(r.send(Misc{'T', 'R'})));
    x = r.extended();
    const bool error = row.ssss >= 0b1000;
    EXPECT_EQ(meanings::state_name(x.mode, x.state), error ? "TRACK_STEP_IDLE" : row.state)
        << "'T' 'R' ends an error submode as if TRACK was entered from RECALL";
  }
}

// ERRATA E-70: only a C/Ku (dual-band) satellite changes band; 'K' is Ku.
TEST(Controller, BandChangeNeedsADualBandSatellite) {
  Profile p = test_profile();
  p.track = {true, TrackActivity::kIdle, TrackBand::kNone, false};
  Rig none(p);
  EXPECT_EQ(none.status().track, 0b110 << 4 | 0b0011) << "band not defined, step track";
  EXPECT_EQ(none.send(Misc{'T', 'K'}).nak, NakRule::kMiscTrackNotDualBand);
  p.track = {true, TrackActivity::kIdle, TrackBand::kKu, true};
  Rig dual(p);
  ASSERT_FALSE(is_nak(dual.send(Misc{'T', 'C'})));
  EXPECT_EQ(dual.status().track >> 4, 0b100);
  ASSERT_FALSE(is_nak(dual.send(Misc{'T', 'K'})));
  EXPECT_EQ(dual.status().track >> 4, 0b101);
}

// What a controller reports at power-on, from the profile: §3.2 bytes 3-12,
// 19, 35 ZZZ, 36-38 'S', 44, and the A/D error fields; §3.8 the cursor.
TEST(Controller, PowerOnStatusFieldsFromTheProfile) {
  Profile p = test_profile();
  p.display = {"SBS 6", 'h', 3, 17, true};
  p.agc_channel = 3;
  p.el.power_on_speed = AxisSpeed::kSlow;
  Rig r(p);
  auto s = r.status();
  EXPECT_EQ(s.sat_name, "SBS 6");
  EXPECT_EQ(s.pol_equipment & 7, 1) << "'h' displayed";
  EXPECT_EQ(s.agc_channel, 3) << "not applicable";
  EXPECT_EQ(s.az_status & 0x10, 0x10) << "azimuth fast";
  EXPECT_EQ(s.el_status & 0x10, 0) << "elevation configured for slow speed";
  auto d = r.reply<DisplayReply>(ReflectDisplayQuery{});
  EXPECT_EQ(d.cursor_row, 3u);
  EXPECT_EQ(d.cursor_column, 17u);
  EXPECT_EQ(d.blinking, '1');
  EXPECT_NE(d.rows[0].find("SBS 6"), std::string::npos) << d.rows[0];

  p = test_profile();
  p.az_sensor = AzSensor::kFluxgate;
  p.fluxgate_heading = 'M';
  p.az.initial_deg = -90;
  Rig flux(p);
  EXPECT_EQ(flux.status().azimuth, (fields::AzimuthReading{fields::AzimuthReading::Kind::kHeading, 2700, 'M'}));
  EXPECT_EQ(flux.reply<JogPositionReply>(JogMinimal{{'W', 'S', 50}}).position, 2700) << "47h as 31h shows it (E-72)";

  p = test_profile();
  p.az.ad_error = true;
  p.pol.ad_error = true;
  Rig ad(p);
  s = ad.status();
  EXPECT_EQ(s.azimuth.kind, fields::AzimuthReading::Kind::kError);
  EXPECT_EQ(s.elevation, 450) << "only the axes with the error";
  EXPECT_EQ(s.polarization, std::nullopt);
  auto o = ad.send(Jog{{'X', 'S', 0}});
  ASSERT_TRUE(o.reply);
  EXPECT_NE(to_hex(*o.reply).find("2a 2a 2a 2a 2a 2a"), std::string::npos) << "'******' on the wire";
  EXPECT_EQ(ad.reply<JogPositionReply>(JogMinimal{{'W', 'S', 50}}).position, std::nullopt) << "§3.24 bytes 4-9";
  EXPECT_EQ(ad.reply<JogPositionReply>(JogMinimal{{'U', 'S', 50}}).position, 450);
}

// ERRATA E-68: a lower-case name is shown and stored in capitals.
TEST(Controller, SatelliteNamesAreShownAndStoredInCapitals) {
  Rig r;
  RemoteLocate l = locate_satellite("probe loc", -971);
  ASSERT_FALSE(is_nak(r.send(l)));
  EXPECT_EQ(r.status().sat_name, "PROBE LOC");
  RemoteStore st;
  st.preset.preset = false;
  st.sat = {"new sat", -971, 0, '1', '0', 0};
  st.pol_selection = 'H';
  ASSERT_FALSE(is_nak(r.send(st)));
  auto q = r.reply<QueryNameReply>(QueryName{{3}});
  EXPECT_EQ(q.name, "NEW SAT");
  EXPECT_FALSE(is_nak(r.send(AutoMove{AutoMoveStored{' ', "NEW SAT"}})));
  EXPECT_EQ(r.send(AutoMove{AutoMoveStored{' ', "new sat"}}).nak, NakRule::kUnknownSatellite) << "§3.3 exact match";
}

// A preset with a blank field or no name cannot be located or stored: an
// error in the satellite data, not a crash.
TEST(Controller, PresetsWithBlankFieldsAreNakedNotUsed) {
  Profile p = test_profile();
  p.presets = {{3, {"NO LONG", std::nullopt, 0, '1', '0', 0}, false}, {4, {"", -971, 0, '1', '0', 0}, false}};
  Rig r(p);
  RemoteLocate l;
  l.preset = {true, 3};
  EXPECT_EQ(r.send(l).nak, NakRule::kLocateField);
  l.preset = {true, 4};
  EXPECT_EQ(r.send(l).nak, NakRule::kLocateField);
  RemoteStore st;
  st.preset = {true, 4};
  st.pol_selection = 'H';
  EXPECT_EQ(r.send(st).nak, NakRule::kStoreField);
}

TEST(Controller, KeypressJogsForTheHoldTime) {
  Rig r;
  auto o = r.send(RemoteKeypress{'6'});  // W/AZ CW
  ASSERT_FALSE(is_nak(o));
  EXPECT_EQ(o.reply->size(), 5u) << "§3.25 minimal reply";
  r.wait(5s);
  EXPECT_EQ(r.status().azimuth.tenths, 10) << "0.5 s at 2 deg/s";
  EXPECT_FALSE(is_nak(r.send(Misc{'K', 'G'}))) << "Mode Group Change";
}

TEST(Controller, DisplayShowsTheModeAndPositions) {
  Rig r;
  auto d = r.reply<DisplayReply>(ReflectDisplayQuery{});
  EXPECT_EQ(d.rows[0].substr(0, 6), "MANUAL");
  EXPECT_NE(d.rows[1].find("EL   45.0"), std::string::npos) << d.rows[1];
  EXPECT_NE(d.rows[2].find("STORED  2"), std::string::npos) << d.rows[2];
  EXPECT_EQ(d.cursor_row, 1u);
}

// ---- §3.10 - §3.23 stored data ---------------------------------------------------------

TEST(Controller, PresetSatelliteRoundTripAndEmptySlot) {
  Rig r;
  WriteSatellite w;
  w.index = 20;
  w.sat = {"AMC 21", 1250, 19, '6', '0', -900};
  ASSERT_FALSE(is_nak(r.send(w)));
  auto back = r.reply<SatelliteDataReply>(ReadSatellite{{20}});
  EXPECT_EQ(back.index, 20);
  EXPECT_EQ(back.sat, w.sat);
  auto empty = r.reply<SatelliteDataReply>(ReadSatellite{{7}});
  EXPECT_FALSE(empty.index.has_value()) << "7Fh 7Fh";
}

TEST(Controller, TleRoundTrip) {
  Rig r;
  WriteTle t;
  t.index = 10;
  t.line1 = "1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927";
  t.line2 = "2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537";
  ASSERT_FALSE(is_nak(r.send(t)));
  auto back = r.reply<TleDataReply>(ReadTle{{10}});
  EXPECT_EQ(back.line1, t.line1);
  EXPECT_EQ(back.line2, t.line2);
  EXPECT_FALSE(r.reply<TleDataReply>(ReadTle{{1}}).index.has_value());
}

TEST(Controller, SignpostsRoundTripWithTheDvbOption) {
  Profile p = test_profile();
  p.dvb_receiver = true;
  Rig r(p);
  WriteSignpost w;
  w.index = 1;
  w.signpost = {-1000, 11700, 27500, '3', 'V', "ABC123", 9, ""};
  ASSERT_FALSE(is_nak(r.send(w)));
  EXPECT_EQ(r.reply<SignpostDataReply>(ReadSignpost{{1}}).signpost, w.signpost);
}

TEST(Controller, WriteNavigationDeletesTheStoreListThenQueryNameNaks) {
  Rig r;
  ASSERT_FALSE(is_nak(r.send(WriteNavigation{1234, -7530, 1234, ""})));
  auto nav = r.reply<NavigationDataReply>(NavigationQuery{});
  EXPECT_EQ(nav.latitude, 12 * 60 + 34);
  EXPECT_EQ(nav.longitude, -(75 * 60 + 30));
  EXPECT_EQ(nav.heading, 1234);
  EXPECT_EQ(nav.latlon_source, 7) << "remotely entered";
  EXPECT_EQ(r.send(QueryName{{1}}).nak, NakRule::kQueryNameIndex) << "§3.23: STORE list deleted";
}

TEST(Controller, RemoteLocateThenStoreWithCalculatedPolarization) {
  Rig r;
  RemoteLocate l;
  l.preset = {true, 1};
  ASSERT_FALSE(is_nak(r.send(l)));
  EXPECT_EQ(meanings::mode_name(r.extended().mode), "LOCATE_MODE");
  r.wait(300s);
  auto x = r.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FUNCTION_COMPLETED");
  RemoteStore s;
  s.preset = {true, 1};
  s.pol_selection = 'C';
  ASSERT_FALSE(is_nak(r.send(s)));
  auto count = r.reply<QueryNameReply>(QueryName{{1}}).total;
  EXPECT_EQ(count, 2u) << "GALAXY 19 overwritten, not added";
}

// §3.19 byte 29 'C': the LOCATE must be "immediately prior"; a search started
// after it ends its claim, a jog to peak up does not.
TEST(Controller, StoreWithCalculatedPolarizationNeedsTheLocateImmediatelyBefore) {
  Rig r;
  RemoteLocate l;
  l.preset = {true, 1};
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(300s);
  ASSERT_FALSE(is_nak(r.send(Jog{{'W', 'S', 50}}))) << "peaking up by hand";
  RemoteStore s;
  s.preset = {true, 1};
  s.pol_selection = 'C';
  EXPECT_FALSE(is_nak(r.send(s))) << "a jog keeps the LOCATE";
  ASSERT_FALSE(is_nak(r.send(Misc{'A', 'E'})));
  EXPECT_EQ(r.send(s).nak, NakRule::kStoreNeedsLocate) << "a search after the LOCATE ends its claim";
  ASSERT_FALSE(is_nak(r.send(l)));
  EXPECT_FALSE(is_nak(r.send(s))) << "a new LOCATE";
}

// ERRATA E-80: from 40 N 75 W a satellite on the site's meridian is due
// south (true azimuth 180) at the plane triangle's elevation; mount azimuth
// 0.0 heading 030.0 true puts it at position 150.
TEST(Controller, LocatePointsAtTheLookAnglesLessTheHeading) {
  Profile p = test_profile();
  p.navigation.heading_tenths = 300;
  Rig r(p);
  RemoteLocate l = locate_satellite("ON MERIDIAN", -750);
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(600s);
  const auto s = r.status();
  EXPECT_EQ(s.azimuth.tenths, 1500);
  EXPECT_EQ(s.elevation, 437) << "atan((cos 40 - R/r) / sin 40) = 43.7";
  const auto x = r.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FUNCTION_COMPLETED");
}

// ERRATA E-84: a mount whose azimuth the compass does not read needs the
// heading; without it the LOCATE waits for it.
TEST(Controller, LocateWithoutAHeadingWaitsForIt) {
  Profile p = test_profile();
  p.navigation.heading_tenths.reset();
  Rig r(p);
  RemoteLocate l = locate_satellite("ON MERIDIAN", -750);
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(600s);
  EXPECT_EQ(meanings::state_name(r.extended().mode, r.extended().state), "LOCATE_WAITING_FOR_HEADING");
  EXPECT_EQ(r.status().azimuth.tenths, 0);
}

// ERRATA E-81: a satellite below the horizon, or outside the azimuth range,
// is ACKed and ends in the range error, the antenna where it was; E-82 a
// stop then exits with a STOP_KEY entry; E-83 'C' after it is NAKed.
TEST(Controller, LocateToAnUnreachableSatelliteIsARangeError) {
  Profile p = test_profile();
  p.az.min_deg = -90;
  p.az.max_deg = 90;  // the southern sky, true 90-270, out of reach
  Rig r(p);
  RemoteLocate l;
  l.preset = {true, 1};  // GALAXY 19 at 97.1 W: in view, south-west
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(600s);
  auto x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.mode), "LOCATE_MODE");
  EXPECT_EQ(meanings::state_name(x.mode, x.state), "LOCATE_AZIMUTH_RANGE_ERROR");
  EXPECT_EQ(r.status().azimuth.tenths, 0) << "the antenna did not move";
  EXPECT_EQ(r.status().elevation, 450);
  RemoteStore st;
  st.preset = {true, 1};
  st.pol_selection = 'C';
  EXPECT_EQ(r.send(st).nak, NakRule::kStoreNeedsLocate) << "E-83: no LOCATE performed";

  l = locate_satellite("FAR SIDE", 1050);
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(600s);
  x = r.extended();
  EXPECT_EQ(meanings::state_name(x.mode, x.state), "LOCATE_ELEVATION_RANGE_ERROR");
  EXPECT_EQ(r.status().elevation, 450);
  ASSERT_FALSE(is_nak(r.send(Jog{{'X', 'S', 0}})));
  x = r.extended();
  EXPECT_EQ(meanings::mode_name(x.last_mode), "LOCATE_MODE");
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FIRST_ELEV_MOVEMENT_STOP_KEY");
}

// The model refuses a satellite below the horizon even where the elevation
// axis could point there (E-81): the earth is in the way.
TEST(Controller, LocateBelowTheHorizonIsARangeErrorOnAnyMount) {
  Profile p = test_profile();
  p.el.min_deg = -90;
  Rig r(p);
  // From 40 N 75 W, 81.3 deg of longitude away is below the horizon.
  RemoteLocate l = locate_satellite("LOW", 100);
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(600s);
  const auto x = r.extended();
  EXPECT_EQ(meanings::state_name(x.mode, x.state), "LOCATE_ELEVATION_RANGE_ERROR");
}

// ---- offline, unknown, length --------------------------------------------------------------

TEST(Controller, OfflineReplyForEveryValidCommandWhileDisabled) {
  Profile p = test_profile();
  p.remote_enabled = false;
  Rig r(p);
  for (const auto& info : catalog()) {
    if (!info.request_length) continue;
    Frame f{FrameKind::kCommand, p.address, info.code, Bytes(*info.request_length - kFrameOverhead, '0')};
    Outcome o = r.c.execute(f);
    ASSERT_TRUE(o.reply) << info.name;
    EXPECT_EQ(*o.reply, encode_frame(offline_reply(p.address, info.code))) << info.name;
  }
  EXPECT_EQ(r.send_raw(0x5A, "").nak, NakRule::kUnknownCommand) << "E-10 default";
}

TEST(Controller, UnknownCodeAndWrongLengthAreNaked) {
  Rig r;
  EXPECT_EQ(r.send_raw(0x5A, "").nak, NakRule::kUnknownCommand);
  EXPECT_EQ(r.send_raw(0x31, "X").nak, NakRule::kWrongLength);
  auto o = r.send_raw(0x5A, "");
  EXPECT_EQ(*o.reply, encode_frame(nak_reply(r.profile.address, 0x5A))) << "§3: NAK A CC ETX LRC";
}

// ---- one case per NAK rule -------------------------------------------------------------------

struct NakCase {
  const char* name;
  NakRule rule;
  std::function<void(Profile&)> profile;
  std::function<void(Rig&)> setup;
  std::function<Outcome(Rig&)> send;
};

// Frame rules (§3), motion (§3.3-§3.5), query name, misc (§3.6, §3.7) and keys (§3.25).
std::vector<NakCase> nak_cases_of_frames_motion_and_misc() {
  auto none = [](Profile&) {};
  auto nothing = [](Rig&) {};
  auto circular = [](Profile& p) { p.pol_type = PolType::kCircular; };
  auto peaking = [](Profile& p) { p.track = {true, TrackActivity::kPeaking, TrackBand::kC, true}; };
  return {
      {"unknown code", NakRule::kUnknownCommand, none, nothing, [](Rig& r) { return r.send_raw(0x29, ""); }},
      {"wrong length", NakRule::kWrongLength, none, nothing, [](Rig& r) { return r.send_raw(0x30, "1"); }},
      {"38h", NakRule::kNotImplemented, none, nothing, [](Rig& r) { return r.send(SignalStrength{}); }},
      {"malformed", NakRule::kMalformedData, none, nothing, [](Rig& r) { return r.send_raw(0x33, "QF0050"); }},
      {"unknown satellite", NakRule::kUnknownSatellite, none, nothing,
       [](Rig& r) { return r.send(AutoMove{AutoMoveStored{'H', "NOSUCHSAT"}}); }},
      {"target range", NakRule::kTargetOutOfRange, none, nothing,
       [](Rig& r) { return r.send(AutoMove{AutoMoveAzEl{0, 999}}); }},
      {"2B without counts", NakRule::kNoCountSensors, none, nothing,
       [](Rig& r) { return r.send(AutoMove{AutoMoveCounts{1, 1}}); }},
      {"2C without 0.01", NakRule::kNoHundredths, none, nothing,
       [](Rig& r) { return r.send(AutoMove{AutoMoveAxis{'A', 0}}); }},
      {"form 3 circular", NakRule::kPolWithCircularFeed, circular, nothing,
       [](Rig& r) { return r.send(AutoMove{AutoMovePol{100}}); }},
      {"jog into limit", NakRule::kJogIntoLimit, [](Profile& p) { p.az.initial_deg = 180; }, nothing,
       [](Rig& r) { return r.send(Jog{{'W', 'F', 100}}); }},
      {"pol jog circular", NakRule::kJogPolCircular, circular, nothing,
       [](Rig& r) { return r.send(Jog{{'L', 'F', 100}}); }},
      {"jog while peaking", NakRule::kTrackPeaking, peaking, nothing,
       [](Rig& r) { return r.send(Jog{{'E', 'F', 100}}); }},
      {"pol preset no satellites", NakRule::kPolPresetNoSatellites, [](Profile& p) { p.store.clear(); }, nothing,
       [](Rig& r) { return r.send(PolPreset{'H'}); }},
      {"pol preset circular", NakRule::kPolPresetCircular, circular, nothing,
       [](Rig& r) { return r.send(PolPreset{'H'}); }},
      {"query name", NakRule::kQueryNameIndex, none, nothing, [](Rig& r) { return r.send(QueryName{{51}}); }},
      {"reset axis", NakRule::kMiscResetAxis, none, nothing, [](Rig& r) { return r.send(Misc{'R', 'X'}); }},
      {"reset pol circular", NakRule::kMiscResetPolNoFeed, circular, nothing,
       [](Rig& r) { return r.send(Misc{'R', 'P'}); }},
      {"track parameter", NakRule::kMiscTrackParameter, peaking, nothing, [](Rig& r) { return r.send(Misc{'T', 'Z'}); }},
      {"track inactive", NakRule::kMiscTrackNotActive, none, nothing, [](Rig& r) { return r.send(Misc{'T', 'C'}); }},
      {"track single band", NakRule::kMiscTrackNotDualBand,
       [](Profile& p) { p.track = {true, TrackActivity::kIdle, TrackBand::kC, false}; }, nothing,
       [](Rig& r) { return r.send(Misc{'T', 'K'}); }},
      {"band change peaking", NakRule::kMiscTrackPolNotAllowed, peaking, nothing,
       [](Rig& r) { return r.send(Misc{'T', 'K'}); }},
      {"no stow", NakRule::kMiscNoStow, [](Profile& p) { p.stow = false; }, nothing,
       [](Rig& r) { return r.send(Misc{'S', ' '}); }},
      {"no deploy", NakRule::kMiscNoDeploy, [](Profile& p) { p.deploy = false; }, nothing,
       [](Rig& r) { return r.send(Misc{'D', ' '}); }},
      {"search parameter", NakRule::kMiscSearchParameter, none, nothing, [](Rig& r) { return r.send(Misc{'A', 'X'}); }},
      {"key code", NakRule::kKeyCode, none, nothing, [](Rig& r) { return r.send(RemoteKeypress{':'}); }},
  };
}

// Stored data: preset satellites, TLEs, IESS, locate, store, signposts, navigation (§3.10-§3.23).
std::vector<NakCase> nak_cases_of_stored_data() {
  auto none = [](Profile&) {};
  auto nothing = [](Rig&) {};
  return {
      {"satellite index", NakRule::kSatelliteIndex, none, nothing, [](Rig& r) { return r.send(ReadSatellite{{21}}); }},
      {"satellite field", NakRule::kSatelliteField, none, nothing,
       [](Rig& r) {
         WriteSatellite w;
         w.sat.inclination = 20;
         return r.send(w);
       }},
      {"ephemeris index", NakRule::kEphemerisIndex, none, nothing,
       [](Rig& r) {
         WriteSatellite w;
         w.index = 11;
         w.sat.ephemeris = '1';
         return r.send(w);
       }},
      {"tle index", NakRule::kTleIndex, none, nothing, [](Rig& r) { return r.send(ReadTle{{11}}); }},
      {"tle checksum", NakRule::kTleChecksum, [](Profile& p) { p.nak_bad_tle_checksum = true; }, nothing,
       [](Rig& r) {
         WriteTle t;
         t.line1 = std::string(69, '1');
         t.line2 = std::string(69, '2');
         return r.send(t);
       }},
      {"iess index", NakRule::kIessIndex, [](Profile& p) { p.implements_iess = true; }, nothing,
       [](Rig& r) { return r.send(ReadIess{{11}}); }},
      {"locate index", NakRule::kLocateIndex, none, nothing,
       [](Rig& r) {
         RemoteLocate l;
         l.preset = {true, 0};
         return r.send(l);
       }},
      {"locate empty preset", NakRule::kLocateEmptyPreset, none, nothing,
       [](Rig& r) {
         RemoteLocate l;
         l.preset = {true, 5};
         return r.send(l);
       }},
      {"locate field", NakRule::kLocateField, none, nothing,
       [](Rig& r) {
         RemoteLocate l;
         l.sat = {"X", 1800, 0, '0', '0', 0};
         return r.send(l);
       }},
      {"store index", NakRule::kStoreIndex, none, nothing,
       [](Rig& r) {
         RemoteStore s;
         s.preset = {true, 21};
         return r.send(s);
       }},
      {"store empty preset", NakRule::kStoreEmptyPreset, none, nothing,
       [](Rig& r) {
         RemoteStore s;
         s.preset = {true, 2};
         return r.send(s);
       }},
      {"store field", NakRule::kStoreField, none, nothing,
       [](Rig& r) {
         RemoteStore s;
         s.sat = {"X", 0, 25, '0', '0', 0};
         return r.send(s);
       }},
      {"store list full", NakRule::kStoreListFull,
       [](Profile& p) {
         p.store.clear();
         for (int i = 0; i < 50; ++i) p.store.push_back({"SAT " + std::to_string(i), 0, 0, 0, 0});
       },
       nothing,
       [](Rig& r) {
         RemoteStore s;
         s.sat = {"NEW ONE", 0, 0, '0', '0', 0};
         s.pol_selection = 'H';
         return r.send(s);
       }},
      {"store needs locate", NakRule::kStoreNeedsLocate, none, nothing,
       [](Rig& r) {
         RemoteStore s;
         s.sat = {"NEW ONE", 0, 0, '0', '0', 0};
         s.pol_selection = 'C';
         return r.send(s);
       }},
      {"no dvb", NakRule::kNoDvbOption, none, nothing, [](Rig& r) { return r.send(ReadSignpost{{1}}); }},
      {"signpost index", NakRule::kSignpostIndex, [](Profile& p) { p.dvb_receiver = true; }, nothing,
       [](Rig& r) { return r.send(ReadSignpost{{0}}); }},
      {"signpost field", NakRule::kSignpostField, [](Profile& p) { p.dvb_receiver = true; }, nothing,
       [](Rig& r) {
         WriteSignpost w;
         w.signpost.frequency = 9000;
         return r.send(w);
       }},
      {"navigation field", NakRule::kNavigationField, none, nothing,
       [](Rig& r) { return r.send(WriteNavigation{9100, 0, 0, ""}); }},
  };
}

std::vector<NakCase> nak_cases() {
  std::vector<NakCase> all = nak_cases_of_frames_motion_and_misc();
  for (auto& c : nak_cases_of_stored_data()) all.push_back(std::move(c));
  return all;
}

TEST(Controller, EveryNakRuleFiresForItsCase) {
  std::set<NakRule> covered;
  for (const auto& c : nak_cases()) {
    Profile p = test_profile();
    c.profile(p);
    Rig r(p);
    c.setup(r);
    Outcome o = c.send(r);
    ASSERT_TRUE(is_nak(o)) << c.name << ": " << o.note;
    EXPECT_EQ(o.nak, c.rule) << c.name << ": " << o.note;
    EXPECT_NE(o.note.find("§"), std::string::npos) << c.name << ": the note names the paragraph";
    covered.insert(c.rule);
  }
  std::set<NakRule> all;
#define SABUS_X(id, paragraph, text) all.insert(NakRule::id);
  SABUS_NAK_RULES(SABUS_X)
#undef SABUS_X
  EXPECT_EQ(covered, all) << "every rule of nak_rules.hpp has a case";
}

// ---- the bus: framing, addresses, parity ------------------------------------------------------

Bytes wire(const Request& r, std::uint8_t address) { return add_even_parity(encode_request(r, address)); }

TEST(Bus, AnswersOnlyItsAddress) {
  VirtualClock clock;
  Profile p = test_profile();
  Bus bus(multi_drop(p, {'2', '3', 'o'}), clock);
  Bytes out;
  bus.receive(wire(StatusPoll{}, '3'), out);
  ASSERT_EQ(out.size(), 52u);
  EXPECT_EQ(out[1] & 0x7F, '3');
  out.clear();
  bus.receive(wire(StatusPoll{}, '4'), out);
  EXPECT_TRUE(out.empty());
}

TEST(Bus, BadLrcParityAndForeignAddressAreIgnored) {
  VirtualClock clock;
  Bus bus({test_profile()}, clock);
  Bytes out;
  Bytes bad = encode_request(StatusPoll{}, '2');
  bad.back() ^= 1;
  bus.receive(add_even_parity(bad), out);
  Bytes parity = wire(StatusPoll{}, '2');
  parity[2] ^= 0x80;
  bus.receive(parity, out);
  bus.receive(wire(StatusPoll{}, '3'), out);
  EXPECT_TRUE(out.empty());
  EXPECT_NE(bus.take_log().find("ignored"), std::string::npos);
  bus.receive(wire(StatusPoll{}, '2'), out);
  EXPECT_EQ(out.size(), 52u) << "still alive";
  for (auto b : out) EXPECT_TRUE(has_even_parity(b));
}

TEST(Bus, ACopyCarriesOnFromTheSameStateAndIsIndependent) {
  VirtualClock clock;
  Bus bus({test_profile()}, clock);
  const Bytes poll = wire(StatusPoll{}, '2');
  Bytes out;
  bus.receive(ByteView(poll).first(3), out);  // half a frame
  Bus copy(bus);
  copy.receive(ByteView(poll).subspan(3), out);
  EXPECT_EQ(out.size(), 52u) << "the copy's receiver has the first half too";
  copy.controller(0).mutable_state().store.clear();
  out.clear();
  bus.receive(ByteView(poll).subspan(3), out);
  EXPECT_EQ(out.size(), 52u) << "the original still waits for its second half";
  EXPECT_EQ(bus.controller(0).state().store.size(), 2u);
}

// A master set to 8N1 (no parity bit): its bytes outside a frame are logged
// as parity errors, and the transcript has one hint line.
TEST(Bus, AMasterWithoutParityGetsParityErrorsAndOneHint) {
  VirtualClock clock;
  Bus bus({test_profile()}, clock);
  Bytes out;
  const Bytes seven_bit = encode_request(StatusPoll{}, '2');  // 02 32 31 03 02: four of five fail
  for (int i = 0; i < 20; ++i) bus.receive(seven_bit, out);
  EXPECT_TRUE(out.empty());
  const std::string log = bus.take_log();
  EXPECT_NE(log.find("parity error: 0x02 (STX)"), std::string::npos) << log;
  EXPECT_EQ(log.find("unknown bytes: 0x02"), std::string::npos) << log;
  const auto hint = log.find("is the master set to 7E1?");
  ASSERT_NE(hint, std::string::npos) << log;
  EXPECT_EQ(log.find("is the master set to 7E1?", hint + 1), std::string::npos) << "one hint";
  for (int i = 0; i < 20; ++i) bus.receive(seven_bit, out);
  EXPECT_EQ(bus.take_log().find("7E1"), std::string::npos) << "and only once";

  // A 7E1 master with a parity error now and then gets no hint.
  Bus good({test_profile()}, clock);
  for (int i = 0; i < 20; ++i) {
    Bytes w = wire(StatusPoll{}, '2');
    if (i % 5 == 0) w[2] ^= 0x80;
    good.receive(w, out);
  }
  EXPECT_EQ(good.take_log().find("7E1"), std::string::npos);
}

// ---- faults ------------------------------------------------------------------------------------

TEST(Faults, EveryFaultHasAUniqueName) {
  std::set<std::string_view> names;
  for (const auto& f : all_faults()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_EQ(find_fault(f.name), f.fault);
    EXPECT_FALSE(f.description.empty());
  }
  EXPECT_GE(all_faults().size(), 25u);
}

// Each fault changes what a controller puts on the wire for some probe.
TEST(Faults, EveryFaultChangesTheWire) {
  struct Probe {
    Fault fault;
    std::function<void(Profile&)> profile;
    Bytes input;  // on the wire, even parity
    Bytes after{};  // sent 1 s after the input (default: a status poll)
  };
  const Bytes poll = wire(StatusPoll{}, '2');
  Bytes bad_lrc = encode_request(StatusPoll{}, '2');
  bad_lrc.back() ^= 1;
  Bytes parity_error = poll;
  parity_error[2] ^= 0x80;
  auto none = [](Profile&) {};
  auto circular = [](Profile& p) { p.pol_type = PolType::kCircular; };
  auto disabled = [](Profile& p) { p.remote_enabled = false; };
  auto cat = [](std::initializer_list<Bytes> parts) {
    Bytes out;
    for (const auto& b : parts) out.insert(out.end(), b.begin(), b.end());
    return out;
  };
  auto raw = [](std::uint8_t code, std::string_view data) {
    return add_even_parity(encode_frame({FrameKind::kCommand, '2', code, Bytes(data.begin(), data.end())}));
  };
  auto fast_locating = [](Profile& p) {
    for (AxisProfile* a : {&p.az, &p.el}) a->fast_dps = a->slow_dps = 1000;
    p.navigation.heading_tenths = 300;
  };
  auto locate_to = [](std::int32_t longitude_tenths) { return wire(locate_satellite("PROBE", longitude_tenths), '2'); };
  const std::vector<Probe> probes = {
      {Fault::kLrcSkipsByte0, none, poll},
      {Fault::kNakBadCheckByte, none, add_even_parity(bad_lrc)},
      {Fault::kAnswersForeignAddress, none, wire(StatusPoll{}, '3')},
      {Fault::kNakWithoutCommand, none, raw(0x5A, "")},
      {Fault::kShortStatus, none, poll},
      {Fault::kSilentUnknownCommand, none, raw(0x5A, "")},
      {Fault::kExecutesOverlong, none, raw(0x31, "X")},
      {Fault::kOfflineWithoutF, disabled, poll},
      {Fault::kWrongNibbleBase, none, poll},
      {Fault::kLeftJustifiedPosition, none, poll},
      {Fault::kStoreCountOffByOne, none, wire(QueryName{{1}}, '2')},
      {Fault::kCheckByteStxRestarts, none, poll},
      {Fault::kModeEnumOffByOne, none, wire(ExtendedStatusPoll{}, '2')},
      {Fault::kIgnoresParity, none, parity_error},
      {Fault::kAcceptsControlInBody, none, raw(0x35, std::string("0\x01", 2))},
      {Fault::kNoStxStxRestart, none, cat({Bytes{with_even_parity(STX)}, poll})},
      {Fault::kReplyAddressZero, none, poll},
      {Fault::kExtendedStatus52, none, wire(ExtendedStatusPoll{}, '2')},
      {Fault::kQueryNameZeroBased, none, wire(QueryName{{1}}, '2')},
      {Fault::kWriteNavKeepsStore, none, cat({wire(WriteNavigation{1234, 1234, 0, ""}, '2'), wire(QueryName{{1}}, '2')})},
      {Fault::kCircularPolAcked, circular, wire(PolPreset{'H'}, '2')},
      {Fault::kJogIntoLimitAcked, [](Profile& p) { p.az.initial_deg = 180; }, wire(Jog{{'W', 'F', 100}}, '2')},
      {Fault::kEmptySlotZeros, none, wire(ReadSatellite{{9}}, '2')},
      {Fault::kJogIgnoresDuration, none, cat({wire(Jog{{'W', 'F', 50}}, '2'), wire(Jog{{'W', 'F', 50}}, '2')})},
      {Fault::kSecondAxisJogKeepsFirst, none, cat({wire(Jog{{'W', 'F', 9999}}, '2'), wire(Jog{{'U', 'F', 9999}}, '2')})},
      {Fault::kStatusForcesRemote, none, cat({poll, wire(ExtendedStatusPoll{}, '2')})},
      {Fault::kUnimplementedAcked, none, wire(SignalStrength{}, '2')},
      {Fault::kTleIndexTo20, none, raw(0x3B, "15" + std::string(138, '1'))},
      {Fault::kSignpostsWithoutDvb, none, wire(ReadSignpost{{1}}, '2')},
      {Fault::kStowWithoutCapability, [](Profile& p) { p.stow = false; }, wire(Misc{'S', ' '}, '2')},
      {Fault::kDropsReplyByte, none, poll},
      {Fault::kDeviceTypeNoDot, none, wire(DeviceTypeQuery{}, '2')},
      {Fault::kRemoteDisabledAnswers, disabled, poll},
      {Fault::kDriveResetKeepsAlarm, [](Profile& p) { p.alarms.az = 11; }, wire(Misc{'R', 'A'}, '2')},
      // 1.5 deg of azimuth at 2 deg/s: there after 1 s, or stopped at 0.5.
      {Fault::kMoveStopsShort, [](Profile& p) { p.az.initial_deg = 0; }, wire(AutoMove{AutoMoveAzEl{15, 450}}, '2')},
      // The same move, ended after 1 s: the status shows it at rest, or still moving.
      {Fault::kNeverShowsRest, [](Profile& p) { p.az.initial_deg = 0; }, wire(AutoMove{AutoMoveAzEl{15, 450}}, '2')},
      {Fault::kExtendedStatusSpeedBit, none, wire(ExtendedStatusPoll{}, '2')},
      // Issue 32: the alarm code with no alarm; the track byte of 40h while TRACK peaks.
      {Fault::kAlarmCodeLowBattery, none, poll},
      {Fault::kExtendedStatusTrackInactive,
       [](Profile& p) {
         p.track.active = true;
         p.track.activity = TrackActivity::kPeaking;
       },
       wire(ExtendedStatusPoll{}, '2')},
      // Resting on the counterclockwise limit: §3.2 byte 32 shows it.
      {Fault::kAzLimitBitsMissing, [](Profile& p) { p.az.initial_deg = p.az.min_deg; }, poll},
      // Issue 22, value checks (VAL): 1 s of a move later the counts follow the mount.
      {Fault::kPulseCountStale, [](Profile& p) { p.az.initial_deg = 0; }, wire(AutoMove{AutoMoveAzEl{15, 450}}, '2'),
       wire(PulseCountQuery{}, '2')},
      {Fault::kPulseCountNoOffset, none, wire(PulseCountQuery{}, '2')},
      {Fault::kHundredthsAlwaysZero, [](Profile& p) { p.hundredths = true; p.az.initial_deg = 12.34; },
       wire(ExtendedStatusPoll{}, '2')},
      // -1.5 deg of azimuth at 2 deg/s: there after 1 s, or at +1.5.
      {Fault::kForm2CSignDropped, [](Profile& p) { p.hundredths = true; p.az.initial_deg = 0; },
       wire(AutoMove{AutoMoveAxis{'A', -150}}, '2')},
      // Form 3 to -5.0 with the zeros left of the sign (E-45's other spelling): NAKed, or a move.
      {Fault::kTargetSpellingsBoth, none, raw(0x32, "P00-5000000")},
      // The default scale (10000 at 0 deg, 100 a degree): -1.5 deg of azimuth, the elevation where it is.
      {Fault::kForm2BMirrored, [](Profile& p) { p.az_sensor = AzSensor::kPulse; p.az.initial_deg = 0; },
       wire(AutoMove{AutoMoveCounts{9850, 14500}}, '2')},
      // A move of 1.5 deg stopped at once by the Stop key, or run on to its end.
      {Fault::kStopKeyIgnoredInRemote, [](Profile& p) { p.az.initial_deg = 0; },
       cat({wire(AutoMove{AutoMoveAzEl{15, 450}}, '2'), wire(RemoteKeypress{'A'}, '2')})},
      {Fault::kXReentersRemote, none, cat({wire(AutoMove{AutoMoveAzEl{15, 450}}, '2'), wire(Jog{{'X', 'F', 0}}, '2')}),
       wire(ExtendedStatusPoll{}, '2')},
      // LOCATEs on a mount fast enough to arrive within the probe's second,
      // from 40 N 75 W with mount azimuth 0.0 heading 030.0 (true az 180 of
      // the satellite on the site's meridian is position 150, ERRATA E-80).
      {Fault::kLocateIgnoresHeading, fast_locating, locate_to(-750)},
      {Fault::kLocateAzimuthCounterclockwise, fast_locating, locate_to(-750)},
      {Fault::kLocateEasternLongitude, fast_locating, locate_to(-750)},
      {Fault::kLocateNorthernLatitude,
       [&](Profile& p) {
         fast_locating(p);
         p.navigation.latitude_min = -40 * 60;  // due north, position -30
       },
       locate_to(-750)},
      // The satellite on the far side of the earth: a range error, not a move.
      {Fault::kLocateMovesOutOfRange, fast_locating, locate_to(1050)},
      // Issue 22, stops: a LOCATE or STOW stopped at once by 'X'; a LOCATE with no site.
      {Fault::kLocateIgnoresStop, fast_locating, cat({locate_to(-750), wire(Jog{{'X', 'F', 0}}, '2')})},
      {Fault::kLocateStopExitCompleted, fast_locating, cat({locate_to(-750), wire(Jog{{'X', 'F', 0}}, '2')}),
       wire(ExtendedStatusPoll{}, '2')},
      {Fault::kLocateStopExitStale, fast_locating, cat({locate_to(-750), wire(Jog{{'X', 'F', 0}}, '2')}),
       wire(ExtendedStatusPoll{}, '2')},
      {Fault::kLocateWithoutSiteCompletes, [](Profile& p) { p.navigation.latitude_min.reset(); }, locate_to(-750),
       wire(ExtendedStatusPoll{}, '2')},
      {Fault::kStowIgnoresStop, [](Profile& p) { p.stow = true; }, cat({wire(Misc{'S', 'S'}, '2'), wire(Jog{{'X', 'F', 0}}, '2')})},
      {Fault::kStowStopExitFinished, [](Profile& p) { p.stow = true; },
       cat({wire(Misc{'S', 'S'}, '2'), wire(Jog{{'X', 'F', 0}}, '2')}), wire(ExtendedStatusPoll{}, '2')},
      // A DEPLOY (to an elevation the profile states) and a search, stopped at once by 'X'.
      {Fault::kDeployIgnoresStop, [](Profile& p) { p.el.deploy_deg = 10.0; },
       cat({wire(Misc{'D', 'D'}, '2'), wire(Jog{{'X', 'F', 0}}, '2')})},
      {Fault::kDeployStopExitFinished, [](Profile& p) { p.el.deploy_deg = 10.0; },
       cat({wire(Misc{'D', 'D'}, '2'), wire(Jog{{'X', 'F', 0}}, '2')}), wire(ExtendedStatusPoll{}, '2')},
      {Fault::kSearchIgnoresStop, [](Profile&) {}, cat({wire(Misc{'A', 'E'}, '2'), wire(Jog{{'X', 'F', 0}}, '2')})},
      {Fault::kSearchStopExitNoPeak, [](Profile&) {}, cat({wire(Misc{'A', 'E'}, '2'), wire(Jog{{'X', 'F', 0}}, '2')}),
       wire(ExtendedStatusPoll{}, '2')},
      // Issue 22, stored records: slot 2 and STORE entry 2 sit between the first and the last.
      {Fault::kSlotReadShiftedInMiddle,
       [](Profile& p) {
         p.presets = {PresetSatellite{1, {}, false}, PresetSatellite{2, {}, false}};
         p.presets[0].data.name = "FIRST";
         p.presets[1].data.name = "MIDDLE";
       },
       wire(ReadSatellite{{2}}, '2')},
      {Fault::kStoreEntryShiftedInMiddle, [](Profile& p) { p.store = {{"ONE"}, {"TWO"}, {"THREE"}}; },
       wire(QueryName{{2}}, '2')},
      // Issue 32, values on every legal profile.
      {Fault::kDeviceTypeFixedVersion, [](Profile& p) { p.firmware = "2.07"; }, wire(DeviceTypeQuery{}, '2')},
      {Fault::kStoresIntoFirstSlot, none, wire(WriteSatellite{5, {"FIVE", 1250, 3, '1', '1', 125}}, '2'),
       wire(ReadSatellite{{5}}, '2')},
      // Resting on the elevation's stow limit: §3.2 byte 33 bit C.
      {Fault::kStowLimitBitsMissing,
       [](Profile& p) {
         p.el.has_stow_limit = true;
         p.el.stow_deg = p.el.initial_deg;
       },
       poll},
      {Fault::kNaksForeignFrames, none, add_even_parity(encode_frame({FrameKind::kCommand, '3', 0x5A, {}}))},
      {Fault::kSpareBytesBlank,
       [](Profile& p) {
         p.dvb_receiver = true;
         p.signposts = {Signpost{}};
       },
       wire(ReadSignpost{{1}}, '2')},
      // The third reply of the probe's three: two polls, then the one after.
      {Fault::kGarblesReplies, none,
       [] {
         Bytes two = wire(StatusPoll{}, '2');
         const Bytes again = two;
         two.insert(two.end(), again.begin(), again.end());
         return two;
       }()},
  };
  std::set<Fault> probed;
  for (const auto& probe : probes) {
    Profile p = test_profile();
    probe.profile(p);
    auto run = [&](FaultSet faults) {
      VirtualClock clock;
      Bus bus({p}, clock, faults);
      Bytes out;
      // Feed the probe, letting 1 s pass after each frame (jogs end).
      bus.receive(probe.input, out);
      clock.advance(std::chrono::seconds(1));
      bus.tick();
      bus.receive(probe.after.empty() ? wire(StatusPoll{}, '2') : probe.after, out);
      return out;
    };
    EXPECT_NE(run({}), run({probe.fault})) << all_faults()[static_cast<std::size_t>(probe.fault)].name;
    probed.insert(probe.fault);
  }
  EXPECT_EQ(probed.size(), all_faults().size()) << "every fault has a probe";
}

TEST(Controller, InvariantsHoldAfterTheTests) {
  Rig r;
  r.send(Jog{{'W', 'F', 9999}});
  r.wait(1000s);
  EXPECT_EQ(r.c.check_invariants(), "");
}

// The fuzz target's oracle: check_invariants must see a name twice however
// far apart the two entries are in a full list.
TEST(Controller, InvariantsSeeANameTwiceAnywhereInTheStoreList) {
  Rig r;
  auto& store = r.c.mutable_state().store;
  store.clear();
  for (int i = 0; i < 50; ++i) store.push_back({"SAT" + std::to_string(i)});
  EXPECT_EQ(r.c.check_invariants(), "");
  store[49].name = store[0].name;
  EXPECT_EQ(r.c.check_invariants(), "a name twice in the STORE list; ");
  store[49].name = "SAT49";
  store[31].name = store[17].name;
  EXPECT_EQ(r.c.check_invariants(), "a name twice in the STORE list; ");
  store.push_back({"SAT50"});
  EXPECT_EQ(r.c.check_invariants(), "STORE list over 50; a name twice in the STORE list; ");
}

}  // namespace
}  // namespace sabus::harness

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "sabus/harness/state_file.hpp"
#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

// A preset the tests store, then save.
WriteSatellite preset_3() {
  WriteSatellite w;
  w.index = 3;
  w.sat = {"AMC 21", 1250, 3, '1', '1', 125};
  return w;
}

TEST(StateFile, ARestartedControllerKeepsItsStoredData) {
  Rig first;
  const WriteSatellite w = preset_3();
  ASSERT_FALSE(is_nak(first.send(w)));
  first.send(WriteNavigation{1234, -7530, 1234, ""});  // deletes the STORE list
  first.send(Jog{{'W', 'F', 1000}});
  first.wait(2s);
  const std::string saved = save_state({&first.c});

  Rig second;
  std::string error;
  ASSERT_TRUE(load_state(saved, {&second.c}, error)) << error;
  EXPECT_EQ(second.reply<SatelliteDataReply>(ReadSatellite{{3}}).sat, w.sat);
  EXPECT_EQ(second.send(QueryName{{1}}).nak, NakRule::kQueryNameIndex) << "the deleted STORE list stays deleted";
  EXPECT_EQ(second.status().azimuth.tenths, 20);
  EXPECT_EQ(second.reply<NavigationDataReply>(NavigationQuery{}).latitude, 12 * 60 + 34);
  EXPECT_FALSE(load_state("{\"format\": \"other\"}", {&second.c}, error));
  EXPECT_FALSE(load_state("not json", {&second.c}, error));
  EXPECT_FALSE(error.empty());
}

// A state file a person edited: each bad value is an error naming its key, and
// the controller keeps the state it had (no half-read file, no cast of 1e300).
TEST(StateFile, ABadValueNamesItsKeyAndChangesNothing) {
  Rig first;
  ASSERT_FALSE(is_nak(first.send(preset_3())));
  const std::string saved = save_state({&first.c});
  // Edits the first `from` of the file, or with in_preset the one in preset
  // 3's record (its keys sort around the name: data before index).
  auto edited = [&](const std::string& from, const std::string& to, bool in_preset) {
    std::string text = saved;
    const auto name = text.find("\"AMC 21\"");
    const auto before = text.rfind(from, name), after = text.find(from, name);
    const auto at = !in_preset ? text.find(from) : before != std::string::npos && before > text.rfind("\"data\"", name) ? before : after;
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  };
  const struct {
    std::string from, to;
    bool in_preset;
    std::string error;
  } cases[] = {
      {"\"index\": 3", "\"index\": 1e300", true, "presets.index: expected a whole number 1 to 20, got 1e+300"},
      {"\"index\": 3", "\"index\": 300", true, "presets.index: expected a whole number 1 to 20, got 300"},
      {"\"index\": 3", "\"index\": -1", true, "presets.index: expected a whole number 1 to 20, got -1"},
      {"\"band\": \"1\"", "\"band\": \"\"", true, "presets 3.band: expected one character, got \"\""},
      {"\"longitude\": 1250", "\"longitude\": 99999999", true,
       "presets 3: not a record the Write Satellite Data command carries"},
      {"\"longitude\": 1250", "\"longitude\": 5e9", true, "presets 3.longitude: expected a whole number"},
      {"\"az\": ", "\"az\": 1e6, \"was\": ", false, "positions.az: 1000000.0 is outside the profile's range"},
      {"\"name\": \"SBS 6\"", "\"name\": \"caf\u00e9\"", false, "store[0].name: not a name the Query Name reply carries"},
      {"\"name\": \"SBS 6\"", "\"name\": \"ELEVEN CHAR\"", false, "store[0].name: not a name the Query Name reply carries"},
      {"\"name\": \"SBS 6\"", "\"name\": \"GALAXY 19\"", false, "store[1].name: \"GALAXY 19\" is in the STORE list twice"},
  };
  for (const auto& c : cases) {
    Rig other;
    const std::string before = save_state({&other.c});
    std::string error;
    EXPECT_FALSE(load_state(edited(c.from, c.to, c.in_preset), {&other.c}, error)) << c.to;
    EXPECT_NE(error.find("controller 50: " + c.error), std::string::npos) << error;
    EXPECT_EQ(save_state({&other.c}), before) << c.to;
  }
}

// The keys of one controller's state, as load_state reads them.
const std::set<std::string> kStateKeys = {"positions", "store", "presets", "tles", "signposts", "navigation"};

std::set<std::string> keys_of(const nlohmann::json& j) {
  std::set<std::string> out;
  for (const auto& [k, v] : j.items()) out.insert(k);
  return out;
}

// save_state on every branch it writes: a controller holding something in
// every list (a name with a quote and a backslash, navigation data with no
// heading: null), beside one holding nothing. The
// text parses, has the keys load_state reads, and reads back to the same
// state (the same text again).
TEST(StateFile, EveryListFullAndEmptyParsesAndReadsBack) {
  Profile dvb = test_profile();
  dvb.dvb_receiver = true;
  dvb.navigation.heading_tenths.reset();
  Rig full(dvb);
  ASSERT_FALSE(is_nak(full.send(WriteTle{2, std::string(69, '1'), std::string(69, '2')})));
  ASSERT_FALSE(is_nak(full.send(preset_3())));
  SignpostData sp;
  sp.id = "a\"b\\";
  ASSERT_FALSE(is_nak(full.send(WriteSignpost{4, sp})));
  Profile bare = test_profile();
  bare.address = 51;
  bare.store.clear();
  bare.presets.clear();
  Rig empty(bare);

  const std::string text = save_state({&full.c, &empty.c});
  const auto doc = nlohmann::json::parse(text);  // throws on a text that is not JSON
  EXPECT_EQ(doc["format"], "sabus-sim-state");
  EXPECT_EQ(doc["version"], 1);
  ASSERT_EQ(keys_of(doc["controllers"]), (std::set<std::string>{"50", "51"}));
  const auto& f = doc["controllers"]["50"];
  EXPECT_EQ(keys_of(f), kStateKeys);
  ASSERT_EQ(f["store"].size(), 2u);
  EXPECT_EQ(f["store"][1]["name"], "GALAXY 19");
  ASSERT_EQ(f["presets"].size(), 2u);
  EXPECT_EQ(f["presets"][1]["index"], 3);
  EXPECT_EQ(f["presets"][1]["data"]["name"], "AMC 21");
  ASSERT_EQ(f["tles"].size(), 1u);
  EXPECT_EQ(f["tles"][0]["line2"], std::string(69, '2'));
  ASSERT_EQ(f["signposts"].size(), 1u);
  EXPECT_EQ(f["signposts"][0]["id"], sp.id);
  EXPECT_EQ(f["signposts"][0]["frequency"], 10700);
  EXPECT_TRUE(f["navigation"]["heading"].is_null());
  const auto& e = doc["controllers"]["51"];
  EXPECT_EQ(keys_of(e), kStateKeys);
  for (const char* list : {"store", "presets", "tles", "signposts"}) EXPECT_EQ(e[list], nlohmann::json::array()) << list;

  Rig full_again(dvb), empty_again(bare);
  full_again.send(WriteSatellite{});  // something to be overwritten by the file
  std::string error;
  ASSERT_TRUE(load_state(text, {&full_again.c, &empty_again.c}, error)) << error;
  EXPECT_EQ(save_state({&full_again.c, &empty_again.c}), text);
}

class StateFileOnDisk : public test::TempDirTest {
 protected:
  StateFileOnDisk() : TempDirTest("sabus-state-file-test") {}
};

// write_state_file replaces only its file: a folder in its place is refused
// and left alone, a file named like the old temporary (PATH.tmp) is not
// touched, and what it writes parses as the state.
TEST_F(StateFileOnDisk, WritesOnlyItsFileWhole) {
  Rig r;
  std::string error;
  std::filesystem::create_directory(path("dir.json"));
  EXPECT_FALSE(write_state_file(path("dir.json"), {&r.c}, error));
  EXPECT_NE(error.find("not a regular file"), std::string::npos) << error;
  EXPECT_TRUE(std::filesystem::is_empty(path("dir.json")));

  std::ofstream(path("state.json.tmp")) << "someone else's";
  ASSERT_TRUE(write_state_file(path("state.json"), {&r.c}, error)) << error;
  EXPECT_EQ(test::slurp(path("state.json.tmp")), "someone else's");
  EXPECT_EQ(test::slurp(path("state.json")), save_state({&r.c}));
  EXPECT_EQ(keys_of(nlohmann::json::parse(test::slurp(path("state.json")))["controllers"]["50"]), kStateKeys);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_), {}), 3) << "no temporary left";
}

// A state file that is there but cannot be read is an error, not a first
// start (which would replace it with the defaults at the first change).
TEST_F(StateFileOnDisk, AnUnreadableStateFileIsAnErrorNotAFirstStart) {
  Rig r;
  std::string error;
  EXPECT_TRUE(read_state_file(path("none.json"), {&r.c}, error)) << "a missing file is a first start";
  // A socket cannot be opened (ENXIO), even by root, for whom a file without
  // read permission still opens.
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const std::string sock = path("sock.json");
  ASSERT_LT(sock.size(), sizeof addr.sun_path);
  std::strcpy(addr.sun_path, sock.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_FALSE(read_state_file(sock, {&r.c}, error));
  EXPECT_EQ(error, sock + ": cannot read: " + std::strerror(ENXIO));
  ::close(fd);
}

}  // namespace
}  // namespace sabus::harness

namespace sabus::harness {
namespace {

// Every command code 30h-48h in every catalog form gets an ACK of the
// catalog's reply length from a controller that has what the form needs.
TEST(Controller, EveryCommandAndFormIsServedWithTheCatalogLength) {
  Profile p = test_profile();
  p.az_sensor = AzSensor::kPulse;
  p.hundredths = true;
  p.dvb_receiver = true;
  p.implements_iess = true;
  p.implements_signal_strength = true;
  p.track = {true, TrackActivity::kIdle, TrackBand::kC, true};
  WriteTle tle;
  tle.line1 = std::string(69, '1');
  tle.line2 = std::string(69, '2');
  RemoteStore store;
  store.preset = {true, 1};
  store.pol_selection = 'H';
  RemoteLocate locate_data;
  locate_data.sat = {"AMC 21", -1250, 0, '1', '0', 0};
  RemoteLocate locate_preset;
  locate_preset.preset = {true, 1};
  RemoteStore store_data;
  store_data.sat.name = "NEW SAT";
  store_data.pol_selection = 'H';
  const std::vector<std::pair<std::string, Request>> cases = {
      {"", DeviceTypeQuery{}},
      {"", StatusPoll{}},
      {"1", AutoMove{AutoMoveStored{'H', "SBS 6"}}},
      {"2A", AutoMove{AutoMoveAzEl{-1525, 456}}},
      {"2B", AutoMove{AutoMoveCounts{11050, 12152}}},
      {"2C", AutoMove{AutoMoveAxis{'E', 4512}}},
      {"3", AutoMove{AutoMovePol{500}}},
      {"E", Jog{{'E', 'F', 50}}}, {"W", Jog{{'W', 'S', 50}}}, {"D", Jog{{'D', 'F', 50}}},
      {"U", Jog{{'U', 'S', 50}}}, {"O", Jog{{'O', 'F', 50}}}, {"L", Jog{{'L', 'S', 50}}},
      {"X", Jog{{'X', 'S', 0}}},
      {"H", PolPreset{'H'}}, {"V", PolPreset{'V'}},
      {"", QueryName{{1}}},
      {"R", Misc{'R', 'A'}}, {"T", Misc{'T', 'K'}}, {"S", Misc{'S', ' '}}, {"D", Misc{'D', ' '}},
      {"A", Misc{'A', 'F'}}, {"K", Misc{'K', '5'}},
      {"", ReflectDisplayQuery{}},
      {"", SignalStrength{0x21, 0x01}},
      {"", WriteSatellite{}},
      {"", ReadSatellite{{1}}},
      {"", tle},
      {"", ReadTle{{1}}},
      {"", WriteIess{1, "EPHEMERIS"}},
      {"", ReadIess{{1}}},
      {"", PulseCountQuery{}},
      {"", ExtendedStatusPoll{}},
      {"preset", locate_preset},
      {"data", locate_data},
      {"preset", store},
      {"data", store_data},
      {"", WriteSignpost{}},
      {"", ReadSignpost{{1}}},
      {"", NavigationQuery{}},
      {"", WriteNavigation{1234, -7530, 1234, ""}},
      {"E", JogMinimal{{'E', 'F', 50}}}, {"W", JogMinimal{{'W', 'S', 50}}}, {"D", JogMinimal{{'D', 'F', 50}}},
      {"U", JogMinimal{{'U', 'S', 50}}}, {"O", JogMinimal{{'O', 'F', 50}}}, {"L", JogMinimal{{'L', 'S', 50}}},
      {"X", JogMinimal{{'X', 'S', 0}}},
      {"", RemoteKeypress{'G'}},
  };
  std::set<std::pair<std::uint8_t, std::string>> served;
  for (const auto& [form, request] : cases) {
    Rig r(p);
    const std::uint8_t code = command_code(request);
    EXPECT_EQ(form_of(request), form) << describe_byte(code);
    Outcome o = r.send(request);
    ASSERT_TRUE(o.reply.has_value()) << describe_byte(code) << " " << form;
    EXPECT_EQ((*o.reply)[0], ACK) << describe_byte(code) << " form " << form << ": " << o.note;
    const CommandInfo* info = find_command(code);
    if (info->reply_length) {
      EXPECT_EQ(o.reply->size(), *info->reply_length) << info->name << " form " << form;
    }
    served.insert({code, form});
  }
  for (const auto& info : catalog())
    for (const auto& f : info.forms)
      EXPECT_TRUE(served.count({info.code, std::string(f.id)})) << info.name << " form " << f.id << " has no case";
}

}  // namespace
}  // namespace sabus::harness
