// The runner on a line that garbles (RunOptions::retries, Verdict::kError):
// a fault the reference controller makes on purpose (garbles-replies: every
// third reply with a wrong check byte) puts a line fault exactly where a test
// wants it; the emulated line (InProcessTransport::set_line_faults) puts
// them at random, from a seed.
#include <gtest/gtest.h>

#include <algorithm>

#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::harness {
namespace {

Vector vector_with(std::string id, std::vector<Step> steps) {
  Vector v;
  v.id = std::move(id);
  v.paragraph = "3.2";
  v.steps = std::move(steps);
  return v;
}

Step send(std::string command, std::string form = "", std::map<std::string, std::string> fields = {},
          Expectation::Kind kind = Expectation::Kind::kAck) {
  Step s;
  s.command = StructuredCommand{std::move(command), std::move(form), std::move(fields), std::nullopt, {}, {}};
  s.expect.kind = kind;
  return s;
}

Step status() { return send("status"); }

Profile reference_profile() { return load_profile_file(default_profile_path()).profile.value(); }

struct Outcome {
  RunResult result;
  std::vector<std::uint8_t> commands;  // the command bytes the controller acted on, in order
};

Outcome run_with(const std::vector<Vector>& vectors, FaultSet faults, RunOptions o,
             std::optional<LineFaultSpec> line = std::nullopt) {
  const Profile p = reference_profile();
  auto t = make_in_process_transport({p}, faults);
  // A line, clean unless `line` says: without one the runner counts no line
  // faults (every fault is the device's), and these tests count them.
  t->set_line_faults(line.value_or(LineFaultSpec{0, kAllLineFaultKinds, 1}));
  t->bus().set_transcript(true);
  Outcome r;
  r.result = Runner(*t, p, o).run(vectors);
  // "command 02 32 31 03 .." lines of the bus log: what the controller executed.
  const std::string log = t->bus().take_log();
  for (std::size_t at = log.find("command 02 "); at != std::string::npos; at = log.find("command 02 ", at + 1))
    r.commands.push_back(static_cast<std::uint8_t>(std::stoi(log.substr(at + 14, 2), nullptr, 16)));
  return r;
}

RunOptions retries(int n) {
  RunOptions o;
  o.retries = n;
  return o;
}

// A mount that never shows rest, on a line that garbles a reply now and
// then: the poll for rest times out with line faults in its minutes, so the
// vector runs again; its short poll for rest (kShortRestPoll) sees no rest,
// and the timeout's failure stands rather than the rerun's inconclusive.
TEST(LineFaults, APollForRestThatTimedOutStillFailsWhenTheLineMadeTheVectorRunAgain) {
  Step poll = status();
  poll.kind = Step::Kind::kPoll;
  poll.timeout = std::chrono::milliseconds(20000);
  FieldMatcher rest;
  rest.field = "az status";
  rest.kind = FieldMatcher::Kind::kRegex;
  rest.values = {"^0x[45]0$"};
  poll.until = {rest};
  Vector v = vector_with("move", {send("auto_move", "2A", {{"azimuth", "-10.0"}, {"elevation", "45.0"}}), poll});
  v.tags = {"motion"};
  RunOptions o = retries(1);
  o.allow_motion = true;
  const Outcome r = run_with({v}, {Fault::kNeverShowsRest, Fault::kGarblesReplies}, o);
  const VectorResult& got = r.result.vectors.at(0);
  ASSERT_EQ(got.verdict, Verdict::kFail) << got.inconclusive_reason;
  EXPECT_EQ(got.failures.at(0).rfind("poll timed out after 20000 ms: byte 36 az status", 0), 0u) << got.failures[0];
  EXPECT_GT(got.line.faults, 0u);
  const bool noted = std::any_of(got.transcript.begin(), got.transcript.end(), [](const TranscriptEntry& e) {
    return e.note.find("the failure of the attempt before stands") != std::string::npos;
  });
  EXPECT_TRUE(noted);
  EXPECT_EQ(r.result.exit_code(), 1);
}

// The liveness check's two replies come first (30h, 31h): the vector's first
// reply is the run's third, which garbles-replies garbles.
TEST(LineFaults, AGarbledReplyToAReadIsSentAgainAndRecovered) {
  const Outcome r = run_with({vector_with("poll", {status()})}, {Fault::kGarblesReplies}, retries(1));
  ASSERT_EQ(r.result.vectors.size(), 1u);
  const VectorResult& v = r.result.vectors[0];
  EXPECT_EQ(v.verdict, Verdict::kPass) << (v.failures.empty() ? v.error_reason : v.failures[0]);
  EXPECT_EQ(v.line.faults, 1u);
  EXPECT_EQ(v.line.recovered, 1u);
  EXPECT_EQ(v.line.repeats, 1u);
  // liveness 30h 31h, the poll (garbled) and its repeat; the liveness
  // check after the last vector 30h 31h (the sixth reply, garbled) 31h.
  const std::vector<std::uint8_t> want = {0x30, 0x31, 0x31, 0x31, 0x30, 0x31, 0x31};
  EXPECT_EQ(r.commands, want);
  EXPECT_EQ(describe(v.line), "line: 1 fault in 2 exchanges, recovered");
  EXPECT_EQ(r.result.exit_code(), 0);
}

TEST(LineFaults, WithNoRetriesTheFailureSaysTheReplyShowedALineFault) {
  const Outcome r = run_with({vector_with("poll", {status()})}, {Fault::kGarblesReplies}, retries(0));
  const VectorResult& v = r.result.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kFail);
  EXPECT_NE(v.failures.at(0).find("the reply showed a line fault"), std::string::npos) << v.failures[0];
  EXPECT_EQ(v.line.faults, 1u);
  EXPECT_EQ(v.line.recovered, 0u);
  EXPECT_EQ(r.result.exit_code(), 1);
}

