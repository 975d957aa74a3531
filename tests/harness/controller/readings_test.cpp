// The reference controller on either side of the spec's open points
// (readings.hpp, the protocol/ERRATA.md entries of class reading): each
// switch changes what its entry says and nothing else, and the profile's
// `readings:` pins load, write back and parse from --reading.
#include <algorithm>
#include <array>
#include <memory>

#include <gtest/gtest.h>

#include "controller_rig.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/readings.hpp"

namespace sabus::harness {
namespace {

using namespace std::chrono_literals;

Profile site_profile() {
  Profile p;
  p.store = {{"SBS 6", -74.0, 40.0, 10.0, -80.0}};
  PresetSatellite g19;
  g19.index = 1;
  g19.data = {"GALAXY 19", -971, 0, '1', '0', -125};
  p.presets = {g19};
  p.navigation.latlon_source = 7;
  p.navigation.latitude_min = 40 * 60;
  p.navigation.longitude_min = -75 * 60;
  p.navigation.heading_source = 7;
  p.navigation.heading_tenths = 0;
  return p;
}

Profile reading(Profile p, std::string_view id, ReadingSide side = ReadingSide::kOther) {
  p.readings[std::string(id)] = side;
  return p;
}

struct Rig : ControllerRig {
  using ControllerRig::ControllerRig;
  std::string mode() { return std::string(meanings::mode_name(extended().mode)); }
  std::string state() {
    const auto x = extended();
    return std::string(meanings::state_name(x.mode, x.state));
  }
};

bool is_offline(const Outcome& o) {
  return o.reply && is_offline_reply(decode_frame(*o.reply).value());
}

RemoteLocate locate_on_meridian() {
  RemoteLocate l;
  l.preset.preset = false;
  l.sat = {"ON MERIDIAN", -750, 0, '1', '0', 0};
  return l;
}

// ---- the table and the pins --------------------------------------------------

TEST(Readings, EveryPointHasAnIdAParagraphAndTwoSides) {
  ASSERT_FALSE(reading_points().empty());
  for (const ReadingPoint& p : reading_points()) {
    EXPECT_TRUE(p.id.starts_with("E-")) << p.id;
    EXPECT_FALSE(p.paragraph.empty()) << p.id;
    EXPECT_FALSE(p.reference.empty()) << p.id;
    EXPECT_FALSE(p.other.empty()) << p.id;
    EXPECT_NE(p.reference, p.other) << p.id;
    EXPECT_EQ(find_reading_point(p.id), &p);
  }
  EXPECT_EQ(find_reading_point("E-1"), nullptr) << "7E1 is the spec's text, no reading";
}

TEST(Readings, ASpecFlipsEveryPointOrTheOnesItNames) {
  ReadingPins pins;
  EXPECT_FALSE(apply_reading_spec("other", pins));
  EXPECT_EQ(pins.size(), reading_points().size());
  for (const auto& [id, side] : pins) EXPECT_EQ(side, ReadingSide::kOther) << id;
  ReadingPins some;
  EXPECT_FALSE(apply_reading_spec("E-90=other,E-93=reference", some));
  EXPECT_EQ(some, (ReadingPins{{"E-90", ReadingSide::kOther}, {"E-93", ReadingSide::kReference}}));
  EXPECT_EQ(side_taken(some, "E-91"), ReadingSide::kReference);
  EXPECT_EQ(side_pinned(some, "E-91"), std::nullopt);
}

TEST(Readings, ABadSpecSaysWhyAndChangesNothing) {
  ReadingPins pins{{"E-90", ReadingSide::kOther}};
  const ReadingPins before = pins;
  for (std::string_view bad : {"", "others", "E-90", "E-1=other", "E-90=other,E-91=sideways", "E-90=other,"}) {
    const auto why = apply_reading_spec(bad, pins);
    ASSERT_TRUE(why) << "\"" << bad << "\" was taken";
    EXPECT_FALSE(why->empty());
    EXPECT_EQ(pins, before) << bad;
  }
  EXPECT_NE(apply_reading_spec("E-1=other", pins)->find("E-90"), std::string::npos) << "names the switchable ones";
  // other-2 only where the point has a third side.
  const auto no_third = apply_reading_spec("E-90=other-2", pins);
  ASSERT_TRUE(no_third);
  EXPECT_NE(no_third->find("reference or other"), std::string::npos) << *no_third;
  EXPECT_EQ(pins, before);
}

// A third side (ERRATA's other-2) by name, or for every point that has one
// (the rest to other).
TEST(Readings, OtherTwoPinsThePointsThatHaveIt) {
  ReadingPins one;
  EXPECT_FALSE(apply_reading_spec("E-23=other-2", one));
  EXPECT_EQ(one, (ReadingPins{{"E-23", ReadingSide::kOther2}}));
  ReadingPins every;
  EXPECT_FALSE(apply_reading_spec("other-2", every));
  EXPECT_EQ(every.size(), reading_points().size());
  std::size_t thirds = 0;
  for (const ReadingPoint& p : reading_points()) {
    const bool third = !p.other_2.empty();
    thirds += third;
    EXPECT_EQ(every.at(std::string(p.id)), third ? ReadingSide::kOther2 : ReadingSide::kOther) << p.id;
    EXPECT_EQ(sides_of(p).size(), third ? 3u : 2u) << p.id;
  }
  EXPECT_GE(thirds, 1u);
  auto loaded = load_profile_text("readings:\n  E-23: other-2\n");
  ASSERT_TRUE(loaded) << loaded.error->text();
  EXPECT_EQ(side_taken(loaded.profile->readings, "E-23"), ReadingSide::kOther2);
  auto again = load_profile_text(to_yaml(*loaded.profile));
  ASSERT_TRUE(again) << again.error->text();
  EXPECT_EQ(*again.profile, *loaded.profile);
  auto lacking = load_profile_text("readings:\n  E-90: other-2\n", "p.yaml");
  ASSERT_FALSE(lacking);
  EXPECT_EQ(lacking.error->key, "readings.E-90");
  EXPECT_NE(lacking.error->message.find("not a side of E-90"), std::string::npos) << lacking.error->message;
  // A controller pinned to E-23 other-2 NAKs priority 0, so it holds none.
  const std::string prio = "dvb_receiver: true\nsignposts:\n  - {index: 1, longitude: -97.0, frequency: 11720, "
                           "symbol_rate: 20000, fec: 3/4, polarization: H, id: G19KU, priority: PRIO}\nreadings:\n  E-23: other-2\n";
  auto zero = load_profile_text(std::string(prio).replace(prio.find("PRIO"), 4, "0"), "p.yaml");
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error->key, "signposts");
  EXPECT_NE(zero.error->message.find("E-23 other-2"), std::string::npos) << zero.error->message;
  EXPECT_TRUE(load_profile_text(std::string(prio).replace(prio.find("PRIO"), 4, "1"), "p.yaml"));
}

TEST(Readings, ProfilePinsLoadAndWriteBack) {
  auto loaded = load_profile_text("readings:\n  E-90: other\n  E-93: reference\n");
  ASSERT_TRUE(loaded) << loaded.error->text();
  EXPECT_EQ(loaded.profile->readings,
            (ReadingPins{{"E-90", ReadingSide::kOther}, {"E-93", ReadingSide::kReference}}));
  auto again = load_profile_text(to_yaml(*loaded.profile));
  ASSERT_TRUE(again) << again.error->text();
  EXPECT_EQ(*again.profile, *loaded.profile);
  auto none = load_profile_text(to_yaml(Profile{}));
  ASSERT_TRUE(none);
  EXPECT_TRUE(none.profile->readings.empty()) << "an open point is no key";
}

TEST(Readings, ABadPinNamesItsLineAndKey) {
  auto side = load_profile_text("name: x\nreadings:\n  E-90: sideways\n", "p.yaml");
  ASSERT_FALSE(side);
  EXPECT_EQ(side.error->line, 3);
  EXPECT_EQ(side.error->key, "readings.E-90");
  EXPECT_NE(side.error->message.find("reference"), std::string::npos) << side.error->message;
  auto id = load_profile_text("readings:\n  E-1: other\n", "p.yaml");
  ASSERT_FALSE(id);
  EXPECT_EQ(id.error->line, 2);
  EXPECT_NE(id.error->message.find("E-90"), std::string::npos) << "lists the keys: " << id.error->message;
}

// ---- each point, both sides ---------------------------------------------------

// E-29: §3.18/§3.19 byte 3, a preset's tens digit of 2 (41h and 42h alike).
TEST(Readings, E29TheOtherSideTakesATensDigitOf2AsMalformed) {
  Profile twenty = site_profile();
  PresetSatellite p20;
  p20.index = 20;
  p20.data = {"GALAXY 20", -990, 0, '1', '0', 0};
  twenty.presets.push_back(p20);
  PresetSatellite p11 = p20;
  p11.index = 11;
  p11.data.name = "GALAXY 11";
  twenty.presets.push_back(p11);
  Rig ref(twenty), other(reading(twenty, "E-29"));
  // 42h by preset 20: byte 3 is 40h | A=1 << 4 | tens 2 ('R'), byte 4 '0'.
  const std::string store20 = "R0" + std::string(24, ' ') + "S20.0 -70.0V     ";
  EXPECT_FALSE(is_nak(ref.send_raw(0x42, store20)));
  EXPECT_EQ(other.send_raw(0x42, store20).nak, NakRule::kMalformedData);
  // Index 21 is out of range on one side, malformed on the other; the same for 41h.
  const std::string store21 = "R1" + std::string(24, ' ') + "S20.0 -70.0V     ";
  EXPECT_EQ(ref.send_raw(0x42, store21).nak, NakRule::kStoreIndex);
  EXPECT_EQ(other.send_raw(0x42, store21).nak, NakRule::kMalformedData);
  const std::string locate21 = "R1" + std::string(24, ' ') + "NA    ";
  EXPECT_EQ(ref.send_raw(0x41, locate21).nak, NakRule::kLocateIndex);
  EXPECT_EQ(other.send_raw(0x41, locate21).nak, NakRule::kMalformedData);
  // Tens 0 and 1 are read alike; with A = 0 the index bytes carry no meaning.
  const std::string store1 = "Q1" + std::string(24, ' ') + "S20.0 -70.0V     ";
  EXPECT_FALSE(is_nak(other.send_raw(0x42, store1)));
  RemoteStore data;
  data.preset = {false, 20};
  data.sat = {"DATA TWENTY", -970, 0, '1', '0', 0};
  data.pol_selection = 'S';
  data.h_pos = 100;
  data.v_pos = -800;
  EXPECT_FALSE(is_nak(other.send(data)));
  // A side taken late is the side the next command meets.
  ref.c.set_reading("E-29", ReadingSide::kOther);
  EXPECT_EQ(ref.send_raw(0x42, store20).nak, NakRule::kMalformedData);
}

// E-60: §3.23 what "valid" navigation data is.
TEST(Readings, E60TheOtherSideNaksThePolesAndMinus180) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-60"));
  const WriteNavigation north_pole{9000, 7530, 0, ""}, south_pole{-9000, 7530, 0, ""};
  const WriteNavigation west180{1234, -18000, 0, ""}, east180{1234, 18000, 0, ""}, near_pole{-8959, 0, 0, ""};
  for (const WriteNavigation& w : {north_pole, south_pole, west180, east180, near_pole})
    EXPECT_FALSE(is_nak(ref.send(w))) << w.latitude << " " << w.longitude;
  for (const WriteNavigation& w : {north_pole, south_pole, west180})
    EXPECT_EQ(other.send(w).nak, NakRule::kNavigationField) << w.latitude << " " << w.longitude;
  EXPECT_EQ(other.c.state().navigation.latitude_min, 40 * 60) << "a NAK changes nothing";
  EXPECT_FALSE(other.c.state().store.empty()) << "a NAK deletes no STOREd satellite";
  for (const WriteNavigation& w : {east180, near_pole})
    EXPECT_FALSE(is_nak(other.send(w))) << w.latitude << " " << w.longitude;
  EXPECT_EQ(other.c.state().navigation.latitude_min, -(89 * 60 + 59));
  ref.c.set_reading("E-60", ReadingSide::kOther);
  EXPECT_EQ(ref.send(north_pole).nak, NakRule::kNavigationField) << "a side taken late";
}

