// The runner: matchers, raw templates, modifiers, requirements, and whole
// runs against the in-process reference controller (also with faults).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/motion.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

FrameDescription status_reply() {
  StatusReply r;
  r.status.sat_name = "SBS 6";
  r.status.azimuth = {fields::AzimuthReading::Kind::kPosition, -1525, 0};
  r.status.az_status = 0x04;
  return describe_frame(encode_reply(r, '2', 0x31).value());
}

FieldMatcher matcher(std::string field, FieldMatcher::Kind kind, std::vector<std::string> values, double lo = 0,
                     double hi = 0) {
  FieldMatcher m;
  m.field = std::move(field);
  m.kind = kind;
  m.values = std::move(values);
  m.low = lo;
  m.high = hi;
  return m;
}

TEST(Matchers, EqOneOfRegexRangeAny) {
  const auto d = status_reply();
  Captures c;
  using K = FieldMatcher::Kind;
  EXPECT_FALSE(check_field(d, matcher("az status", K::kEq, {"0x44"}), c));
  EXPECT_FALSE(check_field(d, matcher("az status", K::kEq, {"68"}), c)) << "numbers in any base";
  EXPECT_FALSE(check_field(d, matcher("sat name", K::kEq, {"SBS 6"}), c));
  EXPECT_FALSE(check_field(d, matcher("sat name", K::kOneOf, {"X", "SBS 6"}), c));
  EXPECT_FALSE(check_field(d, matcher("azimuth", K::kRegex, {"^-15"}), c));
  EXPECT_FALSE(check_field(d, matcher("azimuth", K::kRange, {}, -152.6, -152.4), c));
  EXPECT_FALSE(check_field(d, matcher("agc", K::kAny, {}), c));
  auto fail = check_field(d, matcher("az status", K::kEq, {"0x57"}), c);
  ASSERT_TRUE(fail);
  EXPECT_EQ(*fail, "byte 36 az status: expected 0x57, got 0x44 (slow, ccw automatic movement in progress)");
  EXPECT_TRUE(check_field(d, matcher("azimuth", K::kRange, {}, 0, 10), c));
  EXPECT_TRUE(check_field(d, matcher("no such field", K::kAny, {}), c));
}

TEST(Matchers, ExpectedCodesAreNamedAsTheFieldShowsThem) {
  // An expression such as mode_exit(...) gives a decimal number; beside a
  // code field's "0x44" the failure names it in hex, as the field shows it.
  const auto d = status_reply();
  Captures c;
  using K = FieldMatcher::Kind;
  auto fail = check_field(d, matcher("az status", K::kOneOf, {"32", "87"}), c);
  ASSERT_TRUE(fail);
  EXPECT_EQ(*fail, "byte 36 az status: expected one of 0x20, 0x57, got 0x44 (slow, ccw automatic movement in progress)");
  fail = check_field(d, matcher("az status", K::kEq, {"87"}), c);
  ASSERT_TRUE(fail);
  EXPECT_NE(fail->find("expected 0x57, got 0x44"), std::string::npos) << *fail;
  // A field that is not a code keeps the number as written.
  fail = check_field(d, matcher("sat name", K::kOneOf, {"12", "X"}), c);
  ASSERT_TRUE(fail);
  EXPECT_NE(fail->find("expected one of 12, X, got SBS 6"), std::string::npos) << *fail;
}

TEST(Matchers, CaptureKeepsTheText) {
  const auto d = status_reply();
  Captures c;
  auto m = matcher("sat name", FieldMatcher::Kind::kAny, {});
  m.capture = "$sat";
  EXPECT_FALSE(check_field(d, m, c));
  EXPECT_EQ(c["$sat"], "SBS 6");
  auto raw = expand_raw_bytes("02 {addr} 32 48 {$sat} 20 20 20 20 20 03 {lrc}", '2', c);
  ASSERT_TRUE(raw.ok()) << raw.error().message();
  EXPECT_EQ(raw.value(), encode_frame({FrameKind::kCommand, '2', 0x32, {'H', 'S', 'B', 'S', ' ', '6', ' ', ' ', ' ', ' ', ' '}}));
}

TEST(RawTemplates, AddressAndLrc) {
  auto b = expand_raw_bytes("02 {addr} 31 03 {lrc}", '2', {});
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(to_hex(b.value()), "02 32 31 03 02");
  auto restart = expand_raw_bytes("02 02 {addr} 31 03 {lrc}", '2', {});
  ASSERT_TRUE(restart.ok());
  EXPECT_EQ(to_hex(restart.value()), "02 02 32 31 03 02") << "the LRC of the frame the last STX begins";
  EXPECT_EQ(to_hex(expand_raw_bytes("41 42 02 {addr} 31 03 {lrc}", '2', {}).value()), "41 42 02 32 31 03 02");
  EXPECT_FALSE(expand_raw_bytes("02 {nope} 03", '2', {}).ok());
  EXPECT_FALSE(expand_raw_bytes("02 {addr 03", '2', {}).ok());
  EXPECT_FALSE(expand_raw_bytes("0g", '2', {}).ok());
}

TEST(Modifiers, BadLrcAddressExtraByteTruncateReplace) {
  const Bytes poll = encode_frame({FrameKind::kCommand, '2', 0x31, {}});
  Modifiers m;
  m.lrc_xor = 0x01;
  EXPECT_EQ(apply_modifiers(poll, m).back(), 0x03);
  Modifiers a;
  a.address = '3';
  EXPECT_EQ(apply_modifiers(poll, a), encode_frame({FrameKind::kCommand, '3', 0x31, {}}));
  Modifiers e;
  e.extra_data_bytes = 1;
  EXPECT_EQ(apply_modifiers(poll, e), encode_frame({FrameKind::kCommand, '2', 0x31, {'0'}}));
  Modifiers t;
  t.truncate = 2;
  EXPECT_EQ(apply_modifiers(poll, t).size(), 3u);
  Modifiers r;
  r.replace = {{2, 0x05}};
  EXPECT_EQ(apply_modifiers(poll, r)[2], 0x05);
}

TEST(Requirements, AgainstTheProfile) {
  Profile p;
  EXPECT_FALSE(unmet_requirement(p, {"polarization", {"single_port", "dual_port"}, {}}));
  auto why = unmet_requirement(p, {"polarization", {"circular"}, {}});
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("single_port"), std::string::npos);
  EXPECT_FALSE(unmet_requirement(p, {"dvb_receiver", {"false"}, {}}));
  EXPECT_FALSE(unmet_requirement(p, {"errata.implements_iess", {"false"}, {}}));
  EXPECT_TRUE(unmet_requirement(p, {"no_such_key", {"x"}, {}}));
}

// ---- whole runs in-process ---------------------------------------------------------

Vector vector_with(std::string id, std::vector<Step> steps, std::vector<std::string> tags = {}) {
  Vector v;
  v.id = std::move(id);
  v.paragraph = "3.2";
  v.steps = std::move(steps);
  v.tags = std::move(tags);
  return v;
}

Step send_raw(std::string hex, Expectation::Kind kind) {
  Step s;
  s.raw = RawBytes{std::move(hex), {}};
  s.expect.kind = kind;
  return s;
}

Step send_command(std::string command, std::string form, std::map<std::string, std::string> fields,
                  Expectation::Kind kind) {
  Step s;
  s.command = StructuredCommand{std::move(command), std::move(form), std::move(fields), std::nullopt, {}, {}};
  s.expect.kind = kind;
  return s;
}

RunResult run_in_process(const std::vector<Vector>& vectors, FaultSet faults = {}, RunOptions options = {}) {
  Profile p = load_profile_file(default_profile_path()).profile.value();
  auto t = make_in_process_transport({p}, faults);
  Runner runner(*t, p, options);
  return runner.run(vectors);
}

// The shipped suite against the reference controller, one run a profile with
// motion and destructive vectors allowed: every vector passes or is skipped by
// its requirements, and each NAK names the rule the vector expects.
TEST(Runner, ShippedVectorsPassOnTheShippedProfiles) {
  std::vector<Vector> vectors;
  for (auto& f : load_vectors({default_vectors_dir()}).files)
    for (auto& v : f.vectors) vectors.push_back(std::move(v));
  ASSERT_FALSE(vectors.empty());
  const auto profiles_dir = std::filesystem::path(default_profile_path()).parent_path();
  for (const auto& e : std::filesystem::directory_iterator(profiles_dir)) {
    if (e.path().extension() != ".yaml") continue;
    Profile p = load_profile_file(e.path().string()).profile.value();
    auto t = make_in_process_transport(bus_of(p), {});  // multidrop-bus has peers on its line
    RunOptions o;
    o.allow_motion = true;
    o.allow_destructive = true;
    Runner runner(*t, p, o);
    const RunResult r = runner.run(vectors);
    EXPECT_FALSE(r.aborted) << p.name << ": " << r.abort_reason;
    EXPECT_EQ(r.passed + r.skipped, vectors.size()) << p.name;
    for (const auto& v : r.vectors)
      EXPECT_NE(v.verdict, Verdict::kFail) << p.name << ": " << v.id << ": " << (v.failures.empty() ? "" : v.failures[0]);
  }
}

// The suite on every shipped profile against the reference controller on
// the sides `reading` names (`sabus run --sim --reading READING`), the
// profile left unpinned: no vector fails. Returns the ids that passed or
// ended inconclusive somewhere.
std::set<std::string> holds_on_every_shipped_profile(const std::vector<Vector>& vectors, std::string_view reading) {
  std::set<std::string> ran;
  const auto profiles_dir = std::filesystem::path(default_profile_path()).parent_path();
  for (const auto& e : std::filesystem::directory_iterator(profiles_dir)) {
    if (e.path().extension() != ".yaml") continue;
    const Profile p = load_profile_file(e.path().string()).profile.value();
    Profile device = p;
    EXPECT_FALSE(apply_reading_spec(reading, device.readings));
    auto t = make_in_process_transport(bus_of(device), {});
    RunOptions o;
    o.allow_motion = true;
    o.allow_destructive = true;
    const RunResult r = Runner(*t, p, o).run(vectors);
    EXPECT_FALSE(r.aborted) << p.name << ": " << r.abort_reason;
    for (const auto& v : r.vectors) {
      EXPECT_NE(v.verdict, Verdict::kFail) << reading << ", " << p.name << ": " << v.id << ": "
                                           << (v.failures.empty() ? "" : v.failures[0]);
      if (v.verdict == Verdict::kPass || v.verdict == Verdict::kInconclusive) ran.insert(v.id);
    }
  }
  return ran;
}

// The same suite against the reference controller on the other side of
// every open point of the spec (readings.hpp, `sabus run --sim --reading
// other`): a legal controller that reads the spec the other way never fails.
TEST(Runner, ShippedVectorsHoldOnAControllerThatReadsTheSpecTheOtherWay) {
  std::vector<Vector> vectors;
  for (auto& f : load_vectors({default_vectors_dir()}).files)
    for (auto& v : f.vectors) vectors.push_back(std::move(v));
  EXPECT_FALSE(holds_on_every_shipped_profile(vectors, "other").empty());
}