TEST(LineFaults, StrictLineFailsAFaultThatARepeatRecovered) {
  RunOptions o = retries(1);
  o.strict_line = true;
  const Outcome r = run_with({vector_with("poll", {status()})}, {Fault::kGarblesReplies}, o);
  const VectorResult& v = r.result.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kFail);
  EXPECT_NE(v.failures.at(0).find("--strict-line"), std::string::npos) << v.failures[0];
}

// 33h 'X' changes state, and a second one leaves the device as one does: it
// is sent again, but only after a status poll read the device back.
TEST(LineFaults, AStopIsSentAgainOnlyAfterAStatusPoll) {
  const Outcome r = run_with({vector_with("stop", {send("jog", "X", {{"speed", "S"}, {"duration", "0"}}, Expectation::Kind::kAck)})},
                         {Fault::kGarblesReplies}, retries(1));
  const VectorResult& v = r.result.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kPass) << (v.failures.empty() ? v.error_reason : v.failures[0]);
  // liveness 30h 31h, the stop (garbled), the read-back 31h, the stop
  // again; the liveness check after the last vector 30h (the sixth reply,
  // garbled: a read, sent again at once) 30h 31h.
  const std::vector<std::uint8_t> want = {0x30, 0x31, 0x33, 0x31, 0x33, 0x30, 0x30, 0x31};
  EXPECT_EQ(r.commands, want);
}

// A line that flips a bit of every reply to one command and of no other:
// each time another bit, as a line would, or each time the same, as a
// device that garbles its own reply would. The bit is in the check byte
// (after the header, which still shows the device took the frame) or in
// byte 0 (the header: the reply says nothing sure); `times` replies at most.
enum class Where : std::uint8_t { kCheckByte, kHeader };
class GarblingTransport final : public Transport {
 public:
  GarblingTransport(Transport& inner, std::uint8_t garbled, bool same_each_time, Where where = Where::kCheckByte,
                    unsigned times = ~0u)
      : inner_(inner), garbled_(garbled), same_(same_each_time), where_(where), times_(times) {}
  void send(ByteView chars, std::span<const std::size_t> wrong_parity) override {
    last_ = chars.size() > 2 ? chars[2] : 0;
    first_ = true;
    inner_.send(chars, wrong_parity);
  }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override {
    const std::size_t n = inner_.receive(buf, timeout);
    const bool whole = where_ == Where::kCheckByte || first_;
    if (n > 0 && last_ == garbled_ && whole && flips_ < times_) {
      buf[where_ == Where::kHeader ? 0 : n - 1] ^= static_cast<std::uint8_t>(1u << (same_ ? 0 : flips_ % 7));
      ++flips_;
    }
    if (n > 0) first_ = false;
    return n;
  }
  void pause(std::chrono::milliseconds d) override { inner_.pause(d); }
  TimePoint now() const override { return inner_.now(); }
  bool in_process() const override { return true; }
  bool is_a_line() const override { return true; }
  bool can_send_parity_errors() const override { return true; }
  int baud() const override { return 0; }
  std::string describe() const override { return "a line that garbles every reply to one command"; }