// E-64: §3.5 34h with an empty STORE list while TRACK peaks.
TEST(Readings, E64TheOtherSideDefersAnEmptyListWhileTrackPeaks) {
  Profile peaking = site_profile();
  peaking.store.clear();
  peaking.track.active = true;
  peaking.track.activity = TrackActivity::kPeaking;
  Rig ref(peaking), other(reading(peaking, "E-64"));
  EXPECT_EQ(ref.send(PolPreset{'H'}).nak, NakRule::kPolPresetNoSatellites);
  const Outcome deferred = other.send(PolPreset{'H'});
  EXPECT_FALSE(is_nak(deferred)) << deferred.note;
  EXPECT_EQ(other.c.state().pol.motion, AxisState::Motion::kIdle) << "nothing moves";
  // TRACK idle: nothing defers the command, and both sides NAK it.
  Profile idle = peaking;
  idle.track.activity = TrackActivity::kIdle;
  Rig other_idle(reading(idle, "E-64"));
  EXPECT_EQ(other_idle.send(PolPreset{'H'}).nak, NakRule::kPolPresetNoSatellites);
  ref.c.set_reading("E-64", ReadingSide::kOther);
  EXPECT_FALSE(is_nak(ref.send(PolPreset{'H'}))) << "a side taken late";
}

// E-67: a status poll fed to a bus as STX A CC, then `pause`, then ETX and
// the check byte; 100 ms later a whole one. Whether each was answered.
struct Pieces {
  bool pieces = false, whole = false;
};
Pieces poll_in_pieces(Bus& bus, VirtualClock& clock, std::chrono::milliseconds pause) {
  const Bytes poll = encode_frame({FrameKind::kCommand, bus.controller(0).profile().address, 0x31, {}});
  Pieces r;
  Bytes out;
  bus.receive(ByteView(poll).first(3), out);
  clock.advance(pause);
  bus.receive(ByteView(poll).subspan(3), out);
  r.pieces = !out.empty();
  out.clear();
  clock.advance(100ms);
  bus.receive(poll, out);
  r.whole = !out.empty();
  return r;
}

TEST(Readings, E67TheOtherSideDropsAFrameWhoseBytesPauseLongerThanItsTimeout) {
  VirtualClock clock;
  Bus ref({site_profile()}, clock, {}, Parity::kNone), other({reading(site_profile(), "E-67")}, clock, {}, Parity::kNone);
  auto answered = [&](Bus& bus, std::chrono::milliseconds pause) { return poll_in_pieces(bus, clock, pause); };
  Pieces r = answered(ref, 500ms);
  EXPECT_TRUE(r.pieces) << "no inter-character timeout";
  EXPECT_TRUE(r.whole);
  r = answered(other, 50ms);
  EXPECT_FALSE(r.pieces) << "dropped after " << kInterCharacterTimeout.count() << " ms";
  EXPECT_TRUE(r.whole) << "the receiver recovered";
  EXPECT_NE(other.take_log().find("inter-character timeout"), std::string::npos);
  r = answered(other, kInterCharacterTimeout);
  EXPECT_TRUE(r.pieces) << "a pause of the timeout itself is waited out";
  r = answered(other, kInterCharacterTimeout + 1ms);
  EXPECT_FALSE(r.pieces);
  // A side taken late applies to the next byte.
  ref.controller(0).set_reading("E-67", ReadingSide::kOther);
  EXPECT_FALSE(answered(ref, 50ms).pieces);
  other.controller(0).set_reading("E-67", ReadingSide::kReference);
  EXPECT_TRUE(answered(other, 500ms).pieces);
}

// E-18: the rest of an empty slot's reply (§3.11, §3.13, §3.21): blanks on
// the reference side, zeros on the other; the 7Fh 7Fh index and the length
// on both, and the reply still decodes. A filled slot reads alike.
TEST(Readings, E18TheOtherSideFillsAnEmptySlotWithZeros) {
  Profile p = site_profile();
  p.dvb_receiver = true;
  Rig ref(p), other(reading(p, "E-18"));
  auto rest = [](Rig& r, const Request& read) {
    const Outcome o = r.send(read);
    EXPECT_TRUE(o.reply && o.reply->size() > 7u);
    EXPECT_TRUE(decode_frame(*o.reply)) << "decodes";
    const Bytes& b = *o.reply;
    EXPECT_EQ(b[3], 0x7F);
    EXPECT_EQ(b[4], 0x7F);
    return std::make_pair(std::string(b.begin() + 5, b.end() - 2), b.size());
  };
  for (const Request& read : {Request{ReadSatellite{{2}}}, Request{ReadTle{{3}}}, Request{ReadSignpost{{4}}}}) {
    const auto [blank, length] = rest(ref, read);
    const auto [zeros, other_length] = rest(other, read);
    EXPECT_EQ(length, other_length);
    EXPECT_EQ(blank.find_first_not_of(' '), std::string::npos) << blank;
    EXPECT_EQ(zeros.find_first_not_of('0'), std::string::npos) << zeros;
  }
  EXPECT_EQ(ref.send(ReadSatellite{{1}}).reply, other.send(ReadSatellite{{1}}).reply) << "a filled slot";
}

// E-40: §3.22 bytes 36-41, the magnetic variation: right-justified on the
// reference side, left-justified on the other; both decode to the same
// tenths, and "not ready" is six blanks on both.
TEST(Readings, E40TheOtherSideLeftJustifiesTheMagneticVariation) {
  Profile p = site_profile();
  p.navigation.magvar_tenths = -126;
  Rig ref(p), other(reading(p, "E-40"));
  auto bytes_36_41 = [](Rig& r) {
    const Outcome o = r.send(NavigationQuery{});
    EXPECT_TRUE(o.reply && o.reply->size() == 72u);
    return std::string(o.reply->begin() + 36, o.reply->begin() + 42);
  };
  EXPECT_EQ(bytes_36_41(ref), " -12.6");
  EXPECT_EQ(bytes_36_41(other), "-12.6 ");
  EXPECT_EQ(ref.reply<NavigationDataReply>(NavigationQuery{}).magvar, -126);
  EXPECT_EQ(other.reply<NavigationDataReply>(NavigationQuery{}).magvar, -126);
  p.navigation.magvar_tenths.reset();
  Rig not_ready(reading(p, "E-40"));
  EXPECT_EQ(bytes_36_41(not_ready), "      ");
}

// E-20: §3.8 bytes 164-165, the cursor column: the profile's (0-39) on the
// reference side, one more on the other (1-40, counted as the rows are). A
// side taken late shows in the next reply.
TEST(Readings, E20TheOtherSideCountsCursorColumnsFromOne) {
  Profile p = site_profile();
  for (std::uint8_t column : {0, 9, 39}) {
    p.display.cursor_column = column;
    Rig ref(p), other(reading(p, "E-20"));
    auto bytes_164_165 = [](Rig& r) {
      const Outcome o = r.send(ReflectDisplayQuery{});
      EXPECT_TRUE(o.reply && o.reply->size() == 169u);
      return std::string(o.reply->begin() + 164, o.reply->begin() + 166);
    };
    char want[8];
    std::snprintf(want, sizeof want, "%02d", column);
    EXPECT_EQ(bytes_164_165(ref), want);
    std::snprintf(want, sizeof want, "%02d", column + 1);
    EXPECT_EQ(bytes_164_165(other), want);
    ref.c.set_reading("E-20", ReadingSide::kOther);
    EXPECT_EQ(bytes_164_165(ref), want) << "taken late";
  }
}

// E-23: 43h and 44h without the DVB receiver option are NAKed (reference,
// other-2) or not answered (other); with the option, priority 0 is stored
// (reference, other) or NAKed as 44h's "1 - 9" reads (other-2).
TEST(Readings, E23ThreeSidesOfTheSignposts) {
  Profile bare = site_profile();
  bare.dvb_receiver = false;
  Profile dvb = site_profile();
  dvb.dvb_receiver = true;
  WriteSignpost w;
  w.index = 1;
  w.signpost = {-1000, 11700, 27500, '3', 'V', "ABC123", 0, ""};
  for (ReadingSide side : {ReadingSide::kReference, ReadingSide::kOther, ReadingSide::kOther2}) {
    SCOPED_TRACE(std::string(to_string(side)));
    Rig without(reading(bare, "E-23", side)), with(reading(dvb, "E-23", side));
    const Outcome write = without.send(w), read = without.send(ReadSignpost{{1}});
    if (side == ReadingSide::kOther) {
      EXPECT_FALSE(write.reply);
      EXPECT_FALSE(read.reply);
    } else {
      EXPECT_EQ(write.nak, NakRule::kNoDvbOption);
      EXPECT_EQ(read.nak, NakRule::kNoDvbOption);
    }
    const Outcome zero = with.send(w);
    if (side == ReadingSide::kOther2) {
      EXPECT_EQ(zero.nak, NakRule::kSignpostField);
    } else {
      ASSERT_FALSE(is_nak(zero));
      EXPECT_EQ(with.reply<SignpostDataReply>(ReadSignpost{{1}}).signpost.priority, 0u);
    }
    WriteSignpost one = w;
    one.signpost.priority = 1;
    EXPECT_FALSE(is_nak(with.send(one))) << "priority 1 on every side";
  }
}

// E-30: §3.17 bytes 49-50 on a mount without 0.01 deg feedback: '0' on the
// reference side, blanks on the other (and the reply still decodes); with
// the feedback both sides show the digit. A side taken late shows in the
// next reply.
TEST(Readings, E30TheOtherSideLeavesTheHundredthsBlankWithoutTheFeedback) {
  Profile tenths = site_profile();
  ASSERT_FALSE(tenths.hundredths);
  Rig ref(tenths), other(reading(tenths, "E-30"));
  auto bytes_49_50 = [](Rig& r) {
    const Outcome o = r.send(ExtendedStatusPoll{});
    EXPECT_TRUE(o.reply && o.reply->size() == 58u);
    return std::string(o.reply->begin() + 49, o.reply->begin() + 51);
  };
  EXPECT_EQ(bytes_49_50(ref), "00");
  EXPECT_EQ(bytes_49_50(other), "  ");
  EXPECT_EQ(ref.extended().az_hundredths, 0);
  EXPECT_EQ(other.extended().az_hundredths, std::nullopt);
  EXPECT_EQ(other.extended().el_hundredths, std::nullopt);
  ref.c.set_reading("E-30", ReadingSide::kOther);
  EXPECT_EQ(bytes_49_50(ref), "  ") << "taken late";
  other.c.set_reading("E-30", ReadingSide::kReference);
  EXPECT_EQ(bytes_49_50(other), "00") << "taken back late";

  Profile fine = site_profile();
  fine.hundredths = true;
  Rig fine_ref(fine), fine_other(reading(fine, "E-30"));
  for (Rig* r : {&fine_ref, &fine_other}) {
    ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMoveAxis{'A', 1234}})));
    r->wait(300s);
    EXPECT_EQ(r->extended().az_hundredths, 4) << "12.34: the digit on both sides";
  }
}

// E-90: the reference search lasts 20 s; the other gives up within a second.
TEST(Readings, E90TheOtherSearchEndsWithinASecond) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-90"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(Misc{'A', 'E'})));
    r->wait(1000ms);
  }
  EXPECT_EQ(ref.mode(), "SPIRAL_REMOTE_MODE");
  EXPECT_EQ(other.mode(), "MANUAL_MODE");
  const auto x = other.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "SPIRAL_NO_PEAK_FOUND");
}

// E-91: §3.18 byte 29 and §3.19 bytes 29-39 on a circular feed.
TEST(Readings, E91TheOtherSideDoesNotReadPolarizationOnACircularFeed) {
  Profile circular = site_profile();
  circular.pol_type = PolType::kCircular;
  Rig ref(circular), other(reading(circular, "E-91"));
  // 41h by preset 1 (byte 3 0x40 | A=1 << 4) with receive polarization '?' (byte 29).
  const std::string locate = "P1" + std::string(24, ' ') + "?A    ";
  EXPECT_EQ(ref.send_raw(0x41, locate).nak, NakRule::kMalformedData);
  EXPECT_FALSE(is_nak(other.send_raw(0x41, locate)));
  EXPECT_EQ(other.mode(), "LOCATE_MODE");
  // 42h by preset 1, selection '?' and odd positions (bytes 29-39).
  const std::string store = "P1" + std::string(24, ' ') + "?x1.2.3y4.5H     ";
  EXPECT_EQ(ref.send_raw(0x42, store).nak, NakRule::kMalformedData);
  EXPECT_FALSE(is_nak(other.send_raw(0x42, store)));
  // Every other byte is still read: a bad byte 3 is malformed on either side.
  EXPECT_EQ(other.send_raw(0x41, "01" + locate.substr(2)).nak, NakRule::kMalformedData);
  // On a rotating feed both sides read them.
  Rig single(reading(site_profile(), "E-91"));
  EXPECT_EQ(single.send_raw(0x41, locate).nak, NakRule::kMalformedData);
}

