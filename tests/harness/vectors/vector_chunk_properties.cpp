// Every vector's command bytes, fed to the §1 receiver in pieces, give the
// same events as fed at once (llhttp's fixture replays each case at every
// chunk size): the controller cannot depend on how a line delivers bytes.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "test_support.hpp"

namespace sabus::harness {
namespace {

struct WireCase {
  std::string id;  // vector id and step
  Bytes wire;      // as on a line opened 8N1: parity in bit 7, wrong where the step asks
};

// The bytes of every send and poll step of the suite, modifiers applied, as
// the default profile's device receives them.
const std::vector<WireCase>& suite_wire_cases() {
  static const std::vector<WireCase> cases = [] {
    std::vector<WireCase> out;
    const Profile profile = load_profile_file(default_profile_path()).profile.value();
    for (const auto& f : load_vectors({default_vectors_dir()}).files)
      for (const auto& v : f.vectors) {
        std::size_t n = 0;
        for (const auto* list : {&v.setup, &v.steps, &v.teardown})
          for (const Step& s : *list) {
            ++n;
            if (s.kind == Step::Kind::kWait) continue;
            auto bytes = step_bytes(s, profile.address, {}, true);
            if (!bytes) continue;
            const Bytes chars = apply_modifiers(bytes.value(), s.modifiers);
            out.push_back({v.id + " step " + std::to_string(n), with_software_parity(chars, s.modifiers.parity_flip)});
          }
      }
    return out;
  }();
  return cases;
}

ReceiverOptions device_receiver() {
  const Profile profile = load_profile_file(default_profile_path()).profile.value();
  return receiver_options(profile, {}, Parity::kEvenBit7);
}

test::EventLog receive_in_pieces(const ReceiverOptions& o, ByteView wire, const std::vector<std::size_t>& cuts) {
  Receiver r(o);
  test::EventLog log;
  std::size_t at = 0;
  for (std::size_t cut : cuts) {
    r.feed(wire.subspan(at, cut - at), log);
    at = cut;
  }
  r.feed(wire.subspan(at), log);
  r.finish(log);
  return log;
}

TEST(VectorChunks, TheSuiteHasCommandBytes) {
  // Guards the properties below against an empty suite passing vacuously.
  EXPECT_GT(suite_wire_cases().size(), 400u);
}

TEST(VectorChunks, EverySplitPointGivesTheSameEvents) {
  const ReceiverOptions o = device_receiver();
  for (const WireCase& c : suite_wire_cases()) {
    const auto whole = test::receive(o, c.wire);
    for (std::size_t cut = 1; cut < c.wire.size(); ++cut)
      ASSERT_TRUE(receive_in_pieces(o, c.wire, {cut}).entries == whole.entries) << c.id << ", split at byte " << cut;
  }
}

RC_GTEST_PROP(VectorChunks, AnyChunkingGivesTheSameEvents, ()) {
  const auto& cases = suite_wire_cases();
  RC_PRE(!cases.empty());
  const WireCase& c = cases[static_cast<std::size_t>(*rc::gen::inRange<int>(0, static_cast<int>(cases.size())))];
  std::vector<std::size_t> cuts;
  for (std::size_t at = 0; at < c.wire.size();) {
    at += static_cast<std::size_t>(*rc::gen::inRange(1, 8));
    if (at < c.wire.size()) cuts.push_back(at);
  }
  const ReceiverOptions o = device_receiver();
  RC_ASSERT(receive_in_pieces(o, c.wire, cuts).entries == test::receive(o, c.wire).entries);
}

}  // namespace
}  // namespace sabus::harness
