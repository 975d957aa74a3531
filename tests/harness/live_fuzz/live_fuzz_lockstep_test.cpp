// The lockstep oracle (harness/live_fuzz, Lockstep): every reply judged
// against a reference controller kept in step with the device. The "device"
// here is the in-process reference controller on its own clock, with a fault
// or its replies edited, or run a little later than the model.
#include <filesystem>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/profile_generator.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::harness::live_fuzz {
namespace {

using namespace std::chrono_literals;

// rc3000-1.59 at '2' (0x32), two satellites in its STORE list.
Profile profile() {
  Profile p;
  for (const char* name : {"SBS 6", "GALAXY 3"}) {
    StoredSatellite s;
    s.name = name;
    s.az_deg = 10;
    s.el_deg = 30;
    p.store.push_back(s);
  }
  return p;
}

FuzzFrame write(std::uint8_t code, std::string_view data = "") {
  return {encode_frame({FrameKind::kCommand, '2', code, Bytes(data.begin(), data.end())}), {}, "test"};
}

struct Sink : ReceiverSink {
  std::vector<Frame> frames;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard&) override {}
};

// A device: the reference controller (with faults) on its own virtual clock.
struct Device {
  explicit Device(FaultSet faults = {}) : t(make_in_process_transport({profile()}, faults)) {}
  explicit Device(const Profile& p, FaultSet faults = {}) : t(make_in_process_transport({p}, faults)) {}
  std::vector<Frame> send(const FuzzFrame& f, TimePoint at) {
    t->clock().set(at);
    t->bus().tick();
    t->send(f.chars, f.wrong_parity);
    Receiver rx(ReceiverOptions::master());
    Sink sink;
    std::uint8_t buf[512];
    while (t->pending() > 0) rx.feed(ByteView(buf, t->receive(buf, 0ms)), sink);
    rx.finish(sink);
    return sink.frames;
  }
  std::unique_ptr<InProcessTransport> t;
};

TimePoint at_ms(long ms) { return TimePoint{} + std::chrono::milliseconds(ms); }

// Edits the text of a reply field in place (describe_frame's offsets), the
// check byte made again.
Frame with_field(Frame reply, std::string_view field, std::string_view text) {
  Bytes bytes = encode_frame(reply);
  for (const FieldDescription& fd : describe_frame(bytes).fields)
    if (fd.name == field) {
      EXPECT_EQ(fd.last - fd.first + 1, text.size());
      std::copy(text.begin(), text.end(), bytes.begin() + static_cast<std::ptrdiff_t>(fd.first));
    }
  bytes.back() = lrc(ByteView(bytes).first(bytes.size() - 1));
  return decode_frame(bytes).value();
}

TEST(LiveFuzzLockstep, TheReferenceControllerAgreesWithItself) {
  Lockstep model(profile(), at_ms(0));
  Device device;
  long t = 0;
  for (const FuzzFrame& f : {write(0x30), write(0x31), write(0x35, "01"), write(0x40), write(0x3A, "01"), write(0x3C, "21"),
                             write(0x33, "WF2000"), write(0x31), write(0x40), write(0x33, "XS0000"), write(0x40)}) {
    t += 300;
    EXPECT_EQ(model.step(f, at_ms(t), Duration{0}, device.send(f, at_ms(t))), std::nullopt) << to_hex(f.chars);
  }
  EXPECT_GE(model.coverage().fields_compared.size(), 20u);
  EXPECT_EQ(model.coverage().rules_fired.count("TleIndex"), 1u);
}

TEST(LiveFuzzLockstep, AReplyWithOneWrongFieldIsAValueFindingNamingTheField) {
  Lockstep model(profile(), at_ms(0));
  Device device;
  const FuzzFrame query = write(0x35, "01");  // §3.6: entry 1 and how many the STORE list holds
  const std::vector<Frame> right = device.send(query, at_ms(10));
  ASSERT_EQ(right.size(), 1u);
  const Frame wrong = with_field(right[0], "total", "09");
  const auto v = model.step(query, at_ms(10), Duration{0}, {wrong});
  ASSERT_TRUE(v);
  EXPECT_EQ(v->kind, FindingKind::kValue);
  EXPECT_EQ(v->field, "total");
  EXPECT_NE(v->message.find("field 'total'"), std::string::npos) << v->message;
  EXPECT_NE(v->message.find("is \"09\"; the model expects \""), std::string::npos) << v->message;
  // The same reply unedited: no finding.
  EXPECT_EQ(model.step(query, at_ms(20), Duration{0}, device.send(query, at_ms(20))), std::nullopt);
}

TEST(LiveFuzzLockstep, AnAckWhereTheModelNaksIsANakRuleFindingNamingTheRule) {
  Lockstep model(profile(), at_ms(0));
  Device device(FaultSet{Fault::kUnimplementedAcked});
  const FuzzFrame signal = write(0x38, "@@");  // §3.9: not implemented on the RC3000 (E-16)
  const auto v = model.step(signal, at_ms(10), Duration{0}, device.send(signal, at_ms(10)));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->kind, FindingKind::kNakRule);
  EXPECT_NE(v->message.find("device ACKed"), std::string::npos) << v->message;
  EXPECT_NE(v->message.find("the model NAKs by rule NotImplemented (§3:"), std::string::npos) << v->message;
  // The reverse: a NAK where the model answers.
  const FuzzFrame read_1 = write(0x3C, "01");
  const Frame nak{FrameKind::kNak, '2', 0x3C, {}};
  const auto r = model.step(read_1, at_ms(20), Duration{0}, {nak});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, FindingKind::kNakRule);
  EXPECT_NE(r->message.find("device NAKed"), std::string::npos) << r->message;
  EXPECT_NE(r->message.find("the model answers ACK 3Ch"), std::string::npos) << r->message;
}