// E-92: 41h with a blank satellite name.
TEST(Readings, E92TheOtherSideLocatesABlankName) {
  RemoteLocate blank = locate_on_meridian();
  blank.sat.name = "";
  Rig ref(site_profile()), other(reading(site_profile(), "E-92"));
  EXPECT_EQ(ref.send(blank).nak, NakRule::kLocateField);
  EXPECT_FALSE(is_nak(other.send(blank)));
  EXPECT_EQ(other.mode(), "LOCATE_MODE");
}

// E-93 and E-94: where a completed LOCATE goes, and the order of its movements.
// E-52: which commands take the controller to REMOTE_MODE. From
// MANUAL_MODE: a jog enters REMOTE on the reference side and other-2, not on
// the other; a read (3Ah) only on other-2; a refused command on none. A stop
// 'X' that ends a LOCATE leaves it for REMOTE (reference, other-2) or MANUAL
// (other), its exit the stop's on every side. A 42h ends in MANUAL_MODE, or
// REMOTE_MODE on other-2. The polls never change the mode.
TEST(Readings, E52ThreeSidesOfRemoteMode) {
  const std::array sides{ReadingSide::kReference, ReadingSide::kOther, ReadingSide::kOther2};
  auto manual_rig = [](ReadingSide side) {
    auto r = std::make_unique<Rig>(reading(site_profile(), "E-52", side));
    EXPECT_FALSE(is_nak(r->send(Misc{'K', 'C'})));  // the Mode key: MANUAL_MODE (E-56)
    EXPECT_EQ(r->mode(), "MANUAL_MODE");
    return r;
  };
  for (ReadingSide side : sides) {
    SCOPED_TRACE(std::string(to_string(side)));
    auto jog = manual_rig(side);
    ASSERT_FALSE(is_nak(jog->send(Jog{{'W', 'S', 100}})));
    EXPECT_EQ(jog->mode(), side == ReadingSide::kOther ? "MANUAL_MODE" : "REMOTE_MODE");

    auto read = manual_rig(side);
    ASSERT_FALSE(is_nak(read->send(ReadSatellite{{1}})));
    EXPECT_EQ(read->mode(), side == ReadingSide::kOther2 ? "REMOTE_MODE" : "MANUAL_MODE");
    ASSERT_FALSE(is_nak(read->send(Misc{'K', 'C'})));
    EXPECT_EQ(read->mode(), "MANUAL_MODE") << "the Mode key takes it back";
    EXPECT_TRUE(is_nak(read->send(ReadSatellite{{0}})));
    EXPECT_EQ(read->mode(), "MANUAL_MODE") << "a refused command leaves the mode";
    for (int i = 0; i < 2; ++i) {
      ASSERT_FALSE(is_nak(read->send(StatusPoll{})));
      ASSERT_FALSE(is_nak(read->send(DeviceTypeQuery{})));
    }
    EXPECT_EQ(read->mode(), "MANUAL_MODE") << "the polls keep it";

    auto stop = manual_rig(side);
    ASSERT_FALSE(is_nak(stop->send(locate_on_meridian())));
    stop->wait(200ms);
    ASSERT_EQ(stop->mode(), "LOCATE_MODE");
    ASSERT_FALSE(is_nak(stop->send(Jog{{'X', 'F', 0}})));
    EXPECT_EQ(stop->mode(), side == ReadingSide::kOther ? "MANUAL_MODE" : "REMOTE_MODE");
    const auto x = stop->extended();
    EXPECT_EQ(meanings::mode_name(x.last_mode), "LOCATE_MODE");
    EXPECT_TRUE(meanings::exit_name(x.last_mode, x.exit_status).ends_with("_STOP_KEY"))
        << meanings::exit_name(x.last_mode, x.exit_status);

    auto store = manual_rig(side);
    RemoteStore rs;
    rs.preset.preset = false;
    rs.sat = {"E52 TEST", -750, 0, '1', '0', 0};
    rs.pol_selection = 'H';
    ASSERT_FALSE(is_nak(store->send(rs)));
    EXPECT_EQ(store->mode(), side == ReadingSide::kOther2 ? "REMOTE_MODE" : "MANUAL_MODE");
    EXPECT_EQ(meanings::mode_name(store->extended().last_mode), "STORE_SAT_MODE");
  }
}

TEST(Readings, E93TheOtherLocateCompletesIntoRemoteMode) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-93"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(locate_on_meridian())));
    r->wait(600s);
    const auto x = r->extended();
    EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FUNCTION_COMPLETED");
  }
  EXPECT_EQ(ref.mode(), "MANUAL_MODE");
  EXPECT_EQ(other.mode(), "REMOTE_MODE");
}

TEST(Readings, E94TheOtherLocateMovesElevationThenAzimuth) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-94"));
  const double az0 = other.c.state().az.position;
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(locate_on_meridian())));
  EXPECT_EQ(ref.state(), "LOCATE_AZIM_MOVEMENT");
  EXPECT_EQ(other.state(), "LOCATE_FIRST_ELEV_MOVEMENT");
  other.wait(500ms);
  EXPECT_EQ(other.c.state().az.position, az0) << "the azimuth waits for the elevation";
  EXPECT_NE(ref.c.state().az.motion, AxisState::Motion::kIdle);
  bool azimuth_leg = false;
  for (int i = 0; i < 3000 && other.mode() == "LOCATE_MODE"; ++i) {
    other.wait(200ms);
    azimuth_leg = azimuth_leg || other.state() == "LOCATE_AZIM_MOVEMENT";
  }
  EXPECT_TRUE(azimuth_leg);
  ref.wait(600s);
  // Both end where the look angles are, and complete.
  EXPECT_EQ(other.status().azimuth.tenths, ref.status().azimuth.tenths);
  EXPECT_EQ(other.status().elevation, ref.status().elevation);
  const auto x = other.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FUNCTION_COMPLETED");
}

// E-94 other: a LOCATE stopped in its first movement exits with that movement's entry.
TEST(Readings, E94AStopInTheFirstMovementNamesIt) {
  Rig other(reading(site_profile(), "E-94"));
  ASSERT_FALSE(is_nak(other.send(locate_on_meridian())));
  other.wait(200ms);
  ASSERT_FALSE(is_nak(other.send(Jog{{'X', 'F', 0}})));
  const auto x = other.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FIRST_ELEV_MOVEMENT_STOP_KEY");
}

// E-33: the justification of a reply's positions, pulse counts and 45h
// heading. Both sides read back to the same values (the master's decoders
// take either form); only the text differs.
TEST(Readings, E33TheOtherSideLeftJustifiesPositionsAndPadsCountsWithBlanks) {
  Profile p = site_profile();
  p.az_sensor = AzSensor::kPulse;
  p.count_offset = 0;  // 12.5 deg: count 1250, four digits
  p.az.initial_deg = 12.5;
  p.el.initial_deg = 45.0;
  p.navigation.heading_tenths = 15;  // 1.5 deg
  Rig ref(p), other(reading(p, "E-33"));
  auto text = [](const Outcome& o, std::size_t first, std::size_t width) {
    EXPECT_TRUE(o.reply.has_value());
    return o.reply ? std::string(o.reply->begin() + static_cast<std::ptrdiff_t>(first),
                                 o.reply->begin() + static_cast<std::ptrdiff_t>(first + width))
                   : std::string();
  };
  // §3.2 bytes 14-19 and 20-25; §3.24 bytes 4-9 (47h for 0 ms moves nothing).
  EXPECT_EQ(text(ref.send(StatusPoll{}), 14, 6), "  12.5");
  EXPECT_EQ(text(other.send(StatusPoll{}), 14, 6), "12.5  ");
  EXPECT_EQ(text(other.send(StatusPoll{}), 20, 6), "45.0  ");
  EXPECT_EQ(text(ref.send(ExtendedStatusPoll{}), 14, 6), "  12.5");
  EXPECT_EQ(text(other.send(ExtendedStatusPoll{}), 14, 6), "12.5  ");
  // §3.16: five characters; §3.22 bytes 30-34.
  const std::string ref_count = text(ref.send(PulseCountQuery{}), 3, 5);
  const std::string other_count = text(other.send(PulseCountQuery{}), 3, 5);
  ASSERT_EQ(ref_count.size(), 5U);
  EXPECT_EQ(ref_count.find(' '), std::string::npos) << ref_count;
  EXPECT_EQ(other_count.front(), ' ') << other_count;
  EXPECT_EQ(std::stoi(other_count), std::stoi(ref_count));
  EXPECT_EQ(text(ref.send(NavigationQuery{}), 30, 5), "001.5");
  EXPECT_EQ(text(other.send(NavigationQuery{}), 30, 5), "  1.5");
  // The values are the same on both sides.
  EXPECT_EQ(ref.status().azimuth, other.status().azimuth);
  EXPECT_EQ(ref.status().elevation, other.status().elevation);
  EXPECT_EQ(ref.reply<PulseCountReply>(PulseCountQuery{}), other.reply<PulseCountReply>(PulseCountQuery{}));
  EXPECT_EQ(ref.reply<NavigationDataReply>(NavigationQuery{}).heading,
            other.reply<NavigationDataReply>(NavigationQuery{}).heading);
}

// E-95: byte 35 Y outside TRACK.
TEST(Readings, E95TheOtherSideShowsYZeroOutsideTrack) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-95"));
  EXPECT_EQ(ref.status().pol_equipment & 0x08, 0x08);
  EXPECT_EQ(other.status().pol_equipment & 0x08, 0);
  Profile tracking = reading(site_profile(), "E-95");
  tracking.track.active = true;
  tracking.track.activity = TrackActivity::kIdle;
  Rig in_track(tracking);
  EXPECT_EQ(in_track.status().pol_equipment & 0x08, 0x08) << "meaningful in TRACK: both sides agree";
}

// E-96: byte 35 ZZZ while the feed moves to a 34h preset.
TEST(Readings, E96TheOtherSideShowsLowerCaseWhileTheFeedMoves) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-96"));
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(PolPreset{'V'})));
  ASSERT_NE(other.c.state().pol.motion, AxisState::Motion::kIdle);
  EXPECT_EQ(ref.status().pol_equipment & 0x07, 2) << "V";
  EXPECT_EQ(other.status().pol_equipment & 0x07, 3) << "v while moving";
  other.wait(300s);
  EXPECT_EQ(other.status().pol_equipment & 0x07, 2) << "V once there";
}

// E-97: an unimplemented command while remote control is disabled.
TEST(Readings, E97TheOtherSideNaksAnUnimplementedCommandOffline) {
  Profile offline = site_profile();
  offline.remote_enabled = false;
  Rig ref(offline), other(reading(offline, "E-97"));
  const std::string iess = "01IESS-412";  // index 01 and data: the layout is TBD (E-37)
  EXPECT_TRUE(is_offline(ref.send_raw(0x3D, iess)));
  EXPECT_EQ(other.send_raw(0x3D, iess).nak, NakRule::kNotImplemented);
  EXPECT_TRUE(is_offline(other.send(StatusPoll{}))) << "an implemented one still gets the offline reply";
}

// E-98: the speed bit during an auto move.
TEST(Readings, E98TheOtherSideShowsTheConfiguredSpeedInAnAutoMove) {
  Profile slow = site_profile();
  slow.az.power_on_speed = AxisSpeed::kSlow;
  Rig ref(slow), other(reading(slow, "E-98"));
  EXPECT_EQ(ref.status().az_status & 0x10, 0) << "configured slow at power-on";
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMoveAzEl{200, 450}})));
  }
  EXPECT_EQ(ref.status().az_status, 0x17) << "fast, remote auto move";
  EXPECT_EQ(other.status().az_status, 0x07) << "slow as configured, remote auto move";
}

