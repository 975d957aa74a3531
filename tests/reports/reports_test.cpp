// The report writers, from a run document built in the test.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "sabus/reports/diff.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"
#include "sample_run.hpp"

namespace sabus::reports {
namespace {

using namespace std::chrono_literals;

VectorRecord vector(std::string id, std::string outcome, std::string paragraph = "3.2", std::string level = "must") {
  VectorRecord v;
  v.id = std::move(id);
  v.outcome = std::move(outcome);
  v.paragraph = std::move(paragraph);
  v.level = std::move(level);
  v.duration_ms = 10;
  v.wall_ms = 0.25;
  if (v.outcome == "fail") v.failures = {"byte 36 az status: expected 0x57, got 0x44 (slow)"};
  if (v.outcome == "skip") v.skip_reason = "moves the antenna: needs --allow-motion";
  return v;
}

FrameRecord status_exchange(bool tx, const std::string& hex) {
  FrameRecord f;
  f.dir = tx ? "tx" : "rx";
  f.hex = hex;
  f.command = "status";
  if (tx) f.expect = f.path = "ack";
  return f;
}

RunDocument sample() {
  RunDocument d = test_documents::sample_header();
  d.status = "complete";
  d.vectors = {vector("a-pass", "pass"), vector("b-fail", "fail"), vector("c-skip", "skip", "3.10"),
               vector("d-known", "known failure", "1", "should")};
  d.vectors[0].transcript = {status_exchange(true, "02 32 31 03 02"), status_exchange(false, "06 32 31 30 03 00")};
  d.summary = Summary{1, 1, 1, 1, 0, 1};
  d.generator = "sabus 9.8.7-test";
  d.options = {{"level", "informative"}, {"seed", 42}, {"filters", {"3.*"}}, {"allow_motion", false}};
  return d;
}

// A field-by-field reply, as describe_frame gives it.
std::vector<Field> reply_fields() { return {{0, 0, "start", "0x06", "ACK", true}, {3, 3, "az status", "0x44", "slow", false}}; }

TEST(Console, ProgressLineShowsCountsElapsedAndRemaining) {
  const Progress p{10, 40, 7, 2, 1, 20s, "3.3-form2A-basic"};
  EXPECT_EQ(progress_line(p), "[10/40] 7 pass 2 fail 1 skip  0:20 elapsed  ~1:00 left  3.3-form2A-basic");
  EXPECT_EQ(progress_line(p, 20).size(), 20u) << "one terminal line";
  EXPECT_EQ(progress_line({0, 5, 0, 0, 0, 0ms, ""}), "[0/5] 0 pass 0 fail 0 skip  0:00 elapsed");
  EXPECT_EQ(clock_text(3725s), "1:02:05");
}

TEST(Console, FailureAndSummaryLines) {
  EXPECT_EQ(failure_line(vector("b-fail", "fail")), "FAIL b-fail §3.2 must: byte 36 az status: expected 0x57, got 0x44 (slow)");
  EXPECT_EQ(summary_line({5, 2, 3, 0, 1, 1}), "5 passed, 3 failed, 3 skipped");
  EXPECT_EQ(summary_line({5, 0, 3, 2, 0, 0}), "5 passed, 0 failed, 3 skipped, 2 known failures");
}

TEST(Console, OneVerdictLineAVectorWithTheReasonOrTheFailure) {
  EXPECT_EQ(verdict_line(vector("a-pass", "pass")), "PASS a-pass §3.2 must");
  EXPECT_EQ(verdict_line(vector("b-fail", "fail")), failure_line(vector("b-fail", "fail")));
  EXPECT_EQ(verdict_line(vector("c-skip", "skip", "3.10")), "SKIP c-skip §3.10 must: moves the antenna: needs --allow-motion");
  VectorRecord known = vector("d-known", "known failure");
  known.failures = {"length: expected 52 bytes, got 51"};
  known.known_issue = "vendor ticket 1234";
  EXPECT_EQ(verdict_line(known), "KNOWN d-known §3.2 must: length: expected 52 bytes, got 51 (known issue: vendor ticket 1234)");
  VectorRecord unexpected = vector("e-xpass", "unexpected pass");
  unexpected.known_issue = "vendor ticket 1234";
  EXPECT_EQ(verdict_line(unexpected), "FAIL e-xpass §3.2 must: passed but is listed as a known issue (vendor ticket 1234)");
  EXPECT_EQ(verdict_line(vector("b-fail", "fail"), true).rfind("\033[1;31mFAIL\033[0m b-fail §3.2 must: ", 0), 0u);
  EXPECT_EQ(verdict_line(vector("a-pass", "pass"), true), "\033[32mPASS\033[0m a-pass §3.2 must");
}

TEST(Console, SkipsByCauseInTheSummaryAndWhyNothingRan) {
  Summary s{173, 0, 279, 0, 0, 0};
  s.skipped_by_cause = {{"motion", 113}, {"destructive", 68}, {"profile", 98}};
  EXPECT_EQ(summary_line(s),
            "173 passed, 0 failed, 279 skipped (98 need another profile, 113 need --allow-motion, 68 need --allow-destructive)");
  Summary level{0, 0, 4, 1, 0, 0};
  level.skipped_by_cause = {{"level", 3}, {"parity", 1}};
  EXPECT_EQ(summary_line(level), "0 passed, 0 failed, 4 skipped (3 above --level, 1 need an 8N1 port), 1 known failures");
  // A document from before causes were recorded: no causes, or some unnamed.
  EXPECT_EQ(summary_line({5, 0, 3, 0, 0, 0}), "5 passed, 0 failed, 3 skipped");
  Summary partly{5, 0, 3, 0, 0, 0};
  partly.skipped_by_cause = {{"motion", 1}, {"", 2}};
  EXPECT_EQ(summary_line(partly), "5 passed, 0 failed, 3 skipped (1 need --allow-motion, 2 for other reasons)");

  Summary all_skipped{0, 0, 34, 0, 0, harness::kNothingRanExitCode};
  all_skipped.skipped_by_cause = {{"motion", 30}, {"profile", 4}};
  EXPECT_EQ(nothing_ran_reason(all_skipped), "all 34 vectors selected were skipped (4 need another profile, 30 need --allow-motion)");
  Summary one{0, 0, 1, 0, 0, harness::kNothingRanExitCode};
  one.skipped_by_cause = {{"destructive", 1}};
  EXPECT_EQ(nothing_ran_reason(one), "the one vector selected was skipped (1 need --allow-destructive)");
  EXPECT_EQ(nothing_ran_reason({0, 0, 0, 0, 0, harness::kNothingRanExitCode}), "no vector was selected");
}

// An inconclusive vector (TTCN-3 inconc): its own word and reason, a count
// in the summary when there is one, and a run of nothing else checked nothing.
TEST(Console, AnInconclusiveVectorIsNamedWithWhyAndCounted) {
  VectorRecord v = vector("3.7-stop", "inconclusive", "3.7");
  v.inconclusive_reason = "precondition not met (the search runs): byte 45 current mode: expected 0x26, got 0x20 (MANUAL_MODE)";
  EXPECT_EQ(verdict_word(v), "INCONCLUSIVE");
  EXPECT_EQ(verdict_line(v),
            "INCONCLUSIVE 3.7-stop §3.7 must: precondition not met (the search runs): byte 45 current mode: expected 0x26, got 0x20 "
            "(MANUAL_MODE)");
  EXPECT_EQ(verdict_line(v, true).rfind("\033[36mINCONCLUSIVE\033[0m 3.7-stop", 0), 0u);
  EXPECT_EQ(v.difference(), "inconclusive: " + v.inconclusive_reason);
  EXPECT_FALSE(v.is_failure());
  EXPECT_FALSE(v.is_skip());
  Summary s{5, 0, 3, 0, 0, 0};
  s.inconclusive = 2;
  EXPECT_EQ(summary_line(s), "5 passed, 0 failed, 3 skipped, 2 inconclusive");
  EXPECT_EQ(summary_line({5, 0, 3, 0, 0, 0}), "5 passed, 0 failed, 3 skipped") << "not named when there is none";
  Summary only{0, 0, 0, 0, 0, harness::kNothingRanExitCode};
  only.inconclusive = 1;
  EXPECT_EQ(nothing_ran_reason(only), "the one vector that ran ended inconclusive (its test purpose was not reached)");
  Summary with_skips{0, 0, 2, 0, 0, harness::kNothingRanExitCode};
  with_skips.inconclusive = 3;
  with_skips.skipped_by_cause = {{"motion", 2}};
  EXPECT_EQ(nothing_ran_reason(with_skips),
            "all 3 vectors that ran ended inconclusive (their test purposes were not reached); 2 skipped (2 need --allow-motion)");
}

// A vector in error (TTCN-3 error: the line left it unjudged): its own word
// and reason, a count in the summary, the run's line figures with the fault
// rate, a warning above a healthy line's, and what the errors mean for the
// run, also when nothing was judged.
TEST(Console, AVectorInErrorIsNamedWithWhatTheLineDidAndTheLineIsCounted) {
  VectorRecord v = vector("3.5-locate", "error", "3.5");
  v.error_reason = "step 2 (41h): no clean reply in 2 tries: bad check byte; not sent again: a second LOCATE acts again";
  EXPECT_EQ(verdict_word(v), "ERROR");
  EXPECT_EQ(verdict_line(v), "ERROR 3.5-locate §3.5 must: " + v.error_reason);
  EXPECT_EQ(verdict_line(v, true).rfind("\033[1;34mERROR\033[0m 3.5-locate", 0), 0u);
  EXPECT_EQ(v.difference(), "error: " + v.error_reason);
  EXPECT_FALSE(v.is_failure());
  EXPECT_FALSE(v.is_skip());
  EXPECT_FALSE(v.is_inconclusive());

  Summary s{5, 0, 3, 0, 0, harness::kLineErrorExitCode};
  s.errors = 2;
  EXPECT_EQ(summary_line(s), "5 passed, 0 failed, 3 skipped, 2 errors");
  s.errors = 1;
  EXPECT_EQ(summary_line(s), "5 passed, 0 failed, 3 skipped, 1 error");
  EXPECT_EQ(line_error_text(s), "1 vector ended in error: the line, not the firmware, left it unjudged");
  s.errors = 2;
  EXPECT_EQ(line_error_text(s), "2 vectors ended in error: the line, not the firmware, left them unjudged");
  EXPECT_EQ(line_error_text({5, 0, 3, 0, 0, 0}), "") << "none in error";
  Summary none_judged{0, 0, 4, 0, 0, harness::kLineErrorExitCode};
  none_judged.errors = 3;
  EXPECT_EQ(line_error_text(none_judged),
            "nothing was judged: all 3 vectors that ran ended in error: the line, not the firmware, left them unjudged");
  none_judged.errors = 1;
  EXPECT_EQ(line_error_text(none_judged),
            "nothing was judged: the one vector that ran ended in error: the line, not the firmware, left it unjudged");
  none_judged.inconclusive = 2;
  EXPECT_EQ(line_error_text(none_judged),
            "nothing was judged: 1 vector ended in error (the line, not the firmware, left it unjudged), 2 inconclusive");

  // The line figures: none when no exchange was counted, the rate always
  // beside them, the warning only above a healthy line's rate.
  Summary line{5, 0, 0, 0, 0, 0};
  EXPECT_EQ(line_text(line), "");
  EXPECT_EQ(line_warning(line), "");
  line.line = {1412, 3, 3, 3};
  EXPECT_EQ(line_text(line), "line: 3 faults in 1,412 exchanges, all recovered (fault rate 0.21%)");
  EXPECT_EQ(line_warning(line), "");
  line.line = {1000, 0, 0, 0};
  EXPECT_EQ(line_text(line), "line: 0 faults in 1,000 exchanges (fault rate 0.00%)");
  line.line = {100, 1, 1, 1};
  EXPECT_EQ(line_warning(line), "") << "exactly a healthy line's rate is no warning";
  line.line = {100, 2, 1, 2};
  EXPECT_EQ(line_text(line), "line: 2 faults in 100 exchanges, 1 recovered (fault rate 2.00%)");
  EXPECT_EQ(line_warning(line),
            "the line's fault rate 2.00% is above a healthy line's 1.00%: check the cable, the adapter and the port settings; "
            "failures on such a line may be the line's");
}

// The verdict of a run whose only trouble is vectors in error (exit 6) is
// ERROR: neither PASS nor FAIL.
TEST(Console, ARunExitingSixIsNeitherAPassNorAFailure) {
  RunDocument d = sample();
  d.summary->exit_code = harness::kLineErrorExitCode;
  EXPECT_EQ(d.verdict(), "ERROR");
  d.summary->exit_code = 1;
  EXPECT_EQ(d.verdict(), "FAIL");
}

TEST(Json, RoundTripsEveryField) {
  RunDocument d = sample();
  d.vectors[0].quote = "the reply is 52 bytes";
  d.vectors[0].transcript[0].fields = {{0, 0, "start", "0x02", "STX", true}};
  d.vectors[0].transcript[0].form = "2A";
  d.vectors[2].skip_cause = "motion";
  d.summary->skipped_by_cause = {{"motion", 1}};
  std::string error;
  const auto back = from_json(nlohmann::json::parse(json_text(d)), error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(nlohmann::json::parse(json_text(*back)), nlohmann::json::parse(json_text(d)));
  EXPECT_EQ(back->vectors[0].transcript[0].fields[0].meaning, "STX");
  EXPECT_EQ(back->identity.firmware_version, "1.59");
  EXPECT_EQ(back->vectors[2].skip_cause, "motion");
  EXPECT_EQ(back->summary->skipped_by_cause, (std::map<std::string, std::size_t>{{"motion", 1}}));
}

TEST(Json, ReadsVersion1AndRejectsOtherDocuments) {
  const auto v1 = nlohmann::json::parse(R"({"schema":"sabus-run","schema_version":1,"status":"complete",
    "vectors":[{"id":"x","paragraph":"1","level":"must","outcome":"pass",
                "transcript":[{"t_ms":1.5,"dir":"tx","hex":"02 32 31 03 02","note":"n"}]}]})");
  std::string error;
  const auto d = from_json(v1, error);
  ASSERT_TRUE(d) << error;
  EXPECT_EQ(d->vectors[0].transcript[0].hex, "02 32 31 03 02");
  EXPECT_FALSE(d->identity.ok);
  EXPECT_FALSE(from_json(nlohmann::json::parse(R"({"schema":"other"})"), error));
  EXPECT_NE(error.find("schema"), std::string::npos);
  EXPECT_FALSE(from_json(nlohmann::json::parse(R"({"schema":"sabus-run","schema_version":1,"vectors":[{"id":"x"}]})"), error));
  EXPECT_NE(error.find("vectors[0] (x)"), std::string::npos) << error;
}

// A count that is not a whole number of its type is an error naming the key,
// not a cast (1e300) or a wrapped count (-1).
// Version 4 adds the inconclusive outcome; a version 3 document (none of
// its fields) still reads, and so does one of version 4.
TEST(Json, Version4CarriesInconclusiveAndVersion3StillReads) {
  RunDocument d = sample();
  d.vectors.push_back(vector("e-inconc", "inconclusive"));
  d.vectors.back().inconclusive_reason = "precondition not met (x): y";
  d.summary->inconclusive = 1;
  const nlohmann::json j = nlohmann::json::parse(json_text(d));
  EXPECT_EQ(j["schema_version"], kSchemaVersion);
  EXPECT_EQ(j["summary"]["inconclusive"], 1);
  EXPECT_EQ(j["vectors"][4]["inconclusive_reason"], "precondition not met (x): y");
  EXPECT_EQ(j["vectors"][0]["inconclusive_reason"], "");
  std::string error;
  const auto back = from_json(j, error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->vectors[4].inconclusive_reason, "precondition not met (x): y");
  EXPECT_EQ(back->summary->inconclusive, 1u);
  EXPECT_EQ(back->counts().inconclusive, 1u);
  EXPECT_EQ(nlohmann::json::parse(json_text(*back)), j);

  const auto v3 = nlohmann::json::parse(R"({"schema":"sabus-run","schema_version":3,"status":"complete",
    "summary":{"passed":1,"failed":0,"skipped":0,"known":0,"unexpected":0,"exit_code":0,"skipped_by_cause":{}},
    "vectors":[{"id":"x","paragraph":"1","level":"must","outcome":"pass","failures":[],"transcript":[]}]})");
  const auto old = from_json(v3, error);
  ASSERT_TRUE(old) << error;
  EXPECT_EQ(old->summary->inconclusive, 0u);
  EXPECT_EQ(old->vectors[0].inconclusive_reason, "");
  nlohmann::json v4 = v3;
  v4["schema_version"] = 4;
  EXPECT_TRUE(from_json(v4, error)) << error;
}

// Version 5 adds the error outcome and the line counts, each vector's
// always written (zeros when none was counted); a version 4 document (none
// of its fields) still reads, with no vector in error and no exchange
// counted, and a version above 5 does not.
TEST(Json, ErrorsAndLineCountsAreWrittenAndVersion4StillReads) {
  RunDocument d = sample();
  d.vectors.push_back(vector("e-error", "error"));
  d.vectors.back().error_reason = "step 1 (status): no clean reply in 2 tries: bad check byte";
  d.vectors.back().line = {2, 2, 0, 1};
  d.summary->errors = 1;
  d.summary->line = {1412, 3, 1, 2};
  const nlohmann::json j = nlohmann::json::parse(json_text(d));
  EXPECT_EQ(j["schema_version"], kSchemaVersion);
  EXPECT_EQ(j["summary"]["errors"], 1);
  EXPECT_EQ(j["summary"]["line"], nlohmann::json::parse(R"({"exchanges":1412,"faults":3,"recovered":1,"repeats":2,"surveyed":0})"));
  EXPECT_EQ(j["vectors"][4]["outcome"], "error");
  EXPECT_EQ(j["vectors"][4]["error_reason"], "step 1 (status): no clean reply in 2 tries: bad check byte");
  EXPECT_EQ(j["vectors"][4]["line"], nlohmann::json::parse(R"({"exchanges":2,"faults":2,"recovered":0,"repeats":1,"surveyed":0})"));
  EXPECT_EQ(j["vectors"][0]["error_reason"], "");
  EXPECT_EQ(j["vectors"][0]["line"], nlohmann::json::parse(R"({"exchanges":0,"faults":0,"recovered":0,"repeats":0,"surveyed":0})"))
      << "written when nothing was counted";
  std::string error;
  const auto back = from_json(j, error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->vectors[4].error_reason, "step 1 (status): no clean reply in 2 tries: bad check byte");
  EXPECT_EQ(back->vectors[4].line.faults, 2u);
  EXPECT_EQ(back->vectors[4].line.repeats, 1u);
  EXPECT_EQ(back->summary->errors, 1u);
  EXPECT_EQ(back->summary->line.exchanges, 1412u);
  EXPECT_EQ(back->summary->line.recovered, 1u);
  EXPECT_EQ(back->counts().errors, 1u);
  EXPECT_EQ(back->counts().line.exchanges, 1412u) << "the run's, not the vectors' sum";
  EXPECT_EQ(nlohmann::json::parse(json_text(*back)), j);

  const auto v4 = nlohmann::json::parse(R"({"schema":"sabus-run","schema_version":4,"status":"complete",
    "summary":{"passed":1,"failed":0,"skipped":0,"known":0,"unexpected":0,"inconclusive":0,"exit_code":0,"skipped_by_cause":{}},
    "vectors":[{"id":"x","paragraph":"1","level":"must","outcome":"pass","failures":[],"inconclusive_reason":"","transcript":[]}]})");
  const auto old = from_json(v4, error);
  ASSERT_TRUE(old) << error;
  EXPECT_EQ(old->summary->errors, 0u);
  EXPECT_EQ(old->summary->line.exchanges, 0u);
  EXPECT_EQ(old->vectors[0].error_reason, "");
  EXPECT_EQ(old->vectors[0].line.exchanges, 0u);
  EXPECT_EQ(line_text(old->counts()), "") << "no line figures for a run that counted none";
  nlohmann::json v8 = v4;
  v8["schema_version"] = kSchemaVersion + 1;
  EXPECT_FALSE(from_json(v8, error));
  EXPECT_NE(error.find("schema_version: " + std::to_string(kSchemaVersion + 1) + " is not 1 to " +
                       std::to_string(kSchemaVersion)),
            std::string::npos)
      << error;
}