// A device that executes every write 300 ms after the model's time (0.6 deg
// at the azimuth's 2 deg/s): inside the window of a 400 ms timing
// uncertainty, outside that of none.
TEST(LiveFuzzLockstep, AMovingAxisInsideItsWindowIsNoFinding) {
  for (const Duration uncertainty : {Duration{400ms}, Duration{0}}) {
    SCOPED_TRACE(uncertainty.count());
    Lockstep model(profile(), at_ms(0));
    Device device;
    const FuzzFrame jog = write(0x33, "WF5000"), status = write(0x31);
    EXPECT_EQ(model.step(jog, at_ms(100), uncertainty, device.send(jog, at_ms(100))), std::nullopt);
    const auto v = model.step(status, at_ms(2100), uncertainty, device.send(status, at_ms(1800)));
    if (uncertainty > Duration{0}) {
      EXPECT_EQ(v, std::nullopt) << v->message;
    } else {
      ASSERT_TRUE(v);
      EXPECT_EQ(v->kind, FindingKind::kEffect);
      EXPECT_EQ(v->field, "azimuth");
      EXPECT_NE(v->message.find("outside the motion window"), std::string::npos) << v->message;
    }
  }
}

// A jog stopped 150 ms later on the device than in the model ends 0.3 deg
// further: at rest, within the drift window of a 200 ms uncertainty, the
// model takes the device's reading and then agrees exactly.
TEST(LiveFuzzLockstep, ATolerableDriftIsResynchronizedNotReported) {
  const Duration uncertainty = 200ms;
  Lockstep model(profile(), at_ms(0));
  Device device;
  const FuzzFrame jog = write(0x33, "WF5000"), stop = write(0x33, "XS0000"), status = write(0x31);
  EXPECT_EQ(model.step(jog, at_ms(100), uncertainty, device.send(jog, at_ms(100))), std::nullopt);
  EXPECT_EQ(model.step(stop, at_ms(1100), uncertainty, device.send(stop, at_ms(1250))), std::nullopt);
  const std::vector<Frame> first = device.send(status, at_ms(3000));
  EXPECT_EQ(model.step(status, at_ms(3000), uncertainty, first), std::nullopt);
  EXPECT_EQ(model.coverage().resyncs, 1u);
  const auto az = [](const Frame& f) { return describe_frame(encode_frame(f)).fields.at(5).raw; };
  EXPECT_EQ(az(first.at(0)), "\"   2.3\"");
  EXPECT_EQ(model.model().status_block().azimuth.tenths, 23);
  // In step again: the next poll agrees, nothing more to resynchronize.
  EXPECT_EQ(model.step(status, at_ms(3500), uncertainty, device.send(status, at_ms(3500))), std::nullopt);
  EXPECT_EQ(model.coverage().resyncs, 1u);
  // Beyond the window (a stop that did not stop for 2 s more) it is a finding.
  Lockstep strict(profile(), at_ms(0));
  Device late;
  EXPECT_EQ(strict.step(jog, at_ms(100), uncertainty, late.send(jog, at_ms(100))), std::nullopt);
  // The reply to the stop already shows the azimuth 4 deg further.
  const auto v = strict.step(stop, at_ms(1100), uncertainty, late.send(stop, at_ms(3100)));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->kind, FindingKind::kEffect);
  EXPECT_EQ(v->field, "azimuth");
}

TEST(LiveFuzzLockstep, AStopThatDoesNotStopIsAnEffectFinding) {
  Lockstep model(profile(), at_ms(0));
  Device device(FaultSet{Fault::kJogIgnoresDuration});
  const FuzzFrame jog = write(0x33, "WF1000"), status = write(0x31);
  EXPECT_EQ(model.step(jog, at_ms(100), Duration{0}, device.send(jog, at_ms(100))), std::nullopt);
  const auto v = model.step(status, at_ms(3000), Duration{0}, device.send(status, at_ms(3000)));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->kind, FindingKind::kEffect);
  EXPECT_NE(v->message.find("the model expects"), std::string::npos) << v->message;
}

// On a line (a timing uncertainty), a jog seen moving a few milliseconds
// after it started is what the model says too.
TEST(LiveFuzzLockstep, AJogJustStartedOnALineIsNoFinding) {
  const Duration uncertainty = 163ms;
  Lockstep model(profile(), at_ms(1000));
  Device device;
  const FuzzFrame poll = write(0x31), jog = write(0x33, "OS0001");
  EXPECT_EQ(model.step(poll, at_ms(1100), uncertainty, device.send(poll, at_ms(1100))), std::nullopt);
  EXPECT_EQ(model.step(jog, at_ms(1200), uncertainty, device.send(jog, at_ms(1200))), std::nullopt);
  const auto v = model.step(poll, at_ms(1204), uncertainty, device.send(poll, at_ms(1204)));
  EXPECT_EQ(v, std::nullopt) << v->message;
}