// E-98: a key jog (§3.7 'K') runs at the speed the axis is configured for
// on both sides, not at the speed of the auto move before it (the reference
// side's 'S' after that move is 1; the random profiles of the live fuzzer
// found the sides jogging at different speeds).
TEST(Readings, E98AKeyJogRunsAtTheConfiguredSpeedOnBothSides) {
  Profile slow = site_profile();
  slow.az.power_on_speed = AxisSpeed::kSlow;
  Rig ref(slow), other(reading(slow, "E-98"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMoveAzEl{200, 450}})));
    r->wait(600s);
    ASSERT_FALSE(is_nak(r->send(Misc{'K', '6'})));  // azimuth CW, held for the remote jog time
    EXPECT_EQ(r->status().az_status & 0x1F, 0x05) << "moving clockwise, slow";
  }
}

// E-66: 'C' after a LOCATE and a jog.
TEST(Readings, E66TheOtherSideNeedsTheLocateRightBeforeTheStore) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-66"));
  RemoteLocate l;
  l.preset = {true, 1};
  RemoteStore s;
  s.preset = {true, 1};
  s.pol_selection = 'C';
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(l)));
    r->wait(300s);
    (void)r->status();
    ASSERT_FALSE(is_nak(r->send(Jog{{'W', 'S', 50}})));
  }
  EXPECT_FALSE(is_nak(ref.send(s))) << "a jog keeps the LOCATE's claim";
  EXPECT_EQ(other.send(s).nak, NakRule::kStoreNeedsLocate);
  ASSERT_FALSE(is_nak(other.send(l)));
  (void)other.extended();
  EXPECT_FALSE(is_nak(other.send(s))) << "status reads between are no command";
}

// E-16: 38h, 3Dh and 3Eh where the controller does not implement them.
TEST(Readings, E16TheOtherSideGivesAnUnimplementedCodeNoReplyOnline) {
  Profile p = site_profile();
  Rig ref(p), other(reading(p, "E-16"));
  for (const Request& r : {Request{SignalStrength{}}, Request{WriteIess{}}, Request{ReadIess{}}}) {
    EXPECT_EQ(ref.send(r).nak, NakRule::kNotImplemented) << form_of(r);
    EXPECT_FALSE(other.send(r).reply.has_value()) << form_of(r);
  }
  // Offline the other side of E-97 decides: a NAK, not silence.
  p.remote_enabled = false;
  Rig offline(reading(reading(p, "E-16"), "E-97"));
  EXPECT_EQ(offline.send(SignalStrength{}).nak, NakRule::kNotImplemented);
  // A code the profile implements is answered on both sides.
  Profile with_38 = reading(site_profile(), "E-16");
  with_38.implements_signal_strength = true;
  Rig implemented(with_38);
  EXPECT_TRUE(implemented.send(SignalStrength{}).reply.has_value());
}

// E-32: FEC codes 4 and 8, inside the range "1 - 9" and named by no code.
TEST(Readings, E32TheOtherSideStoresFecCodesFourAndEight) {
  Profile p = site_profile();
  p.dvb_receiver = true;
  Rig ref(p), other(reading(p, "E-32"));
  WriteSignpost w;
  w.index = 3;
  w.signpost = {0, 11000, 20000, '4', 'H', "FEC", 1, "0000"};
  EXPECT_EQ(ref.send(w).nak, NakRule::kMalformedData);
  ASSERT_FALSE(is_nak(other.send(w)));
  ReadSignpost r;
  r.index = 3;
  const auto back = other.reply<SignpostDataReply>(r);
  EXPECT_EQ(back.signpost.fec, '4') << "read back as stored";
  w.signpost.fec = '0';
  EXPECT_EQ(other.send(w).nak, NakRule::kMalformedData) << "0 is outside the range on both sides";
  w.signpost.fec = '7';
  EXPECT_FALSE(is_nak(ref.send(w))) << "a defined code on both";
}

// E-45: the spelling of a negative 32h target (forms 2A, 2C, 3).
TEST(Readings, E45TheOtherSideReadsZerosLeftOfTheSign) {
  Profile p = site_profile();
  p.hundredths = true;
  Rig ref(p), other(reading(p, "E-45"));
  // Form 3 to -5.0: the reference spelling, then the other side's.
  EXPECT_FALSE(is_nak(ref.send_raw(0x32, "P-005000000")));
  EXPECT_EQ(other.send_raw(0x32, "P-005000000").nak, NakRule::kMalformedData);
  EXPECT_TRUE(is_nak(ref.send_raw(0x32, "P00-5000000")));
  ASSERT_FALSE(is_nak(other.send_raw(0x32, "P00-5000000")));
  other.wait(60s);
  ref.wait(60s);
  EXPECT_NEAR(other.c.state().pol.position, -5.0, 0.05);
  EXPECT_NEAR(ref.c.state().pol.position, -5.0, 0.05);
  // Form 2C to az -12.34 and form 2A to az -2.0, el -1.5.
  EXPECT_TRUE(is_nak(other.send_raw(0x32, "A-01234    ")));
  ASSERT_FALSE(is_nak(other.send_raw(0x32, "A0-1234    ")));
  other.wait(120s);
  EXPECT_NEAR(other.c.state().az.position, -12.34, 0.01);
  ASSERT_FALSE(is_nak(other.send_raw(0x32, " 00-2000-15")));
  other.wait(120s);
  EXPECT_NEAR(other.c.state().az.position, -2.0, 0.05);
  EXPECT_NEAR(other.c.state().el.position, -1.5, 0.05);
  // Digits that fill the field read alike: §3.3's own "-152500456".
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send_raw(0x32, " -152500456"))) << "§3.3's example";
    r->wait(300s);
    EXPECT_NEAR(r->c.state().az.position, -152.5, 0.05);
    EXPECT_NEAR(r->c.state().el.position, 45.6, 0.05);
  }
  // A '-' anywhere else, or after a nonzero digit, is malformed on both.
  for (Rig* r : {&ref, &other}) {
    EXPECT_EQ(r->send_raw(0x32, "P1-00000000").nak, NakRule::kMalformedData);
    EXPECT_EQ(r->send_raw(0x32, "P0050-00000").nak, NakRule::kMalformedData);
  }
}

// A field that names a stored satellite is form 1 on both sides of E-45
// (READING-NOTES 31), whatever it spells.
TEST(Readings, E45LeavesAStoredNameThatLooksSignedToFormOne) {
  Profile p = site_profile();
  p.store.push_back({"-0050", -60.0, 30.0, 0, 0});
  Rig other(reading(p, "E-45"));
  ASSERT_FALSE(is_nak(other.send_raw(0x32, " -0050     ")));
  other.wait(300s);
  EXPECT_NEAR(other.c.state().az.position, -60.0, 0.05);
}

// E-50: forms 2B and 2C on a mount without their sensors.
TEST(Readings, E50TheOtherSideMovesByFormsWhoseSensorsTheMountLacks) {
  Profile p = site_profile();
  p.az_sensor = AzSensor::kPot;
  p.hundredths = false;
  Rig ref(p), other(reading(p, "E-50"));
  const AutoMove counts{AutoMoveCounts{static_cast<std::uint32_t>(p.count_offset + 10 * p.counts_per_degree),
                                       static_cast<std::uint32_t>(p.count_offset + 20 * p.counts_per_degree)}};
  EXPECT_EQ(ref.send(counts).nak, NakRule::kNoCountSensors);
  ASSERT_FALSE(is_nak(other.send(counts)));
  other.wait(300s);
  EXPECT_NEAR(other.c.state().az.position, 10.0, 0.05) << "by the profile's scale";
  EXPECT_NEAR(other.c.state().el.position, 20.0, 0.05);
  const AutoMove hundredths{AutoMoveAxis{'E', 2537}};
  EXPECT_EQ(ref.send(hundredths).nak, NakRule::kNoHundredths);
  ASSERT_FALSE(is_nak(other.send(hundredths)));
  other.wait(300s);
  EXPECT_NEAR(other.c.state().el.position, 25.4, 0.001) << "to the mount's tenth";
}

// E-65: a Remote Store of a new name with the STORE list full.
TEST(Readings, E65TheOtherSideAcksAStoreIntoAFullListAndStoresNothing) {
  Profile full = site_profile();
  full.store.clear();
  for (int i = 0; i < 50; ++i) full.store.push_back({"SAT " + std::to_string(i), 0, 0, 0, 0});
  Rig ref(full), other(reading(full, "E-65"));
  RemoteStore s;
  s.sat = {"NEW ONE", 0, 0, '1', '0', 0};
  s.pol_selection = 'H';
  EXPECT_EQ(ref.send(s).nak, NakRule::kStoreListFull);
  const Outcome o = other.send(s);
  ASSERT_TRUE(o.reply.has_value());
  EXPECT_EQ((*o.reply)[0], ACK);
  EXPECT_EQ(other.c.state().store.size(), 50u) << "nothing stored";
  EXPECT_EQ(other.mode(), "MANUAL_MODE");
  const auto x = other.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "STORE_LIST_FULL");
  // A name already in the full list is overwritten on both sides.
  s.sat.name = "SAT 7";
  for (Rig* r : {&ref, &other}) {
    EXPECT_FALSE(is_nak(r->send(s)));
    const auto y = r->extended();
    EXPECT_EQ(meanings::exit_name(y.last_mode, y.exit_status), "STORE_SAT_DATA_STORED_OK");
  }
}

// E-83: 42h 'C' after a LOCATE that ended in a range error (E-81).
TEST(Readings, E83TheOtherSideCountsALocateThatEndedInARangeErrorAsPerformed) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-83"));
  RemoteLocate low = locate_on_meridian();
  low.sat.name = "LOW";
  low.sat.longitude = 1050;  // 105.0 E: below the horizon from 40 N 75 W
  RemoteStore s;
  s.sat = low.sat;
  s.pol_selection = 'C';
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(low)));
    r->wait(60s);
    EXPECT_TRUE(r->state().ends_with("_RANGE_ERROR")) << r->state();
  }
  EXPECT_EQ(ref.send(s).nak, NakRule::kStoreNeedsLocate);
  EXPECT_FALSE(is_nak(other.send(s)));
  const auto& store = other.c.state().store;
  EXPECT_TRUE(std::any_of(store.begin(), store.end(), [](const StoredSatellite& x) { return x.name == "LOW"; }))
      << "'C' stores the failed LOCATE's satellite";
  // A side taken late judges the same history (the lockstep flips a side
  // after the writes that show it).
  ref.c.set_reading("E-83", ReadingSide::kOther);
  EXPECT_FALSE(is_nak(ref.send(s)));
}

// E-43: the "unused" key codes of §3.25 (48h) and §3.7 'K' (36h).
TEST(Readings, E43TheOtherSideAcksAnUnusedKeyAndDoesNothing) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-43"));
  for (char key : {'\x3A', '\x3F', '\x40'}) {
    EXPECT_EQ(ref.send(RemoteKeypress{key}).nak, NakRule::kKeyCode) << int(key);
    EXPECT_EQ(ref.send(Misc{'K', key}).nak, NakRule::kKeyCode) << int(key);
    const ControllerState before = other.c.state();  // a copy
    const Outcome o = other.send(RemoteKeypress{key});
    ASSERT_TRUE(o.reply.has_value());
    EXPECT_EQ((*o.reply)[0], ACK) << int(key);
    EXPECT_EQ((*o.reply)[2], 0x48);
    const Outcome k = other.send(Misc{'K', key});
    ASSERT_TRUE(k.reply.has_value());
    EXPECT_EQ((*k.reply)[0], ACK) << int(key);
    const ControllerState& after = other.c.state();
    EXPECT_EQ(after.mode, before.mode) << "an unused key does nothing";
    EXPECT_EQ(after.last_key, before.last_key);
    EXPECT_EQ(after.az, before.az);
    EXPECT_EQ(after.el, before.el);
    EXPECT_EQ(after.pol, before.pol);
  }
  // Codes outside the table's 30h-47h are no key codes on either side.
  for (char key : {'\x2F', '\x48', 'a'}) {
    EXPECT_EQ(other.send(RemoteKeypress{key}).nak, NakRule::kKeyCode) << int(key);
    EXPECT_EQ(other.send(Misc{'K', key}).nak, NakRule::kKeyCode) << int(key);
  }
}