// Version 6: the line survey's garbled replies are counted apart
// (`surveyed`), so a run whose faults were all recovered says so; a
// document read from an older version is written in this version's layout,
// with this version's number.
TEST(Json, Version6CountsTheSurveysGarbledRepliesApartAndOlderDocumentsAreWrittenAsVersion6) {
  std::string error;
  // the failing paths first: counts no run could have counted
  for (const auto& [line, why] : std::vector<std::pair<std::string, std::string>>{
           {R"({"exchanges":10,"faults":6,"recovered":6,"repeats":0,"surveyed":5})", "6 faults and 5 surveyed in 10 exchanges"},
           {R"({"exchanges":10,"faults":0,"recovered":0,"repeats":0,"surveyed":-1})", "surveyed"},
           {R"({"exchanges":10,"faults":0,"recovered":0,"repeats":0,"surveyed":"2"})", "surveyed"}}) {
    auto doc = nlohmann::json::parse(R"({"schema":"sabus-run","schema_version":6,"status":"complete",
      "vectors":[{"id":"x","paragraph":"1","level":"must","outcome":"pass","failures":[],"transcript":[]}]})");
    doc["vectors"][0]["line"] = nlohmann::json::parse(line);
    EXPECT_FALSE(from_json(doc, error)) << line;
    EXPECT_NE(error.find(why), std::string::npos) << line << ": " << error;
  }
  RunDocument d = sample();
  d.summary->line = {900, 31, 31, 20, 2};
  const nlohmann::json j = nlohmann::json::parse(json_text(d));
  EXPECT_EQ(j["summary"]["line"]["surveyed"], 2);
  const auto back = from_json(j, error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->summary->line.surveyed, 2u);
  EXPECT_EQ(line_text(back->counts()),
            "line: 31 faults in 900 exchanges, all recovered; 2 garbled replies counted by the line survey (fault rate 3.67%)");
  nlohmann::json v5 = j;
  v5["schema_version"] = 5;
  v5["summary"]["line"].erase("surveyed");
  const auto old = from_json(v5, error);
  ASSERT_TRUE(old) << error;
  EXPECT_EQ(old->summary->line.surveyed, 0u);
  EXPECT_EQ(nlohmann::json::parse(json_text(*old))["schema_version"], kSchemaVersion)
      << "the layout written is this version's: its number is too";
}