// §3.7 'A' (ERRATA E-90): how a search moves is the controller's. A device
// whose spiral takes other steps than the model's is no finding; its stop
// still has to stop, and after it both are compared again.
TEST(LiveFuzzLockstep, ASearchOtherThanTheModelsIsNoFindingButItsStopIs) {
  Profile wide = profile();
  wide.az.tolerance_deg = wide.el.tolerance_deg = 2.5;  // the reference's legs: 5 deg, not 1
  const FuzzFrame search = write(0x36, "AE"), status = write(0x31), extended = write(0x40), stop = write(0x36, "KA");
  for (const bool stop_ignored : {false, true}) {
    SCOPED_TRACE(stop_ignored ? "the device's search ignores the stop" : "the device's search stops");
    Lockstep model(profile(), at_ms(0));
    Device device(wide, stop_ignored ? FaultSet{Fault::kSearchIgnoresStop} : FaultSet{});
    auto step = [&](const FuzzFrame& f, long ms) { return model.step(f, at_ms(ms), Duration{0}, device.send(f, at_ms(ms))); };
    std::optional<Verdict> v = step(search, 100);
    for (long ms = 1100; ms < 4000 && !v; ms += 1000) {
      v = step(status, ms);
      if (!v) v = step(extended, ms + 50);
    }
    EXPECT_EQ(v, std::nullopt) << v->message;
    if (!v) v = step(stop, 4000);
    if (!v) v = step(status, 6000);
    if (!stop_ignored) {
      EXPECT_EQ(v, std::nullopt) << v->message;
      if (!v) v = step(extended, 6100);
      EXPECT_EQ(v, std::nullopt) << v->message;
      // Out of the search and at rest: judged as before, positions included.
      if (!v) v = step(write(0x33, "WF1000"), 7000);
      if (!v) v = step(status, 7500);
      EXPECT_EQ(v, std::nullopt) << v->message;
    } else {
      for (const auto& n : model.notes()) ADD_FAILURE() << "noted " << n.errata << ": " << n.example;
      ASSERT_TRUE(v);
      EXPECT_EQ(v->kind, FindingKind::kEffect) << v->message;
    }
  }
}

// After a stop out of a search, an axis's speed bit (§3.2 bytes 36-38, 0x10)
// is that of the last leg the device ran, which the spec leaves to it
// (E-90): not judged, and taken into the model when the episode ends; the
// bits of whether it moves still are.
TEST(LiveFuzzLockstep, AfterASearchTheSpeedBitIsTheDevicesButNotWhetherItMoves) {
  const FuzzFrame search = write(0x36, "AE"), status = write(0x31), extended = write(0x40), stop = write(0x36, "KA");
  auto flipped = [](Frame reply, std::uint8_t bits) {
    for (const FieldDescription& fd : describe_frame(encode_frame(reply)).fields)
      if (fd.name == "el status") {
        const auto raw = static_cast<char>(encode_frame(reply)[fd.first] ^ bits);
        return with_field(std::move(reply), "el status", std::string(1, raw));
      }
    return reply;
  };
  for (const std::uint8_t bits : {std::uint8_t{0x10}, std::uint8_t{0x04}}) {
    SCOPED_TRACE(bits == 0x10 ? "speed bit" : "moving bit");
    Lockstep model(profile(), at_ms(0));
    Device device(profile());
    auto step = [&](const FuzzFrame& f, long ms, bool edit) {
      std::vector<Frame> replies = device.send(f, at_ms(ms));
      if (edit)
        for (Frame& r : replies) r = flipped(std::move(r), bits);
      return model.step(f, at_ms(ms), Duration{0}, replies);
    };
    ASSERT_EQ(step(search, 100, false), std::nullopt);
    ASSERT_EQ(step(status, 1100, false), std::nullopt);
    ASSERT_EQ(step(stop, 2000, false), std::nullopt);
    const std::optional<Verdict> v = step(status, 4000, true);
    if (bits == 0x04) {
      ASSERT_TRUE(v);
      EXPECT_EQ(v->field, "el status") << v->message;
      continue;
    }
    EXPECT_EQ(v, std::nullopt) << v->message;
    const std::optional<Verdict> x = step(extended, 4100, true);  // at rest: the episode ends
    EXPECT_EQ(x, std::nullopt) << x->message;
    const std::optional<Verdict> after = step(status, 4200, true);  // the model has the device's speed
    EXPECT_EQ(after, std::nullopt) << after->message;
  }
}

// fast-mount-manual-nav (a site at 40 N 100 W, mount azimuth 0 at heading
// 90), a 41h LOCATE of a satellite at 81.5 W that its axes reach within a
// second, and the extended status poll.
struct LocateFromASite {
  Profile p = [] {
    const ProfileResult loaded = load_profile_file(
        (std::filesystem::path(default_profile_path()).parent_path() / "fast-mount-manual-nav.yaml").string());
    EXPECT_TRUE(loaded);
    return loaded ? *loaded.profile : Profile{};
  }();
  FuzzFrame locate{encode_request(build_request(*find_command(0x41), "data",
                                                {{"sat name", "FUZZ LOC"}, {"longitude", "-81.5"}, {"inclination", "0"},
                                                 {"band", "1"}, {"pol offset", "0.0"}, {"receive polarization", "N"},
                                                 {"position update", "A"}})
                                      .value(),
                                  p.address),
                   {}, "test"};
  FuzzFrame extended{encode_frame({FrameKind::kCommand, p.address, 0x40, {}}), {}, "test"};
};

