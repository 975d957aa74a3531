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
#include "sabus/protocol/codec.hpp"

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

// A LOCATE whose first movement is the elevation's (E-94's other side),
// asked for its extended status at once: a note, not an effect finding.
TEST(LiveFuzzReadings, ALocateThatMovesElevationFirstIsANote) {
  const Profile model = default_profile();
  Profile device = model;
  device.readings["E-94"] = ReadingSide::kOther;
  auto t = make_in_process_transport({device}, {});
  SessionOptions o;
  o.allow_motion = o.allow_destructive = true;
  Session s(*t, model, o);
  for (std::string_view hex : {"02 32 47 44 53 30 30 30 30 03 63", "02 32 33 58 53 30 30 30 30 03 0b",
                               "02 32 41 40 30 46 55 5a 5a 20 4c 4f 43 20 20 2d 39 33 2e 35 20 30 20 31 30 2e 30 20 20 4e 41 20 20 20 20 03 6d",
                               "02 32 40 03 73"}) {
    const auto v = s.step(raw(hex));
    EXPECT_FALSE(v) << hex << ": " << v->message;
  }
  EXPECT_EQ(noted(s), "E-94:other");
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

// Each switchable reading on its own (sabus sim --reading E-NN=other), on a
// profile where it shows (a circular feed for E-91, remote control disabled
// for E-97): 3,000 writes with motion and stored writes give no finding,
// and the entries the generator reaches within them are noted.
struct OneReading {
  const char* id;
  const char* profile;  // a shipped profile's file name
  bool noted;           // reached and noted within the writes (seed 1)
};
class LiveFuzzOneReading : public ::testing::TestWithParam<OneReading> {};

TEST_P(LiveFuzzOneReading, IsNotedNeverFound) {
  const OneReading c = GetParam();
  const auto dir = std::filesystem::path(default_profile_path()).parent_path();
  const Profile model = load_profile_file((dir / c.profile).string()).profile.value();
  Profile device = model;
  device.readings[c.id] = ReadingSide::kOther;
  auto t = make_in_process_transport({device}, {});
  SessionOptions o;
  o.allow_motion = o.allow_destructive = true;
  Session session(*t, model, o);
  GeneratorOptions go{model.address, true, true, true, {}, {}, &model};
  for (const StoredSatellite& st : model.store) go.names.push_back(st.name);
  Generator generator(go, 1);
  const Lockstep* l = session.lockstep();
  generator.set_rules_fired(&l->coverage().rules_fired);
  generator.set_model([l] { return Generator::ModelView{&l->model(), l->now()}; });
  for (int i = 0; i < 3000; ++i) {
    FuzzFrame f = generator.next();
    for (int k = 0; k < 2 && session.would_be_ignored(f); ++k) {
      const Bytes poll = encode_frame({FrameKind::kCommand, model.address, 0x31, {}});
      f.chars.insert(f.chars.end(), poll.begin(), poll.end());
    }
    const auto v = session.step(f);
    ASSERT_FALSE(v) << "write " << i << " (" << f.what << "): " << to_string(v->kind) << ": " << v->message;
  }
  if (c.noted) {
    EXPECT_NE(noted(session).find(std::string(c.id) + ":other"), std::string::npos) << noted(session);
  }
}

INSTANTIATE_TEST_SUITE_P(Readings, LiveFuzzOneReading,
                         ::testing::Values(OneReading{"E-66", "rc3000-1.59.yaml", false},
                                           OneReading{"E-90", "rc3000-1.59.yaml", false},
                                           OneReading{"E-91", "circular-no-stow.yaml", false},
                                           OneReading{"E-92", "rc3000-1.59.yaml", true},
                                           OneReading{"E-93", "rc3000-1.59.yaml", false},
                                           OneReading{"E-94", "rc3000-1.59.yaml", false},
                                           OneReading{"E-95", "rc3000-1.59.yaml", true},
                                           OneReading{"E-96", "rc3000-1.59.yaml", false},
                                           OneReading{"E-97", "remote-disabled.yaml", false},
                                           OneReading{"E-98", "rc3000-1.59.yaml", true}),
                         [](const auto& info) { return std::string(info.param.id).replace(1, 1, ""); });

}  // namespace
}  // namespace sabus::harness::live_fuzz