// A run that never ended (no summary) has the line counts of its vectors.
TEST(Json, WithoutASummaryTheLineCountsAreTheVectorsTogether) {
  RunDocument d = sample();
  d.summary.reset();
  d.vectors[0].line = {3, 1, 1, 1};
  d.vectors[1].line = {4, 2, 0, 1};
  const Summary c = d.counts();
  EXPECT_EQ(c.line.exchanges, 7u);
  EXPECT_EQ(c.line.faults, 3u);
  EXPECT_EQ(c.line.recovered, 1u);
  EXPECT_EQ(c.line.repeats, 2u);
}

TEST(Json, CountsAreWholeNumbersOfTheirType) {
  const std::string head = R"({"schema":"sabus-run","schema_version":1,"status":"complete","vectors":[{"id":"x","paragraph":"1","level":"must","outcome":"pass",)";
  for (const auto& [field, error_part] : std::vector<std::pair<std::string, std::string>>{
           {R"("repeats":1e300)", "repeats: expected a whole number -2147483648 to 2147483647, got 1e+300"},
           {R"("repeats":2.5)", "repeats: expected a whole number"},
           {R"("transcript":[{"t_ms":1,"dir":"rx","hex":"06","fields":[{"first":-1,"last":0,"name":"n"}]}])",
            "first: expected a whole number 0 to 18446744073709551615, got -1"}}) {
    std::string error;
    EXPECT_FALSE(from_json(nlohmann::json::parse(head + field + "}]}"), error)) << field;
    EXPECT_NE(error.find("vectors[0] (x)"), std::string::npos) << error;
    EXPECT_NE(error.find(error_part), std::string::npos) << error;
  }
  std::string error;
  const auto ok = from_json(nlohmann::json::parse(head + R"("repeats":3})" + "]}"), error);
  ASSERT_TRUE(ok) << error;
  EXPECT_EQ(ok->vectors[0].repeats, 3);
}

