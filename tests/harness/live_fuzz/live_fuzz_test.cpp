// The live fuzzer's parts: the safety gate, the generator, the oracle, ddmin,
// the session against the in-process reference controller, and findings
// written as vectors that the runner replays.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <sstream>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "test_support.hpp"
#include "yaml_text.hpp"

namespace sabus::harness::live_fuzz {
namespace {

using test::hex;

Profile profile() { return Profile{}; }  // rc3000-1.59 at '2' (0x32)

Frame cmd(std::uint8_t code, std::string_view data = "") {
  return {FrameKind::kCommand, '2', code, Bytes(data.begin(), data.end())};
}

// ---- safety -----------------------------------------------------------------------

TEST(LiveFuzzSafety, MovingAndStoringCommandsAreRefusedWithoutTheFlags) {
  const Bytes status = hex("02 32 31 03 02");
  EXPECT_TRUE(is_safe_to_send(status, false, false));
  const Bytes stow = encode_frame(cmd(0x36, "S "));  // §3.7 'S': moves
  const Bytes reset = encode_frame(cmd(0x36, "RA"));  // §3.7 'R': drive reset, no effect
  std::string why;
  EXPECT_FALSE(is_safe_to_send(stow, false, false, {}, &why));
  EXPECT_NE(why.find("move the antenna"), std::string::npos) << why;
  EXPECT_TRUE(is_safe_to_send(stow, true, false));
  EXPECT_TRUE(is_safe_to_send(reset, false, false));
  const Bytes write_nav = encode_frame(cmd(0x46, std::string(28, '0')));
  EXPECT_FALSE(is_safe_to_send(write_nav, true, false));
  EXPECT_TRUE(is_safe_to_send(write_nav, false, true));
  // Damaged: a bad check byte, or junk before it, does not make it safe.
  Bytes damaged = stow;
  damaged.back() ^= 0x01;
  EXPECT_FALSE(is_safe_to_send(damaged, false, false));
  EXPECT_FALSE(is_safe_to_send(test::concat({hex("20 03"), stow}), false, false));
  // A frame split across two writes: STX and address in the last, the command in this one.
  EXPECT_FALSE(is_safe_to_send(hex("32 41 03 00"), false, false, hex("31 03 02 32")));
  EXPECT_TRUE(is_safe_to_send(hex("32 41 03 00"), false, false, hex("31 03 05 20")));
}

// ---- generator ----------------------------------------------------------------------

TEST(LiveFuzzGenerator, BaseFramesComeFromTheCatalogAndAreSafe) {
  const auto bases = base_frames({});
  ASSERT_FALSE(bases.empty());
  std::set<std::uint8_t> codes;
  for (const Bytes& b : bases) {
    EXPECT_TRUE(is_safe_to_send(b, false, false)) << to_hex(b);
    EXPECT_FALSE(describe_frame(b).error) << to_hex(b);
    codes.insert(b[2]);
  }
  EXPECT_TRUE(codes.count(0x30) && codes.count(0x31) && codes.count(0x40));
  EXPECT_FALSE(codes.count(0x32) || codes.count(0x39) || codes.count(0x48));
  // With both flags, commands that move and store are there too.
  std::set<std::uint8_t> all;
  for (const Bytes& b : base_frames({'2', true, true, true})) all.insert(b[2]);
  EXPECT_TRUE(all.count(0x32) && all.count(0x39));
}

TEST(LiveFuzzGenerator, EveryWriteIsSafeAndTheSeedRepeatsTheRun) {
  Generator a({}, 7), b({}, 7), c({}, 8);
  bool differs = false;
  for (int i = 0; i < 3000; ++i) {
    const FuzzFrame x = a.next();
    ASSERT_TRUE(is_safe_to_send(x.chars, false, false)) << x.what << ": " << to_hex(x.chars);
    EXPECT_EQ(x, b.next());
    for (auto c7 : x.chars) ASSERT_LE(c7, 0x7F);
    differs |= !(x == c.next());
  }
  EXPECT_TRUE(differs);
}

TEST(LiveFuzzGenerator, DamageIsWhatTheReferenceReceiverIgnores) {
  Generator g({}, 3);
  for (int i = 0; i < 200; ++i) {
    for (Mutation m : {Mutation::kBadLrc, Mutation::kParityFlip, Mutation::kForeignAddress, Mutation::kInvalidAddress,
                       Mutation::kControlInBody}) {
      Oracle o(profile());
      const FuzzFrame f = g.make(m);
      EXPECT_TRUE(o.accept(f).empty()) << to_string(m) << ": " << to_hex(f.chars);
    }
    Oracle o(profile());
    EXPECT_EQ(o.accept(g.make(Mutation::kValid)).size(), 1u);
    Oracle o2(profile());
    EXPECT_EQ(o2.accept(g.make(Mutation::kUnknownCommand)).size(), 1u);  // accepted, then NAKed (§3)
    Oracle o3(profile());
    EXPECT_GE(o3.accept(g.make(Mutation::kBurst)).size(), 2u);
  }
}

// ---- oracle ---------------------------------------------------------------------------

Frame reference_reply(const Frame& request, const Profile& p = profile()) {
  auto t = make_in_process_transport({p});
  t->send(encode_frame(request));
  std::uint8_t buf[512];
  const std::size_t n = t->receive(buf, std::chrono::milliseconds(1));
  Bytes b(buf, buf + n);
  for (auto& c : b) c &= 0x7F;
  auto f = decode_frame(b);
  EXPECT_TRUE(f.ok()) << to_hex(b);
  return f.value();
}

TEST(LiveFuzzOracle, TheReferenceControllersRepliesAreAcceptable) {
  const Oracle o(profile());
  for (const Bytes& b : base_frames({})) {
    const Frame request = decode_frame(b).value();
    EXPECT_FALSE(o.judge(request, reference_reply(request))) << to_hex(b);
  }
  EXPECT_FALSE(o.judge(cmd(0x31), nak_reply('2', 0x31)));
}

TEST(LiveFuzzOracle, RepliesTheSpecRulesOut) {
  const Oracle o(profile());
  const Frame status = reference_reply(cmd(0x31));
  // The offline reply with remote control enabled.
  EXPECT_EQ(o.judge(cmd(0x31), offline_reply('2', 0x31))->kind, FindingKind::kWrongReply);
  // An ACK to an unknown code, to a wrong length, to an unimplemented command (§3).
  Frame ack_unknown = status;
  ack_unknown.command = 0x55;
  EXPECT_EQ(o.judge(cmd(0x55), ack_unknown)->kind, FindingKind::kWrongReply);
  EXPECT_EQ(o.judge(cmd(0x31, "0"), status)->kind, FindingKind::kWrongReply);
  // One byte short (§3.2: 52 bytes), another address, another command.
  Frame short_status = status;
  short_status.data.pop_back();
  EXPECT_EQ(o.judge(cmd(0x31), short_status)->kind, FindingKind::kMalformedReply);
  Frame other = status;
  other.address = '0';
  EXPECT_EQ(o.judge(cmd(0x31), other)->kind, FindingKind::kWrongAddress);
  EXPECT_EQ(o.judge(cmd(0x30), status)->kind, FindingKind::kWrongReply);
  // With remote control disabled: the offline reply, and nothing executed.
  Profile off = profile();
  off.remote_enabled = false;
  const Oracle offline(off);
  EXPECT_FALSE(offline.judge(cmd(0x31), offline_reply('2', 0x31)));
  EXPECT_EQ(offline.judge(cmd(0x31), status)->kind, FindingKind::kWrongReply);
}

TEST(LiveFuzzOracle, JudgesAWriteAsAWhole) {
  const Oracle o(profile());
  const Frame status = reference_reply(cmd(0x31));
  Observation silence;
  Observation one;
  one.replies = {status};
  Observation two;
  two.replies = {nak_reply('2', 0x31), status};
  Observation garbage;
  garbage.garbage = {"bad LRC"};
  EXPECT_FALSE(o.judge({}, silence));
  EXPECT_FALSE(o.judge({cmd(0x31)}, one));
  EXPECT_EQ(o.judge({}, one)->kind, FindingKind::kReplyToIgnored);
  EXPECT_EQ(o.judge({cmd(0x31)}, two)->kind, FindingKind::kReplyToIgnored);
  EXPECT_EQ(o.judge({cmd(0x31)}, silence)->kind, FindingKind::kNoReply);
  EXPECT_EQ(o.judge({}, garbage)->kind, FindingKind::kMalformedReply);
}

TEST(LiveFuzzOracle, KeepsTheReceiversStateAcrossWrites) {
  Oracle o(profile());
  // Everything but the check byte: §1 State 4. The next STX is taken as the
  // check byte (E-7), a wrong one (the LRC is 03h), so the query that
  // follows is lost, and the one after it is read.
  EXPECT_TRUE(o.accept({hex("02 32 30 03"), {}, ""}).empty());
  EXPECT_TRUE(o.accept({hex("02 32 30 03 03"), {}, ""}).empty());
  EXPECT_EQ(o.accept({hex("02 32 30 03 03"), {}, ""}).size(), 1u);
  // A parity error in the address byte: ignored.
  EXPECT_TRUE(o.accept({hex("02 32 31 03 02"), {1}, ""}).empty());
}

// ---- ddmin ------------------------------------------------------------------------------

TEST(LiveFuzzDdmin, FindsTheOneMinimalSubsequence) {
  std::vector<int> items(100);
  for (int i = 0; i < 100; ++i) items[static_cast<std::size_t>(i)] = i;
  std::size_t tests = 0;
  const auto fails = [&](const std::vector<int>& v) {
    ++tests;
    bool a = false, b = false;
    for (int x : v) {
      a |= x == 13;
      b |= x == 71 && a;  // 71 after 13
    }
    return b;
  };
  EXPECT_EQ(ddmin<int>(items, fails), (std::vector<int>{13, 71}));
  EXPECT_LT(tests, 200u);
  EXPECT_EQ(ddmin<int>({5}, [](const std::vector<int>& v) { return !v.empty(); }), std::vector<int>{5});
  // A bound on the tests keeps a failing set, if not a minimal one.
  const auto left = ddmin<int>(items, fails, 3);
  EXPECT_TRUE(fails(left));
}

// ---- session ----------------------------------------------------------------------------

TEST(LiveFuzzSession, TheReferenceControllerGivesNoFinding) {
  // The oracle and the reference controller read the spec alike: thousands
  // of damaged writes, no finding.
  auto t = make_in_process_transport({profile()});
  Session s(*t, profile(), {});
  Generator g({}, 11);
  ASSERT_FALSE(s.probe());
  for (int i = 0; i < 3000; ++i) {
    const FuzzFrame f = g.next();
    const auto v = s.step(f);
    ASSERT_FALSE(v) << f.what << ": " << to_hex(f.chars) << ": " << v->message;
    if (i % 100 == 0) {
      ASSERT_FALSE(s.probe());
    }
  }
  EXPECT_EQ(s.counts().refused, 0u);
  EXPECT_GT(s.counts().nak, 0u);
  EXPECT_GT(s.counts().silence, 0u);
}

TEST(LiveFuzzSession, AnInjectedFaultIsAFinding) {
  auto t = make_in_process_transport({profile()}, FaultSet{Fault::kNakBadCheckByte});
  Session s(*t, profile(), {});
  const auto v = s.step({hex("02 32 31 03 03"), {}, "bad LRC"});
  ASSERT_TRUE(v);
  EXPECT_EQ(v->kind, FindingKind::kReplyToIgnored);
  // A device that does not answer at all is dead.
  auto dead = make_in_process_transport({profile()}, FaultSet{Fault::kCheckByteStxRestarts});
  Session d(*dead, profile(), {});
  const auto probe = d.probe();  // 02 32 30 03 03: answered; 31h at '2' has check byte 02h
  EXPECT_FALSE(probe);
  const auto lost = d.step({hex("02 32 31 03 02"), {}, "status poll"});
  ASSERT_TRUE(lost);
  EXPECT_EQ(lost->kind, FindingKind::kNoReply);
}

TEST(LiveFuzzSession, TheSafetyGateRefusesWithoutSending) {
  auto t = make_in_process_transport({profile()});
  Session s(*t, profile(), {});
  const ModeState before = t->bus().controller(0).state().mode;
  EXPECT_FALSE(s.step({encode_frame(cmd(0x36, "S ")), {}, "stow"}));
  EXPECT_EQ(s.counts().refused, 1u);
  EXPECT_EQ(s.counts().writes, 0u);
  EXPECT_EQ(t->pending(), 0u);
  EXPECT_EQ(t->bus().controller(0).state().mode, before);
}

// ---- minimize and write ----------------------------------------------------------------

Finding found(FaultSet faults, std::uint64_t seed, std::size_t max_writes) {
  auto t = make_in_process_transport({profile()}, faults);
  Session s(*t, profile(), {});
  Generator g({}, seed);
  std::vector<FuzzFrame> history;
  for (std::size_t i = 0; i < max_writes; ++i) {
    history.push_back(g.next());
    if (auto v = s.step(history.back())) return {v->kind, v->message, history, {}, false};
  }
  return {FindingKind::kDead, "nothing found", {}, {}, false};
}

TEST(LiveFuzzMinimize, ShrinksTheHistoryAndTheVectorReplaysIt) {
  for (Fault fault : {Fault::kNakBadCheckByte, Fault::kAnswersForeignAddress, Fault::kDropsReplyByte}) {
    const FaultSet faults{fault};
    Finding f = found(faults, 5, 2000);
    ASSERT_FALSE(f.history.empty()) << static_cast<int>(fault);
    const DeviceFactory fresh = [faults] { return std::unique_ptr<Transport>(make_in_process_transport({profile()}, faults)); };
    minimize(f, profile(), {}, fresh, nullptr);
    EXPECT_TRUE(f.reproduced);
    EXPECT_LE(f.reproducer.size(), 2u);
    EXPECT_LE(f.reproducer.size(), f.history.size());

    const std::string yaml = finding_vector_yaml(f, profile(), {5, "sabus fuzz --sim --seed 5", 1});
    EXPECT_NE(yaml.find("seed 5"), std::string::npos);
    EXPECT_NE(yaml.find("paragraph: framing"), std::string::npos);
    LoadResult loaded = load_vector_text(yaml, "finding.yaml");
    ASSERT_TRUE(loaded.ok()) << loaded.errors.front().text() << "\n" << yaml;
    const auto errors = lint(loaded.files);
    ASSERT_TRUE(errors.empty()) << errors.front().text() << "\n" << yaml;
    const auto& vectors = loaded.files.at(0).vectors;
    auto faulty = make_in_process_transport({profile()}, faults);
    EXPECT_EQ(Runner(*faulty, profile(), {}).run(vectors).exit_code(), 1) << yaml;
    auto clean = make_in_process_transport({profile()});
    EXPECT_EQ(Runner(*clean, profile(), {}).run(vectors).exit_code(), 0) << yaml;
  }
}

// Every kind of finding from the one table (SABUS_LIVE_FUZZ_FINDINGS).
constexpr FindingKind kEveryKind[] = {
#define SABUS_X(id, name, paragraph, quote) FindingKind::id,
    SABUS_LIVE_FUZZ_FINDINGS(SABUS_X)
#undef SABUS_X
};

// What a device said and a person typed, in a finding's message, its
// command line and the writes' descriptions: line breaks, YAML, control
// characters, DEL, a line separator, a byte that is not UTF-8.
const std::string kHostile = "x\nparagraph: nak\r\n  - send: {raw: \"00\"}\x01\x7f \xe2\x80\xa8 # \xc3\xa9 \xff {{$a}}";

// Writes of every shape a vector step takes: an answered poll, a frame the
// device must ignore with a poll after it in one write (two steps), a wrong
// parity bit (modify.parity_flip, tag parity), a wrong length
// (length_mismatch), a move (tag motion) and a store (tag destructive).
std::vector<FuzzFrame> writes_of_every_shape() {
  return {{hex("02 32 31 03 02"), {}, "status poll " + kHostile},
          {test::concat({hex("02 32 31 03 03"), hex("02 32 31 03 02")}), {}, "bad LRC + status poll after it " + kHostile},
          {hex("02 32 31 03 02"), {2}, "parity " + kHostile},
          {hex("02 32 31 41 03 43"), {}, "one data byte too many " + kHostile},
          {encode_frame(cmd(0x36, "S ")), {}, "stow " + kHostile},
          {encode_frame(cmd(0x46, std::string(28, '0'))), {}, "write navigation " + kHostile}};
}

// A finding written with finding_vector_yaml: loaded and linted with no
// error, held to a strict check of its characters, its comments all
// comment, and replayed clean against the reference controller it took its
// expectations from.
void expect_a_clean_vector_file(const std::string& yaml, const Profile& p) {
  EXPECT_EQ(test::yaml_text_problem(yaml), "") << yaml;
  LoadResult loaded = load_vector_text(yaml, "finding.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.errors.front().text() << "\n" << yaml;
  const auto errors = lint(loaded.files);
  ASSERT_TRUE(errors.empty()) << errors.front().text() << "\n" << yaml;
  std::istringstream lines(yaml);
  std::string line;
  while (std::getline(lines, line) && line.rfind("paragraph:", 0) != 0) EXPECT_EQ(line.rfind("# ", 0), 0u) << line;
  EXPECT_EQ(line, "paragraph: framing") << yaml;
  RunOptions o;
  o.allow_motion = o.allow_destructive = true;
  o.backup_stored_data = false;
  auto clean = make_in_process_transport({p});
  const RunResult r = Runner(*clean, p, o).run(loaded.files.at(0).vectors);
  EXPECT_EQ(r.exit_code(), 0) << (r.vectors.empty() || r.vectors[0].failures.empty() ? "" : r.vectors[0].failures[0]) << "\n"
                              << yaml;
}

TEST(LiveFuzzWriter, EveryFindingKindIsALintCleanVectorWhateverItsTextSays) {
  for (const FindingKind kind : kEveryKind) {
    for (const bool reproduced : {true, false}) {
      SCOPED_TRACE(std::string(to_string(kind)) + (reproduced ? ", reproduced" : ", not reproduced"));
      const Finding f{kind, "message " + kHostile, writes_of_every_shape(),
                      reproduced ? writes_of_every_shape() : std::vector<FuzzFrame>{}, reproduced};
      const std::string yaml = finding_vector_yaml(f, profile(), {5, "sabus fuzz --sim --profile " + kHostile + " --seed 5", 2});
      expect_a_clean_vector_file(yaml, profile());
      const YAML::Node doc = YAML::Load(yaml);
      const YAML::Node v = doc["vectors"][0];
      EXPECT_EQ(v["id"].Scalar(), "framing-fuzz-5-2-" + std::string(to_string(kind)));
      EXPECT_EQ(v["spec"]["paragraph"].Scalar(), paragraph_of(kind));
      EXPECT_EQ(v["spec"]["quote"].Scalar(), quote_of(kind));
      EXPECT_EQ(v["tags"].size(), 3u) << yaml;  // motion, destructive, parity
      const YAML::Node steps = v["steps"];
      ASSERT_EQ(steps.size(), 7u) << yaml;
      const char* expected[] = {"ack", "silence", "ack", "silence", "nak", "ack", "nak"};
      // The lockstep kinds name the rule of each NAK the reference gives.
      const bool model_kind = kind == FindingKind::kNakRule || kind == FindingKind::kValue || kind == FindingKind::kEffect;
      for (std::size_t i = 0; i < steps.size(); ++i) {
        const YAML::Node e = steps[i]["expect"];
        EXPECT_EQ(e.IsMap() ? e["reply"].Scalar() : e.Scalar(), expected[i]) << i << "\n" << yaml;
        EXPECT_EQ(e.IsMap(), model_kind && std::string(expected[i]) == "nak") << i << "\n" << yaml;
        if (e.IsMap()) {
          EXPECT_TRUE(find_nak_rule(e["rule"].Scalar())) << yaml;
        }
      }
      EXPECT_EQ(steps[3]["modify"]["parity_flip"][0].as<int>(), 2) << yaml;
      EXPECT_TRUE(steps[4]["length_mismatch"].as<bool>()) << yaml;
      EXPECT_NE(v["comment"].Scalar().find("message x\nparagraph: nak\\x0d\n  - send: {raw: \"00\"}\\x01\\x7f \\xe2\\x80\\xa8 # "
                                           "\xc3\xa9 \\xff {{$a}}"),
                std::string::npos)
          << yaml;
      EXPECT_EQ(yaml.find("NOT reproduced") == std::string::npos, reproduced) << yaml;
    }
  }
}

// A finding not reproduced keeps the writes before it, as many as a vector
// holds (kMaxSteps steps, a wait counting as one): the file still loads.
TEST(LiveFuzzWriter, AFindingNotReproducedKeepsTheLastWritesAVectorHolds) {
  std::vector<FuzzFrame> history;
  for (int i = 0; i < 512; ++i) {
    history.push_back({hex("02 32 31 03 02"), {}, "status poll " + std::to_string(i)});
    if (i % 10 == 0) history.back().pause = std::chrono::milliseconds(5);
  }
  const Finding f{FindingKind::kEffect, "m", history, {}, false, "azimuth"};
  const std::string yaml = finding_vector_yaml(f, profile(), {1, "sabus fuzz --sim", 1});
  expect_a_clean_vector_file(yaml, profile());
  const YAML::Node steps = YAML::Load(yaml)["vectors"][0]["steps"];
  EXPECT_EQ(steps.size(), kMaxSteps) << yaml;
  // The last writes of the history, and no earlier one.
  EXPECT_NE(yaml.find("# status poll 511\n"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("# status poll 400\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("the last "), std::string::npos) << yaml;
}

TEST(LiveFuzzWriter, AFindingOnAControllerWithRemoteControlDisabledExpectsTheOfflineReply) {
  Profile off = profile();
  off.remote_enabled = false;
  const Finding f{FindingKind::kWrongReply, "m", {{hex("02 32 31 03 02"), {}, "status poll"}}, {}, false};
  const std::string yaml = finding_vector_yaml(f, off, {1, "sabus fuzz --sim", 1});
  expect_a_clean_vector_file(yaml, off);
  EXPECT_EQ(YAML::Load(yaml)["vectors"][0]["steps"][0]["expect"].Scalar(), "offline") << yaml;
}

}  // namespace
}  // namespace sabus::harness::live_fuzz