// A LOCATE the device computes from the wrong hemisphere of its site's
// longitude (§3.22, §3.23) ends at once in an elevation range error where
// the model's moves: on a line that is a finding by the next reply (the
// extended status the arrival asks as its move begins).
TEST(LiveFuzzLockstep, OnALineALocateTheDeviceDoesNotRunIsAFinding) {
  const LocateFromASite l;
  Lockstep model(l.p, at_ms(0));
  Device device(l.p, FaultSet{Fault::kLocateEasternLongitude});
  ASSERT_EQ(model.step(l.locate, at_ms(600), 5ms, device.send(l.locate, at_ms(600))), std::nullopt);
  const auto v = model.step(l.extended, at_ms(604), 5ms, device.send(l.extended, at_ms(604)));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->kind, FindingKind::kEffect) << v->message;
}

// A device whose mode code names a STOW, a DEPLOY or a search where the model
// has not been in one is judged, not followed (E-89, E-90): here every mode
// code one too high (the mode taken from the device at the start, as a
// session on a bench does), a moving LOCATE shows as 0x26, the spiral
// search's code (a LOCATE without a site would wait for one at rest, E-59,
// and be judged as a held mode).
TEST(LiveFuzzLockstep, AModeCodeNamingASearchTheModelWasNotInIsJudged) {
  const LocateFromASite l;
  Lockstep model(l.p, at_ms(0));
  Device device(l.p, FaultSet{Fault::kModeEnumOffByOne});
  model.adopt(l.extended, at_ms(10), device.send(l.extended, at_ms(10)));
  ASSERT_EQ(model.step(l.locate, at_ms(100), 0ms, device.send(l.locate, at_ms(100))), std::nullopt);
  ASSERT_TRUE(moves_by_itself(0x26));
  const auto v = model.step(l.extended, at_ms(200), 0ms, device.send(l.extended, at_ms(200)));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->field, "current mode") << v->message;
}

// The whole session in-process, motion and stored writes allowed, on random
// legal profiles (the sweep's generator): the lockstep oracle never fires on
// the reference controller, and it compares fields and meets NAK rules.
TEST(LiveFuzzLockstep, RandomLegalProfilesGiveNoFinding) {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u, 5u, 6u}) {
    const Profile p = random_profile(seed);
    SCOPED_TRACE(p.name);
    auto device = make_in_process_transport({p});
    SessionOptions o;
    o.allow_motion = o.allow_destructive = true;
    Session session(*device, p, o);
    GeneratorOptions go{p.address, true, true, true, {}, {}, &p};
    for (const StoredSatellite& s : p.store) go.names.push_back(s.name);
    Generator generator(go, seed);
    const Lockstep* l = session.lockstep();
    generator.set_rules_fired(&l->coverage().rules_fired);
    generator.set_model([l] { return Generator::ModelView{&l->model(), l->now(), l->device_led()}; });
    for (int i = 0; i < 3000; ++i) {
      FuzzFrame f = generator.next();
      // As sabus fuzz does: a write the device must ignore is followed by a
      // status poll, which also closes a frame it left open.
      for (int k = 0; k < 2 && session.would_be_ignored(f); ++k) {
        const Bytes poll = encode_frame({FrameKind::kCommand, p.address, 0x31, {}});
        f.chars.insert(f.chars.end(), poll.begin(), poll.end());
      }
      const auto v = session.step(f);
      ASSERT_FALSE(v) << "write " << i << " (" << f.what << ", " << to_hex(f.chars) << "): " << to_string(v->kind) << ": "
                      << v->message;
      if (i % 50 == 49) {
        const auto p = session.probe();
        ASSERT_FALSE(p) << "probe after write " << i << ": " << to_string(p->kind) << ": " << p->message;
      }
    }
    EXPECT_GE(session.lockstep()->coverage().rules_fired.size(), 10u);
    EXPECT_GE(session.lockstep()->coverage().fields_compared.size(), 60u);
  }
}

// A session over the in-process reference controller, motion allowed, and
// a generator that follows its lockstep model, as sabus fuzz --sim sets
// them up.
struct ModelledSession {
  ModelledSession(const Profile& profile, std::uint64_t seed)
      : p(profile), device(make_in_process_transport({p})), session(*device, p, motion_allowed()),
        generator(GeneratorOptions{p.address, true, false, true, {}, {}, &p}, seed), l(session.lockstep()) {
    generator.set_model([this] { return Generator::ModelView{&l->model(), l->now(), l->device_led()}; });
  }
  static SessionOptions motion_allowed() {
    SessionOptions o;
    o.allow_motion = true;
    return o;
  }
  // As sabus fuzz does: a write the device must ignore is followed by a
  // status poll.
  std::optional<Verdict> step(FuzzFrame f) {
    for (int k = 0; k < 2 && session.would_be_ignored(f); ++k) {
      const Bytes poll = encode_frame({FrameKind::kCommand, p.address, 0x31, {}});
      f.chars.insert(f.chars.end(), poll.begin(), poll.end());
    }
    return session.step(f);
  }
  Profile p;
  std::unique_ptr<InProcessTransport> device;
  Session session;
  Generator generator;
  const Lockstep* l;
};