// The third sides (ERRATA's other-2, `--reading other-2`: every point's
// third side where it has one, other elsewhere): none fails, and the vectors
// whose flags rest on such a point pass somewhere (or, where E-90's other
// side ends the search first, are inconclusive).
TEST(Runner, ShippedVectorsHoldOnAControllerThatTakesTheThirdSides) {
  std::vector<std::string> thirds;
  for (const ReadingPoint& point : reading_points())
    if (!point.other_2.empty()) thirds.emplace_back(point.id);
  ASSERT_FALSE(thirds.empty());
  std::vector<Vector> vectors;
  std::set<std::string> of_thirds;
  for (auto& f : load_vectors({default_vectors_dir()}).files)
    for (auto& v : f.vectors) {
      for (const std::string& flag : v.flags)
        if (const auto note = f.notes.find(flag);
            note != f.notes.end() && std::find(thirds.begin(), thirds.end(), note->second.errata) != thirds.end())
          of_thirds.insert(v.id);
      vectors.push_back(std::move(v));
    }
  ASSERT_FALSE(of_thirds.empty());
  const std::set<std::string> ran = holds_on_every_shipped_profile(vectors, "other-2");
  for (const std::string& id : of_thirds) EXPECT_TRUE(ran.count(id)) << id << " ran on no shipped profile";
}

// A profile that pins a side holds the shipped vectors that list the point
// to it: on the default profile, the reference controller on the side
// pinned passes them and on the side pinned away fails them (E-14, E-46,
// E-82, E-88, E-89; E-46's other side names any axis, the azimuth too, so only
// the reference pin refuses a side). `run` is run in order, `judged` judged.
TEST(Runner, APinnedSideHoldsTheVectorsThatListItToThatSide) {
  struct Case {
    const char* id;
    std::vector<std::string> run, judged;
    bool other_pin_refuses_reference = true;
  };
  const Case cases[] = {
      {"E-14", {"3.4-nak-direction-c"}, {"3.4-nak-direction-c"}},
      {"E-46", {"3.24-jog-minimal-L", "3.24-x-reply"}, {"3.24-x-reply"}, false},
      {"E-82", {"3.18-remote-locate-x-stops", "3.18-remote-locate-range-error-stop-exit"},
       {"3.18-remote-locate-x-stops", "3.18-remote-locate-range-error-stop-exit"}},
      {"E-88", {"3.25-keypress-stop-stops-auto-move", "3.7-misc-stop-key-stops-auto-move"},
       {"3.25-keypress-stop-stops-auto-move", "3.7-misc-stop-key-stops-auto-move"}},
      {"E-89", {"3.7-misc-x-stops-stow", "3.7-misc-x-stops-deploy"}, {"3.7-misc-x-stops-stow", "3.7-misc-x-stops-deploy"}},
  };
  std::map<std::string, Vector> by_id;
  for (auto& f : load_vectors({default_vectors_dir()}).files)
    for (auto& v : f.vectors) by_id.emplace(v.id, std::move(v));
  for (const Case& c : cases) {
    std::vector<Vector> vectors;
    for (const std::string& id : c.run) {
      ASSERT_TRUE(by_id.count(id)) << id;
      vectors.push_back(by_id.at(id));
    }
    for (ReadingSide pin : {ReadingSide::kReference, ReadingSide::kOther})
      for (ReadingSide side : {ReadingSide::kReference, ReadingSide::kOther}) {
        SCOPED_TRACE(std::string(c.id) + " pinned " + std::string(to_string(pin)) + ", the device on " +
                     std::string(to_string(side)));
        Profile p = load_profile_file(default_profile_path()).profile.value();
        p.readings[c.id] = pin;
        Profile device = p;
        device.readings[c.id] = side;
        auto t = make_in_process_transport(bus_of(device), {});
        RunOptions o;
        o.allow_motion = o.allow_destructive = true;
        const RunResult r = Runner(*t, p, o).run(vectors);
        const bool refused = pin != side && (pin == ReadingSide::kReference || c.other_pin_refuses_reference);
        for (const auto& v : r.vectors) {
          if (std::find(c.judged.begin(), c.judged.end(), v.id) == c.judged.end()) continue;
          EXPECT_EQ(v.verdict, refused ? Verdict::kFail : Verdict::kPass)
              << v.id << ": " << (v.failures.empty() ? "" : v.failures[0]);
          if (refused && !v.failures.empty())
            EXPECT_NE(v.failures[0].find(std::string("(ERRATA ") + c.id), std::string::npos) << v.failures[0];
        }
      }
  }
}

// An expectation's `readings:` (ERRATA class reading): the reply passes when
// it meets a side the profile leaves open; a pinned side is held strictly;
// the failure names every side it was held to.
TEST(Runner, AReadingsAlternativeAcceptsEitherSideUnlessThePofilePinsOne) {
  auto with_start = [](std::string byte) {
    Step s = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
    s.expect.fields.push_back(matcher("start", FieldMatcher::Kind::kEq, {std::move(byte)}));
    return s;
  };
  // The reference side wants a start byte the controller never sends; the
  // other side of E-91 the ACK it sends.
  Step step = with_start("0x15");
  step.expect.readings.push_back(ReadingAlternative{"E-91", with_start("0x06").expect});
  auto run_pinned = [&](std::optional<ReadingSide> pin) {
    Profile p = load_profile_file(default_profile_path()).profile.value();
    if (pin) p.readings["E-91"] = *pin;
    auto t = make_in_process_transport({p}, {});
    return Runner(*t, p, RunOptions{}).run({vector_with("reading", {step})}).vectors.at(0);
  };
  EXPECT_EQ(run_pinned(std::nullopt).verdict, Verdict::kPass) << "open: either side";
  EXPECT_EQ(run_pinned(ReadingSide::kOther).verdict, Verdict::kPass);
  const VectorResult strict = run_pinned(ReadingSide::kReference);
  ASSERT_EQ(strict.verdict, Verdict::kFail);
  EXPECT_NE(strict.failures[0].find("E-91 reference: byte 0 start"), std::string::npos) << strict.failures[0];
  EXPECT_EQ(strict.failures[0].find("E-91 other"), std::string::npos) << "the pinned-away side is not tried";
  // Neither side holds: both named.
  step.expect.readings[0].expect = with_start("0x02").expect;
  const VectorResult neither = run_pinned(std::nullopt);
  ASSERT_EQ(neither.verdict, Verdict::kFail);
  EXPECT_NE(neither.failures[0].find("no legal reading holds (ERRATA E-91): E-91 reference:"), std::string::npos)
      << neither.failures[0];
  EXPECT_NE(neither.failures[0].find("; E-91 other:"), std::string::npos) << neither.failures[0];
  // Every side failing alike (here the same NAK expected of both) is said
  // once: nothing the reading decides.
  Step alike = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);
  alike.expect.readings.push_back(ReadingAlternative{"E-91", alike.expect});
  auto p = load_profile_file(default_profile_path()).profile.value();
  auto t = make_in_process_transport({p}, {});
  const VectorResult same = Runner(*t, p, RunOptions{}).run({vector_with("alike", {alike})}).vectors.at(0);
  ASSERT_EQ(same.verdict, Verdict::kFail);
  EXPECT_EQ(same.failures[0].rfind("expected a NAK reply, got ACK", 0), 0u) << same.failures[0];
  EXPECT_EQ(same.failures[0].find("E-91"), std::string::npos) << same.failures[0];
}

// A point with a third side: each of its sides is an alternative; a pin to
// one of them holds the reply to it alone, and a failure names the sides
// tried by their labels.
TEST(Runner, AThirdSideIsAnAlternativeOfItsOwn) {
  auto with_start = [](std::string byte) {
    Step s = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
    s.expect.fields.push_back(matcher("start", FieldMatcher::Kind::kEq, {std::move(byte)}));
    return s;
  };
  // Only other-2 meets the ACK the controller sends.
  Step step = with_start("0x15");
  step.expect.readings.push_back(ReadingAlternative{"E-23", with_start("0x02").expect, ReadingSide::kOther});
  step.expect.readings.push_back(ReadingAlternative{"E-23", with_start("0x06").expect, ReadingSide::kOther2});
  auto run_pinned = [&](std::optional<ReadingSide> pin) {
    Profile p = load_profile_file(default_profile_path()).profile.value();
    if (pin) p.readings["E-23"] = *pin;
    auto t = make_in_process_transport({p}, {});
    return Runner(*t, p, RunOptions{}).run({vector_with("reading", {step})}).vectors.at(0);
  };
  EXPECT_EQ(run_pinned(std::nullopt).verdict, Verdict::kPass) << "open: any side";
  EXPECT_EQ(run_pinned(ReadingSide::kOther2).verdict, Verdict::kPass);
  const VectorResult other = run_pinned(ReadingSide::kOther);
  ASSERT_EQ(other.verdict, Verdict::kFail);
  EXPECT_NE(other.failures[0].find("E-23 other: byte 0 start"), std::string::npos) << other.failures[0];
  EXPECT_EQ(other.failures[0].find("other-2"), std::string::npos) << "the pinned-away sides are not tried";
  EXPECT_EQ(other.failures[0].find("E-23 reference"), std::string::npos) << other.failures[0];
  // A side the step does not list answers as the reference does.
  Step only_other = with_start("0x06");
  only_other.expect.readings.push_back(ReadingAlternative{"E-23", with_start("0x02").expect, ReadingSide::kOther});
  step = only_other;
  EXPECT_EQ(run_pinned(ReadingSide::kOther2).verdict, Verdict::kPass) << "other-2 unlisted: the reference's";
  EXPECT_EQ(run_pinned(ReadingSide::kOther).verdict, Verdict::kFail);
}

// An alternative with `ends` (vectors/README.md): when it holds and the
// reference side does not, the steps end there, passed; when the reference
// side holds, or the alternative has no `ends`, the steps go on.
TEST(Runner, AReadingsAlternativeThatEndsEndsTheStepsOnlyWhenItIsTheSideThatHeld) {
  auto with_start = [](std::string byte) {
    Step s = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
    s.expect.fields.push_back(matcher("start", FieldMatcher::Kind::kEq, {std::move(byte)}));
    return s;
  };
  const Step never = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);  // the status poll is ACKed
  auto run = [&](std::string reference_start, bool ends, std::optional<ReadingSide> pin = std::nullopt) {
    Step step = with_start(std::move(reference_start));
    step.expect.readings.push_back(ReadingAlternative{"E-91", with_start("0x06").expect});
    step.expect.readings[0].expect.ends = ends;
    Profile p = load_profile_file(default_profile_path()).profile.value();
    if (pin) p.readings["E-91"] = *pin;
    auto t = make_in_process_transport({p}, {});
    return Runner(*t, p, RunOptions{}).run({vector_with("ends", {step, never})}).vectors.at(0);
  };
  EXPECT_EQ(run("0x15", true).verdict, Verdict::kPass) << "the other side held: the rest is not run";
  EXPECT_EQ(run("0x15", false).verdict, Verdict::kFail) << "without ends the steps go on";
  EXPECT_EQ(run("0x06", true).verdict, Verdict::kFail) << "the reference side held: the steps go on";
  EXPECT_EQ(run("0x15", true, ReadingSide::kReference).verdict, Verdict::kFail) << "pinned away";
}

