// The live fuzzer on the spec's open points (readings.hpp, ERRATA class
// reading; issue 31): a device on the other side of one is a legal
// controller, so the lockstep model notes the difference with its ERRATA
// entry and takes that side, and never makes a finding of it.
#include <gtest/gtest.h>

#include <filesystem>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/profile_generator.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/messages.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::harness::live_fuzz {
namespace {

using namespace std::chrono_literals;

Profile default_profile() { return load_profile_file(default_profile_path()).profile.value(); }

FuzzFrame raw(std::string_view hex) {
  auto bytes = parse_hex(hex);
  EXPECT_TRUE(bytes.ok()) << hex;
  return {bytes.value(), {}, "test"};
}

std::string noted(const Session& s) {
  std::string out;
  for (const auto& n : s.lockstep()->notes()) out += (out.empty() ? "" : " ") + n.errata + ":" + std::string(to_string(n.side));
  return out;
}

// A session, motion and stored writes allowed, with the model on `model`
// and the device on `model` with E-94 on its other side.
struct OtherLocateOrder {
  explicit OtherLocateOrder(Profile m, FaultSet faults = {})
      : model(std::move(m)),
        t(make_in_process_transport({[&] {
                                       Profile d = model;
                                       d.readings["E-94"] = ReadingSide::kOther;
                                       return d;
                                     }()},
                                    faults)),
        s(*t, model, SessionOptions{.allow_motion = true, .allow_destructive = true}) {}
  Profile model;
  std::unique_ptr<InProcessTransport> t;
  Session s;
};

// 41h Remote Locate of a satellite at 81.5 W (§3.18), data form.
FuzzFrame locate_at_81_5_west(const Profile& model) {
  return {encode_request(build_request(*find_command(0x41), "data",
                                       {{"sat name", "FUZZ LOC"}, {"longitude", "-81.5"}, {"inclination", "0"},
                                        {"band", "1"}, {"pol offset", "0.0"}, {"receive polarization", "N"},
                                        {"position update", "A"}})
                             .value(),
                         model.address),
          {}, "test"};
}

// Polls the extended status (40h) every `every` until the model's LOCATE and
// the device's have both ended (neither in LOCATE_MODE) and the device rests,
// at most `polls` times: the first finding, if any.
std::optional<Verdict> poll_until_located(Session& s, const Profile& model, InProcessTransport& t, int polls,
                                          std::chrono::milliseconds every) {
  FuzzFrame extended{encode_frame({FrameKind::kCommand, model.address, 0x40, {}}), {}, "test", every};
  for (int i = 0; i < polls; ++i) {
    if (auto v = s.step(extended)) return v;
    const auto locating = [](const Controller& c) { return meanings::mode_name(c.state().mode.mode) == "LOCATE_MODE"; };
    if (!locating(s.lockstep()->model()) && !locating(t.bus().controller(0)) && all_at_rest(t.bus().controller(0)) &&
        all_at_rest(s.lockstep()->model()))
      return std::nullopt;
  }
  ADD_FAILURE() << "the LOCATE did not end in " << polls << " polls";
  return std::nullopt;
}

// A LOCATE whose first movement is the elevation's (E-94's other side),
// asked for its extended status at once and then until it has ended: the
// order of its movements is the device's, as a STOW's is, so no finding and
// no note; where it ends is judged, and agrees.
TEST(LiveFuzzReadings, ALocateThatMovesElevationFirstIsTheDevicesUntilItEnds) {
  OtherLocateOrder f(default_profile());
  const Profile& model = f.model;
  auto& t = f.t;
  Session& s = f.s;
  for (std::string_view hex : {"02 32 47 44 53 30 30 30 30 03 63", "02 32 33 58 53 30 30 30 30 03 0b",
                               "02 32 41 40 30 46 55 5a 5a 20 4c 4f 43 20 20 2d 39 33 2e 35 20 30 20 31 30 2e 30 20 20 4e 41 20 20 20 20 03 6d",
                               "02 32 40 03 73"}) {
    const auto v = s.step(raw(hex));
    EXPECT_FALSE(v) << hex << ": " << v->message;
  }
  const auto v = poll_until_located(s, model, *t, 200, 2000ms);
  EXPECT_FALSE(v) << v->message;
  EXPECT_EQ(noted(s), "");
  EXPECT_NEAR(s.lockstep()->model().state().az.position, t->bus().controller(0).state().az.position, 0.1);
  EXPECT_NEAR(s.lockstep()->model().state().el.position, t->bus().controller(0).state().el.position, 0.1);
}

// A LOCATE started and stopped in one write (a burst): the model's stop
// finds its azimuth movement, the device's its first elevation movement
// (E-94's other side); each exits by its own stop entry, and that is no
// finding (gate.fuzz_readings, iess-implemented, fuzz seed 1). A device
// that went on moving after it would still be one.
TEST(LiveFuzzReadings, ALocateStoppedInTheWriteThatStartsItExitsByItsOwnStop) {
  OtherLocateOrder f(default_profile());
  auto& t = f.t;
  Session& s = f.s;
  const FuzzFrame burst = raw(
      "02 32 41 40 30 46 55 5a 5a 20 4c 4f 43 20 20 2d 39 33 2e 35 20 30 20 31 30 2e 30 20 20 4e 41 20 20 20 20 03 6d "
      "02 32 47 58 53 30 30 30 30 03 7f");
  const auto v = s.step(burst);
  EXPECT_FALSE(v) << v->message;
  FuzzFrame extended = raw("02 32 40 03 73");
  extended.pause = 2000ms;
  for (int i = 0; i < 3; ++i) {
    const auto w = s.step(extended);
    EXPECT_FALSE(w) << w->message;
  }
  const auto* x = &t->bus().controller(0).state().mode;
  EXPECT_EQ(meanings::exit_name(x->last_mode, x->exit_status), "LOCATE_FIRST_ELEV_MOVEMENT_STOP_KEY");
  EXPECT_EQ(meanings::mode_name(s.lockstep()->model().state().mode.last_mode), "LOCATE_MODE");
}

// The same LOCATE led by a device that turns the azimuth the wrong way
// (fault locate-azimuth-counterclockwise) on a pot-sensed mount whose 0.0 is
// not true north: while it runs, nothing of its motion is judged (E-94
// open); once both have completed, the device's azimuth is a finding.
TEST(LiveFuzzReadings, ALocateTheDeviceLeadsIsJudgedWhereItEnds) {
  const ProfileResult loaded = load_profile_file(
      (std::filesystem::path(default_profile_path()).parent_path() / "fast-mount-manual-nav.yaml").string());
  ASSERT_TRUE(loaded);
  ASSERT_FALSE(side_pinned(loaded.profile->readings, "E-94"));
  OtherLocateOrder f(*loaded.profile, FaultSet{Fault::kLocateAzimuthCounterclockwise});
  const Profile& model = f.model;
  auto& t = f.t;
  Session& s = f.s;
  const FuzzFrame locate = locate_at_81_5_west(model);
  const auto started = s.step(locate);
  ASSERT_FALSE(started) << started->message;
  const auto v = poll_until_located(s, model, *t, 200, 500ms);
  ASSERT_TRUE(v) << "the wrong azimuth was not found where the LOCATE ended; notes: " << noted(s);
  EXPECT_EQ(v->kind, FindingKind::kEffect) << v->message;
  EXPECT_EQ(v->field, "azimuth") << v->message;
  // Both at rest out of the LOCATE, its exit LOCATE_FUNCTION_COMPLETED (0x38).
  EXPECT_NE(v->message.find("last exited mode=0x25, exit status=0x38"), std::string::npos) << v->message;
  EXPECT_EQ(noted(s), "");
}

// §3.2 byte 35 'Y' "only contains meaningful data when TRACK mode is
// active" (E-95, class text): a device showing 0 outside TRACK is no
// finding and needs no note, even where the model's profile pins the side
// that shows 1.
TEST(LiveFuzzReadings, YOutsideTrackIsTheDevicesEvenPinned) {
  Profile model = default_profile();
  ASSERT_FALSE(model.track.active);
  model.readings["E-95"] = ReadingSide::kReference;
  Profile device = model;
  device.readings["E-95"] = ReadingSide::kOther;
  auto t = make_in_process_transport({device}, {});
  Session s(*t, model, SessionOptions{});
  for (std::uint8_t code : {0x31, 0x40}) {
    const FuzzFrame poll{encode_frame({FrameKind::kCommand, model.address, code, {}}), {}, "test"};
    const auto v = s.step(poll);
    EXPECT_FALSE(v) << v->message;
  }
  EXPECT_EQ(noted(s), "");
}

// §3.17 bytes 49-50 on a mount without 0.01 deg feedback (ERRATA E-30): a
// device showing blanks is on the other side (a note, no finding), unless
// the profile pins the reference side; on the other side any digit (a stale
// one) is the device's too, so a model pinned there accepts the '0'.
TEST(LiveFuzzReadings, E30BlankHundredthsAreNotedAndPinnedSidesAreStrict) {
  Profile model = default_profile();
  ASSERT_FALSE(model.hundredths);
  ASSERT_FALSE(side_pinned(model.readings, "E-30"));
  Profile other = model;
  other.readings["E-30"] = ReadingSide::kOther;
  const FuzzFrame extended = raw("02 32 40 03 73");
  {
    auto t = make_in_process_transport({other}, {});
    Session s(*t, model, SessionOptions{});
    for (int i = 0; i < 2; ++i) {
      const auto v = s.step(extended);
      EXPECT_FALSE(v) << v->message;
    }
    EXPECT_EQ(noted(s), "E-30:other");
  }
  {
    Profile pinned = model;
    pinned.readings["E-30"] = ReadingSide::kReference;
    auto t = make_in_process_transport({other}, {});
    Session s(*t, pinned, SessionOptions{});
    const auto v = s.step(extended);
    ASSERT_TRUE(v) << "blanks where the profile pins '0'";
    EXPECT_EQ(v->field, "az hundredths") << v->message;
  }
  {
    auto t = make_in_process_transport({model}, {});
    Session s(*t, other, SessionOptions{});
    const auto v = s.step(extended);
    EXPECT_FALSE(v) << "a digit is the other side's too: " << v->message;
  }
}

// A status poll begun by one write and ended by the next (ERRATA E-67): a
// device with an inter-character timeout drops it, since the writes are
// further apart than 20 ms (the first waits out its silence window). The
// framing oracle accepts the silence and the model notes the side; the
// next whole poll is answered. Where the profile pins the reference side
// the silence is a finding.
TEST(LiveFuzzReadings, E67AFrameEndedByALaterWriteMayBeDropped) {
  Profile model = default_profile();
  ASSERT_FALSE(side_pinned(model.readings, "E-67"));
  Profile device = model;
  device.readings["E-67"] = ReadingSide::kOther;
  {
    auto t = make_in_process_transport({device}, {});
    Session s(*t, model, SessionOptions{});
    for (std::string_view hex : {"02 32 31", "03 02", "02 32 31 03 02"}) {
      const auto v = s.step(raw(hex));
      EXPECT_FALSE(v) << hex << ": " << v->message;
    }
    EXPECT_EQ(noted(s), "E-67:other");
  }
  {
    Profile pinned = model;
    pinned.readings["E-67"] = ReadingSide::kReference;
    auto t = make_in_process_transport({device}, {});
    Session s(*t, pinned, SessionOptions{});
    EXPECT_FALSE(s.step(raw("02 32 31")));
    const auto v = s.step(raw("03 02"));
    ASSERT_TRUE(v) << "silence where the profile pins the reference side";
    EXPECT_EQ(v->kind, FindingKind::kNoReply) << v->message;
  }
}

// A search over within a second (E-90's other side) on a mount whose
// elevation reads '*' (an A/D error, E-42): where the device's search left
// the axis shows first in its pulse count, which the model takes after the
// episode instead of judging it (random profile 0x202924717a94d6aa gave an
// 'elevation count' effect finding). The search's own end is the device's
// (an episode the lockstep does not judge), so it needs no note.
TEST(LiveFuzzReadings, AnAxisWithoutAReadingIsTakenFromItsCountAfterASearch) {
  Profile model = random_profile(0x202924717a94d6aaull);
  model.readings.clear();
  ASSERT_TRUE(model.el.ad_error);
  Profile device = model;
  ASSERT_FALSE(apply_reading_spec("other", device.readings));
  auto t = make_in_process_transport({device}, {});
  SessionOptions o;
  o.allow_motion = o.allow_destructive = true;
  Session s(*t, model, o);
  auto frame = [&](std::uint8_t code, std::string data) {
    return FuzzFrame{encode_frame({FrameKind::kCommand, model.address, code, Bytes(data.begin(), data.end())}), {}, "t"};
  };
  std::vector<FuzzFrame> writes = {frame(0x36, "AF"), frame(0x31, ""), frame(0x48, "A"),
                                   frame(0x31, ""),   frame(0x40, ""), frame(0x3f, "")};
  writes[1].pause = 710ms;
  for (const FuzzFrame& f : writes) {
    const auto v = s.step(f);
    EXPECT_FALSE(v) << v->message;
  }
  EXPECT_NEAR(s.lockstep()->model().state().el.position, t->bus().controller(0).state().el.position, 0.02);
}

// E-93 decided late: a LOCATE to where the antenna already stands completes
// in the write that starts it; the model (reference side) goes to
// MANUAL_MODE, a device on the other side to REMOTE_MODE, and no 40h shows
// it before a jog changes the model's mode too. The 40h after the jog
// differs in its last exited mode (MANUAL in the model, LOCATE in the
// device), which only the other side of E-93, taken back at the LOCATE,
// explains: a note, not a finding (gate.fuzz_readings, fast-mount-manual-nav,
// fuzz seed 16393).
TEST(LiveFuzzReadings, AModeALocateWentToUnseenUntilLaterIsNoted) {
  const ProfileResult loaded = load_profile_file(
      (std::filesystem::path(default_profile_path()).parent_path() / "fast-mount-manual-nav.yaml").string());
  ASSERT_TRUE(loaded);
  Profile model = *loaded.profile;
  model.readings.clear();
  Profile device = model;
  device.readings["E-93"] = ReadingSide::kOther;
  auto t = make_in_process_transport({device}, {});
  Session s(*t, model, SessionOptions{.allow_motion = true, .allow_destructive = true});
  const FuzzFrame locate = locate_at_81_5_west(model);
  auto step = [&](const FuzzFrame& f) {
    const auto v = s.step(f);
    EXPECT_FALSE(v) << v->message;
  };
  step(locate);
  EXPECT_FALSE(poll_until_located(s, model, *t, 200, 500ms));
  ASSERT_EQ(noted(s), "");  // the first LOCATE's mode was shown by a 40h, and taken
  step(locate);             // at once: where the first one ended
  ASSERT_EQ(meanings::mode_name(s.lockstep()->model().state().mode.mode), "MANUAL_MODE");
  ASSERT_EQ(meanings::mode_name(t->bus().controller(0).state().mode.mode), "REMOTE_MODE");
  step(FuzzFrame{encode_frame({FrameKind::kCommand, model.address, 0x47, {'W', 'S', '0', '0', '0', '0'}}), {}, "test"});
  step(FuzzFrame{encode_frame({FrameKind::kCommand, model.address, 0x40, {}}), {}, "test"});
  EXPECT_EQ(noted(s), "E-93:other");
  EXPECT_EQ(s.lockstep()->model().state().mode, t->bus().controller(0).state().mode);
}

// §3.4: an elevation without a reading ('*', E-42) that a search leads: a
// jog down NAKed by the device (its axis at the lower limit) where the
// model's axis stands elsewhere is explained by that limit, and the model
// takes it (gate.fuzz_readings, sweep-975835de1c9756ce, fuzz seed 1). A
// device that NAKs a jog on an axis whose reading the model has is still
// judged by the model's position.
TEST(LiveFuzzReadings, AJogNakedOnAnAxisWithoutAReadingPutsItAtTheLimit) {
  Profile model = random_profile(0x975835de1c9756ceull);
  model.readings.clear();
  ASSERT_TRUE(model.el.ad_error);
  Profile device = model;
  ASSERT_FALSE(apply_reading_spec("other", device.readings));
  auto t = make_in_process_transport({device}, {});
  Session s(*t, model, SessionOptions{.allow_motion = true, .allow_destructive = true});
  const std::vector<std::pair<std::string_view, int>> writes = {
      {"02 56 32 20 2d 31 34 34 30 30 30 32 34 34 03 5b", 0},  // auto move to the lower elevation limit
      {"02 56 38 40 61 03 4e", 0},
      {"02 56 38 5a 7a 03 4f", 0},
      {"02 56 33 58 53 30 30 30 30 03 6f", 0},  // stop
      {"02 56 31 03 66", 768},
      {"02 56 36 41 46 03 66", 0},  // flat spiral search
      {"02 56 31 03 66", 640},
      {"02 56 33 58 53 30 30 30 30 03 6f", 0},  // stop
      {"02 56 31 03 66", 500}};
  ASSERT_EQ(model.address, 0x56);
  for (const auto& [hex, pause] : writes) {
    FuzzFrame f = raw(hex);
    f.pause = std::chrono::milliseconds(pause);
    const auto v = s.step(f);
    ASSERT_FALSE(v) << hex << ": " << v->message;
  }
  // The device's search (over within the second, E-90's other side) has
  // left its elevation at the lower limit; the model's, stopped, elsewhere.
  ASSERT_NEAR(t->bus().controller(0).state().el.position, model.el.min_deg, 1e-6);
  ASSERT_GT(s.lockstep()->model().state().el.position, model.el.min_deg + 0.1);
  ASSERT_EQ(s.lockstep()->model().state().el.motion, AxisState::Motion::kIdle);
  const auto v = s.step(raw("02 56 33 44 53 39 39 39 39 03 73"));  // jog down
  EXPECT_FALSE(v) << v->message;
  EXPECT_NEAR(s.lockstep()->model().state().el.position, model.el.min_deg, 1e-6);
}

// The receiver-level readings (E-6, E-8): a frame with a control character
// in its body, and one of 146 bytes, each with a good check byte, then a
// poll in the same write. A device on the other side NAKs them: the framing
// oracle takes that from a side the profile leaves open (a note, the model
// taking the side and cutting the write as it does), not from a pinned one.
TEST(LiveFuzzReadings, AFrameTheOtherReceiverKeepsIsNotedUnlessPinned) {
  const Profile model = default_profile();
  const Bytes poll = encode_frame({FrameKind::kCommand, model.address, 0x31, {}});
  for (const char* id : {"E-6", "E-8"}) {
    const Bytes odd = encode_frame({FrameKind::kCommand, model.address, 0x35,
                                    std::string_view(id) == "E-6" ? Bytes{'0', 0x01} : Bytes(141, '0')});
    FuzzFrame write{odd, {}, "test"};
    write.chars.insert(write.chars.end(), poll.begin(), poll.end());
    for (bool pinned : {false, true}) {
      Profile device = model;
      device.readings[id] = ReadingSide::kOther;
      Profile judged = model;
      if (pinned) judged.readings[id] = ReadingSide::kReference;
      auto t = make_in_process_transport({device}, {});
      Session s(*t, judged, SessionOptions{});
      const auto v = s.step(write);
      if (pinned) {
        ASSERT_TRUE(v) << id << " pinned: the NAK is a finding";
        EXPECT_EQ(v->kind, FindingKind::kReplyToIgnored) << v->message;
      } else {
        EXPECT_FALSE(v) << id << ": " << to_string(v->kind) << ": " << v->message;
        EXPECT_EQ(noted(s), std::string(id) + ":other");
        EXPECT_EQ(side_taken(s.lockstep()->model().profile().readings, id), ReadingSide::kOther);
      }
    }
  }
}

// Each switchable reading on its own (sabus sim --reading E-NN=other), on a
// profile where it shows (a circular feed for E-91, remote control disabled
// for E-97): 3,000 writes with motion and stored writes give no finding,
// and the entries the generator reaches within them are noted. E-94 and
// E-95 never are: a LOCATE's movements are the device's episode, and 'Y'
// outside TRACK is the device's by the spec's own word.
struct OneReading {
  const char* id;
  const char* profile;  // a shipped profile's file name
  bool noted;           // reached and noted within the writes (seed 1)
  ReadingSide side = ReadingSide::kOther;
  void (*adjust)(Profile&) = nullptr;  // where no shipped profile shows the point
};
void azimuth_ad_error(Profile& p) { p.az.ad_error = true; }
void elevation_jammed_too(Profile& p) { p.alarms.el = 0xB; }
void manual_search(Profile& p) {
  p.track.active = true;
  p.track.activity = TrackActivity::kManualSearch;
}
class LiveFuzzOneReading : public ::testing::TestWithParam<OneReading> {};

// `writes` generated writes (seed 1, motion and stored writes on) from a
// session with the model on `model` and the device on `device`: the first
// finding as "write N (what): kind: message", or "" and the notes in `notes`.
std::string first_finding(const Profile& model, const Profile& device, int writes, std::string& notes) {
  auto t = make_in_process_transport({device}, {});
  SessionOptions o;
  o.allow_motion = o.allow_destructive = true;
  Session session(*t, model, o);
  GeneratorOptions go{model.address, true, true, true, {}, {}, &model};
  for (const StoredSatellite& st : model.store) go.names.push_back(st.name);
  Generator generator(go, 1);
  const Lockstep* l = session.lockstep();
  generator.set_rules_fired(&l->coverage().rules_fired);
  generator.set_model([l] { return Generator::ModelView{&l->model(), l->now(), l->device_led()}; });
  for (int i = 0; i < writes; ++i) {
    FuzzFrame f = generator.next();
    for (int k = 0; k < 2 && session.would_be_ignored(f); ++k) {
      const Bytes poll = encode_frame({FrameKind::kCommand, model.address, 0x31, {}});
      f.chars.insert(f.chars.end(), poll.begin(), poll.end());
    }
    if (const auto v = session.step(f))
      return "write " + std::to_string(i) + " (" + f.what + "): " + std::string(to_string(v->kind)) + ": " + v->message;
  }
  notes = noted(session);
  return "";
}

TEST_P(LiveFuzzOneReading, IsNotedNeverFound) {
  const OneReading c = GetParam();
  const auto dir = std::filesystem::path(default_profile_path()).parent_path();
  Profile model = load_profile_file((dir / c.profile).string()).profile.value();
  if (c.adjust) c.adjust(model);
  Profile device = model;
  device.readings[c.id] = c.side;
  std::string notes;
  ASSERT_EQ(first_finding(model, device, 3000, notes), "");
  if (c.noted) EXPECT_NE(notes.find(std::string(c.id) + ":" + std::string(to_string(c.side))), std::string::npos) << notes;
}

// E-100: a TRACK that peaks in a pattern of its own (a device whose axes
// step 0.6 deg, where the model's other side would step 0.2): its
// positions and motion bits are the device's while TRACK has control, so
// no finding and nothing to note; pinned to the reference side (TRACK holds
// still), the same device is found.
TEST(LiveFuzzReadings, E100TrackMovesInAPatternOfItsOwn) {
  const auto dir = std::filesystem::path(default_profile_path()).parent_path();
  Profile model = load_profile_file((dir / "track-peaking.yaml").string()).profile.value();
  Profile device = model;
  device.readings["E-100"] = ReadingSide::kOther;
  device.az.tolerance_deg = device.el.tolerance_deg = 0.3;
  std::string notes;
  EXPECT_EQ(first_finding(model, device, 3000, notes), "");
  EXPECT_EQ(notes, "");
  model.readings["E-100"] = ReadingSide::kReference;
  EXPECT_NE(first_finding(model, device, 3000, notes), "") << "a TRACK pinned to hold still that moves";
}

INSTANTIATE_TEST_SUITE_P(Readings, LiveFuzzOneReading,
                         ::testing::Values(OneReading{"E-6", "rc3000-1.59.yaml", true},
                                           OneReading{"E-8", "rc3000-1.59.yaml", true},
                                           OneReading{"E-14", "rc3000-1.59.yaml", false},
                                           OneReading{"E-16", "rc3000-1.59.yaml", true},
                                           OneReading{"E-18", "rc3000-1.59.yaml", false},
                                           OneReading{"E-20", "rc3000-1.59.yaml", false},
                                           OneReading{"E-23", "rc3000-1.59.yaml", true},
                                           OneReading{"E-23", "dual-port-dvb-fluxgate.yaml", false, ReadingSide::kOther2},
                                           OneReading{"E-29", "rc3000-1.59.yaml", false},
                                           OneReading{"E-31", "rc3000-1.59.yaml", false},
                                           OneReading{"E-34", "rc3000-1.59.yaml", false, ReadingSide::kOther, manual_search},
                                           OneReading{"E-40", "rc3000-1.59.yaml", false},
                                           OneReading{"E-41", "rc3000-1.59.yaml", false},
                                           OneReading{"E-42", "rc3000-1.59.yaml", true, ReadingSide::kOther, azimuth_ad_error},
                                           OneReading{"E-46", "rc3000-1.59.yaml", false},
                                           OneReading{"E-52", "rc3000-1.59.yaml", true},
                                           OneReading{"E-52", "rc3000-1.59.yaml", false, ReadingSide::kOther2},
                                           OneReading{"E-30", "rc3000-1.59.yaml", true},
                                           OneReading{"E-32", "dual-port-dvb-fluxgate.yaml", false},
                                           OneReading{"E-33", "rc3000-1.59.yaml", false},
                                           OneReading{"E-45", "rc3000-1.59.yaml", false},
                                           OneReading{"E-50", "rc3000-1.59.yaml", false},
                                           OneReading{"E-56", "rc3000-1.59.yaml", false},
                                           OneReading{"E-57", "rc3000-1.59.yaml", false},
                                           OneReading{"E-58", "rc3000-1.59.yaml", false},
                                           OneReading{"E-58", "rc3000-1.59.yaml", false, ReadingSide::kOther2},
                                           OneReading{"E-60", "rc3000-1.59.yaml", false},
                                           OneReading{"E-61", "rc3000-1.59.yaml", true},
                                           OneReading{"E-64", "track-peaking.yaml", false},
                                           OneReading{"E-66", "rc3000-1.59.yaml", false},
                                           OneReading{"E-67", "rc3000-1.59.yaml", false},
                                           OneReading{"E-74", "rc3000-1.59.yaml", false},
                                           OneReading{"E-76", "rc3000-1.59.yaml", false},
                                           OneReading{"E-76", "southern-slow-mount.yaml", false, ReadingSide::kOther2},
                                           OneReading{"E-82", "rc3000-1.59.yaml", false},
                                           OneReading{"E-87", "southern-slow-mount.yaml", false},
                                           OneReading{"E-88", "rc3000-1.59.yaml", false},
                                           OneReading{"E-89", "rc3000-1.59.yaml", false},
                                           OneReading{"E-90", "rc3000-1.59.yaml", false},
                                           OneReading{"E-91", "circular-no-stow.yaml", false},
                                           OneReading{"E-92", "rc3000-1.59.yaml", true},
                                           OneReading{"E-93", "rc3000-1.59.yaml", false},
                                           OneReading{"E-94", "rc3000-1.59.yaml", false},
                                           OneReading{"E-95", "rc3000-1.59.yaml", false},
                                           OneReading{"E-96", "rc3000-1.59.yaml", false},
                                           OneReading{"E-97", "remote-disabled.yaml", false},
                                           OneReading{"E-98", "rc3000-1.59.yaml", true},
                                           OneReading{"E-99", "rc3000-1.59.yaml", false},
                                           OneReading{"E-100", "track-peaking.yaml", false},
                                           OneReading{"E-101", "az-jammed.yaml", false, ReadingSide::kOther, elevation_jammed_too}),
                         [](const auto& info) {
                           return std::string(info.param.id).replace(1, 1, "") +
                                  (info.param.side == ReadingSide::kOther2 ? "Other2" : "");
                         });

}  // namespace
}  // namespace sabus::harness::live_fuzz