TEST(Junit, OneSuitePerParagraphFailuresWithTranscriptSkipsWithReason) {
  RunDocument d = sample();
  d.vectors[1].transcript = {status_exchange(true, "02 32 31 03 02")};
  const std::string x = junit_xml(d);
  EXPECT_NE(x.find("<testsuite name=\"§3.2\" tests=\"2\" failures=\"1\" errors=\"0\" skipped=\"0\""), std::string::npos) << x;
  EXPECT_NE(x.find("<testsuite name=\"§3.10\" tests=\"1\" failures=\"0\" errors=\"0\" skipped=\"1\""), std::string::npos);
  EXPECT_NE(x.find("02 32 31 03 02"), std::string::npos) << "the hex transcript";
  EXPECT_NE(x.find("<skipped message=\"moves the antenna: needs --allow-motion\"/>"), std::string::npos);
  EXPECT_NE(x.find("<skipped message=\"known issue: "), std::string::npos);
}

TEST(Junit, ClassnamesHaveOneDotSoJenkinsKeepsOnePackage) {
  const std::string x = junit_xml(sample());
  EXPECT_NE(x.find("<testcase name=\"b-fail\" classname=\"sabus.section_3_2_must\""), std::string::npos) << x;
  EXPECT_NE(x.find("classname=\"sabus.section_3_10_must\""), std::string::npos);
  EXPECT_NE(x.find("classname=\"sabus.section_1_should\""), std::string::npos);
  for (std::size_t at = x.find("classname=\""); at != std::string::npos; at = x.find("classname=\"", at + 1)) {
    const std::string name = x.substr(at + 11, x.find('"', at + 11) - at - 11);
    EXPECT_EQ(std::count(name.begin(), name.end(), '.'), 1) << name;
  }
}