// A device takes one side of a point: a step that lists one entry and meets
// only one side binds the rest of its vector to it (Session::sides_shown),
// so two steps that each accept both sides fail a device that takes neither.
TEST(Runner, AStepThatShowsOneSideHoldsTheRestOfItsVectorToIt) {
  auto with_start = [](std::string byte) {
    Step s = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
    s.expect.fields.push_back(matcher("start", FieldMatcher::Kind::kEq, {std::move(byte)}));
    return s;
  };
  auto either = [&](std::string reference, std::string other) {
    Step step = with_start(std::move(reference));
    step.expect.readings.push_back(ReadingAlternative{"E-91", with_start(std::move(other)).expect});
    return step;
  };
  const Step shows_reference = either("0x06", "0x15"), needs_other = either("0x15", "0x06");
  const RunResult r = run_in_process({vector_with("alone", {needs_other}), vector_with("bound", {shows_reference, needs_other}),
                                      vector_with("both", {either("0x06", "0x06"), needs_other})});
  EXPECT_EQ(r.vectors.at(0).verdict, Verdict::kPass) << "on its own the step takes either side";
  ASSERT_EQ(r.vectors.at(1).verdict, Verdict::kFail) << "the first step showed the reference side";
  EXPECT_NE(r.vectors.at(1).failures[0].find("no legal reading holds (ERRATA E-91; the device showed E-91 reference earlier): "
                                              "E-91 reference: byte 0 start"),
            std::string::npos)
      << r.vectors.at(1).failures[0];
  EXPECT_EQ(r.vectors.at(2).verdict, Verdict::kPass) << "a step that both sides pass shows neither";
}

// ERRATA E-45: a negative 32h target built from fields goes out '-' first
// while the device's spelling is unknown; a NAK that fails the step sends it
// again with the zeros left of the sign, and the spelling the device ACKs is
// its side for the rest of the run. A pinned profile sends its side's
// spelling at once; a target NAKed in both spellings fails, naming both.
TEST(Runner, ANegativeTargetGoesOutInTheSpellingTheDeviceAcks) {
  const Profile p = load_profile_file(default_profile_path()).profile.value();
  Step to_minus_five = send_command("auto_move", "3", {{"pol target", "-5.0"}}, Expectation::Kind::kAck);
  const std::vector<Vector> twice = {vector_with("first", {to_minus_five}, {"motion"}),
                                     vector_with("second", {to_minus_five}, {"motion"})};
  struct Sent {
    std::vector<std::string> targets;  // each 32h's bytes 4-8, in order
    RunResult result;
  };
  auto run = [&](std::optional<ReadingSide> device, std::optional<ReadingSide> pin) {
    Profile d = p, m = p;
    if (device) d.readings["E-45"] = *device;
    if (pin) m.readings["E-45"] = *pin;
    auto t = make_in_process_transport({d}, {});
    RunOptions o;
    o.allow_motion = true;
    o.record_transcripts = true;
    Sent s{{}, Runner(*t, m, o).run(twice)};
    for (const auto& v : s.result.vectors)
      for (const auto& e : v.transcript)
        if (e.sent && e.bytes.size() == 16 && e.bytes[2] == 0x32) s.targets.emplace_back(e.bytes.begin() + 4, e.bytes.begin() + 9);
    return s;
  };
  const Sent learned = run(ReadingSide::kOther, std::nullopt);
  for (const auto& v : learned.result.vectors) EXPECT_EQ(v.verdict, Verdict::kPass) << v.id;
  EXPECT_EQ(learned.targets, (std::vector<std::string>{"-0050", "00-50", "00-50"})) << "NAKed once, then the device's spelling";
  EXPECT_EQ(run(ReadingSide::kReference, std::nullopt).targets, (std::vector<std::string>{"-0050", "-0050"}));
  EXPECT_EQ(run(ReadingSide::kOther, ReadingSide::kOther).targets, (std::vector<std::string>{"00-50", "00-50"}));
  const Sent wrong_pin = run(ReadingSide::kOther, ReadingSide::kReference);
  EXPECT_EQ(wrong_pin.targets, (std::vector<std::string>{"-0050", "-0050"})) << "a pinned side is never sent the other way";
  EXPECT_EQ(wrong_pin.result.vectors.at(0).verdict, Verdict::kFail);
  // Out of the feed's range (-90.0 to 90.0): NAKed in both spellings.
  to_minus_five.command->fields["pol target"] = "-95.0";
  auto t = make_in_process_transport({p}, {});
  RunOptions o;
  o.allow_motion = true;
  const RunResult out = Runner(*t, p, o).run({vector_with("out", {to_minus_five}, {"motion"})});
  ASSERT_EQ(out.vectors.at(0).verdict, Verdict::kFail);
  EXPECT_NE(out.vectors.at(0).failures[0].find("; sent again with the zeros left of the sign (ERRATA E-45): expected an ACK"),
            std::string::npos)
      << out.vectors.at(0).failures[0];
}

TEST(Runner, PassFailSkipAndLiveness) {
  auto status = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  status.expect.fields.push_back(matcher("start", FieldMatcher::Kind::kEq, {"0x06"}));
  auto silent = send_raw("02 {addr} 31 03 00", Expectation::Kind::kSilence);
  auto wrong = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);
  auto motion = send_command("jog", "E", {{"speed", "F"}, {"duration", "50"}}, Expectation::Kind::kAck);
  RunResult r = run_in_process({vector_with("a-status", {status}), vector_with("b-bad-lrc", {silent}),
                                vector_with("c-wrong", {wrong}), vector_with("d-motion", {motion}, {"motion"})});
  ASSERT_EQ(r.vectors.size(), 4u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass);
  EXPECT_EQ(r.vectors[1].verdict, Verdict::kPass);
  EXPECT_EQ(r.vectors[2].verdict, Verdict::kFail);
  EXPECT_NE(r.vectors[2].failures[0].find("expected a NAK reply, got ACK"), std::string::npos) << r.vectors[2].failures[0];
  EXPECT_EQ(r.vectors[3].verdict, Verdict::kSkip);
  EXPECT_NE(r.vectors[3].skip_reason.find("--allow-motion"), std::string::npos);
  // before the first vector, after the silence vector, after the last
  EXPECT_EQ(r.liveness.size(), 3u);
  EXPECT_EQ(r.exit_code(), 1);
  EXPECT_FALSE(r.vectors[0].transcript.empty());
}

// A signal stops the run after the vector it came during: the run is
// aborted, says which signal, and exits 4 whatever failed before it (the run
// has no verdict); a run that is not stopped exits 1 on the same failure.
TEST(Runner, ASignalStopsTheRunWithItsOwnExitCode) {
  const auto wrong = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);
  const auto status = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  const std::vector<Vector> vectors = {vector_with("a-wrong", {wrong}), vector_with("b-status", {status})};
  for (const std::string_view signal : {"SIGINT", "SIGTERM"}) {
    RunOptions o;
    std::size_t results = 0;
    o.on_result = [&](const VectorResult&) { ++results; };
    o.stop = [&]() -> std::string_view { return results > 0 ? signal : ""; };
    const RunResult r = run_in_process(vectors, {}, o);
    ASSERT_EQ(r.vectors.size(), 1u) << signal;
    EXPECT_EQ(r.vectors[0].verdict, Verdict::kFail);
    EXPECT_TRUE(r.aborted);
    EXPECT_EQ(r.stopped_by, signal);
    EXPECT_EQ(r.abort_reason, "stopped by " + std::string(signal));
    EXPECT_EQ(r.exit_code(), kStoppedExitCode) << signal;
  }
  const RunResult not_stopped = run_in_process(vectors);
  EXPECT_TRUE(not_stopped.stopped_by.empty());
  EXPECT_EQ(not_stopped.exit_code(), 1);
}

// The reference controller behind a network whose round trip is `delay`
// (on a virtual clock): every reply shows up `delay` after its request. It
// reports `reported` as its measured round trip, as Rfc2217Line does.
class DistantTransport final : public Transport {
 public:
  DistantTransport(std::chrono::milliseconds delay, std::chrono::microseconds reported)
      : inner_({load_profile_file(default_profile_path()).profile.value()}), delay_(delay), reported_(reported) {}
  void send(ByteView chars, std::span<const std::size_t> wrong_parity = {}) override {
    inner_.send(chars, wrong_parity);
    due_ = inner_.now() + delay_;
  }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override {
    if (inner_.pending() > 0 && inner_.now() < due_)
      inner_.pause(std::min(timeout, std::chrono::ceil<std::chrono::milliseconds>(due_ - inner_.now())));
    else if (inner_.pending() == 0)
      inner_.pause(timeout);
    return inner_.pending() > 0 && inner_.now() >= due_ ? inner_.receive(buf, std::chrono::milliseconds{0}) : 0;
  }
  void pause(std::chrono::milliseconds d) override { inner_.pause(d); }
  TimePoint now() const override { return inner_.now(); }
  bool can_send_parity_errors() const override { return true; }
  int baud() const override { return 9600; }
  std::string describe() const override { return "reference controller behind a slow network"; }
  std::chrono::microseconds network_round_trip() const override { return reported_; }

 private:
  InProcessTransport inner_;
  std::chrono::milliseconds delay_;
  std::chrono::microseconds reported_;
  TimePoint due_{};
};

// Behind a terminal server the first replies come a network round trip
// later than the profile's turnaround says; the round trip measured when the
// line was opened is waited for from the first command on.
TEST(Runner, TheNetworksRoundTripIsWaitedForFromTheFirstCommand) {
  Profile p = load_profile_file(default_profile_path()).profile.value();
  auto status = send_command("status", "", {}, Expectation::Kind::kAck);
  for (const bool reported : {true, false}) {
    DistantTransport t(std::chrono::milliseconds{400}, std::chrono::microseconds{reported ? 400000 : 0});
    Runner runner(t, p, RunOptions{});
    const RunResult r = runner.run({vector_with("a-status", {status})});
    if (reported) {
      EXPECT_FALSE(r.aborted) << r.abort_reason;
      ASSERT_EQ(r.vectors.size(), 1u);
      EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass) << (r.vectors[0].failures.empty() ? "" : r.vectors[0].failures[0]);
    } else {
      // Not told of the network, the runner gives up before the first reply
      // comes: the liveness check before the first vector finds no device.
      EXPECT_TRUE(r.aborted);
      EXPECT_NE(r.abort_reason.find("the device did not answer"), std::string::npos) << r.abort_reason;
    }
  }
}

// Each frame of a transcript carries its description as the runner made it
// when it sent or received the frame: the reports show those fields.
TEST(Runner, TranscriptFramesCarryTheirFieldsAsDescribed) {
  auto status = send_command("status", "", {}, Expectation::Kind::kAck);
  RunResult r = run_in_process({vector_with("a-status", {status})});
  ASSERT_EQ(r.vectors.size(), 1u);
  std::size_t described = 0;
  for (const auto& t : r.vectors[0].transcript) {
    if (t.bytes.empty()) continue;
    const FrameDescription d = describe_frame(t.bytes);
    ASSERT_EQ(t.fields.size(), d.fields.size()) << t.note;
    for (std::size_t i = 0; i < d.fields.size(); ++i) {
      EXPECT_EQ(t.fields[i].name, d.fields[i].name);
      EXPECT_EQ(t.fields[i].raw, d.fields[i].raw);
      EXPECT_EQ(t.fields[i].meaning, d.fields[i].meaning);
    }
    EXPECT_EQ(t.note, d.summary);
    ++described;
  }
  EXPECT_GE(described, 2u) << "the status poll and its reply";
}

TEST(Runner, AShouldFailureFailsTheRunOnlyWhenStrict) {
  Vector v = vector_with("should-wrong", {send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak)});
  v.level = Level::kShould;
  const RunResult lenient = run_in_process({v});
  ASSERT_EQ(lenient.vectors.size(), 1u);
  EXPECT_EQ(lenient.vectors[0].verdict, Verdict::kFail);
  EXPECT_EQ(lenient.exit_code(), 0) << "should warns";
  RunOptions o;
  o.strict = true;
  EXPECT_EQ(run_in_process({v}, {}, o).exit_code(), 1) << "--strict: should fails the run";
}

