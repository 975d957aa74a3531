// The report writers, from a run document built in the test.
#include <gtest/gtest.h>

#include "sabus/reports/diff.hpp"
#include "sabus/reports/writers.hpp"

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
  RunDocument d;
  d.status = "complete";
  d.started_at = "2024-01-01T00:00:00Z";
  d.device = "in-process";
  d.identity = {true, "3K", "1.59", "06 32 30 33 4b 31 2e 35 39 03 6c", ""};
  d.vectors = {vector("a-pass", "pass"), vector("b-fail", "fail"), vector("c-skip", "skip", "3.10"),
               vector("d-known", "known failure", "1", "should")};
  d.vectors[0].transcript = {status_exchange(true, "02 32 31 03 02"), status_exchange(false, "06 32 31 30 03 00")};
  d.summary = Summary{1, 1, 1, 1, 0, 1};
  return d;
}

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

TEST(Json, RoundTripsEveryField) {
  RunDocument d = sample();
  d.vectors[0].quote = "the reply is 52 bytes";
  d.vectors[0].transcript[0].fields = {{0, 0, "start", "0x02", "STX", true}};
  d.vectors[0].transcript[0].form = "2A";
  std::string error;
  const auto back = from_json(nlohmann::json::parse(json_text(d)), error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(nlohmann::json::parse(json_text(*back)), nlohmann::json::parse(json_text(d)));
  EXPECT_EQ(back->vectors[0].transcript[0].fields[0].meaning, "STX");
  EXPECT_EQ(back->identity.firmware_version, "1.59");
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

TEST(Junit, OneSuitePerParagraphFailuresWithTranscriptSkipsWithReason) {
  RunDocument d = sample();
  d.vectors[1].transcript = {status_exchange(true, "02 32 31 03 02")};
  const std::string x = junit_xml(d);
  EXPECT_NE(x.find("<testsuite name=\"§3.2\" tests=\"2\" failures=\"1\" errors=\"0\" skipped=\"0\""), std::string::npos) << x;
  EXPECT_NE(x.find("<testsuite name=\"§3.10\" tests=\"1\" failures=\"0\" errors=\"0\" skipped=\"1\""), std::string::npos);
  EXPECT_NE(x.find("<testcase name=\"b-fail\" classname=\"sabus.3.2.must\""), std::string::npos);
  EXPECT_NE(x.find("02 32 31 03 02"), std::string::npos) << "the hex transcript";
  EXPECT_NE(x.find("<skipped message=\"moves the antenna: needs --allow-motion\"/>"), std::string::npos);
  EXPECT_NE(x.find("<skipped message=\"known issue: "), std::string::npos);
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
  EXPECT_EQ(h.find("<script"), std::string::npos);
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

TEST(Markdown, ShortSummaryWithFailures) {
  RunDocument d = sample();
  d.vectors[1].failures = {"a | b"};
  const std::string m = markdown_summary(d);
  EXPECT_NE(m.find("**FAIL**"), std::string::npos);
  EXPECT_NE(m.find("controller 3K, firmware 1.59"), std::string::npos);
  EXPECT_NE(m.find("- `b-fail` §3.2 must: a \\| b"), std::string::npos) << m;
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
  EXPECT_NE(junit_xml(d).find("<property name=\"generator\" value=\"sabus 9.8.7 (git v9.8.7-3-gabc1234-dirty)\"/>"),
            std::string::npos);
  EXPECT_NE(html_report(d).find(d.generator), std::string::npos);
  EXPECT_NE(markdown_summary(d).find(d.generator), std::string::npos);
}

}  // namespace
}  // namespace sabus::reports