// E-51: an ephemeris code for a preset above index 10.
TEST(Readings, E51TheOtherSideStoresEphemerisAboveIndexTen) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-51"));
  WriteSatellite w;
  w.index = 11;
  w.sat = {"EPHEM 11", -740, 0, '1', '1', 0};
  EXPECT_EQ(ref.send(w).nak, NakRule::kEphemerisIndex);
  EXPECT_FALSE(is_nak(other.send(w)));
  EXPECT_EQ(other.reply<SatelliteDataReply>(ReadSatellite{{11}}).sat.ephemeris, '1');
  w.sat.ephemeris = '0';
  EXPECT_FALSE(is_nak(ref.send(w))) << "no ephemeris: stored on both sides";
}

// E-53: the axis status during a remote jog (33h) and a key jog (48h).
TEST(Readings, E53TheOtherSideShowsJogMovementPending) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-53"));
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(Jog{{'W', 'F', 3000}})));
  ref.wait(1s);
  other.wait(1s);
  EXPECT_EQ(ref.status().az_status, 0x15) << "fast, cw movement in progress";
  EXPECT_EQ(other.status().az_status, 0x13) << "fast, cw jog movement pending";
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(Jog{{'D', 'S', 3000}})));
  ref.wait(1s);
  other.wait(1s);
  EXPECT_EQ(ref.status().el_status, 0x04) << "slow, down movement in progress";
  EXPECT_EQ(other.status().el_status, 0x02) << "slow, down jog movement pending";
  ref.wait(10s);
  other.wait(10s);
  EXPECT_EQ(other.status().el_status, 0x00) << "at rest once its time has run";
  // An auto move shows 0111 on both sides.
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMoveAzEl{300, 450}})));
  EXPECT_EQ(ref.status().az_status & 0x0F, 0x07);
  EXPECT_EQ(other.status().az_status & 0x0F, 0x07);
}

// E-54: an auto-move target outside the axis's limits (el -5..90).
TEST(Readings, E54TheOtherSideDrivesAnOutOfRangeTargetToTheLimit) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-54"));
  const AutoMove too_high{AutoMoveAzEl{0, 905}};
  EXPECT_EQ(ref.send(too_high).nak, NakRule::kTargetOutOfRange);
  EXPECT_FALSE(is_nak(other.send(too_high)));
  other.wait(600s);
  EXPECT_NEAR(other.c.state().el.position, 90.0, 0.1);
  EXPECT_EQ(other.status().el_limits & 0x04, 0x04) << "at the upper limit";
  // Form 2C and form 3 alike.
  EXPECT_EQ(ref.send(AutoMove{AutoMovePol{-905}}).nak, NakRule::kTargetOutOfRange);
  EXPECT_FALSE(is_nak(other.send(AutoMove{AutoMovePol{-905}})));
  other.wait(600s);
  EXPECT_NEAR(other.c.state().pol.position, -90.0, 0.1);
}

// E-63: 34h 'V' on a dual-port feed (SBS 6: H 10.0, V -80.0).
TEST(Readings, E63TheOtherSideMovesADualPortFeedToItsVerticalPosition) {
  Profile dual = site_profile();
  dual.pol_type = PolType::kDualPort;
  Rig ref(dual), other(reading(dual, "E-63"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(PolPreset{'V'})));
    r->wait(300s);
  }
  EXPECT_NEAR(ref.c.state().pol.position, 10.0, 0.1);
  EXPECT_NEAR(other.c.state().pol.position, -80.0, 0.1);
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(PolPreset{'H'})));
    r->wait(300s);
  }
  EXPECT_NEAR(ref.c.state().pol.position, 10.0, 0.1) << "'H' too";
  EXPECT_NEAR(other.c.state().pol.position, -80.0, 0.1) << "'H' too";
  // A single-port feed keeps 'V' vertical on both sides.
  Rig single(reading(site_profile(), "E-63"));
  ASSERT_FALSE(is_nak(single.send(PolPreset{'V'})));
  single.wait(300s);
  EXPECT_NEAR(single.c.state().pol.position, -80.0, 0.1);
}

// E-68: a lower-case name in the data forms of 41h and 42h.
TEST(Readings, E68TheOtherSideNaksALowerCaseName) {
  RemoteLocate lower = locate_on_meridian();
  lower.sat.name = "probe loc";
  Rig ref(site_profile()), other(reading(site_profile(), "E-68"));
  EXPECT_FALSE(is_nak(ref.send(lower)));
  EXPECT_EQ(ref.status().sat_name, "PROBE LOC");
  EXPECT_EQ(other.send(lower).nak, NakRule::kLocateField);
  EXPECT_EQ(other.mode(), "MANUAL_MODE") << "no LOCATE";
  EXPECT_FALSE(is_nak(other.send(locate_on_meridian()))) << "a name in capitals is located";
  RemoteStore st;
  st.preset = {false, 0};
  st.sat = {"store low", -740, 0, '1', '0', 0};
  st.pol_selection = 'H';
  EXPECT_FALSE(is_nak(ref.send(st)));
  EXPECT_EQ(ref.c.state().store.back().name, "STORE LOW");
  EXPECT_EQ(other.send(st).nak, NakRule::kStoreField);
}

}  // namespace
}  // namespace sabus::harness

namespace sabus::harness {
namespace {

// A side taken mid-session (the live fuzzer's model, once a device has
// shown it) redoes what it decides and has already happened.
// E-63 taken while a dual-port feed moves to its 34h position: on to the
// position of the side taken.
TEST(Readings, ASideTakenLateRetargetsADualPortFeedOnItsWay) {
  Profile dual = site_profile();
  dual.pol_type = PolType::kDualPort;
  Rig r(dual);
  ASSERT_FALSE(is_nak(r.send(PolPreset{'V'})));
  r.wait(1s);
  ASSERT_NE(r.c.state().pol.motion, AxisState::Motion::kIdle);
  ASSERT_NEAR(r.c.state().pol.position, 5.0, 0.01) << "1 s at 5 deg/s towards H (10.0)";
  r.c.set_reading("E-63", ReadingSide::kOther);
  EXPECT_NEAR(r.c.state().pol.position, -5.0, 0.01) << "the move again from its start, towards V (-80.0)";
  r.wait(300s);
  EXPECT_NEAR(r.c.state().pol.position, -80.0, 0.1);
  // And back: on its way to the vertical position, the reference side taken.
  Rig back(reading(dual, "E-63"));
  ASSERT_FALSE(is_nak(back.send(PolPreset{'V'})));
  back.wait(1s);
  ASSERT_NE(back.c.state().pol.motion, AxisState::Motion::kIdle);
  back.c.set_reading("E-63", ReadingSide::kReference);
  back.wait(300s);
  EXPECT_NEAR(back.c.state().pol.position, 10.0, 0.1);
  // A feed at rest stays where it is.
  back.c.set_reading("E-63", ReadingSide::kOther);
  back.wait(300s);
  EXPECT_NEAR(back.c.state().pol.position, 10.0, 0.1);
}

TEST(Readings, ASideTakenLateRedoesALocatesMovementsAndItsMode) {
  Rig late(site_profile()), early(reading(site_profile(), "E-94"));
  for (Rig* r : {&late, &early}) {
    ASSERT_FALSE(is_nak(r->send(locate_on_meridian())));
    r->wait(700ms);
  }
  late.c.set_reading("E-94", ReadingSide::kOther);
  EXPECT_EQ(late.state(), early.state());
  EXPECT_EQ(late.c.state().az.position, early.c.state().az.position);
  EXPECT_EQ(late.c.state().el.position, early.c.state().el.position);
  late.wait(600s);
  early.wait(600s);
  EXPECT_EQ(late.mode(), "MANUAL_MODE");
  late.c.set_reading("E-93", ReadingSide::kOther);
  EXPECT_EQ(late.mode(), "REMOTE_MODE");
  const auto x = late.extended();
  EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "LOCATE_FUNCTION_COMPLETED") << "still the LOCATE's exit";
  late.c.set_reading("E-93", ReadingSide::kReference);
  EXPECT_EQ(late.mode(), "MANUAL_MODE");
}

// E-90 and E-66 decide when they are used: a side taken late applies to a
// search already running and a LOCATE already made.
TEST(Readings, ASideTakenLateAppliesToASearchAndAClaimAlreadyBegun) {
  Rig r(site_profile()), early(reading(site_profile(), "E-90"));
  for (Rig* x : {&r, &early}) {
    ASSERT_FALSE(is_nak(x->send(Misc{'A', 'E'})));
    x->wait(700ms);
  }
  EXPECT_EQ(r.mode(), "SPIRAL_REMOTE_MODE");
  r.c.set_reading("E-90", ReadingSide::kOther);
  EXPECT_EQ(r.mode(), "MANUAL_MODE") << "over within a second, as if it had been so from the start";
  EXPECT_EQ(r.c.state().az.position, early.c.state().az.position);
  EXPECT_EQ(r.c.state().el.position, early.c.state().el.position);
  RemoteLocate l;
  l.preset = {true, 1};
  RemoteStore s;
  s.preset = {true, 1};
  s.pol_selection = 'C';
  ASSERT_FALSE(is_nak(r.send(l)));
  r.wait(300s);
  ASSERT_FALSE(is_nak(r.send(Jog{{'W', 'S', 50}})));
  r.c.set_reading("E-66", ReadingSide::kOther);
  EXPECT_EQ(r.send(s).nak, NakRule::kStoreNeedsLocate);
}

}  // namespace
}  // namespace sabus::harness

namespace sabus::harness {
namespace {

// ---- the receiver-level readings (E-6, E-8): a whole controller on its line ----

// What a controller on a line answers to `chars` (7-bit characters; the line
// adds even parity), one reply frame or none.
struct Line {
  explicit Line(Profile p) : bus({std::move(p)}, clock) { bus.set_transcript(false); }
  VirtualClock clock;
  Bus bus;
  Bytes send(const Bytes& chars) {
    Bytes out;
    bus.receive(add_even_parity(chars), out);
    for (auto& b : out) b &= 0x7F;
    return out;
  }
  Bytes send(std::uint8_t code, const Bytes& data) {
    return send(encode_frame({FrameKind::kCommand, bus.controller(0).profile().address, code, data}));
  }
};

Bytes text(std::string_view s) { return Bytes(s.begin(), s.end()); }

Bytes nak_for(std::uint8_t code) { return encode_frame(nak_reply('2', code)); }

// E-14: direction 'C', which §3.4's NAK and TRACK sentences list beside W,
// U, D: no direction on the reference side (NAKed), azimuth
// counterclockwise ('E') on the other, under 33h and 47h alike.
TEST(Readings, E14TheOtherSideJogsCAsE) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-14")), e(site_profile());
  const double az0 = ref.c.state().az.position;
  ASSERT_GT(az0, ref.profile.az.min_deg + 5) << "room to jog counterclockwise";
  EXPECT_EQ(ref.send_raw(0x33, "CF1000").nak, NakRule::kMalformedData);
  EXPECT_EQ(ref.send_raw(0x47, "CF1000").nak, NakRule::kMalformedData);
  ASSERT_FALSE(is_nak(other.send_raw(0x33, "CF1000")));
  ASSERT_FALSE(is_nak(e.send(Jog{{'E', 'F', 1000}})));
  for (Rig* r : {&ref, &other, &e}) r->wait(3s);
  EXPECT_EQ(ref.c.state().az.position, az0) << "nothing moved";
  EXPECT_LT(other.c.state().az.position, az0 - 0.5) << "counterclockwise";
  EXPECT_EQ(other.c.state().az.position, e.c.state().az.position) << "as 'E'";
  const Outcome minimal = other.send_raw(0x47, "CS0050");
  ASSERT_TRUE(minimal.reply && minimal.reply->size() > 3 && !is_nak(minimal));
  EXPECT_EQ((*minimal.reply)[3], 'A');
  EXPECT_EQ(other.send_raw(0x33, "QF1000").nak, NakRule::kMalformedData) << "other letters stay no direction";
}

// E-31: a 2A field that also names a stored satellite (" 0100000300" is
// az 100.0, el 30.0; "0100000300" is stored at az 10.0, el 20.0): form 1 on
// the reference side, form 2A on the other.
TEST(Readings, E31TheOtherSideReadsATwoAPairAsTwoAWhateverIsStored) {
  Profile p = site_profile();
  p.store.push_back({"0100000300", 10.0, 20.0, 0, 0});
  Rig ref(p), other(reading(p, "E-31"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send_raw(0x32, " 0100000300")));
    r->wait(600s);
  }
  EXPECT_NEAR(ref.c.state().az.position, 10.0, 0.05);
  EXPECT_NEAR(ref.c.state().el.position, 20.0, 0.05);
  EXPECT_EQ(ref.status().sat_name, "0100000300");
  EXPECT_NEAR(other.c.state().az.position, 100.0, 0.05);
  EXPECT_NEAR(other.c.state().el.position, 30.0, 0.05);
  // A name that is no 2A pair is form 1 on both sides.
  ASSERT_FALSE(is_nak(other.send_raw(0x32, " SBS 6     ")));
  other.wait(600s);
  EXPECT_NEAR(other.c.state().az.position, -74.0, 0.05);
}