TEST(Runner, MotionRunsWithPermissionAndEndsWithAStop) {
  auto jog = send_command("jog", "W", {{"speed", "S"}, {"duration", "9999"}}, Expectation::Kind::kAck);
  RunOptions o;
  o.allow_motion = true;
  RunResult r = run_in_process({vector_with("jog", {jog}, {"motion"})}, {}, o);
  ASSERT_EQ(r.vectors.size(), 1u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass);
  const auto& last = r.vectors[0].transcript;
  bool stopped = false;
  for (const auto& t : last)
    if (t.sent && t.bytes.size() > 3 && t.bytes[2] == 0x33 && t.bytes[3] == 'X') stopped = true;
  EXPECT_TRUE(stopped) << "an X stop follows every motion vector";
}

TEST(Runner, KnownIssuesAndUnexpectedPasses) {
  auto nak = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);
  auto ack = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  RunOptions o;
  o.known_issues = {{"known-fail", "firmware 1.59 bug #12"}, {"fixed-now", "was broken"}};
  RunResult r = run_in_process({vector_with("known-fail", {nak}), vector_with("fixed-now", {ack})}, {}, o);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kKnownFailure);
  EXPECT_EQ(r.vectors[1].verdict, Verdict::kUnexpectedPass);
  EXPECT_EQ(r.exit_code(), 1) << "an unexpected pass fails the run, so the list cannot rot";
}

TEST(Runner, AFaultIsCaughtAndReproduced) {
  auto status = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  RunOptions o;
  o.repeat = 2;
  RunResult r = run_in_process({vector_with("status", {status})}, {Fault::kShortStatus}, o);
  ASSERT_EQ(r.vectors.size(), 1u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kFail);
  EXPECT_NE(r.vectors[0].failures[0].find("length"), std::string::npos) << r.vectors[0].failures[0];
  EXPECT_NE(r.vectors[0].failures.back().find("reproducible"), std::string::npos);
}

TEST(Runner, StoredDataIsBackedUpAndRestored) {
  Profile p = load_profile_file(default_profile_path()).profile.value();
  auto t = make_in_process_transport({p}, {});
  Controller& c = t->bus().controller(0);
  const auto preset1 = c.state().presets[0];
  ASSERT_TRUE(preset1.has_value());
  auto write1 = send_command("write_satellite", "", {{"index", "1"}, {"sat name", "OVERWRITE"}}, Expectation::Kind::kAck);
  auto write5 = send_command("write_satellite", "", {{"index", "5"}, {"sat name", "NEW"}}, Expectation::Kind::kAck);
  auto nav = send_command("write_navigation", "", {{"latitude", "1000"}, {"longitude", "1000"}}, Expectation::Kind::kAck);
  RunOptions o;
  o.allow_destructive = true;
  Runner runner(*t, p, o);
  RunResult r = runner.run({vector_with("3.10-overwrite", {write1, write5, nav}, {"destructive"})});
  ASSERT_EQ(r.vectors[0].verdict, Verdict::kPass) << r.vectors[0].failures[0];
  EXPECT_TRUE(r.backup.taken);
  EXPECT_EQ(r.backup.store_names.size(), p.store.size());
  EXPECT_EQ(c.state().presets[0]->data, preset1->data) << "preset 1 written back";
  EXPECT_EQ(c.state().navigation.latitude_min, p.navigation.latitude_min) << "navigation data written back";
  std::string notes;
  for (const auto& n : r.restore_notes) notes += n + "\n";
  EXPECT_NE(notes.find("preset satellite 5 was empty"), std::string::npos) << notes;
  EXPECT_NE(notes.find("STORE entry"), std::string::npos) << "the STORE list cannot be rebuilt remotely:\n" << notes;
  EXPECT_NE(r.backup.to_json().find("\"presets\""), std::string::npos);
}

// ---- the backup file (StoredDataBackup::to_json) ----------------------------------

// The backup as its file gives it back, read with the JSON library: every
// key, of its type, nothing else.
StoredDataBackup read_backup(const std::string& text) {
  const auto j = nlohmann::json::parse(text);  // throws on a text that is not JSON
  std::set<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.insert(k);
  EXPECT_EQ(keys, (std::set<std::string>{"store_names", "presets", "tles", "signposts", "navigation"})) << text;
  StoredDataBackup b;
  b.taken = true;
  b.store_names = j.at("store_names").get<std::vector<std::string>>();
  for (auto [list, slots] : {std::pair{"presets", &b.presets}, {"tles", &b.tles}, {"signposts", &b.signposts}})
    for (const auto& [slot, hex] : j.at(list).items()) (*slots)[static_cast<std::uint8_t>(std::stoi(slot))] = parse_hex(hex.get<std::string>()).value();
  if (!j.at("navigation").is_null()) b.navigation = parse_hex(j.at("navigation").get<std::string>()).value();
  return b;
}

void expect_same(const StoredDataBackup& read, const StoredDataBackup& b) {
  EXPECT_EQ(read.store_names, b.store_names);
  EXPECT_EQ(read.presets, b.presets);
  EXPECT_EQ(read.tles, b.tles);
  EXPECT_EQ(read.signposts, b.signposts);
  EXPECT_EQ(read.navigation, b.navigation);
}

// Every list full and empty, names with JSON's special characters, the
// navigation data there and not (no reply): the file reads back as the
// backup; a name that is not UTF-8 is written with U+FFFD, not thrown on.
TEST(Backup, EveryListFullAndEmptyReadsBackAsTheBackup) {
  StoredDataBackup full;
  full.store_names = {"SBS 6", "a\"b\\c", "tab\there", ""};
  full.presets = {{1, Bytes{'0', '1', 'G', '1', '9'}}, {20, Bytes{0x7F, 0x7F}}};
  full.tles = {{10, Bytes(138, '1')}};
  full.signposts = {{3, Bytes{'0', '3', ' '}}};
  full.navigation = Bytes{'7', '+', '4', '0', '0', '0'};
  StoredDataBackup empty;
  for (const auto* b : {&full, &empty}) expect_same(read_backup(b->to_json()), *b);
  EXPECT_EQ(read_backup(empty.to_json()).navigation, std::nullopt) << "null, not \"\"";

  StoredDataBackup latin1;
  latin1.store_names = {"caf\xe9"};
  EXPECT_EQ(read_backup(latin1.to_json()).store_names, std::vector<std::string>{"caf\xEF\xBF\xBD"});
}

class BackupFile : public test::TempDirTest {
 protected:
  BackupFile() : TempDirTest("sabus-backup-test") {}
  // A destructive run (one preset overwritten) against the in-process
  // controller with the backup written to `backup_path`.
  RunResult run(const std::string& backup_path, Controller** controller = nullptr) {
    static const Profile p = load_profile_file(default_profile_path()).profile.value();
    transport_ = make_in_process_transport({p}, {});
    if (controller) *controller = &transport_->bus().controller(0);
    RunOptions o;
    o.allow_destructive = true;
    o.backup_path = backup_path;
    Runner runner(*transport_, p, o);
    auto write1 = send_command("write_satellite", "", {{"index", "1"}, {"sat name", "OVERWRITE"}}, Expectation::Kind::kAck);
    return runner.run({vector_with("3.10-overwrite", {write1}, {"destructive"})});
  }
  std::unique_ptr<InProcessTransport> transport_;
};

// A backup already there may be the only copy of what the device held
// before an earlier run: the new one goes beside it, and reads back as
// the backup the run took.
TEST_F(BackupFile, NeverReplacesOneThereAndReadsBackAsTheBackup) {
  std::ofstream(path("backup.json")) << "the earlier run's";
  const RunResult r = run(path("backup.json"));
  ASSERT_FALSE(r.aborted) << r.abort_reason;
  EXPECT_EQ(test::slurp(path("backup.json")), "the earlier run's");
  EXPECT_EQ(r.backup.file, path("backup-2.json"));
  const StoredDataBackup read = read_backup(test::slurp(path("backup-2.json")));
  expect_same(read, r.backup);
  EXPECT_FALSE(read.presets.empty());
  EXPECT_FALSE(read.store_names.empty());
}

// No file, no destructive vector: the run stops before the first one, saying why.
TEST_F(BackupFile, ABackupThatCannotBeWrittenStopsTheRunBeforeTheDestructiveVector) {
  Controller* c = nullptr;
  const RunResult r = run(path("no/such/folder/backup.json"), &c);
  EXPECT_TRUE(r.aborted);
  EXPECT_NE(r.abort_reason.find("the stored-data backup cannot be written: " + path("no/such/folder/backup.json")),
            std::string::npos) << r.abort_reason;
  EXPECT_NE(r.abort_reason.find("no destructive vector runs without it"), std::string::npos) << r.abort_reason;
  EXPECT_TRUE(r.backup.file.empty());
  ASSERT_TRUE(c->state().presets[0].has_value());
  EXPECT_NE(c->state().presets[0]->data.name, "OVERWRITE") << "the destructive vector did not run";
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_), {}), 0) << "nothing written";
}

TEST(Runner, NoBackupWithoutDestructiveVectors) {
  RunResult r = run_in_process({vector_with("status", {send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck)})});
  EXPECT_FALSE(r.backup.taken);
  EXPECT_TRUE(r.restore_notes.empty());
}

TEST(Runner, UnreachableDeviceExits3) {
  // The only controller on the line is at 51: nothing answers the runner's 50.
  Profile device = load_profile_file(default_profile_path()).profile.value();
  const Profile expected = device;
  device.address = 51;
  auto t = make_in_process_transport({device});
  RunResult r = Runner(*t, expected, {}).run({vector_with("status", {send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck)})});
  EXPECT_EQ(r.exit_code(), 3);
  EXPECT_TRUE(r.aborted);
  EXPECT_TRUE(r.vectors.empty());
  ASSERT_FALSE(r.liveness.empty());
  EXPECT_FALSE(r.liveness.front().heard);
}

TEST(Runner, DeviceThatSendsBytesIsReachableAndItsVectorsRun) {
  // The status poll 02 32 31 03 02 is never answered (its check byte is taken
  // as a new STX), but the device type query is: the device is there, broken.
  RunResult r = run_in_process({vector_with("status", {send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck)})},
                               {Fault::kCheckByteStxRestarts});
  EXPECT_EQ(r.exit_code(), 1);
  EXPECT_FALSE(r.aborted);
  ASSERT_EQ(r.vectors.size(), 1u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kFail);
  ASSERT_FALSE(r.liveness.empty());
  EXPECT_FALSE(r.liveness.front().alive);
  EXPECT_TRUE(r.liveness.front().heard);
}