 private:
  Transport& inner_;
  std::uint8_t garbled_, last_ = 0;
  bool same_;
  Where where_;
  unsigned times_;
  unsigned flips_ = 0;
  bool first_ = false;
};

// What the controller acted on, from its bus log (run_with's reading).
std::vector<std::uint8_t> commands_in(InProcessTransport& device) {
  std::vector<std::uint8_t> out;
  const std::string log = device.bus().take_log();
  for (std::size_t at = log.find("command 02 "); at != std::string::npos; at = log.find("command 02 ", at + 1))
    out.push_back(static_cast<std::uint8_t>(std::stoi(log.substr(at + 14, 2), nullptr, 16)));
  return out;
}

// 48h: a key pressed twice is not a key pressed once (catalog acts_again).
// Its reply garbled after the header (here the check byte) still shows the
// device took the key: a step that checks no more than the header is judged
// by it, the key is not sent again, and nothing runs again.
TEST(LineFaults, AGarbledReplyWhoseHeaderShowsTheDeviceTookAKeyJudgesIt) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  device->bus().set_transcript(true);
  GarblingTransport line(*device, 0x48, false);
  RunOptions o = retries(1);
  o.record_transcripts = true;
  const RunResult r = Runner(line, p, o).run({vector_with("key", {send("keypress", "", {{"key code", "0x35"}})})});
  const VectorResult& v = r.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kPass) << v.error_reason << (v.failures.empty() ? "" : v.failures[0]);
  const std::vector<std::uint8_t> commands = commands_in(*device);
  EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x48), 1) << "the key was pressed once";
  EXPECT_EQ(v.line.faults, 1u);
  EXPECT_EQ(v.line.recovered, 1u);
  EXPECT_EQ(v.line.repeats, 0u);
  const bool noted = std::any_of(v.transcript.begin(), v.transcript.end(), [](const TranscriptEntry& e) {
    return e.note.find("the reply's header shows the device took the frame") != std::string::npos;
  });
  EXPECT_TRUE(noted) << "the transcript says how it was judged";
}

// With --retries 0 nothing is judged but the reply as it came.
TEST(LineFaults, WithNoRetriesAGarbledKeyReplyIsJudgedAsItCame) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  GarblingTransport line(*device, 0x48, false);
  const RunResult r = Runner(line, p, retries(0)).run({vector_with("key", {send("keypress", "", {{"key code", "0x35"}})})});
  const VectorResult& v = r.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kFail) << v.error_reason;
  EXPECT_NE(v.failures.at(0).find("the reply showed a line fault"), std::string::npos) << v.failures[0];
}

// A header the line garbled says nothing sure (a NAK made into an ACK would
// look alike): the key is not sent again in its attempt; the vector runs
// again from its setup, and the attempt the line left alone decides.
TEST(LineFaults, ACommandThatActsAgainIsNotSentTwiceTheVectorRunsAgain) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  device->bus().set_transcript(true);
  GarblingTransport line(*device, 0x48, false, Where::kHeader, 1);
  const RunResult r = Runner(line, p, retries(1)).run({vector_with("key", {send("keypress", "", {{"key code", "0x35"}})})});
  const VectorResult& v = r.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kPass) << v.error_reason << (v.failures.empty() ? "" : v.failures[0]);
  // liveness 30h 31h, the key (garbled, the attempt ends), the key of the second attempt
  const std::vector<std::uint8_t> commands = commands_in(*device);
  ASSERT_GE(commands.size(), 4u);
  EXPECT_EQ(std::vector<std::uint8_t>(commands.begin(), commands.begin() + 4), (std::vector<std::uint8_t>{0x30, 0x31, 0x48, 0x48}));
  EXPECT_EQ(v.line.faults, 1u);
  EXPECT_EQ(v.line.recovered, 1u) << "the clean attempt settled it";
  EXPECT_EQ(v.line.repeats, 0u) << "no exchange was sent again";
}