// E-34: a remote pol jog in a manual search keeps TRACK and shows its
// track_states state: JOG_POL_CW is 48h as printed (reference) or 45h in
// manual_states' order (other); CCW 45h or 46h. The search's own state
// (ACTIVE) follows when the jog is over, and a side taken during the jog
// keeps the state, at its new value.
TEST(Readings, E34TheOtherSideNumbersTheTrackPolStatesAsManualStates) {
  Profile p = site_profile();
  p.track.active = true;
  p.track.activity = TrackActivity::kManualSearch;
  Rig ref(p), other(reading(p, "E-34"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(Jog{{'L', 'S', 1000}})));
    EXPECT_EQ(r->mode(), "TRACK_MODE");
  }
  EXPECT_EQ(ref.extended().state, 0x48);
  EXPECT_EQ(other.extended().state, 0x45);
  ref.wait(2s);
  other.wait(2s);
  EXPECT_EQ(ref.state(), "TRACK_MANUAL_SEARCH_ACTIVE");
  EXPECT_EQ(other.extended().state, ref.extended().state) << "ACTIVE is not one of the four";
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(Jog{{'O', 'S', 1000}})));
  EXPECT_EQ(ref.extended().state, 0x45);
  EXPECT_EQ(other.extended().state, 0x46);
  ref.c.set_reading("E-34", ReadingSide::kOther);
  EXPECT_EQ(ref.extended().state, 0x46) << "taken late: the same state at its other value";
  // An azimuth jog hands control to REMOTE (§3.4), as before.
  ASSERT_FALSE(is_nak(other.send(Jog{{'W', 'S', 100}})));
  EXPECT_EQ(other.mode(), "REMOTE_MODE");
}

// E-41: a longitude or pol offset without its decimal digit ("45"), in 39h,
// 41h and 42h: 45.0 on the reference side, malformed on the other (the NAK
// names the byte). With the digit, both take it.
TEST(Readings, E41TheOtherSideNaksANumberWithoutItsDecimalDigit) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-41"));
  //                    index name        longitude incl band eph pol offset
  const std::string write_whole = std::string("01") + "WHOLE     " + "-97   " + "0 " + "1" + "0" + "0.0  ";
  const std::string write_tenth = std::string("01") + "TENTH     " + "-97.0 " + "0 " + "1" + "0" + "12   ";
  const std::string write_both = std::string("01") + "BOTH      " + "-97.0 " + "0 " + "1" + "0" + "12.0 ";
  EXPECT_FALSE(is_nak(ref.send_raw(0x39, write_whole)));
  EXPECT_FALSE(is_nak(ref.send_raw(0x39, write_tenth)));
  EXPECT_EQ(ref.reply<SatelliteDataReply>(ReadSatellite{{1}}).sat.pol_offset, 120);
  const Outcome whole = other.send_raw(0x39, write_whole);
  EXPECT_EQ(whole.nak, NakRule::kMalformedData);
  EXPECT_NE(whole.note.find("byte 15"), std::string::npos) << whole.note;
  const Outcome tenth = other.send_raw(0x39, write_tenth);
  EXPECT_EQ(tenth.nak, NakRule::kMalformedData);
  EXPECT_NE(tenth.note.find("byte 25"), std::string::npos) << tenth.note;
  EXPECT_FALSE(is_nak(other.send_raw(0x39, write_both)));
  EXPECT_EQ(other.reply<SatelliteDataReply>(ReadSatellite{{1}}).sat.pol_offset, 120);
  // 42h 'S' with a whole H position.
  RemoteStore rs;
  rs.preset.preset = false;
  rs.sat = {"E41 STORE", -970, 0, '1', '0', 0};
  rs.pol_selection = 'S';
  rs.h_pos = 100;
  rs.v_pos = -800;
  Bytes data = request_frame(rs, '1').data;
  const std::string with_digit(data.begin() + 27, data.begin() + 32);
  ASSERT_EQ(with_digit, "10.0 ");
  const std::string whole_h = "10   ";
  std::copy(whole_h.begin(), whole_h.end(), data.begin() + 27);
  const std::string raw(data.begin(), data.end());
  EXPECT_FALSE(is_nak(ref.send_raw(0x42, raw)));
  EXPECT_EQ(other.send_raw(0x42, raw).nak, NakRule::kMalformedData);
  EXPECT_FALSE(is_nak(other.send(rs)));
}

// E-42: the azimuth's A/D error field: six '*' on the reference side, the
// five the text prints after a blank on the other (31h, 33h, 40h, 47h);
// the elevation and polarization keep six. Both decode as the error.
TEST(Readings, E42TheOtherSideShowsFiveStarsForTheAzimuth) {
  Profile p = site_profile();
  p.az.ad_error = true;
  p.pol.ad_error = true;
  Rig ref(p), other(reading(p, "E-42"));
  auto bytes = [](const Outcome& o, std::size_t first) {
    EXPECT_TRUE(o.reply.has_value());
    return std::string(o.reply->begin() + static_cast<std::ptrdiff_t>(first),
                       o.reply->begin() + static_cast<std::ptrdiff_t>(first + 6));
  };
  EXPECT_EQ(bytes(ref.send(StatusPoll{}), 14), "******");
  EXPECT_EQ(bytes(other.send(StatusPoll{}), 14), " *****");
  EXPECT_EQ(bytes(other.send(StatusPoll{}), 26), "******") << "the polarization keeps six";
  EXPECT_EQ(bytes(other.send(ExtendedStatusPoll{}), 14), " *****");
  EXPECT_EQ(bytes(other.send(Jog{{'X', 'S', 0}}), 14), " *****");
  EXPECT_EQ(bytes(ref.send(JogMinimal{{'X', 'S', 0}}), 4), "******");
  EXPECT_EQ(bytes(other.send(JogMinimal{{'X', 'S', 0}}), 4), " *****");
  EXPECT_EQ(other.status().azimuth.kind, fields::AzimuthReading::Kind::kError);
  EXPECT_EQ(other.reply<JogPositionReply>(JogMinimal{{'X', 'S', 0}}).position, std::nullopt);
}

// E-46: 47h 'X' names no axis: the reference replies 'A' and the azimuth,
// the other side the axis last jogged (the azimuth before any jog).
TEST(Readings, E46TheOtherSideRepliesTheAxisLastJogged) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-46"));
  EXPECT_EQ(other.reply<JogPositionReply>(JogMinimal{{'X', 'S', 0}}).axis, 'A') << "no jog yet";
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(JogMinimal{{'U', 'S', 500}})));
    r->wait(1s);
  }
  const JogPositionReply x_ref = ref.reply<JogPositionReply>(JogMinimal{{'X', 'S', 0}});
  const JogPositionReply x_other = other.reply<JogPositionReply>(JogMinimal{{'X', 'S', 0}});
  EXPECT_EQ(x_ref.axis, 'A');
  EXPECT_EQ(x_ref.position, ref.status().azimuth.tenths);
  EXPECT_EQ(x_other.axis, 'E');
  EXPECT_EQ(x_other.position, other.status().elevation);
  ASSERT_FALSE(is_nak(other.send(Jog{{'W', 'S', 100}})));
  EXPECT_EQ(other.reply<JogPositionReply>(JogMinimal{{'X', 'S', 0}}).axis, 'A') << "a 33h jog counts too";
}

// E-56: a jog key held remotely: 0.5 s (the §2 example's 20 x 1/40 s) on the
// reference side, the configured hold time (40 x 1/40 s) on the other.
TEST(Readings, E56TheOtherSideHoldsAJogKeyForTheConfiguredTime) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-56"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(RemoteKeypress{'2'})));  // elevation up
    r->wait(700ms);
  }
  EXPECT_EQ(ref.c.state().el.motion, AxisState::Motion::kIdle) << "held 0.5 s";
  EXPECT_NE(other.c.state().el.motion, AxisState::Motion::kIdle) << "held 1 s";
  other.wait(500ms);
  EXPECT_EQ(other.c.state().el.motion, AxisState::Motion::kIdle);
  EXPECT_GT(other.c.state().el.position, ref.c.state().el.position);
  // A side taken late holds the last key again for its time, from where
  // and when it was pressed.
  ref.c.set_reading("E-56", ReadingSide::kOther);
  EXPECT_NE(ref.c.state().el.motion, AxisState::Motion::kIdle) << "held on";
  ref.wait(500ms);
  EXPECT_EQ(ref.c.state().el.position, other.c.state().el.position);
  other.c.set_reading("E-56", ReadingSide::kReference);
  Rig half(site_profile());
  ASSERT_FALSE(is_nak(half.send(RemoteKeypress{'2'})));
  half.wait(1200ms);
  EXPECT_EQ(other.c.state().el.position, half.c.state().el.position);
}

// E-57: 34h with no auto move since power-on: the first STORE entry on the
// reference side, a NAK on the other; after a form 1 auto move, its target
// on both.
TEST(Readings, E57TheOtherSideNaksAPolPresetBeforeAnyAutoMove) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-57"));
  EXPECT_FALSE(is_nak(ref.send(PolPreset{'V'})));
  const Outcome o = other.send(PolPreset{'V'});
  EXPECT_EQ(o.nak, NakRule::kPolPresetNoSatellites);
  EXPECT_NE(o.note.find("E-57"), std::string::npos) << o.note;
  ASSERT_FALSE(is_nak(other.send(AutoMove{AutoMoveStored{' ', "SBS 6"}})));
  ASSERT_FALSE(is_nak(other.send(PolPreset{'V'})));
  other.wait(300s);
  EXPECT_NEAR(other.c.state().pol.position, -80.0, 0.1);
}

// E-58: 42h 'H' and 'V' put the other position 90 deg away: folded into
// -90.0..90.0 on the reference side, V = H + 90 and H = V - 90 unfolded on
// the other; other-2 takes 'C' from the skew at the site (latitude 40 N,
// longitude 75 W; GALAXY 19 at 97.1 W: atan(sin(-22.1)/tan(40)) = -24.15, -24.1 to the tenth),
// the reference from the pol offset.
TEST(Readings, E58ThreeSidesOfTheRemoteStorePolarization) {
  auto store = [](Rig& r, char selection, const char* name) {
    RemoteStore rs;
    rs.preset.preset = false;
    rs.sat = {name, -971, 0, '1', '0', 50};
    rs.pol_selection = selection;
    EXPECT_FALSE(is_nak(r.send(rs))) << selection;
    for (const StoredSatellite& s : r.c.state().store)
      if (s.name == name) return s;
    ADD_FAILURE() << name << " not stored";
    return StoredSatellite{};
  };
  Rig ref(site_profile()), other(reading(site_profile(), "E-58")),
      other_2(reading(site_profile(), "E-58", ReadingSide::kOther2));
  for (Rig* r : {&ref, &other, &other_2}) {
    ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMovePol{300}})));
    r->wait(300s);
  }
  EXPECT_NEAR(store(ref, 'H', "E58 H").v_pol_deg, -60.0, 0.05);
  EXPECT_NEAR(store(other, 'H', "E58 H").v_pol_deg, 120.0, 0.05);
  EXPECT_NEAR(store(other_2, 'H', "E58 H").v_pol_deg, -60.0, 0.05) << "other-2 folds as the reference";
  EXPECT_NEAR(store(ref, 'V', "E58 V").h_pol_deg, -60.0, 0.05);
  EXPECT_NEAR(store(other, 'V', "E58 V").h_pol_deg, -60.0, 0.05) << "V - 90 lies inside";
  for (Rig* r : {&ref, &other, &other_2}) {
    ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMovePol{-300}})));
    r->wait(300s);
  }
  EXPECT_NEAR(store(ref, 'V', "E58 V2").h_pol_deg, 60.0, 0.05);
  EXPECT_NEAR(store(other, 'V', "E58 V2").h_pol_deg, -120.0, 0.05);
  for (Rig* r : {&ref, &other, &other_2}) {
    RemoteLocate l;
    l.preset.preset = false;
    l.sat = {"E58 C", -971, 0, '1', '0', 50};
    ASSERT_FALSE(is_nak(r->send(l)));
    r->wait(600s);
  }
  EXPECT_NEAR(store(ref, 'C', "E58 C").h_pol_deg, 5.0, 0.05) << "the pol offset";
  EXPECT_NEAR(store(other, 'C', "E58 C2").h_pol_deg, 5.0, 0.05);
  const StoredSatellite skew = store(other_2, 'C', "E58 C3");
  EXPECT_NEAR(skew.h_pol_deg, -24.1, 0.01) << "the skew";
  EXPECT_NEAR(skew.v_pol_deg, 65.9, 0.01);
}