TEST(Junit, WallClockTimesTransportTimeAndRunPropertiesFromTheDocument) {
  RunDocument d = sample();
  d.vectors[0].wall_ms = 1500;       // a vector that took 1.5 s of real time
  d.vectors[0].duration_ms = 340995;  // and 341 s of virtual time in-process
  const std::string x = junit_xml(d);
  EXPECT_NE(x.find("<testcase name=\"a-pass\" classname=\"sabus.section_3_2_must\" time=\"1.500\">"), std::string::npos) << x;
  EXPECT_NE(x.find("<property name=\"transport_time\" value=\"340.995\"/>"), std::string::npos);
  EXPECT_EQ(x.find("time=\"340.995\""), std::string::npos) << "virtual time is never a JUnit time";
  EXPECT_NE(x.find("<testsuites name=\"sabus\" tests=\"4\" failures=\"1\" errors=\"0\" time=\"1.501\">"), std::string::npos);
  for (const char* want : {"<property name=\"suite_version\" value=\"sabus 9.8.7-test\"/>", "<property name=\"firmware\" value=\"1.59\"/>",
                           "<property name=\"profile\" value=\"rc3000-1.59\"/>", "<property name=\"seed\" value=\"42\"/>",
                           "<property name=\"level\" value=\"must\"/>"})
    EXPECT_NE(x.find(want), std::string::npos) << want;
  // Without wall-clock times (schema 1 and 2) there is no time at all.
  for (auto& v : d.vectors) v.wall_ms.reset();
  const std::string old = junit_xml(d);
  EXPECT_EQ(old.find(" time=\""), std::string::npos) << old;
  d.identity = {false, "", "", "", "no answer"};
  EXPECT_NE(junit_xml(d).find("<property name=\"firmware\" value=\"unknown: no answer\"/>"), std::string::npos);
}