// An arrival sequence (Generator::arrival): a move, then writes that cannot
// move anything while the model moves, then, once it rests, status and
// extended status; the reference device agrees all along.
TEST(LiveFuzzLockstep, AnArrivalWaitsForTheModelToRestThenAsksWhereItIs) {
  ModelledSession m(profile(), 3);
  const Profile& p = m.p;
  const Lockstep* l = m.l;
  auto at_rest = [&] {
    const ControllerState& s = l->model().state();
    return s.az.motion == AxisState::Motion::kIdle && s.el.motion == AxisState::Motion::kIdle &&
           s.pol.motion == AxisState::Motion::kIdle;
  };
  std::size_t arrivals = 0, moved = 0;
  bool arriving = false;
  double az0 = 0, el0 = 0, pol0 = 0;
  TimePoint start{};
  std::string last;
  for (int i = 0; i < 60000 && arrivals < 4; ++i) {
    FuzzFrame f = m.generator.next();
    if (f.what.starts_with("sequence: arrival")) {
      arriving = true;
      start = l->now();
      az0 = l->model().state().az.position;
      el0 = l->model().state().el.position;
      pol0 = l->model().state().pol.position;
    } else if (f.what == "status after the arrival") {
      ASSERT_TRUE(arriving) << "status after an arrival that did not begin";
      // At rest, or given up after the generator's 30 s.
      EXPECT_TRUE(at_rest() || l->now() - start >= 30s) << "the arrival ended early with the model moving";
      arriving = false;
      ++arrivals;
      const ControllerState& s = l->model().state();
      if (std::abs(s.az.position - az0) > 0.05 || std::abs(s.el.position - el0) > 0.05 || std::abs(s.pol.position - pol0) > 0.05)
        ++moved;
      EXPECT_GE(s.az.position, p.az.min_deg);
      EXPECT_LE(s.az.position, p.az.max_deg);
    } else if (arriving) {
      EXPECT_TRUE(is_safe_to_send(f.chars, false, false)) << "a write that can move while arriving: " << f.what;
    }
    if (last == "status after the arrival") {
      EXPECT_EQ(f.what, "extended status after the arrival");
    }
    last = f.what;
    const auto v = m.step(f);
    ASSERT_FALSE(v) << "write " << i << " (" << f.what << "): " << v->message;
  }
  EXPECT_EQ(arrivals, 4u);
  EXPECT_GE(moved, 2u);
}

// On a line the hundredths digit is judged once an auto move has arrived:
// the reading it extends lies within the target's arrival window
// (tolerance_deg less the display's 0.1, plus 0.01: ERRATA E-86).
TEST(LiveFuzzLockstep, OnALineTheHundredthsOfAnArrivalLieInItsWindow) {
  Profile p = profile();
  p.hundredths = true;
  p.el.tolerance_deg = 0.1;
  const auto request = build_request(*find_command(0x32), "2C", {{"axis", "E"}, {"target", "12.37"}});
  ASSERT_TRUE(request);
  const FuzzFrame move{encode_request(request.value(), '2'), {}, "test"}, status = write(0x31), extended = write(0x40);
  const Duration line = 50ms;
  struct Case {
    const char* name;
    FaultSet faults;
    const char* digit;  // the device's el hundredths edited to this; null: as it is
    bool finding;
  };
  for (const Case& c : {Case{"clean", {}, nullptr, false}, Case{"hundredths-always-zero", FaultSet{Fault::kHundredthsAlwaysZero}, nullptr, true},
                        Case{"stopped 0.01 past", {}, "8", false}, Case{"stopped 0.02 past", {}, "9", true}}) {
    SCOPED_TRACE(c.name);
    Lockstep model(p, at_ms(0));
    Device device(p, c.faults);
    ASSERT_EQ(model.step(move, at_ms(100), line, device.send(move, at_ms(100))), std::nullopt);
    // From the power-on 45 deg: arrived within a minute.
    ASSERT_EQ(model.step(status, at_ms(60000), line, device.send(status, at_ms(60000))), std::nullopt);
    std::vector<Frame> reply = device.send(extended, at_ms(60100));
    ASSERT_EQ(reply.size(), 1u);
    if (c.digit) reply[0] = with_field(reply[0], "el hundredths", c.digit);
    const auto v = model.step(extended, at_ms(60100), line, reply);
    ASSERT_EQ(v.has_value(), c.finding) << (v ? v->message : "no finding");
    if (v) {
      EXPECT_EQ(v->kind, FindingKind::kEffect);
      EXPECT_EQ(v->field, "el hundredths");
      EXPECT_NE(v->message.find("arrived at 12.37"), std::string::npos) << v->message;
    }
  }
}

// A profile whose azimuth ends at -20 deg, the 32h move there, a status poll
// and a jog further into the limit (§3.4).
struct AzimuthLimit {
  Profile p = [] {
    Profile p = profile();
    p.az.min_deg = -20;
    return p;
  }();
  FuzzFrame move{encode_request(build_request(*find_command(0x32), "2A", {{"azimuth", "-20.0"}, {"elevation", "45.0"}}).value(), '2'),
                 {}, "test"};
  FuzzFrame status = write(0x31), into = write(0x33, "ES0500");
};

// §3.4, §3.2 bytes 32-34 on a line: a device at rest whose status asserts a
// limit, or that refuses a jog into it where a run a hair off it takes the
// jog, has said its axis is there: the model's axis stands exactly at the
// limit, and a clean device gives no finding.
TEST(LiveFuzzLockstep, OnALineADeviceAtALimitPutsTheModelExactlyThere) {
  const AzimuthLimit l;
  const Profile& p = l.p;
  const FuzzFrame &move = l.move, &status = l.status, &into = l.into;
  Lockstep model(p, at_ms(0));
  Device device(p);
  auto step = [&](const FuzzFrame& f, long ms) { return model.step(f, at_ms(ms), 50ms, device.send(f, at_ms(ms))); };
  ASSERT_EQ(step(move, 100), std::nullopt);
  model.model().mutable_state().az.position = -19.97;  // the model a hair off, as a nudged run kept leaves it
  ASSERT_EQ(step(status, 60000), std::nullopt);  // at rest, the limit asserted
  EXPECT_EQ(model.model().state().az.position, -20.0);
  ASSERT_EQ(step(into, 60100), std::nullopt);    // NAKed by both (JogIntoLimit)
  EXPECT_EQ(model.coverage().rules_fired.count("JogIntoLimit"), 1u);
  EXPECT_EQ(step(status, 60200), std::nullopt);
  EXPECT_EQ(model.model().state().az.position, -20.0);
}