TEST(Runner, PollUntilTheMoveEnds) {
  auto move = send_command("auto_move", "2A", {{"azimuth", "-10.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck);
  Step poll = send_command("status", "", {}, Expectation::Kind::kAck);
  poll.kind = Step::Kind::kPoll;
  poll.timeout = std::chrono::milliseconds(60000);
  poll.until = {matcher("az status", FieldMatcher::Kind::kEq, {"0x50"}),
                matcher("azimuth", FieldMatcher::Kind::kRange, {}, -10.05, -9.95)};
  RunOptions o;
  o.allow_motion = true;
  RunResult r = run_in_process({vector_with("move-and-poll", {move, poll}, {"motion"})}, {}, o);
  ASSERT_EQ(r.vectors.size(), 1u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass) << (r.vectors[0].failures.empty() ? "" : r.vectors[0].failures[0]);
}

// ---- profile expressions, motion and capabilities --------------------------------

std::vector<Vector> shipped_vectors(const std::string& file) {
  std::vector<Vector> out;
  for (auto& f : load_vectors({default_vectors_dir() + "/" + file}).files)
    for (auto& v : f.vectors) out.push_back(std::move(v));
  return out;
}

TEST(Matchers, NearTakesTheAxisToleranceFromTheProfile) {
  Profile p;
  p.az.tolerance_deg = 0.3;
  FieldMatcher m = matcher("azimuth", FieldMatcher::Kind::kNear, {"{home(az) - 152.5}"});
  const ResolvedMatcher r = resolve_matcher(m, ExprContext{p});
  ASSERT_EQ(r.kind, Expansion::Kind::kValue) << r.problem;
  EXPECT_DOUBLE_EQ(r.matcher.low, -152.8);
  EXPECT_DOUBLE_EQ(r.matcher.high, -152.2);
  Captures c;
  EXPECT_FALSE(check_field(status_reply(), r.matcher, c)) << "-152.5 is within 0.3 of -152.5";
  p.az.tolerance_deg = 0.1;
  const auto off = check_field(status_reply(), resolve_matcher(matcher("azimuth", FieldMatcher::Kind::kNear, {"-152.8"}), ExprContext{p}).matcher, c);
  ASSERT_TRUE(off);
  EXPECT_NE(off->find("-152.8 within 0.1"), std::string::npos) << *off;
}

TEST(Matchers, JoggedIsWhereTheJogCanEndAndAHeadingIsModulo360) {
  Profile p;
  p.az.fast_dps = 2;
  FieldMatcher m = matcher("azimuth", FieldMatcher::Kind::kJogged, {"10", "1000"});
  m.jog = 'W';
  m.speed = 'F';
  const ResolvedMatcher r = resolve_matcher(m, ExprContext{p});
  ASSERT_EQ(r.kind, Expansion::Kind::kValue) << r.problem;
  // 1.9 to 2.1 deg from a reading of 10.0 (a position of 9.95 to 10.1 as
  // rounded or truncated): a reading of 11.8 to 12.1, never more than the
  // 21 tenths of the longest travel above the start's reading.
  EXPECT_EQ(r.matcher.readings.tenths, (motion::Readings{118, 121}));
  EXPECT_FALSE(r.matcher.readings.hundredths) << "a tenths display";
  EXPECT_DOUBLE_EQ(r.matcher.low, 11.8);
  EXPECT_DOUBLE_EQ(r.matcher.high, 12.1);
  EXPECT_NE(r.matcher.expected.find("'W' jog at fast speed"), std::string::npos) << r.matcher.expected;
  // A fluxgate heading of 359.9 is -0.1 next to a window around 0.
  p.az_sensor = AzSensor::kFluxgate;
  StatusReply reply;
  reply.status.azimuth = {fields::AzimuthReading::Kind::kHeading, 3599, 'T'};
  const auto d = describe_frame(encode_reply(reply, '2', 0x31).value());
  Captures c;
  EXPECT_FALSE(check_field(d, resolve_matcher(matcher("azimuth", FieldMatcher::Kind::kNear, {"0"}), ExprContext{p}).matcher, c));
}

FrameDescription extended_status_reply(std::int32_t az_tenths, std::int32_t az_digit) {
  ExtendedStatusReply r;
  r.status.azimuth = {fields::AzimuthReading::Kind::kPosition, az_tenths, 0};
  r.status.elevation = 300;
  r.az_hundredths = az_digit;
  return describe_frame(encode_reply(r, '2', 0x40).value());
}

// §3.17 bytes 49-50 (E-30): on a mount with 0.01 deg feedback a 40h
// position is read with its hundredths digit, which extends the magnitude,
// or for a negative position is added to tenths rounded down (E-87's other
// side: -0.4 and '7' is -0.47 or -0.33); a tenths field of 0.0 leaves the
// digit's sign to either.
TEST(Matchers, APositionIsReadWithItsHundredthsDigitOnAMountThatHasThem) {
  Profile p;
  p.hundredths = true;
  p.az.tolerance_deg = 0.1;
  Captures c;
  auto near = [&](const FrameDescription& d, const std::string& target) {
    return check_field(d, resolve_matcher(matcher("azimuth", FieldMatcher::Kind::kNear, {target}), ExprContext{p}).matcher, c);
  };
  const FrameDescription d = extended_status_reply(-4, 7);  // -0.47
  EXPECT_FALSE(near(d, "-0.47"));
  EXPECT_FALSE(near(d, "-0.57"));
  EXPECT_FALSE(near(d, "-0.33")) << "the digit added (E-87's other side)";
  const auto off = near(d, "-0.2");  // -0.30 to -0.10: neither -0.47 nor -0.33; the tenths alone (-0.4) not
  ASSERT_TRUE(off);
  EXPECT_NE(off->find("-0.30 to -0.10, read with the hundredths digit as -0.47"), std::string::npos) << *off;
  EXPECT_TRUE(near(d, "-0.6")) << "-0.70 to -0.50";
  EXPECT_FALSE(near(status_reply(), "-152.47")) << "31h has no digit: its tenths, -152.5, truncated from -152.37 to -152.57";
  EXPECT_FALSE(near(extended_status_reply(0, 4), "-0.04")) << "0.0 and 4: -0.04 or 0.04";
  EXPECT_FALSE(near(extended_status_reply(0, 4), "0.04"));
  EXPECT_TRUE(near(extended_status_reply(0, 4), "0.2"));
  FieldMatcher range = matcher("azimuth", FieldMatcher::Kind::kRange, {"-0.48", "-0.46"});
  EXPECT_FALSE(check_field(d, resolve_matcher(range, ExprContext{p}).matcher, c));
  range.values = {"-0.46", "-0.40"};
  EXPECT_TRUE(check_field(d, resolve_matcher(range, ExprContext{p}).matcher, c));
  p.hundredths = false;  // the digit is '0' there (E-30) and not read: the tenths are the reading
  EXPECT_FALSE(near(d, "-0.3"));
}

// A heading's turn is taken at most twice: from 1e300 a loop of turns never
// ended (1e300 - 360 is 1e300), and a poll's derived timeout is at most an hour.
TEST(Matchers, HugeNumbersOnAFluxgateAxisResolveAndTimeOutInAnHour) {
  Profile p;
  p.az_sensor = AzSensor::kFluxgate;
  FieldMatcher jogged = matcher("azimuth", FieldMatcher::Kind::kJogged, {"1e9", "1000"});
  jogged.jog = 'W';
  jogged.speed = 'F';
  EXPECT_EQ(resolve_matcher(jogged, ExprContext{p}).kind, Expansion::Kind::kValue);
  jogged.values[0] = "1e300";  // no reading in tenths: said so, at once
  const ResolvedMatcher huge = resolve_matcher(jogged, ExprContext{p});
  EXPECT_EQ(huge.kind, Expansion::Kind::kError);
  EXPECT_NE(huge.problem.find("not a reading in tenths"), std::string::npos) << huge.problem;
  const ResolvedMatcher range = resolve_matcher(matcher("azimuth", FieldMatcher::Kind::kRange, {"1e300", "0"}), ExprContext{p});
  EXPECT_EQ(range.kind, Expansion::Kind::kValue);
  EXPECT_GT(range.matcher.low, range.matcher.high) << "left as written: no position is in it";
  EXPECT_EQ(motion::longest_move(p.az, 1e20), std::chrono::milliseconds(motion::kLongestMoveMs));
  EXPECT_EQ(motion::longest_move(p.az, -1e300), std::chrono::milliseconds(motion::kLongestMoveMs));
  EXPECT_LT(motion::longest_move(p.az, 360), std::chrono::milliseconds(motion::kLongestMoveMs));
}

TEST(Runner, AMissingCapabilityIsASkipThatNamesIt) {
  Vector v = vector_with("needs-empty-slot", {send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck)});
  v.needs = {"{first_empty(presets)}"};
  Profile p = load_profile_file(default_profile_path()).profile.value();
  for (int i = 1; i <= 20; ++i)
    if (std::none_of(p.presets.begin(), p.presets.end(), [&](const PresetSatellite& s) { return s.index == i; }))
      p.presets.push_back({static_cast<std::uint8_t>(i), {}, false});
  auto t = make_in_process_transport({p});
  const RunResult r = Runner(*t, p, {}).run({v});
  ASSERT_EQ(r.vectors.size(), 1u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kSkip);
  EXPECT_EQ(r.vectors[0].skip_reason, "needs an empty preset satellite slot: the profile has every one filled");
}

// A mount that stops 1 deg short of its targets (the fault) fails the vector
// whose setup waits for the target as soon as its axes have stopped, not at a
// timeout: on a 20 deg/s mount, within 30 s of virtual time, move included.
// record_transcripts = false (sabus vectors sweep): the same verdicts and
// failure messages, a faulty controller's too, and no frame described.
TEST(Runner, WithoutTranscriptsTheVerdictsAreTheSame) {
  const Profile p = load_profile_file(default_profile_path()).profile.value();
  auto run = [&](bool record) {
    auto t = make_in_process_transport({p}, {Fault::kMoveStopsShort});
    RunOptions o;
    o.allow_motion = true;
    o.record_transcripts = record;
    return Runner(*t, p, o).run(shipped_vectors("3.3-auto-move.yaml"));
  };
  const RunResult with = run(true), without = run(false);
  ASSERT_EQ(with.vectors.size(), without.vectors.size());
  std::size_t failed = 0, described = 0;
  for (std::size_t i = 0; i < with.vectors.size(); ++i) {
    EXPECT_EQ(with.vectors[i].verdict, without.vectors[i].verdict) << with.vectors[i].id;
    EXPECT_EQ(with.vectors[i].failures, without.vectors[i].failures) << with.vectors[i].id;
    EXPECT_TRUE(without.vectors[i].transcript.empty()) << with.vectors[i].id;
    failed += with.vectors[i].verdict == Verdict::kFail;
    described += with.vectors[i].transcript.size();
  }
  EXPECT_GT(failed, 0u) << "the fault fails some vector";
  EXPECT_GT(described, 0u);
}

TEST(Runner, AMountThatStopsShortFailsEachSetupWithinSecondsNotAtATimeout) {
  Profile p = load_profile_file(default_profile_path()).profile.value();
  for (AxisProfile* a : {&p.az, &p.el, &p.pol}) {
    a->fast_dps = 20;
    a->slow_dps = 5;
  }
  auto t = make_in_process_transport({p}, {Fault::kMoveStopsShort});
  RunOptions o;
  o.allow_motion = true;
  const RunResult r = Runner(*t, p, o).run(shipped_vectors("3.4-jog.yaml"));
  std::size_t failed = 0;
  for (const auto& v : r.vectors) {
    if (v.verdict != Verdict::kFail) continue;
    ++failed;
    EXPECT_LT(v.duration_ms, 30000) << v.id << ": " << v.failures[0];
    EXPECT_NE(v.failures[0].find("the mount stopped (every axis idle for 3 polls) before the poll's condition held"),
              std::string::npos)
        << v.id << ": " << v.failures[0];
  }
  // Each failure leaves the mount 1 deg short; a later move of 1 deg or less
  // is not cut short, so not every vector fails.
  EXPECT_GE(failed, 3u);
}

TEST(Runner, APollWithoutATimeoutDerivesOneFromDistanceAndSpeed) {
  // Nothing moves the azimuth to 100: outside a moving vector the poll runs
  // to its derived timeout, (100 deg / 0.5 deg/s) x 1.5 + 10 s = 310 s.
  Step poll = send_command("status", "", {}, Expectation::Kind::kAck);
  poll.kind = Step::Kind::kPoll;
  poll.until = {matcher("azimuth", FieldMatcher::Kind::kNear, {"100"})};
  RunResult r = run_in_process({vector_with("never-there", {poll})});
  ASSERT_EQ(r.vectors.size(), 1u);
  ASSERT_EQ(r.vectors[0].verdict, Verdict::kFail);
  EXPECT_NE(r.vectors[0].failures[0].find("poll timed out after 310000 ms"), std::string::npos) << r.vectors[0].failures[0];
  // In a vector that moves the antenna, the stopped mount ends it in 3 polls.
  RunOptions o;
  o.allow_motion = true;
  r = run_in_process({vector_with("never-there-moving", {poll}, {"motion"})}, {}, o);
  ASSERT_EQ(r.vectors[0].verdict, Verdict::kFail);
  EXPECT_LT(r.vectors[0].duration_ms, 5000);
}

TEST(Runner, FromProfileWritesTheProfilesRecordBackAndChecksAReadAgainstIt) {
  Profile p = load_profile_file(default_profile_path()).profile.value();
  auto t = make_in_process_transport({p});
  Controller& c = t->bus().controller(0);
  auto overwrite = send_command("write_satellite", "", {{"index", "{first_filled(presets)}"}, {"sat name", "OTHER"}},
                                Expectation::Kind::kAck);
  Step restore = send_command("write_satellite", "", {}, Expectation::Kind::kAck);
  restore.command->from_profile = "{first_filled(presets)}";
  Step read = send_command("read_satellite", "", {{"index", "{first_filled(presets)}"}}, Expectation::Kind::kAck);
  read.expect.from_profile = "{first_filled(presets)}";
  RunOptions o;
  o.allow_destructive = true;
  Runner runner(*t, p, o);
  // Read against the profile after an overwrite: fails, naming the field.
  RunResult r = runner.run({vector_with("3.10-overwritten", {overwrite, read}, {"destructive"})});
  ASSERT_EQ(r.vectors[0].verdict, Verdict::kFail);
  EXPECT_NE(r.vectors[0].failures[0].find("sat name: the profile holds"), std::string::npos) << r.vectors[0].failures[0];
  // Written back from the profile, the read holds.
  r = runner.run({vector_with("3.10-restored", {overwrite, restore, read}, {"destructive"})});
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass) << r.vectors[0].failures[0];
  EXPECT_EQ(c.state().presets[0]->data, p.presets[0].data);
}

// A count computed from an expression (a wait, a timeout, an address byte, a
// slot, a jog's duration) outside its range fails the step and names the
// value; it is never converted to an integer it does not fit.
TEST(Runner, ExpandedCountsOutOfRangeFailTheStepNamingTheValue) {
  Step wait;
  wait.kind = Step::Kind::kWait;
  wait.timeout_text = "{2 * 1e12}";
  Step poll = send_command("status", "", {}, Expectation::Kind::kAck);
  poll.kind = Step::Kind::kPoll;
  poll.timeout_text = "{-5}";
  poll.until = {matcher("azimuth", FieldMatcher::Kind::kAny, {})};
  Step address = send_command("status", "", {}, Expectation::Kind::kSilence);
  address.modifiers.address_text = "{0x80}";
  Step slot = send_command("write_satellite", "", {}, Expectation::Kind::kAck);
  slot.command->from_profile = "{first_filled(presets) + 20}";
  Step jogged = send_command("status", "", {}, Expectation::Kind::kAck);
  FieldMatcher m = matcher("azimuth", FieldMatcher::Kind::kJogged, {"0", "{1e12}"});
  m.jog = 'E';
  m.speed = 'F';
  jogged.expect.fields = {m};
  RunOptions o;
  o.allow_destructive = true;
  const RunResult r = run_in_process({vector_with("wait", {wait}), vector_with("poll", {poll}),
                                      vector_with("address", {address}), vector_with("slot", {slot}, {"destructive"}),
                                      vector_with("jogged", {jogged})},
                                     {}, o);
  ASSERT_EQ(r.vectors.size(), 5u);
  const char* reasons[] = {"wait: 2000000000000 is out of range 1 to 3600000",
                           "poll: timeout_ms: -5 is out of range 1 to 3600000",
                           "modify.address: 128 is out of range 0 to 127",
                           "from_profile: 21 is out of range 1 to 20",
                           "jogged: ms 1000000000000 is out of range 0 to 3600000"};
  for (std::size_t i = 0; i < 5; ++i) {
    const VectorResult& v = r.vectors[i];
    EXPECT_NE(v.verdict, Verdict::kPass) << v.id;
    ASSERT_FALSE(v.failures.empty()) << v.id;
    EXPECT_NE(v.failures[0].find(reasons[i]), std::string::npos) << v.id << ": " << v.failures[0];
  }
}

TEST(Runner, AnsweredIsAnAckOrANakToTheFrameSentNeverSilence) {
  const auto nak = send_raw("02 {addr} 5a 03 {lrc}", Expectation::Kind::kAnswered);      // unknown code: NAK
  const auto ack = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAnswered);      // status: ACK
  const auto none = send_raw("02 {addr} 31 03 00", Expectation::Kind::kAnswered);        // bad LRC: silence
  const RunResult r = run_in_process({vector_with("nak", {nak}), vector_with("ack", {ack}), vector_with("none", {none})});
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass);
  EXPECT_EQ(r.vectors[1].verdict, Verdict::kPass);
  ASSERT_EQ(r.vectors[2].verdict, Verdict::kFail);
  EXPECT_NE(r.vectors[2].failures[0].find("got silence"), std::string::npos) << r.vectors[2].failures[0];
}

}  // namespace
}  // namespace sabus::harness