TEST(Html, EscapesEveryDeviceStringAndLoadsNothing) {
  RunDocument d = sample();
  d.identity.controller_type = "<script>alert(1)</script>";
  d.identity.firmware_version = "1.59 & \"up\"";
  d.device = "<img src=http://example.com/x.png>";
  d.vectors[1].failures = {"got \"<b>bold</b>\" & more"};
  d.vectors[0].transcript[1].fields = {{3, 4, "controller type", "\"<script>\"", "</td></table><script>x()</script>", true}};
  d.vectors[0].transcript[1].note = "<iframe src=//evil>";
  const std::string h = html_report(d);
  // One script, the filter's, allowed by its hash and nothing else.
  const auto script = h.find("<script");
  ASSERT_NE(script, std::string::npos);
  EXPECT_EQ(h.find("<script", script + 1), std::string::npos) << "a second script";
  EXPECT_EQ(h.compare(script, 49, "<script>// The HTML report's vector filter (repor"), 0) << h.substr(script, 60);
  EXPECT_NE(h.find("script-src 'sha256-"), std::string::npos);
  EXPECT_EQ(h.find("unsafe-inline'; script-src 'unsafe"), std::string::npos);
  EXPECT_EQ(h.find("<img"), std::string::npos);
  EXPECT_EQ(h.find("<iframe"), std::string::npos);
  EXPECT_EQ(h.find("</table><script"), std::string::npos);
  EXPECT_NE(h.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(h.find("1.59 &amp; &quot;up&quot;"), std::string::npos);
  EXPECT_NE(h.find("got &quot;&lt;b&gt;bold&lt;/b&gt;&quot; &amp; more"), std::string::npos);
  for (const char* external : {"src=\"", "href=\"http", "@import", "url("}) EXPECT_EQ(h.find(external), std::string::npos) << external;
  EXPECT_NE(h.find("<p id=\"summary\">1 passed, 1 failed, 1 skipped, 1 known failures</p>"), std::string::npos);
}

TEST(Html, CoverageMatrixCountsCommandFormAndPath) {
  const RunDocument d = sample();
  const auto rows = coverage(d);
  const auto status = std::find_if(rows.begin(), rows.end(), [](const CoverageRow& r) { return r.command == "status"; });
  ASSERT_NE(status, rows.end());
  ASSERT_EQ(status->paths.count("ack"), 1u);
  EXPECT_EQ(status->paths.at("ack").passed, 1u);
  EXPECT_EQ(status->paths.count("nak"), 0u);
  EXPECT_GE(rows.size(), 25u) << "every catalog command has a row";
}

TEST(Html, FilterChartsOptionsTimingAndGroupedFailures) {
  RunDocument d = sample();
  d.vectors.push_back(vector("e-fail", "fail", "3.3"));  // the same difference as b-fail
  d.vectors[1].transcript = {status_exchange(true, "02 32 31 03 02"), status_exchange(false, "06 32 31 44 03 00")};
  d.vectors[1].transcript[0].fields = {{0, 0, "start", "0x02", "STX command", true}};
  d.vectors[1].transcript[1].fields = reply_fields();
  d.vectors[1].transcript[1].t_ms = 4.5;
  d.vectors[0].transcript[1].t_ms = 2;
  d.traffic = {{"measured_turnaround_ms", 12.5}, {"silence_windows", 3}, {"silence_listened_ms", 1500}, {"bytes_sent", 10}, {"bytes_received", 20}};
  const std::string h = html_report(d);
  // The filter, with every paragraph of the run; each vector carries what it filters on.
  EXPECT_NE(h.find("<form id=\"filter\" hidden>"), std::string::npos);
  EXPECT_NE(h.find("<select name=\"paragraph\" id=\"f-paragraph\"><option value=\"\">all</option><option value=\"1\">§1</option>"
                   "<option value=\"3.2\">§3.2</option><option value=\"3.3\">§3.3</option><option value=\"3.10\">§3.10</option></select>"),
            std::string::npos);
  EXPECT_NE(h.find("<details class=\"v\" id=\"v-e-fail\" data-status=\"fail\" data-level=\"must\" data-paragraph=\"3.3\" open>"),
            std::string::npos);
  EXPECT_NE(h.find("id=\"v-d-known\" data-status=\"known\" data-level=\"should\" data-paragraph=\"1\">"), std::string::npos);
  // 2 vectors, one reason: one group.
  EXPECT_NE(h.find("<h2 id=\"failures\">Failures: 2 vectors, 1 reasons</h2>"), std::string::npos);
  EXPECT_NE(h.find("<b class=\"count\">2 ×</b> byte 36 az status: expected 0x57, got 0x44 (slow)</summary>"), std::string::npos);
  // Options as a table, lists joined.
  EXPECT_NE(h.find("<tr><th>filters</th><td>3.*</td></tr>"), std::string::npos);
  EXPECT_NE(h.find("<tr><th>seed</th><td>42</td></tr>"), std::string::npos);
  // Timing, both charts, the suite version in the header.
  EXPECT_NE(h.find("<tr><th>Measured turnaround</th><td>12.5 ms"), std::string::npos);
  EXPECT_NE(h.find("<tr><th>Wall clock, all vectors</th><td>0.001 s</td></tr>"), std::string::npos);
  EXPECT_NE(h.find("<svg id=\"chart-turnaround\""), std::string::npos);
  EXPECT_NE(h.find("status (Device Status Poll, §3.2): 2 replies, min 2.00 ms, median 3.25 ms, max 4.50 ms"), std::string::npos)
      << "the chart's title for the status poll";
  EXPECT_NE(h.find("<svg id=\"chart-coverage\""), std::string::npos);
  EXPECT_NE(h.find("<rect class=\"cell fail\""), std::string::npos);
  EXPECT_NE(h.find("<p id=\"suite\">sabus 9.8.7-test · schema sabus-run v"), std::string::npos);
  // A failing vector shows its reply field by field; a passing one its frames as lines.
  const std::string failing = h.substr(h.find("id=\"v-b-fail\""), h.find("id=\"v-c-skip\"") - h.find("id=\"v-b-fail\""));
  EXPECT_NE(failing.find("<td>az status</td>"), std::string::npos);
  EXPECT_EQ(failing.find("STX command"), std::string::npos) << "commands as hex and summary only";
  const std::string passing = h.substr(h.find("id=\"v-a-pass\""), h.find("id=\"v-b-fail\"") - h.find("id=\"v-a-pass\""));
  EXPECT_NE(passing.find("<pre class=\"transcript\">     0.000 tx 02 32 31 03 02"), std::string::npos) << passing;
  EXPECT_EQ(passing.find("<table"), std::string::npos);
}

TEST(Html, CompactingADocumentChangesNoReport) {
  RunDocument d = sample();
  d.vectors[0].transcript[1].fields = reply_fields();  // a passing vector's reply fields
  d.vectors[1].transcript = {status_exchange(true, "02 32 31 03 02"), status_exchange(false, "06 32 31 44 03 00")};
  d.vectors[1].transcript[1].fields = reply_fields();
  RunDocument compact = d;
  for (auto& v : compact.vectors) compact_for_reports(v);
  EXPECT_TRUE(compact.vectors[0].transcript[1].fields.empty());
  EXPECT_FALSE(compact.vectors[1].transcript[1].fields.empty()) << "a failure keeps its fields";
  EXPECT_EQ(html_report(compact), html_report(d));
  EXPECT_EQ(junit_xml(compact), junit_xml(d));
  EXPECT_EQ(markdown_summary(compact), markdown_summary(d));
}

TEST(Tables, FailureGroupsLargestFirstThenInRunOrder) {
  RunDocument d;
  for (const char* id : {"a", "b", "c", "d"}) d.vectors.push_back(vector(id, "fail"));
  d.vectors[0].failures = {"one"};
  d.vectors[2].failures = {"one"};
  d.vectors[1].failures = {"two"};
  d.vectors[3].failures = {"three"};
  d.vectors.push_back(vector("e", "pass"));
  const auto g = failure_groups(d);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0].reason, "one");
  ASSERT_EQ(g[0].vectors.size(), 2u);
  EXPECT_EQ(g[0].vectors[1]->id, "c");
  EXPECT_EQ(g[1].reason, "two");
  EXPECT_EQ(g[2].reason, "three");
}