// E-61: a jog duration on the 50 ms timer: rounded up on the reference side
// (0020 moves 50 ms), to the nearest on the other (0020 does not move,
// 0030 moves 50 ms).
TEST(Readings, E61TheOtherSideRoundsAJogDurationToTheNearestTick) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-61"));
  const double el0 = ref.c.state().el.position;
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(Jog{{'U', 'S', 20}})));
    r->wait(1s);
  }
  EXPECT_GT(ref.c.state().el.position, el0);
  EXPECT_EQ(other.c.state().el.position, el0) << "under 25 ms: no move";
  ASSERT_FALSE(is_nak(other.send(Jog{{'U', 'S', 30}})));
  other.wait(1s);
  EXPECT_EQ(other.c.state().el.position, ref.c.state().el.position) << "one tick, as 0020 on the reference";
  // A side taken late redoes the last remote jog from where and when it
  // began: 0020 no move (other), or one tick (reference); a stop since
  // leaves it as it is.
  Rig late(site_profile());
  const double from = late.c.state().el.position;
  ASSERT_FALSE(is_nak(late.send(Jog{{'U', 'S', 20}})));
  late.wait(20ms);
  EXPECT_NE(late.c.state().el.motion, AxisState::Motion::kIdle);
  late.c.set_reading("E-61", ReadingSide::kOther);
  EXPECT_EQ(late.c.state().el.motion, AxisState::Motion::kIdle);
  EXPECT_EQ(late.c.state().el.position, from);
  late.wait(1s);
  late.c.set_reading("E-61", ReadingSide::kReference);
  EXPECT_EQ(late.c.state().el.position, ref.c.state().el.position) << "the tick again";
  ASSERT_FALSE(is_nak(late.send(Jog{{'X', 'S', 0}})));
  late.c.set_reading("E-61", ReadingSide::kOther);
  EXPECT_EQ(late.c.state().el.position, ref.c.state().el.position) << "stopped since: kept";
}

// E-74: the name in status bytes 3-12: left-justified on the reference
// side, after a blank on the other (a name that fills the field as it is).
TEST(Readings, E74TheOtherSideShowsANameAfterABlank) {
  Profile p = site_profile();
  p.display.satellite = "SBS 6";
  Rig ref(p), other(reading(p, "E-74"));
  EXPECT_EQ(ref.status().sat_name, "SBS 6");
  auto bytes_3_12 = [](Rig& r) {
    const Outcome o = r.send(StatusPoll{});
    EXPECT_TRUE(o.reply && o.reply->size() > 13);
    return std::string(o.reply->begin() + 3, o.reply->begin() + 13);
  };
  EXPECT_EQ(bytes_3_12(ref), "SBS 6     ");
  EXPECT_EQ(bytes_3_12(other), " SBS 6    ");
  p.display.satellite = "GALAXY 19X";
  Rig full(reading(p, "E-74"));
  EXPECT_EQ(bytes_3_12(full), "GALAXY 19X") << "no room for a blank";
}

// E-76: a position in display units. At 45.06 deg (a jog of 60 ms at
// 1 deg/s from 45.0): 45.1 rounded (reference), 45.0 dropped toward zero
// (other) and toward minus infinity (other-2); at -0.06: -0.1, -0.0 and
// -0.1. With 0.01 deg feedback the hundredths are read the same way.
TEST(Readings, E76ThreeWaysOfReadingAPositionToItsUnit) {
  Profile p = site_profile();
  p.el.initial_deg = 45.06;
  p.az.initial_deg = -0.06;
  const std::array sides{ReadingSide::kReference, ReadingSide::kOther, ReadingSide::kOther2};
  const std::array<std::int32_t, 3> el{451, 450, 450}, az{-1, 0, -1};
  for (std::size_t k = 0; k < sides.size(); ++k) {
    SCOPED_TRACE(std::string(to_string(sides[k])));
    Rig r(reading(p, "E-76", sides[k]));
    EXPECT_EQ(r.status().elevation, el[k]);
    EXPECT_EQ(r.status().azimuth.tenths, az[k]);
  }
  Profile h = p;
  h.hundredths = true;
  h.el.initial_deg = 45.068;
  const std::array<std::int32_t, 3> digit{7, 6, 6};
  for (std::size_t k = 0; k < sides.size(); ++k) {
    Rig r(reading(h, "E-76", sides[k]));
    EXPECT_EQ(r.status().elevation, 450) << to_string(sides[k]);
    EXPECT_EQ(r.extended().el_hundredths, digit[k]) << to_string(sides[k]);
  }
  Rig exact(reading(p, "E-76", ReadingSide::kOther));
  exact.c.mutable_state().el.position = 44.99999999;
  EXPECT_EQ(exact.status().elevation, 450) << "a hair short of a unit is the unit";
}

// E-87: -123.45 deg with 0.01 deg feedback: -123.4 and '5' (the digit
// extends the magnitude) or -123.5 and '5' (added to tenths rounded down);
// a positive position reads alike.
TEST(Readings, E87TheOtherSideAddsTheHundredthsDigitArithmetically) {
  Profile p = site_profile();
  p.hundredths = true;
  p.az.initial_deg = -123.45;
  p.el.initial_deg = 12.34;
  Rig ref(p), other(reading(p, "E-87"));
  EXPECT_EQ(ref.status().azimuth.tenths, -1234);
  EXPECT_EQ(other.status().azimuth.tenths, -1235);
  EXPECT_EQ(ref.extended().az_hundredths, 5);
  EXPECT_EQ(other.extended().az_hundredths, 5);
  p.az.initial_deg = -123.47;
  Rig other_7(reading(p, "E-87"));
  EXPECT_EQ(other_7.status().azimuth.tenths, -1235);
  EXPECT_EQ(other_7.extended().az_hundredths, 3) << "-123.5 + 0.03";
  for (Rig* r : {&ref, &other}) {
    EXPECT_EQ(r->status().elevation, 123);
    EXPECT_EQ(r->extended().el_hundredths, 4);
  }
}

// E-82: a LOCATE stopped by 'X' exits with its movement's STOP_KEY entry
// (reference) or its MODE_CHANGED entry (other); the Stop key keeps
// STOP_KEY on both. One left before it moves (waiting for a site) takes
// LOCATE_FIRST_ELEV_MOVEMENT's entry, or LOCATE_AZIM_MOVEMENT's.
TEST(Readings, E82TheOtherSideExitsAStoppedLocateAsAModeChange) {
  auto exit_after = [](ReadingSide side, const Request& stop, bool site) {
    Profile p = reading(site_profile(), "E-82", side);
    if (!site) {
      p.navigation.latitude_min.reset();
      p.navigation.longitude_min.reset();
    }
    Rig r(p);
    EXPECT_FALSE(is_nak(r.send(locate_on_meridian())));
    r.wait(200ms);
    EXPECT_EQ(r.mode(), "LOCATE_MODE");
    EXPECT_FALSE(is_nak(r.send(stop)));
    const auto x = r.extended();
    return std::string(meanings::exit_name(x.last_mode, x.exit_status));
  };
  const Request x = Jog{{'X', 'F', 0}}, stop_key = RemoteKeypress{'A'};
  EXPECT_EQ(exit_after(ReadingSide::kReference, x, true), "LOCATE_AZIM_MOVEMENT_STOP_KEY");
  EXPECT_EQ(exit_after(ReadingSide::kOther, x, true), "LOCATE_AZIM_MOVEMENT_MODE_CHANGED");
  EXPECT_EQ(exit_after(ReadingSide::kOther, stop_key, true), "LOCATE_AZIM_MOVEMENT_STOP_KEY");
  EXPECT_EQ(exit_after(ReadingSide::kReference, stop_key, false), "LOCATE_FIRST_ELEV_MOVEMENT_STOP_KEY");
  EXPECT_EQ(exit_after(ReadingSide::kOther, stop_key, false), "LOCATE_AZIM_MOVEMENT_STOP_KEY");
  EXPECT_EQ(exit_after(ReadingSide::kOther, x, false), "LOCATE_AZIM_MOVEMENT_MODE_CHANGED");
}

// E-88: the Stop key (41h) on a remote auto move stops it; REMOTE_MODE keeps
// control (reference) or MANUAL_MODE idle follows (other).
TEST(Readings, E88TheOtherSideLeavesRemoteOnTheStopKey) {
  Rig ref(site_profile()), other(reading(site_profile(), "E-88"));
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(AutoMove{AutoMoveAzEl{600, 450}})));
    r->wait(1s);
    ASSERT_FALSE(is_nak(r->send(RemoteKeypress{'A'})));
    r->wait(1s);
    EXPECT_EQ(r->c.state().az.motion, AxisState::Motion::kIdle);
  }
  EXPECT_EQ(ref.mode(), "REMOTE_MODE");
  EXPECT_EQ(ref.state(), "WAITING_FOR_USER_INPUT");
  EXPECT_EQ(other.mode(), "MANUAL_MODE");
  EXPECT_EQ(other.state(), "MANUAL_IDLE");
}

// E-89: 'X' on a STOW or DEPLOY: MOVE_STOPPED (reference) or MODE_CHANGED
// (other); the Stop key MOVE_STOPPED on both. The other side's STOW moves
// the azimuth first and the elevation after it; both end stowed.
TEST(Readings, E89TheOtherSideStowsAxisByAxisAndExitsAStopAsAModeChange) {
  Profile p = site_profile();
  p.stow = p.deploy = true;
  p.az.initial_deg = 40;
  p.el.initial_deg = 60;
  p.el.deploy_deg = 20;
  Rig ref(p), other(reading(p, "E-89"));
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(Misc{'S', ' '})));
  ref.wait(500ms);
  other.wait(500ms);
  EXPECT_EQ(ref.state(), "STOW_MOVING_TO_AZIM_STOW");
  EXPECT_NE(ref.c.state().el.motion, AxisState::Motion::kIdle) << "together";
  EXPECT_EQ(other.state(), "STOW_MOVING_TO_AZIM_STOW");
  EXPECT_EQ(other.c.state().el.position, 60.0) << "the elevation waits for the azimuth";
  bool elevation_leg = false;
  for (int i = 0; i < 3000 && other.mode() == "STOW_MODE"; ++i) {
    other.wait(200ms);
    elevation_leg = elevation_leg || other.state() == "STOW_MOVING_TO_ELEV_STOW";
  }
  EXPECT_TRUE(elevation_leg);
  ref.wait(600s);
  for (Rig* r : {&ref, &other}) {
    const auto x = r->extended();
    EXPECT_EQ(meanings::exit_name(x.last_mode, x.exit_status), "STOW_FINISHED_NORMALLY");
    EXPECT_NEAR(r->c.state().az.position, 0.0, 0.1);
    EXPECT_NEAR(r->c.state().el.position, r->c.stow_elevation(), 0.1);
  }
  auto exit_after = [&](ReadingSide side, const Request& stop, char sub) {
    Rig r(reading(p, "E-89", side));
    EXPECT_FALSE(is_nak(r.send(Misc{sub, ' '})));
    r.wait(200ms);
    EXPECT_FALSE(is_nak(r.send(stop)));
    const auto x = r.extended();
    return std::string(meanings::exit_name(x.last_mode, x.exit_status));
  };
  const Request x = Jog{{'X', 'F', 0}}, stop_key = RemoteKeypress{'A'};
  EXPECT_EQ(exit_after(ReadingSide::kReference, x, 'S'), "STOW_MOVING_TO_AZIM_STOW_MOVE_STOPPED");
  EXPECT_EQ(exit_after(ReadingSide::kOther, x, 'S'), "STOW_MOVING_TO_AZIM_STOW_MODE_CHANGED");
  EXPECT_EQ(exit_after(ReadingSide::kOther, stop_key, 'S'), "STOW_MOVING_TO_AZIM_STOW_MOVE_STOPPED");
  EXPECT_EQ(exit_after(ReadingSide::kReference, x, 'D'), "DEPLOY_MOVING_ELEVATION_MOVE_STOPPED");
  EXPECT_EQ(exit_after(ReadingSide::kOther, x, 'D'), "DEPLOY_MOVING_ELEVATION_MODE_CHANGED");
}