// On a line an axis the device has said is at a limit (its status at rest
// asserts it, or it refused a jog into it) stands exactly there in every run
// of a write of one frame: a jog into it must be NAKed (§3.4), and its limit
// bits must show it (§3.2 bytes 32-34). Runs nudged a hair off would take
// either fault for a device standing a hair off.
TEST(LiveFuzzLockstep, OnALineTheLimitFaultsAreFoundAtALimitTheDeviceHasNamed) {
  const AzimuthLimit l;
  const Profile& p = l.p;
  const FuzzFrame &move = l.move, &status = l.status, &into = l.into;
  for (const Fault fault : {Fault::kJogIntoLimitAcked, Fault::kAzLimitBitsMissing}) {
    SCOPED_TRACE(fault == Fault::kJogIntoLimitAcked ? "jog-into-limit-acked" : "az-limit-bits-missing");
    Lockstep model(p, at_ms(0));
    Device device(p, FaultSet{fault});
    auto step = [&](const FuzzFrame& f, long ms) { return model.step(f, at_ms(ms), 50ms, device.send(f, at_ms(ms))); };
    ASSERT_EQ(step(move, 100), std::nullopt);
    // Both faults pass here: at rest the status's limit bits are judged
    // only where the device has said where the axis is.
    ASSERT_EQ(step(status, 60000), std::nullopt);
    std::optional<Verdict> v = step(into, 60100);
    if (fault == Fault::kJogIntoLimitAcked) {
      ASSERT_TRUE(v);
      EXPECT_EQ(v->kind, FindingKind::kNakRule) << v->message;
      EXPECT_NE(v->message.find("JogIntoLimit"), std::string::npos) << v->message;
    } else {
      ASSERT_EQ(v, std::nullopt) << v->message;  // NAKed by both: the device's word
      v = step(status, 60200);
      ASSERT_TRUE(v);
      EXPECT_EQ(v->field, "az limits") << v->message;
    }
  }
}

// A 0 ms jog away from a limit may take a device's axis a step off it (a
// device executes it at once; the model's jog is still pending when the next
// write comes), and a jog back into the limit is then ACKed: a run of the
// model with that axis nudged off the limit agrees (§3.4). A sweep profile
// over a pty gave a JogIntoLimit finding for this.
TEST(LiveFuzzLockstep, OnALineAZeroJogOffALimitThenAJogBackIntoItIsNoFinding) {
  Profile p = profile();
  p.az.max_deg = 20;
  const auto request = build_request(*find_command(0x32), "2A", {{"azimuth", "20.0"}, {"elevation", "45.0"}});
  ASSERT_TRUE(request);
  const FuzzFrame move{encode_request(request.value(), '2'), {}, "test"}, status = write(0x31),
      away = write(0x33, "ES0000"), back = write(0x47, "WS0000");
  Lockstep model(p, at_ms(0));
  Device device(p);
  auto step = [&](const FuzzFrame& f, long ms) { return model.step(f, at_ms(ms), 20ms, device.send(f, at_ms(ms))); };
  ASSERT_EQ(step(move, 100), std::nullopt);
  ASSERT_EQ(step(status, 60000), std::nullopt);  // at rest at the limit
  ASSERT_EQ(step(away, 60100), std::nullopt);
  device.t->bus().controller(0).mutable_state().az.position = 19.999;  // the device's jog took a step
  const auto v = step(back, 60125);
  EXPECT_EQ(v, std::nullopt) << v->message;
}

// On a line a jog that reaches a limit within the timing's window may have
// ended there in the device while the model still moves: its motion bits
// are not judged then (a clean device executed it a few milliseconds
// earlier), and its positions still are.
TEST(LiveFuzzLockstep, OnALineAJogEndingAtALimitWithinTheWindowIsNoFinding) {
  Profile p = profile();
  p.el.min_deg = 0;
  p.el.fast_dps = 6;
  const auto request = build_request(*find_command(0x32), "2A", {{"azimuth", "0.0"}, {"elevation", "0.3"}});
  ASSERT_TRUE(request);
  const FuzzFrame move{encode_request(request.value(), '2'), {}, "test"}, status = write(0x31), down = write(0x33, "DF2000");
  Lockstep model(p, at_ms(0));
  Device device(p);
  ASSERT_EQ(model.step(move, at_ms(100), 20ms, device.send(move, at_ms(100))), std::nullopt);
  ASSERT_EQ(model.step(status, at_ms(20000), 20ms, device.send(status, at_ms(20000))), std::nullopt);
  // The device jogs 20 ms before the model's time for it (1 ms either
  // side): at 0.0 and at rest 53 ms later, when every run of the model
  // (nudged 0.08 deg down too) still moves, the nominal one 0.1 deg short
  // of the limit (inside the window).
  ASSERT_EQ(model.step(down, at_ms(20100), 1ms, device.send(down, at_ms(20080))), std::nullopt);
  const auto v = model.step(status, at_ms(20133), 1ms, device.send(status, at_ms(20133)));
  EXPECT_EQ(v, std::nullopt) << v->message;
  EXPECT_NE(model.model().state().el.motion, AxisState::Motion::kIdle);
}