namespace sabus::harness {
namespace {

// The gate names a cause for every skip, and the run counts them; a run in
// which every vector was skipped checked nothing: exit code 5, not 0.
TEST(Runner, SkipsAreCountedByCauseAndARunThatRanNothingExits5) {
  const Step status = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  Vector above = vector_with("3.2-informative", {status});
  above.level = Level::kInformative;
  Vector other_profile = vector_with("3.2-other-profile", {status});
  other_profile.requires_ = {Requirement{"name", {"no-such-profile"}, {}}};
  const Vector moves = vector_with("3.2-moves", {status}, {"motion"});
  const Vector stores = vector_with("3.2-stores", {status}, {"destructive"});
  RunOptions o;
  o.max_level = Level::kMust;
  RunResult r = run_in_process({above, other_profile, moves, stores}, {}, o);
  ASSERT_EQ(r.vectors.size(), 4u);
  EXPECT_EQ(r.vectors[0].skip_cause, SkipCause::kLevel);
  EXPECT_EQ(r.vectors[1].skip_cause, SkipCause::kProfile);
  EXPECT_EQ(r.vectors[2].skip_cause, SkipCause::kMotion);
  EXPECT_EQ(r.vectors[3].skip_cause, SkipCause::kDestructive);
  EXPECT_EQ(r.skipped, 4u);
  EXPECT_EQ(r.skipped_by_cause,
            (std::map<SkipCause, std::size_t>{{SkipCause::kLevel, 1}, {SkipCause::kProfile, 1}, {SkipCause::kMotion, 1},
                                              {SkipCause::kDestructive, 1}}));
  EXPECT_EQ(r.ran(), 0u);
  EXPECT_EQ(r.exit_code(), kNothingRanExitCode);
  EXPECT_EQ(run_in_process({}).exit_code(), kNothingRanExitCode) << "no vector at all";
  RunResult one_ran = run_in_process({moves, vector_with("3.2-status", {status})});
  EXPECT_EQ(one_ran.vectors[1].skip_cause, SkipCause::kNone);
  EXPECT_EQ(one_ran.exit_code(), 0) << "one vector ran and passed";
  EXPECT_EQ(to_string(SkipCause::kParity), "parity");
}

// The in-process controller as a bench controller looks to the runner: not
// in-process, so nothing says it stands as its profile powers on.
class OnABench : public Transport {
 public:
  explicit OnABench(Transport& inner) : inner_(inner) {}
  void send(ByteView chars, std::span<const std::size_t> wrong_parity) override { inner_.send(chars, wrong_parity); }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override {
    return inner_.receive(buf, timeout);
  }
  void pause(std::chrono::milliseconds d) override { inner_.pause(d); }
  TimePoint now() const override { return inner_.now(); }
  bool is_a_line() const override { return false; }
  bool can_send_parity_errors() const override { return true; }
  int baud() const override { return 0; }
  std::string describe() const override { return "the reference controller, as on a bench"; }