// A jog step that reads the azimuth of its status reply (§3.4) cannot be
// judged by the header alone: with the data garbled it is left unjudged,
// and the reason says the device took it.
TEST(LineFaults, AStepThatChecksTheDataIsNotJudgedByTheHeader) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  GarblingTransport line(*device, 0x33, false);
  Step jog = send("jog", "W", {{"speed", "S"}, {"duration", "0"}});
  jog.expect.fields.push_back(FieldMatcher{"azimuth", FieldMatcher::Kind::kAny, {}, 0, 0, "$from"});
  const RunResult r = Runner(line, p, retries(1)).run({vector_with("jog", {jog})});
  const VectorResult& v = r.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kError) << (v.failures.empty() ? "" : v.failures[0]);
  EXPECT_NE(v.error_reason.find("its header shows the device took it, and the step checks the data the line garbled"),
            std::string::npos)
      << v.error_reason;
}

TEST(LineFaults, ACommandThatActsAgainAndIsGarbledEveryTimeEndsInError) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  GarblingTransport line(*device, 0x48, false, Where::kHeader);
  const RunResult r = Runner(line, p, retries(1)).run({vector_with("key", {send("keypress", "", {{"key code", "0x35"}})})});
  ASSERT_EQ(r.vectors.size(), 1u) << r.abort_reason;
  const VectorResult& v = r.vectors[0];
  ASSERT_EQ(v.verdict, Verdict::kError) << (v.failures.empty() ? "" : v.failures[0]);
  EXPECT_NE(v.error_reason.find("not sent again: a second one would act again"), std::string::npos) << v.error_reason;
  EXPECT_EQ(v.line.repeats, 0u) << "never sent twice in an attempt";
  EXPECT_EQ(v.line.faults, 3u) << "one in each of the three attempts (retries + 1 runs again)";
  EXPECT_EQ(r.errors, 1u);
  EXPECT_EQ(r.exit_code(), kLineErrorExitCode);
}

TEST(LineFaults, AReadThatNeverGetsACleanReplyEndsInErrorNotFailed) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  GarblingTransport line(*device, 0x3F, false);
  const RunResult r = Runner(line, p, retries(2)).run({vector_with("pulses", {send("pulse_count")})});
  ASSERT_EQ(r.vectors.size(), 1u) << r.abort_reason;
  const VectorResult& v = r.vectors[0];
  EXPECT_EQ(v.verdict, Verdict::kError) << (v.failures.empty() ? "" : v.failures[0]);
  EXPECT_NE(v.error_reason.find("no clean reply in 3 tries"), std::string::npos) << v.error_reason;
  // Four attempts of the vector (retries 2: it runs again up to three
  // times), each with one exchange tried three times.
  EXPECT_EQ(v.line.faults, 4u);
  EXPECT_EQ(v.line.repeats, 8u);
  EXPECT_EQ(v.line.recovered, 0u);
  EXPECT_EQ(r.exit_code(), kLineErrorExitCode);
  // and the two liveness checks, 30h and 31h, before and after
  EXPECT_EQ(describe(r.line), "line: 4 faults in 16 exchanges, 0 recovered");
}

TEST(LineFaults, TheSameGarbledBytesOnARepeatAreTheDevicesReplyAndFail) {
  const Profile p = reference_profile();
  auto device = make_in_process_transport({p});
  GarblingTransport line(*device, 0x3F, true);
  const RunResult r = Runner(line, p, retries(2)).run({vector_with("pulses", {send("pulse_count")})});
  ASSERT_EQ(r.vectors.size(), 1u) << r.abort_reason;
  const VectorResult& v = r.vectors[0];
  ASSERT_EQ(v.verdict, Verdict::kFail) << v.error_reason;
  EXPECT_NE(v.failures.at(0).find("the same bytes on a repeat: the device's, not the line's"), std::string::npos)
      << v.failures[0];
  // One repeat tells, in each of the vector's four attempts: the same
  // bytes twice could still be a line's (any one of ten blanks lost alike),
  // so the vector runs again, and fails each time.
  EXPECT_EQ(v.line.repeats, 4u);
  EXPECT_EQ(v.line.faults, 0u) << "not the line's";
}