TEST(Tables, TurnaroundFromEachCommandToItsFirstReply) {
  RunDocument d;
  VectorRecord v = vector("a", "pass");
  auto at = [](FrameRecord f, double t) {
    f.t_ms = t;
    return f;
  };
  FrameRecord note = status_exchange(false, "");  // bytes the receiver ignored: not a reply
  v.transcript = {at(status_exchange(true, "02 32 31 03 02"), 10), at(note, 11), at(status_exchange(false, "06"), 13),
                  at(status_exchange(true, "02 32 31 03 02"), 20), at(status_exchange(false, "06"), 21),
                  at(status_exchange(true, "02 32 31 03 02"), 30), at(status_exchange(false, "06"), 38),
                  at(status_exchange(true, "02 32 31 03 02"), 40)};  // no reply: no sample
  d.vectors = {v};
  const auto rows = turnaround_by_command(d);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].command, "status");
  EXPECT_EQ(rows[0].count, 3u);
  EXPECT_DOUBLE_EQ(rows[0].min_ms, 1);
  EXPECT_DOUBLE_EQ(rows[0].median_ms, 3);
  EXPECT_DOUBLE_EQ(rows[0].max_ms, 8);
}

TEST(Markdown, ShortSummaryWithFailures) {
  RunDocument d = sample();
  d.vectors[1].failures = {"a | b"};
  const std::string m = markdown_summary(d);
  EXPECT_NE(m.find("**FAIL**"), std::string::npos);
  EXPECT_NE(m.find("controller 3K, firmware 1.59"), std::string::npos);
  EXPECT_NE(m.find("sabus 9.8.7-test"), std::string::npos) << "the suite version";
  EXPECT_NE(m.find("- `b-fail` §3.2 must: a \\| b"), std::string::npos) << m;
}

TEST(Markdown, ARunThatCheckedNothingSaysSoAndWhy) {
  RunDocument d = sample();
  d.vectors = {vector("c-skip", "skip"), vector("d-skip", "skip")};
  d.vectors[0].skip_cause = d.vectors[1].skip_cause = "motion";
  d.summary = Summary{0, 0, 2, 0, 0, harness::kNothingRanExitCode};
  const std::string m = markdown_summary(d);
  EXPECT_NE(m.find("### SAbus conformance: **NOTHING RAN**"), std::string::npos) << m;
  EXPECT_NE(m.find("0 passed, 0 failed, 2 skipped (2 need --allow-motion)"), std::string::npos) << m;
  EXPECT_NE(m.find("**Nothing ran**: all 2 vectors selected were skipped (2 need --allow-motion)."), std::string::npos) << m;
  EXPECT_EQ(d.verdict(), "NOTHING RAN");
}

TEST(Tables, ParagraphsInSpecOrder) {
  EXPECT_TRUE(paragraph_less("3.2", "3.10"));
  EXPECT_FALSE(paragraph_less("3.10", "3.2"));
  EXPECT_TRUE(paragraph_less("1", "3.1"));
  EXPECT_FALSE(paragraph_less("3.2", "3.2"));
}

TEST(Diff, RegressionsFixesChangedRepliesAndTiming) {
  RunDocument a = sample(), b = sample();
  b.vectors[0].transcript[1].hex = "06 32 31 31 03 01";  // a-pass still passes, another reply
  b.vectors[0].duration_ms = 500;
  b.vectors[1] = vector("b-fail", "pass");                // fixed
  b.vectors.push_back(vector("e-new", "fail"));          // new and failing
  a.vectors.push_back(vector("f-gone", "pass"));         // passed, now missing
  const RunDiff d = diff_runs(a, b, *parse_timing_threshold("100ms"));
  ASSERT_EQ(d.new_failures.size(), 1u);
  EXPECT_EQ(d.new_failures[0].id, "e-new");
  ASSERT_EQ(d.fixes.size(), 1u);
  EXPECT_EQ(d.fixes[0].id, "b-fail");
  ASSERT_EQ(d.now_missing.size(), 1u);
  EXPECT_EQ(d.now_missing[0].id, "f-gone");
  ASSERT_EQ(d.replies_changed.size(), 1u);
  EXPECT_EQ(d.replies_changed[0].id, "a-pass");
  ASSERT_EQ(d.timing_shifts.size(), 1u);
  EXPECT_TRUE(d.regressed());
  EXPECT_NE(diff_text(d).find("REGRESSION New failures (1):\n  e-new"), std::string::npos) << diff_text(d);
  EXPECT_FALSE(diff_runs(a, a, {}).regressed());
}

TEST(Diff, MustPassToSkipAndAnAbortedRunRegress) {
  RunDocument a = sample(), b = sample();
  b.vectors[0] = vector("a-pass", "skip");
  EXPECT_EQ(diff_runs(a, b, {}).must_now_skipped.size(), 1u);
  RunDocument c = sample();
  c.status = "aborted";
  EXPECT_TRUE(diff_runs(a, c, {}).regressed());
}

// An inconclusive vector neither passes nor fails: pass -> inconclusive
// and fail -> inconclusive are changes (not a regression, not a fix), with
// the reason; inconclusive -> fail is a new failure.
TEST(Diff, MovesToAndFromInconclusiveAreShown) {
  const RunDocument a = sample();
  RunDocument b = sample();
  b.vectors[0] = vector("a-pass", "inconclusive");
  b.vectors[0].inconclusive_reason = "precondition not met (the search runs): byte 45 current mode: expected 0x26, got 0x20";
  b.vectors[1] = vector("b-fail", "inconclusive");
  b.vectors[1].inconclusive_reason = "precondition not met (the search runs): z";
  const RunDiff d = diff_runs(a, b, {});
  EXPECT_FALSE(d.regressed());
  EXPECT_TRUE(d.fixes.empty()) << "a failure now inconclusive is not fixed";
  ASSERT_EQ(d.other_changes.size(), 2u);
  EXPECT_EQ(d.other_changes[0].id, "a-pass");
  EXPECT_EQ(d.other_changes[0].old_outcome, "pass");
  EXPECT_EQ(d.other_changes[0].new_outcome, "inconclusive");
  EXPECT_EQ(d.other_changes[0].detail, "inconclusive: " + b.vectors[0].inconclusive_reason);
  EXPECT_EQ(d.other_changes[1].id, "b-fail");
  EXPECT_NE(diff_text(d).find("Other outcome changes (2):\n  a-pass §3.2 must: pass → inconclusive  inconclusive: precondition not met"),
            std::string::npos)
      << diff_text(d);
  EXPECT_NE(diff_markdown(d).find("| `a-pass` | 3.2 | must | pass → inconclusive | inconclusive: precondition not met"),
            std::string::npos)
      << diff_markdown(d);
  const RunDiff worse = diff_runs(b, a, {});
  ASSERT_EQ(worse.new_failures.size(), 1u);
  EXPECT_EQ(worse.new_failures[0].id, "b-fail");
  EXPECT_EQ(worse.new_failures[0].old_outcome, "inconclusive");
  EXPECT_TRUE(worse.regressed());
  ASSERT_EQ(worse.other_changes.size(), 1u);
  EXPECT_EQ(worse.other_changes[0].id, "a-pass") << "inconclusive -> pass";
}