 private:
  Transport& inner_;
};

// A `power-on` vector compares the status with the profile's power-on state
// (issue 32), which a bench controller need not stand in: it is skipped with
// the cause `fresh` unless the run says the device is fresh (--fresh-device),
// and runs in-process, where the controller is the profile's just powered on.
TEST(Runner, PowerOnVectorsRunOnlyOnAFreshDevice) {
  const Step status = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  const Vector power_on = vector_with("3.2-power-on", {status}, {"as-found", "power-on"});
  const Profile p = load_profile_file(default_profile_path()).profile.value();
  auto device = make_in_process_transport({p});
  OnABench bench(*device);
  const RunResult skipped = Runner(bench, p, RunOptions{}).run({power_on});
  ASSERT_EQ(skipped.vectors.size(), 1u);
  EXPECT_EQ(skipped.vectors[0].verdict, Verdict::kSkip);
  EXPECT_EQ(skipped.vectors[0].skip_cause, SkipCause::kFresh);
  EXPECT_NE(skipped.vectors[0].skip_reason.find("--fresh-device"), std::string::npos) << skipped.vectors[0].skip_reason;
  EXPECT_EQ(to_string(SkipCause::kFresh), "fresh");
  RunOptions fresh;
  fresh.fresh_device = true;
  EXPECT_EQ(Runner(bench, p, fresh).run({power_on}).vectors[0].verdict, Verdict::kPass);
  EXPECT_EQ(run_in_process({power_on}).vectors[0].verdict, Verdict::kPass) << "in-process: the profile's controller";
}

// ---- preconditions and the inconclusive verdict (TTCN-3 inconc) ------------------

const std::string kSearchRuns = "the search is still running when the stop goes out";

// 40h whose current mode must be SPIRAL_REMOTE_MODE (26h), a precondition:
// the reference controller at rest is in no search, so it does not hold.
Step search_running() {
  Step s = send_command("extended_status", "", {}, Expectation::Kind::kAck);
  s.expect.fields.push_back(matcher("current mode", FieldMatcher::Kind::kEq, {"0x26"}));
  s.precondition = kSearchRuns;
  return s;
}

// The command bytes of the frames a vector sent, in order.
std::vector<std::uint8_t> commands_sent(const VectorResult& v) {
  std::vector<std::uint8_t> out;
  for (const auto& t : v.transcript)
    if (t.sent && t.bytes.size() > 2) out.push_back(t.bytes[2]);
  return out;
}

// A precondition that does not hold: the vector ends inconclusive with why,
// the steps after it do not run, the teardown does; it fails nothing, and a
// run in which it is all that ran checked nothing (exit 5).
TEST(Runner, APreconditionNotMetEndsTheVectorInconclusiveAndTheTeardownRuns) {
  const Step status = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  const Step device_type = send_raw("02 {addr} 30 03 {lrc}", Expectation::Kind::kAck);
  Vector v = vector_with("3.7-stop", {status, search_running(), device_type});
  v.teardown = {send_raw("02 {addr} 35 30 30 03 {lrc}", Expectation::Kind::kAny)};
  RunResult r = run_in_process({v});
  ASSERT_EQ(r.vectors.size(), 1u);
  const VectorResult& got = r.vectors[0];
  EXPECT_EQ(got.verdict, Verdict::kInconclusive);
  EXPECT_EQ(to_string(got.verdict), "inconclusive");
  EXPECT_TRUE(got.failures.empty()) << got.failures[0];
  EXPECT_EQ(got.inconclusive_reason.rfind("precondition not met (" + kSearchRuns + "): byte ", 0), 0u) << got.inconclusive_reason;
  EXPECT_NE(got.inconclusive_reason.find("current mode: expected 0x26, got 0x"), std::string::npos) << got.inconclusive_reason;
  EXPECT_EQ(commands_sent(got), (std::vector<std::uint8_t>{0x31, 0x40, 0x35}))
      << "the status, the precondition's 40h, then the teardown's 35h; never the 30h after the precondition";
  EXPECT_EQ(r.inconclusive, 1u);
  EXPECT_EQ(r.passed + r.failed + r.known + r.unexpected + r.skipped, 0u);
  EXPECT_EQ(r.ran(), 0u) << "an inconclusive vector checked nothing";
  EXPECT_EQ(r.exit_code(), kNothingRanExitCode) << "every vector that ran ended inconclusive";

  RunResult with_a_pass = run_in_process({v, vector_with("3.2-status", {status})});
  EXPECT_EQ(with_a_pass.vectors[0].verdict, Verdict::kInconclusive);
  EXPECT_EQ(with_a_pass.vectors[1].verdict, Verdict::kPass);
  EXPECT_EQ(with_a_pass.exit_code(), 0) << "an inconclusive vector never fails the run";
  RunOptions strict;
  strict.strict = true;
  EXPECT_EQ(run_in_process({v, vector_with("3.2-status", {status})}, {}, strict).exit_code(), 0) << "nor under --strict";
}

// A precondition that holds is an ordinary step: the vector goes on and
// passes; in setup it ends the vector inconclusive the same way, named so.
TEST(Runner, APreconditionThatHoldsGoesOnAndOneInSetupIsNamedSo) {
  Step at_rest = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  at_rest.expect.fields.push_back(matcher("start", FieldMatcher::Kind::kEq, {"0x06"}));
  at_rest.precondition = "the controller answers a status poll";
  const Step device_type = send_raw("02 {addr} 30 03 {lrc}", Expectation::Kind::kAck);
  RunResult r = run_in_process({vector_with("3.2-holds", {at_rest, device_type})});
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kPass) << r.vectors[0].inconclusive_reason;
  EXPECT_TRUE(r.vectors[0].inconclusive_reason.empty());
  EXPECT_EQ(commands_sent(r.vectors[0]), (std::vector<std::uint8_t>{0x31, 0x30}));

  Vector in_setup = vector_with("3.7-setup", {device_type});
  in_setup.setup = {search_running()};
  RunResult s = run_in_process({in_setup});
  EXPECT_EQ(s.vectors[0].verdict, Verdict::kInconclusive);
  EXPECT_EQ(s.vectors[0].inconclusive_reason.rfind("setup: precondition not met (" + kSearchRuns + "): ", 0), 0u)
      << s.vectors[0].inconclusive_reason;
  EXPECT_EQ(commands_sent(s.vectors[0]), (std::vector<std::uint8_t>{0x40})) << "the steps did not run";
}

// precondition_reading: a precondition that only the other side of an
// ERRATA reading leaves unmet. Unpinned or pinned to that other side, not
// met is inconclusive as any precondition; pinned to the reference side, it
// is a failure that names the pin.
TEST(Runner, APreconditionOnAReadingIsStrictWhereTheProfilePinsTheReferenceSide) {
  Step s = search_running();
  s.precondition_reading = "E-100";
  const Vector v = vector_with("3.4-peaking", {s});
  Profile p = load_profile_file(default_profile_path()).profile.value();
  auto run_pinned = [&](std::optional<ReadingSide> side) {
    Profile model = p;
    if (side) model.readings["E-100"] = *side;
    auto t = make_in_process_transport({p}, {});
    return Runner(*t, model, {}).run({v});
  };
  for (const auto side : {std::optional<ReadingSide>{}, std::optional<ReadingSide>{ReadingSide::kOther}}) {
    const RunResult r = run_pinned(side);
    EXPECT_EQ(r.vectors[0].verdict, Verdict::kInconclusive);
    EXPECT_EQ(r.inconclusive, 1u);
  }
  const RunResult strict = run_pinned(ReadingSide::kReference);
  ASSERT_EQ(strict.vectors[0].verdict, Verdict::kFail);
  ASSERT_EQ(strict.vectors[0].failures.size(), 1u);
  EXPECT_EQ(strict.vectors[0].failures[0].rfind("precondition (" + kSearchRuns + ") held strictly, E-100 pinned to its reference side: byte ", 0), 0u)
      << strict.vectors[0].failures[0];
  EXPECT_EQ(strict.exit_code(), 1);
}

// A verdict only gets worse: a step that fails before the precondition makes
// the vector a failure (the precondition step never runs), and so does a
// teardown that fails after a precondition not met.
TEST(Runner, AFailureBeforeOrAfterAPreconditionStaysAFailure) {
  const Step wrong = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);
  RunResult before = run_in_process({vector_with("3.7-fails-first", {wrong, search_running()})});
  ASSERT_EQ(before.vectors.size(), 1u);
  EXPECT_EQ(before.vectors[0].verdict, Verdict::kFail);
  EXPECT_TRUE(before.vectors[0].inconclusive_reason.empty()) << before.vectors[0].inconclusive_reason;
  EXPECT_EQ(commands_sent(before.vectors[0]), (std::vector<std::uint8_t>{0x31}));
  EXPECT_EQ(before.failed, 1u);
  EXPECT_EQ(before.inconclusive, 0u);
  EXPECT_EQ(before.exit_code(), 1);

  Vector teardown_fails = vector_with("3.7-teardown-fails", {search_running()});
  teardown_fails.teardown = {wrong};
  RunResult after = run_in_process({teardown_fails});
  EXPECT_EQ(after.vectors[0].verdict, Verdict::kFail);
  ASSERT_EQ(after.vectors[0].failures.size(), 1u);
  EXPECT_EQ(after.vectors[0].failures[0].rfind("teardown: expected a NAK reply", 0), 0u) << after.vectors[0].failures[0];
  EXPECT_FALSE(after.vectors[0].inconclusive_reason.empty()) << "why the steps ended is kept";
  EXPECT_EQ(after.exit_code(), 1);
}

// A known issue says nothing of a vector that checked nothing: an
// inconclusive vector stays inconclusive (not a known failure, not an
// unexpected pass that would fail the run), and --repeat does not repeat it.
TEST(Runner, KnownIssuesAndRepeatsLeaveAnInconclusiveVectorAsItIs) {
  RunOptions o;
  o.known_issues = {{"3.7-stop", "vendor ticket 12"}};
  o.repeat = 2;
  RunResult r = run_in_process({vector_with("3.7-stop", {search_running()})}, {}, o);
  ASSERT_EQ(r.vectors.size(), 1u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kInconclusive);
  EXPECT_TRUE(r.vectors[0].known_issue_reason.empty()) << r.vectors[0].known_issue_reason;
  EXPECT_EQ(r.vectors[0].repeats, 0);
  EXPECT_TRUE(r.vectors[0].failures.empty()) << "no \"reproducible\" line: nothing failed";
  EXPECT_EQ(r.known + r.unexpected, 0u);
  EXPECT_EQ(r.exit_code(), kNothingRanExitCode);
  EXPECT_EQ(commands_sent(r.vectors[0]), (std::vector<std::uint8_t>{0x40})) << "run once";
}

// ERRATA E-90, §3.7: how long a search lasts is the controller's
// configuration. The reference controller's lasts 20 s, then drives back
// to where it began: stopped 1 s after it began (as shipped) each
// search-stop vector passes; stopped 10 minutes after, the search is over,
// the precondition right before the stop does not hold, and each vector
// ends inconclusive, not failed.
TEST(Runner, TheSearchStopVectorsAreInconclusiveWhenTheSearchHasEnded) {
  const std::set<std::string> ids = {"3.7-misc-x-stops-search", "3.7-misc-stop-key-stops-search",
                                     "3.7-misc-keypress-48h-stops-search"};
  std::vector<Vector> shipped;
  for (auto& f : load_vectors({default_vectors_dir()}).files)
    for (auto& v : f.vectors)
      if (ids.count(v.id)) shipped.push_back(v);
  ASSERT_EQ(shipped.size(), 3u);
  RunOptions o;
  o.allow_motion = true;
  const RunResult as_shipped = run_in_process(shipped, {}, o);
  for (const auto& v : as_shipped.vectors)
    EXPECT_EQ(v.verdict, Verdict::kPass) << v.id << ": " << (v.failures.empty() ? v.inconclusive_reason : v.failures[0]);

  std::vector<Vector> late = shipped;
  for (auto& v : late) {
    const auto wait = std::find_if(v.steps.begin(), v.steps.end(), [](const Step& s) { return s.kind == Step::Kind::kWait; });
    ASSERT_NE(wait, v.steps.end()) << v.id;
    wait->timeout = std::chrono::milliseconds(600000);
  }
  const RunResult r = run_in_process(late, {}, o);
  ASSERT_EQ(r.vectors.size(), 3u);
  for (const auto& v : r.vectors) {
    EXPECT_EQ(v.verdict, Verdict::kInconclusive) << v.id << ": " << (v.failures.empty() ? "" : v.failures[0]);
    EXPECT_EQ(v.inconclusive_reason.rfind("precondition not met (the search is still running when the stop goes out): byte ", 0), 0u)
        << v.id << ": " << v.inconclusive_reason;
    EXPECT_NE(v.inconclusive_reason.find("current mode: expected 0x26, got 0x"), std::string::npos) << v.inconclusive_reason;
  }
  EXPECT_EQ(r.exit_code(), kNothingRanExitCode);
}

// Against a controller that is gone when the run ends (the in-process one),
// nothing is backed up or restored.
TEST(Runner, NoBackupWhenTheDeviceDoesNotOutliveTheRun) {
  auto write5 = send_command("write_satellite", "", {{"index", "5"}, {"sat name", "NEW"}}, Expectation::Kind::kAck);
  RunOptions o;
  o.allow_destructive = true;
  o.backup_stored_data = false;
  RunResult r = run_in_process({vector_with("3.10-write", {write5}, {"destructive"})}, {}, o);
  ASSERT_EQ(r.vectors[0].verdict, Verdict::kPass) << r.vectors[0].failures[0];
  EXPECT_FALSE(r.backup.taken);
  EXPECT_TRUE(r.restore_notes.empty());
}

// ---- -x/--exitfirst -----------------------------------------------------------