// Without a line (the in-process controller, no --line-faults) a garbled
// reply is the device's own: no line fault is counted, and the failure does
// not name a line.
TEST(LineFaults, WithoutALineNoLineFaultIsCounted) {
  const Profile p = reference_profile();
  auto t = make_in_process_transport({p}, {Fault::kGarblesReplies});
  const RunResult r = Runner(*t, p, retries(0)).run({vector_with("poll", {status()})});
  const VectorResult& v = r.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kFail);
  EXPECT_EQ(v.failures.at(0).find("line fault"), std::string::npos) << v.failures[0];
  EXPECT_EQ(v.line.faults, 0u);
  EXPECT_EQ(r.line.faults, 0u);
  EXPECT_EQ(r.line.exchanges, 0u) << "no line figures at all";
}

TEST(LineFaults, ANoisyLineGivesTheVerdictsOfACleanOne) {
  std::vector<Vector> vectors;
  for (int i = 0; i < 100; ++i) vectors.push_back(vector_with("poll-" + std::to_string(i), {status(), send("device_type")}));
  const Outcome clean = run_with(vectors, {}, retries(2));
  const Outcome noisy = run_with(vectors, {}, retries(2), LineFaultSpec{2e-3, kAllLineFaultKinds, 42});
  ASSERT_EQ(clean.result.vectors.size(), noisy.result.vectors.size());
  for (std::size_t i = 0; i < vectors.size(); ++i)
    EXPECT_EQ(noisy.result.vectors[i].verdict, clean.result.vectors[i].verdict)
        << vectors[i].id << ": " << noisy.result.vectors[i].error_reason
        << (noisy.result.vectors[i].failures.empty() ? "" : noisy.result.vectors[i].failures[0]);
  EXPECT_GT(noisy.result.line.faults, 0u) << "the line injected faults the runner saw";
  EXPECT_EQ(noisy.result.line.recovered, noisy.result.line.faults);
  EXPECT_EQ(clean.result.line.faults, 0u);
}

std::vector<Vector> survey_vector() {
  std::vector<Vector> out;
  for (auto& f : load_vectors({default_vectors_dir() + "/framing.yaml"}).files)
    for (auto& v : f.vectors)
      if (v.id == "framing-status-replies-not-garbled") out.push_back(std::move(v));
  return out;
}

TEST(LineSurvey, FailsAControllerThatGarblesItsOwnReplies) {
  const auto survey = survey_vector();
  ASSERT_EQ(survey.size(), 1u);
  const Outcome r = run_with(survey, {Fault::kGarblesReplies}, retries(1));
  const VectorResult& v = r.result.vectors.at(0);
  ASSERT_EQ(v.verdict, Verdict::kFail);
  EXPECT_NE(v.failures.at(0).find("the controller garbles its replies"), std::string::npos) << v.failures[0];
}

TEST(LineSurvey, PassesACleanControllerOnACleanAndOnANoisyLine) {
  const auto survey = survey_vector();
  ASSERT_EQ(survey.size(), 1u);
  EXPECT_EQ(run_with(survey, {}, retries(1)).result.vectors.at(0).verdict, Verdict::kPass);
  for (std::uint64_t seed : {1, 2, 3, 4, 5}) {
    const Outcome r = run_with(survey, {}, retries(1), LineFaultSpec{1e-3, kAllLineFaultKinds, seed});
    const VectorResult& v = r.result.vectors.at(0);
    EXPECT_EQ(v.verdict, Verdict::kPass) << "seed " << seed << ": " << (v.failures.empty() ? "" : v.failures[0]);
  }
}

}  // namespace
}  // namespace sabus::harness