// On a line the model's state after a burst is the one after its last
// frame: the motion bits of an earlier frame's reply are not judged by it.
// Here the device stands exactly on a 32h target the model's azimuth misses
// by 0.02 deg (a jog stopped 10 ms apart), and a 0 ms jog follows the move
// in the same write.
TEST(LiveFuzzLockstep, OnALineTheMotionBitsOfABurstsEarlierReplyAreNotJudgedByItsEnd) {
  const Profile p = profile();
  const auto request = build_request(*find_command(0x32), "2A", {{"azimuth", "0.1"}, {"elevation", "45.0"}});
  ASSERT_TRUE(request);
  FuzzFrame burst{encode_request(request.value(), '2'), {}, "test"};
  const Bytes jog = write(0x47, "WS0000").chars;
  burst.chars.insert(burst.chars.end(), jog.begin(), jog.end());
  const FuzzFrame jog_cw = write(0x33, "WF2000"), stop = write(0x33, "XS0000"), status = write(0x31);
  Lockstep model(p, at_ms(0));
  Device device(p);
  // The model jogs 60 ms (0.12 deg at 2 deg/s), the device 50 ms (0.10).
  ASSERT_EQ(model.step(jog_cw, at_ms(100), 20ms, device.send(jog_cw, at_ms(110))), std::nullopt);
  ASSERT_EQ(model.step(stop, at_ms(160), 20ms, device.send(stop, at_ms(160))), std::nullopt);
  ASSERT_EQ(model.step(status, at_ms(1000), 20ms, device.send(status, at_ms(1000))), std::nullopt);
  ASSERT_GT(std::abs(model.model().state().az.position - 0.1), 0.015);
  const auto v = model.step(burst, at_ms(2000), 20ms, device.send(burst, at_ms(2000)));
  EXPECT_EQ(v, std::nullopt) << v->message;
}

// Within a STOW episode the mode bytes are the device's, but not the mode a
// later command entered and holds at rest: a LOCATE without a site waits for
// one (E-59), and a device that says it completed is a finding.
TEST(LiveFuzzLockstep, AModeACommandHoldsAtRestIsJudgedInsideAStowEpisode) {
  const Profile p = profile();
  const auto request = build_request(*find_command(0x41), "data",
                                     {{"sat name", "FUZZ LOC"}, {"longitude", "10.0"}, {"inclination", "0"}, {"band", "1"},
                                      {"pol offset", "0.0"}, {"receive polarization", "N"}, {"position update", "A"}});
  ASSERT_TRUE(request);
  const FuzzFrame stow = write(0x36, "SS"), locate{encode_request(request.value(), '2'), {}, "test"}, extended = write(0x40);
  for (const bool faulty : {false, true}) {
    SCOPED_TRACE(faulty ? "locate-without-site-completes" : "clean");
    Lockstep model(p, at_ms(0));
    Device device(p, faulty ? FaultSet{Fault::kLocateWithoutSiteCompletes} : FaultSet{});
    auto step = [&](const FuzzFrame& f, long ms) { return model.step(f, at_ms(ms), 20ms, device.send(f, at_ms(ms))); };
    ASSERT_EQ(step(stow, 100), std::nullopt);
    ASSERT_EQ(step(extended, 600), std::nullopt);  // STOW moving: the device's
    ASSERT_EQ(step(locate, 1000), std::nullopt);
    const auto v = step(extended, 120000);
    ASSERT_EQ(v.has_value(), faulty) << (v ? v->message : "no finding");
    if (v) {
      EXPECT_EQ(v->field, "current mode") << v->message;
    }
  }
}

// Motion sequences go to the (motion, stop) pair and arrivals to the aim
// least covered so far: in the first three rounds every pair and every aim
// the profile allows has been drawn, and the reference device agrees.
TEST(LiveFuzzLockstep, MotionsAndArrivalsGoToWhatIsLeastCovered) {
  ModelledSession m(profile(), 11);
  const Profile& p = m.p;
  std::map<std::string, int> motions, arrivals;
  std::size_t motion_count = 0, arrival_count = 0;
  for (int i = 0; i < 200000 && (motion_count < 3 * 21 || arrival_count < 3 * 6); ++i) {
    FuzzFrame f = m.generator.next();
    if (f.what.starts_with("sequence: motion (")) ++motions[f.what], ++motion_count;
    if (f.what.starts_with("sequence: arrival (")) {
      // From rest, out of a STOW, DEPLOY or search (which a damaged frame
      // may have begun): a stop goes first.
      for (const AxisState* ax : {&m.l->model().state().az, &m.l->model().state().el, &m.l->model().state().pol})
        EXPECT_EQ(ax->motion, AxisState::Motion::kIdle) << f.what;
      EXPECT_FALSE(moves_by_itself(m.l->model().state().mode.mode)) << f.what;
      if (arrival_count == 0) {
        EXPECT_EQ(f.what, "sequence: arrival (LOCATE)");  // the most rules, first
      }
      ++arrivals[f.what], ++arrival_count;
    }
    const auto v = m.step(f);
    ASSERT_FALSE(v) << "write " << i << " (" << f.what << "): " << v->message;
  }
  ASSERT_GE(motion_count, 3u * 21);
  for (const char* kind : {"legal move", "jog", "search", "STOW", "DEPLOY", "LOCATE", "any motion frame"})
    for (const char* stop : {"33h X", "36h K A", "48h A"})
      EXPECT_GE(motions[std::string("sequence: motion (") + kind + ", stopped by " + stop + ")"], 1) << kind << ", " << stop;
  // 2C needs the hundredths (§3.3), a polarization limit a rotating feed.
  const std::map<std::string, bool> aims = {{"azimuth limit", true},        {"elevation limit", true},
                                            {"polarization limit", p.pol_type != PolType::kCircular},
                                            {"negative target", true},      {"2C hundredths", p.hundredths},
                                            {"LOCATE", true}};
  for (const auto& [aim, available] : aims) {
    const int drawn = arrivals[std::string("sequence: arrival (") + aim + ")"];
    if (available) EXPECT_GE(drawn, 2) << aim;
    else EXPECT_EQ(drawn, 0) << aim;
  }
}