// The run stops after the first vector that fails it: a must failure (with
// --strict a should one); a should failure before it does not stop it. The
// run is aborted, exits 1, and names the vectors that did not run.
TEST(Runner, ExitFirstStopsAfterTheFirstFailureThatFailsTheRunAndNamesWhatDidNotRun) {
  const auto ok = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kAck);
  const auto wrong = send_raw("02 {addr} 31 03 {lrc}", Expectation::Kind::kNak);
  Vector should = vector_with("b-should-wrong", {wrong});
  should.level = Level::kShould;
  const std::vector<Vector> vectors = {vector_with("a-ok", {ok}), should, vector_with("c-must-wrong", {wrong}),
                                       vector_with("d-ok", {ok}), vector_with("e-must-wrong", {wrong})};
  RunOptions o;
  o.exit_first = true;
  RunResult r = run_in_process(vectors, {}, o);
  ASSERT_EQ(r.vectors.size(), 3u);
  EXPECT_EQ(r.vectors[1].verdict, Verdict::kFail) << "a should failure does not stop the run";
  EXPECT_EQ(r.vectors[2].id, "c-must-wrong");
  EXPECT_TRUE(r.aborted);
  EXPECT_TRUE(r.stopped_by.empty()) << "the run's own stop, not the bench's";
  EXPECT_EQ(r.exit_code(), 1);
  EXPECT_EQ(r.not_run, (std::vector<std::string>{"d-ok", "e-must-wrong"}));
  EXPECT_EQ(r.abort_reason,
            "stopped at the first failure (--exitfirst): c-must-wrong failed; 2 vector(s) did not run: d-ok, e-must-wrong");
  // --strict: the should failure is the first that fails the run.
  o.strict = true;
  r = run_in_process(vectors, {}, o);
  ASSERT_EQ(r.vectors.size(), 2u);
  EXPECT_EQ(r.not_run.size(), 3u);
  // Without -x every vector runs; a failure of the last vector cuts nothing short.
  EXPECT_EQ(run_in_process(vectors).vectors.size(), 5u);
  o = {};
  o.exit_first = true;
  r = run_in_process({vector_with("a-ok", {ok}), vector_with("z-must-wrong", {wrong})}, {}, o);
  EXPECT_FALSE(r.aborted) << r.abort_reason;
  EXPECT_EQ(r.exit_code(), 1);
}

// ---- a mount that never shows rest (kShortRestPoll) ---------------------------

Step poll_for(std::vector<FieldMatcher> until) {
  Step poll = send_command("status", "", {}, Expectation::Kind::kAck);
  poll.kind = Step::Kind::kPoll;
  poll.timeout = std::chrono::milliseconds(60000);
  poll.until = std::move(until);
  return poll;
}

FieldMatcher at_rest(std::string field) { return matcher(std::move(field), FieldMatcher::Kind::kRegex, {"^0x[45]0$"}); }

// The status polls a vector sent.
std::size_t status_polls(const VectorResult& v) {
  return static_cast<std::size_t>(std::count_if(v.transcript.begin(), v.transcript.end(), [](const TranscriptEntry& e) {
    return e.sent && e.bytes.size() > 2 && e.bytes[2] == 0x31;
  }));
}

// The frames a vector sent, of any command.
std::size_t frames_sent(const VectorResult& v) {
  return static_cast<std::size_t>(
      std::count_if(v.transcript.begin(), v.transcript.end(), [](const TranscriptEntry& e) { return e.sent; }));
}

// Once a poll for rest has timed out with the azimuth still moving, later
// polls for its rest are short: their vectors end inconclusive, naming the
// vector whose poll timed out. A poll for the elevation's rest alone, which
// it shows, is a normal one and passes.
TEST(Runner, AfterAPollForRestTimedOutLaterOnesAreShortAndTheirVectorsInconclusive) {
  const auto move = send_command("auto_move", "2A", {{"azimuth", "-10.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck);
  RunOptions o;
  o.allow_motion = true;
  const RunResult r = run_in_process({vector_with("a-move", {move, poll_for({at_rest("az status")})}, {"motion"}),
                                      vector_with("b-az-rest", {poll_for({at_rest("az status")})}),
                                      vector_with("c-az-and-el-rest", {poll_for({at_rest("el status"), at_rest("az status")})}),
                                      vector_with("d-el-rest", {poll_for({at_rest("el status")})}),
                                      vector_with("e-az-rest", {poll_for({at_rest("az status")})})},
                                     {Fault::kNeverShowsRest}, o);
  ASSERT_EQ(r.vectors.size(), 5u);
  const auto& first = r.vectors[0];
  ASSERT_EQ(first.verdict, Verdict::kFail);
  EXPECT_GE(status_polls(first), 60u) << "a full poll: a minute of polls a second apart";
  EXPECT_EQ(first.failures[0].rfind("poll timed out after 60000 ms: byte 36 az status", 0), 0u) << first.failures[0];
  for (const auto* v : {&r.vectors[1], &r.vectors[2], &r.vectors[4]}) {
    EXPECT_EQ(v->verdict, Verdict::kInconclusive) << v->id << ": " << (v->failures.empty() ? "" : v->failures[0]);
    EXPECT_TRUE(v->failures.empty()) << v->id;
    EXPECT_NE(v->inconclusive_reason.find("the mount did not show rest in a short poll"), std::string::npos)
        << v->inconclusive_reason;
    EXPECT_NE(v->inconclusive_reason.find("the poll for rest of a-move timed out"), std::string::npos)
        << v->inconclusive_reason;
    // A short poll: one status request, before the vector's steps, and nothing else.
    EXPECT_EQ(v->inconclusive_reason.rfind("before the setup: ", 0), 0u) << v->inconclusive_reason;
    EXPECT_EQ(status_polls(*v), static_cast<std::size_t>(kShortRestPoll)) << v->id;
    EXPECT_EQ(frames_sent(*v), static_cast<std::size_t>(kShortRestPoll)) << v->id;
  }
  EXPECT_EQ(r.vectors[3].verdict, Verdict::kPass) << "the elevation shows rest";
  EXPECT_EQ(r.exit_code(), 1);
  EXPECT_EQ(r.inconclusive, 3u);
}

// A vector that needs the mount at rest (a poll for rest in its setup), after
// a poll for rest timed out on a mount that never shows rest: one status
// request before its setup, and nothing else (no setup move, no teardown, no
// 'X' stop from the runner: it moved nothing); it ends inconclusive, naming
// the vector whose poll timed out, and its steps are not judged.
TEST(Runner, AVectorThatNeedsRestSendsOneStatusRequestAndNothingElseWhileRestIsUnseen) {
  const auto move = send_command("auto_move", "2A", {{"azimuth", "-10.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck);
  const auto stop = send_command("jog", "X", {{"speed", "S"}, {"duration", "0"}}, Expectation::Kind::kAck);
  // Its step would fail (an ACK where a NAK is due) if it ran.
  Vector setup_rest = vector_with("b-setup-rest", {send_command("status", "", {}, Expectation::Kind::kNak)}, {"motion"});
  setup_rest.setup = {move, poll_for({at_rest("az status"), at_rest("el status")})};
  setup_rest.teardown = {stop};
  RunOptions o;
  o.allow_motion = true;
  const RunResult r = run_in_process({vector_with("a-move", {move, poll_for({at_rest("az status")})}, {"motion"}), setup_rest},
                                     {Fault::kNeverShowsRest}, o);
  ASSERT_EQ(r.vectors.size(), 2u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kFail);
  const auto& v = r.vectors[1];
  EXPECT_EQ(v.verdict, Verdict::kInconclusive) << (v.failures.empty() ? "" : v.failures[0]);
  EXPECT_TRUE(v.failures.empty());
  EXPECT_EQ(v.inconclusive_reason.rfind("before the setup: the mount did not show rest in a short poll of 1 request (byte 36 az status", 0),
            0u)
      << v.inconclusive_reason;
  EXPECT_NE(v.inconclusive_reason.find("the poll for rest of a-move timed out"), std::string::npos) << v.inconclusive_reason;
  EXPECT_EQ(frames_sent(v), 1u) << "one status request, nothing else";
  EXPECT_EQ(status_polls(v), 1u);
}

// A poll for rest that timed out while the mount was still on its way (a
// long move, a short timeout): the next vector that needs the azimuth at
// rest sends one status request and ends inconclusive; once a status request
// sees the azimuth at rest, the run is back to normal: that vector runs as
// it would have (its setup, its full polls), and a later poll for rest that
// times out fails its vector again. The status request comes before the
// vector's own steps: one that waits before its poll for rest (c-wait here
// is a vector of its own) would end inconclusive with the mount not yet at
// rest.
TEST(Runner, APollThatSeesRestPutsTheRunBackToNormal) {
  const auto far = send_command("auto_move", "2A", {{"azimuth", "150.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck);
  const auto back = send_command("auto_move", "2A", {{"azimuth", "-150.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck);
  Step brief = poll_for({at_rest("az status")});
  brief.timeout = std::chrono::milliseconds(3000);
  Step wait;
  wait.kind = Step::Kind::kWait;
  wait.timeout = std::chrono::milliseconds(3600000);
  RunOptions o;
  o.allow_motion = true;
  // The vector that sees rest moves in its setup and polls for rest there.
  Vector rest = vector_with("d-setup-rest", {send_command("status", "", {}, Expectation::Kind::kAck)});
  rest.setup = {send_command("auto_move", "2A", {{"azimuth", "140.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck),
                poll_for({at_rest("az status")})};
  // No motion tag on b, c and d: their vectors do not stop the mount after them.
  const RunResult r = run_in_process({vector_with("a-far", {far, brief}), vector_with("b-az-rest", {poll_for({at_rest("az status")})}),
                                      vector_with("c-wait", {wait}), rest, vector_with("e-back", {back, brief})},
                                     {}, o);
  ASSERT_EQ(r.vectors.size(), 5u);
  EXPECT_EQ(r.vectors[0].verdict, Verdict::kFail);
  EXPECT_EQ(r.vectors[1].verdict, Verdict::kInconclusive) << (r.vectors[1].failures.empty() ? "" : r.vectors[1].failures[0]);
  EXPECT_NE(r.vectors[1].inconclusive_reason.find("the poll for rest of a-far timed out"), std::string::npos);
  EXPECT_EQ(frames_sent(r.vectors[1]), 1u);
  EXPECT_EQ(r.vectors[2].verdict, Verdict::kPass);
  const auto& d = r.vectors[3];
  EXPECT_EQ(d.verdict, Verdict::kPass) << d.inconclusive_reason << (d.failures.empty() ? "" : d.failures[0]);
  // The status request, then the setup's move, its full poll (the move takes
  // seconds) and the step.
  ASSERT_FALSE(d.transcript.empty());
  EXPECT_EQ(d.transcript[0].bytes.at(2), 0x31);
  EXPECT_GT(status_polls(d), 3u);
  ASSERT_EQ(r.vectors[4].verdict, Verdict::kFail) << r.vectors[4].inconclusive_reason;
  EXPECT_EQ(r.vectors[4].failures[0].rfind("poll timed out after 3000 ms", 0), 0u) << r.vectors[4].failures[0];
}

// The same vectors on a controller without the fault: every poll sees rest.
TEST(Runner, PollsForRestPassOnAControllerThatShowsRest) {
  const auto move = send_command("auto_move", "2A", {{"azimuth", "-10.0"}, {"elevation", "45.0"}}, Expectation::Kind::kAck);
  RunOptions o;
  o.allow_motion = true;
  const RunResult r = run_in_process({vector_with("a-move", {move, poll_for({at_rest("az status")})}, {"motion"}),
                                      vector_with("b-az-rest", {poll_for({at_rest("az status")})})},
                                     {}, o);
  ASSERT_EQ(r.vectors.size(), 2u);
  for (const auto& v : r.vectors) EXPECT_EQ(v.verdict, Verdict::kPass) << v.id << ": " << (v.failures.empty() ? "" : v.failures[0]);
}

}  // namespace
}  // namespace sabus::harness