// E-101: an azimuth and an elevation jammed, byte 39 showing the azimuth's
// code (2): a drive reset of the azimuth sets it to 0 (reference) or shows
// the elevation's, 4 (other); a reset of the elevation then 0 on both.
TEST(Readings, E101TheOtherSideShowsTheCodeOfAnAlarmStillActive) {
  Profile p = site_profile();
  p.alarms.az = 0xB;
  p.alarms.el = 0xB;
  p.alarms.code = 2;
  Rig ref(p), other(reading(p, "E-101"));
  for (Rig* r : {&ref, &other}) ASSERT_FALSE(is_nak(r->send(Misc{'R', 'A'})));
  EXPECT_EQ(ref.status().alarm_code, 0);
  EXPECT_EQ(other.status().alarm_code, 4);
  for (Rig* r : {&ref, &other}) {
    ASSERT_FALSE(is_nak(r->send(Misc{'R', 'E'})));
    EXPECT_EQ(r->status().alarm_code, 0);
  }
}

// E-99: a STOW from elevation 60 with the stow position at 10: at it and
// STOW_FINISHED_NORMALLY (reference); a degree short, bit C clear, and
// STOW_FINISHED_WITH_ELEV_NOT_AT_STOW (other), after movements in either
// order (E-89). An elevation already within that degree stays and ends the
// same way; one already at its stow position ends normally on both sides.
TEST(Readings, E99TheOtherSideLeavesTheElevationShortOfItsStow) {
  Profile p = site_profile();
  p.stow = true;
  p.el.has_stow_limit = true;
  p.el.stow_deg = 10;
  p.az.initial_deg = 40;
  p.el.initial_deg = 60;
  auto stow = [](Rig& r) {
    EXPECT_FALSE(is_nak(r.send(Misc{'S', ' '})));
    r.wait(600s);
    const auto x = r.extended();
    return std::string(meanings::exit_name(x.last_mode, x.exit_status));
  };
  Rig ref(p);
  EXPECT_EQ(stow(ref), "STOW_FINISHED_NORMALLY");
  EXPECT_NEAR(ref.c.state().el.position, 10.0, 0.05);
  EXPECT_EQ(ref.status().el_limits & 0x01, 1);
  for (const std::string_view also : {"", "E-89"}) {
    Profile q = reading(p, "E-99");
    if (!also.empty()) q = reading(q, also);
    Rig other(q);
    EXPECT_EQ(stow(other), "STOW_FINISHED_WITH_ELEV_NOT_AT_STOW") << also;
    EXPECT_NEAR(other.c.state().el.position, 11.0, 0.1) << also;
    EXPECT_EQ(other.status().el_limits & 0x01, 0) << also;
    EXPECT_NEAR(other.c.state().az.position, 0.0, 0.1) << "the azimuth is stowed as on the reference side";
  }
  p.el.initial_deg = 10.5;
  Rig near_stow(reading(p, "E-99"));
  EXPECT_EQ(stow(near_stow), "STOW_FINISHED_WITH_ELEV_NOT_AT_STOW");
  EXPECT_NEAR(near_stow.c.state().el.position, 10.5, 0.01) << "within the degree: not moved";
  p.el.initial_deg = 10;
  Rig stowed(reading(p, "E-99"));
  EXPECT_EQ(stow(stowed), "STOW_FINISHED_NORMALLY");
}

// E-100: TRACK peaking at power-on. The reference holds the antenna still;
// the other side moves the azimuth out 0.2 deg and back, then the
// elevation, showing movement in progress, and goes on doing so; both keep
// 'Y' 0 and NAK a jog (§3.4). A search moves the same way and after one
// round shows step track peaking (SSSS 0100, then 0011). Out of TRACK
// nothing moves by itself.
TEST(Readings, E100TheOtherSideMovesTheAntennaWhileTrackPeaks) {
  Profile p = site_profile();
  p.track.active = true;
  p.track.activity = TrackActivity::kPeaking;
  p.az.initial_deg = 40;
  p.el.initial_deg = 30;
  Rig ref(p), other(reading(p, "E-100"));
  double az_min = 360, az_max = 0, el_min = 90, el_max = 0;
  bool az_up_shown = false, el_up_shown = false;
  for (int i = 0; i < 400; ++i) {
    ref.wait(50ms);
    other.wait(50ms);
    EXPECT_EQ(ref.c.state().az.position, 40.0) << "the reference holds still";
    EXPECT_EQ(ref.status().az_status & 0x0F, 0);
    const StatusBlock st = other.status();
    az_up_shown = az_up_shown || (st.az_status & 0x0F) == 0x05;
    el_up_shown = el_up_shown || (st.el_status & 0x0F) == 0x05;
    az_min = std::min(az_min, other.c.state().az.position);
    az_max = std::max(az_max, other.c.state().az.position);
    el_min = std::min(el_min, other.c.state().el.position);
    el_max = std::max(el_max, other.c.state().el.position);
  }
  EXPECT_TRUE(az_up_shown && el_up_shown) << "movement in progress, clockwise and up";
  EXPECT_NEAR(az_min, 40.0, 1e-9);
  EXPECT_NEAR(az_max, 40.2, 1e-9);
  EXPECT_NEAR(el_min, 30.0, 1e-9);
  EXPECT_NEAR(el_max, 30.2, 1e-9);
  const double az_then = other.c.state().az.position, el_then = other.c.state().el.position;
  other.wait(150ms);
  EXPECT_TRUE(other.c.state().az.position != az_then || other.c.state().el.position != el_then) << "it goes on peaking";
  for (Rig* r : {&ref, &other}) {
    EXPECT_EQ(r->status().pol_equipment & 0x08, 0) << "'Y': no pol moves while peaking";
    EXPECT_EQ(r->send(Jog{{'W', 'F', 1000}}).nak, NakRule::kTrackPeaking);
    EXPECT_EQ(r->mode(), "TRACK_MODE");
  }
  p.track.activity = TrackActivity::kSearching;
  Rig search(reading(p, "E-100"));
  EXPECT_EQ(search.status().track & 0x0F, 0b0100);
  search.wait(60s);
  EXPECT_EQ(search.status().track & 0x0F, 0b0011);
  EXPECT_EQ(search.state(), "TRACK_STEP_PEAKING");
  p.track.activity = TrackActivity::kIdle;
  Rig idle(reading(p, "E-100"));
  idle.wait(10s);
  EXPECT_EQ(idle.c.state().az.position, 40.0) << "step track idle: not a peaking or search operation";
}

TEST(Readings, E6TheReferenceSideIgnoresAControlCharacterInTheBody) {
  Line line{Profile{}};
  EXPECT_TRUE(line.send(0x05, {}).empty());
  EXPECT_TRUE(line.send(0x35, text("\x01" "1")).empty());
  EXPECT_TRUE(line.send(0x31, text("\r")).empty());
  EXPECT_EQ(line.send(0x31, {}).at(0), ACK) << "then a poll is answered";
}

TEST(Readings, E6TheOtherSideReadsToEtxAndNaksWithTheCommandByteAsCC) {
  Line line{reading(Profile{}, "E-6")};
  EXPECT_EQ(line.send(0x05, {}), nak_for(0x05)) << "a control command byte is an unknown code, echoed";
  EXPECT_EQ(line.send(0x15, {}), nak_for(0x15));
  EXPECT_EQ(line.send(0x1F, text("1")), nak_for(0x1F));
  EXPECT_EQ(line.send(0x35, text("\x01" "1")), nak_for(0x35)) << "invalid data";
  EXPECT_EQ(line.send(0x31, text("\r")), nak_for(0x31)) << "a length that does not fit 31h";
  EXPECT_EQ(line.bus.take_nak_rules(),
            (std::vector<std::string>{"UnknownCommand", "UnknownCommand", "UnknownCommand", "MalformedData", "WrongLength"}));
  EXPECT_EQ(line.send(0x31, {}).at(0), ACK);
}

TEST(Readings, E8TheReferenceSideIgnoresAFrameLongerThan145Bytes) {
  Line line{Profile{}};
  EXPECT_EQ(line.send(0x31, Bytes(140, '0')), nak_for(0x31)) << "145 bytes: a wrong length";
  EXPECT_TRUE(line.send(0x31, Bytes(141, '0')).empty()) << "146 bytes: an overrun";
  EXPECT_TRUE(line.send(0x31, Bytes(200, '0')).empty());
  EXPECT_EQ(line.send(0x31, {}).at(0), ACK);
}

TEST(Readings, E8TheOtherSideNaksALongFrameForItsLength) {
  Line line{reading(Profile{}, "E-8")};
  EXPECT_EQ(line.send(0x31, Bytes(141, '0')), nak_for(0x31));
  EXPECT_EQ(line.send(0x31, Bytes(200, '0')), nak_for(0x31));
  EXPECT_EQ(line.bus.take_nak_rules(), (std::vector<std::string>{"WrongLength", "WrongLength"}));
  // Unterminated: still under way when the next poll's STX restarts
  // reception (E-7), so the poll is answered.
  Bytes open = encode_frame({FrameKind::kCommand, '2', 0x31, Bytes(200, '0')});
  open.resize(open.size() - 2);
  EXPECT_TRUE(line.send(open).empty());
  EXPECT_EQ(line.send(0x31, {}).at(0), ACK);
}

// The bus's receiver follows a side taken late (the live fuzzer's model),
// even in the middle of a frame.
TEST(Readings, E6AndE8TakenLateReconfigureTheReceiver) {
  Line line{Profile{}};
  const Bytes frame = encode_frame({FrameKind::kCommand, '2', 0x31, Bytes(141, '0')});
  EXPECT_TRUE(line.send(Bytes(frame.begin(), frame.begin() + 50)).empty());
  line.bus.controller(0).set_reading("E-8", ReadingSide::kOther);
  EXPECT_EQ(line.send(Bytes(frame.begin() + 50, frame.end())), nak_for(0x31));
  EXPECT_TRUE(line.send(0x05, {}).empty());
  line.bus.controller(0).set_reading("E-6", ReadingSide::kOther);
  EXPECT_EQ(line.send(0x05, {}), nak_for(0x05));
  line.bus.controller(0).set_reading("E-6", ReadingSide::kReference);
  line.bus.controller(0).set_reading("E-8", ReadingSide::kReference);
  EXPECT_TRUE(line.send(0x05, {}).empty());
  EXPECT_TRUE(line.send(0x31, Bytes(141, '0')).empty());
}

// The fault accepts-control-in-body does what neither side does: it drops
// the control character and executes the rest (the check byte covers it).
TEST(Readings, E6TheFaultAcceptsControlInBodyExecutesWhatNeitherSideDoes) {
  for (ReadingSide side : {ReadingSide::kReference, ReadingSide::kOther}) {
    VirtualClock clock;
    Bus bus({reading(Profile{}, "E-6", side)}, clock, FaultSet{Fault::kAcceptsControlInBody});
    Bytes out;
    bus.receive(add_even_parity(encode_frame({FrameKind::kCommand, '2', 0x31, text("\r")})), out);
    ASSERT_FALSE(out.empty());
    EXPECT_EQ(out[0] & 0x7F, ACK) << "a status poll, answered";
  }
}

}  // namespace
}  // namespace sabus::harness