// A read of a stored list goes to any index the list has, or one past its
// end (§3.6, §3.11, §3.13, §3.21): an entry in the middle as often as the
// ends (a fault that answers the next entry only between the ends was
// missed in a minute when reads went to the boundary indexes).
TEST(LiveFuzzLockstep, ReadsOfStoredListsReachEveryIndex) {
  ModelledSession m(profile(), 5);
  std::map<std::uint8_t, std::set<std::string>> indexes;
  for (int i = 0; i < 100000 && indexes[0x35].size() + indexes[0x3A].size() < 3 + 21; ++i) {
    const FuzzFrame f = m.generator.next();
    if (f.what == "sequence: read of a stored list") {
      const Frame read = decode_frame(f.chars).value();
      indexes[read.command].insert(std::string(read.data.begin(), read.data.end()));
    }
    const auto v = m.step(f);
    ASSERT_FALSE(v) << "write " << i << " (" << f.what << "): " << v->message;
  }
  EXPECT_EQ(indexes[0x35], (std::set<std::string>{"01", "02", "03"}));  // two STORE entries, and one past
  EXPECT_EQ(indexes[0x3A].size(), 21u);                                // 20 preset slots, and one past
  EXPECT_FALSE(indexes[0x3C].empty());
  EXPECT_FALSE(indexes[0x44].empty());
}

// §3.7 'D' stopped (ERRATA E-90): how a DEPLOY ends is the device's, but a
// stop that finds it moving ends it by a stop: DEPLOY_FINISHED_NORMALLY after
// it is a value finding naming the exit status.
TEST(LiveFuzzLockstep, AStopThatFindsTheDeviceMovingEndsItsModeByAStop) {
  Profile p = profile();
  p.el.deploy_deg = 10.0;  // 35 s from the power-on 45 at 1 deg/s
  const FuzzFrame deploy = write(0x36, "DD"), status = write(0x31), extended = write(0x40), stop = write(0x36, "KA");
  for (const bool faulty : {false, true}) {
    SCOPED_TRACE(faulty ? "deploy-stop-exit-finished" : "no fault");
    Lockstep model(p, at_ms(0));
    Device device(p, faulty ? FaultSet{Fault::kDeployStopExitFinished} : FaultSet{});
    auto step = [&](const FuzzFrame& f, long ms) { return model.step(f, at_ms(ms), Duration{0}, device.send(f, at_ms(ms))); };
    // The stop goes out behind a status in one write (the generator's
    // "status and stop"): that status shows what the stop found.
    FuzzFrame status_and_stop = status;
    status_and_stop.chars.insert(status_and_stop.chars.end(), stop.chars.begin(), stop.chars.end());
    std::optional<Verdict> v = step(deploy, 100);
    if (!v) v = step(status, 1100);           // moving
    if (!v) v = step(status_and_stop, 1200);  // still moving when stopped
    if (!v) v = step(status, 3000);
    if (!v) v = step(extended, 3100);
    if (faulty) {
      ASSERT_TRUE(v);
      EXPECT_EQ(v->kind, FindingKind::kValue);
      EXPECT_EQ(v->field, "exit status");
      EXPECT_NE(v->message.find("DEPLOY_FINISHED_NORMALLY"), std::string::npos) << v->message;
    } else {
      EXPECT_EQ(v, std::nullopt) << v->message;
    }
  }
}

// §3.16 on a line: a count is a position, judged in the axis's window once
// the axis has moved (its exact value rests on timing): counts that stay at
// the power-on position are an effect, a clean device's none.
TEST(LiveFuzzLockstep, ACountOnALineIsAPositionInItsWindow) {
  Profile p = profile();
  p.az_sensor = AzSensor::kPulse;
  const FuzzFrame move = write(0x32, " 0010000450"), counts = write(0x3F), status = write(0x31);
  for (const bool stale : {false, true}) {
    SCOPED_TRACE(stale ? "pulse-count-stale" : "no fault");
    Lockstep model(p, at_ms(0));
    Device device(p, stale ? FaultSet{Fault::kPulseCountStale} : FaultSet{});
    // The device executes 3 ms after the nominal time, within the uncertainty.
    auto step = [&](const FuzzFrame& f, long ms) {
      return model.step(f, at_ms(ms), 10ms, device.send(f, at_ms(ms + 3)));
    };
    std::optional<Verdict> v = step(move, 100);  // azimuth to 10.0 at 2 deg/s
    for (long ms = 1000; ms <= 7000 && !v; ms += 1000) v = step(status, ms);
    if (!v) v = step(counts, 7500);
    if (stale) {
      ASSERT_TRUE(v);
      EXPECT_EQ(v->kind, FindingKind::kEffect);
      EXPECT_EQ(v->field, "azimuth count") << v->message;
    } else {
      EXPECT_EQ(v, std::nullopt) << v->message;
    }
  }
}

}  // namespace
}  // namespace sabus::harness::live_fuzz