// A vector in error was not judged: pass -> error and fail -> error are
// other changes (not a regression, not a fix: nothing was learnt of the
// device), with what the line did; error -> pass is an other change too
// (not a fix of a failure), error -> fail a new failure (the device was
// judged, and failed), as inconclusive -> fail is.
TEST(Diff, MovesToAndFromErrorAreShown) {
  const RunDocument a = sample();
  RunDocument b = sample();
  b.vectors[0] = vector("a-pass", "error");
  b.vectors[0].error_reason = "step 1 (status): no clean reply in 2 tries: bad check byte";
  b.vectors[1] = vector("b-fail", "error");
  b.vectors[1].error_reason = "step 1 (status): no clean reply in 2 tries: cut short";
  const RunDiff d = diff_runs(a, b, {});
  EXPECT_FALSE(d.regressed());
  EXPECT_TRUE(d.fixes.empty()) << "a failure now in error is not fixed";
  EXPECT_TRUE(d.new_failures.empty());
  ASSERT_EQ(d.other_changes.size(), 2u);
  EXPECT_EQ(d.other_changes[0].id, "a-pass");
  EXPECT_EQ(d.other_changes[0].old_outcome, "pass");
  EXPECT_EQ(d.other_changes[0].new_outcome, "error");
  EXPECT_EQ(d.other_changes[0].detail, "error: step 1 (status): no clean reply in 2 tries: bad check byte");
  EXPECT_EQ(d.other_changes[1].id, "b-fail");
  EXPECT_EQ(d.other_changes[1].old_outcome, "fail");
  EXPECT_NE(diff_text(d).find("Other outcome changes (2):\n  a-pass §3.2 must: pass → error  error: step 1 (status)"),
            std::string::npos)
      << diff_text(d);
  const RunDiff back = diff_runs(b, a, {});
  ASSERT_EQ(back.new_failures.size(), 1u);
  EXPECT_EQ(back.new_failures[0].id, "b-fail");
  EXPECT_EQ(back.new_failures[0].old_outcome, "error");
  EXPECT_TRUE(back.regressed());
  EXPECT_TRUE(back.fixes.empty());
  ASSERT_EQ(back.other_changes.size(), 1u);
  EXPECT_EQ(back.other_changes[0].id, "a-pass") << "error -> pass";
}

TEST(Diff, WarnsWhenOptionsProfileOrSelectionDiffer) {
  const RunDocument a = sample();
  EXPECT_TRUE(diff_runs(a, a, {}).warnings.empty());
  RunDocument filtered = sample();
  filtered.options["filters"] = {"3.2-*"};
  filtered.vectors.resize(2);  // c-skip and d-known did not run
  const RunDiff d = diff_runs(a, filtered, {});
  ASSERT_GE(d.warnings.size(), 3u);
  EXPECT_EQ(d.warnings[0], "option filters: [\"3.*\"] -> [\"3.2-*\"]");
  EXPECT_EQ(d.warnings[1], "selection: OLD ran 3 vectors, NEW ran 2; 1 ran only in OLD, 0 only in NEW");
  EXPECT_NE(d.warnings.back().find("may come from that, not from the device"), std::string::npos);
  EXPECT_NE(diff_text(d).find("WARNING option filters"), std::string::npos) << diff_text(d);
  EXPECT_NE(diff_markdown(d).find("> **Warning:** selection"), std::string::npos);
  RunDocument other = sample();
  other.profile = "rc3000-dvb";
  other.faults = {"short-status"};
  const RunDiff p = diff_runs(a, other, {});
  ASSERT_EQ(p.warnings.size(), 2u);
  EXPECT_EQ(p.warnings[0], "profile: rc3000-1.59 -> rc3000-dvb");
  EXPECT_NE(std::find(p.run_changes.begin(), p.run_changes.end(), "faults: none -> short-status"), p.run_changes.end())
      << "injected faults stand in for a firmware: a change, not a warning";
}

TEST(Diff, TimingThresholds) {
  EXPECT_TRUE(parse_timing_threshold("50ms")->exceeded(100, 151));
  EXPECT_FALSE(parse_timing_threshold("50")->exceeded(100, 149));
  EXPECT_TRUE(parse_timing_threshold("20%")->exceeded(100, 121));
  EXPECT_FALSE(parse_timing_threshold("20%")->exceeded(100, 119));
  EXPECT_FALSE(parse_timing_threshold("fast"));
  EXPECT_FALSE(parse_timing_threshold("-5ms"));
  EXPECT_FALSE(parse_timing_threshold(""));
}

// The version of the suite that ran (sabus --version) is in every report.
TEST(Reports, EveryReportCarriesTheGenerator) {
  RunDocument d = sample();
  d.generator = "sabus 9.8.7 (git v9.8.7-3-gabc1234-dirty)";
  EXPECT_EQ(nlohmann::json::parse(json_text(d)).at("generator"), d.generator);
  EXPECT_NE(junit_xml(d).find("name=\"suite_version\" value=\"sabus 9.8.7 (git v9.8.7-3-gabc1234-dirty)\""),
            std::string::npos);
  EXPECT_NE(html_report(d).find(d.generator), std::string::npos);
  EXPECT_NE(markdown_summary(d).find(d.generator), std::string::npos);
}

}  // namespace
}  // namespace sabus::reports
