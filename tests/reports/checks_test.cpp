// The readers that prove the record of a run (reports/checks.hpp), failing
// paths first: each finds what a broken file breaks; then the records of
// runs against a faulty controller and of a document full of hostile text
// read back clean.
#include "sabus/reports/checks.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "sabus/harness/faults.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"
#include "sample_run.hpp"

namespace sabus::reports {
namespace {

using checks::Problems;
using nlohmann::json;

std::string joined(const Problems& p) {
  std::string out;
  for (const auto& line : p) out += line + "\n";
  return out;
}

// Whether one of the problems says `what` (if not, what they say).
testing::AssertionResult says(const Problems& p, std::string_view what) {
  if (std::any_of(p.begin(), p.end(), [&](const std::string& line) { return line.find(what) != std::string::npos; }))
    return testing::AssertionSuccess();
  return testing::AssertionFailure() << "no problem says \"" << what << "\"; they say:\n" << joined(p);
}

// The text as the device might send it: markup, quotes, controls, DEL, a
// byte that is not UTF-8, line ends, Markdown's markup.
const std::string kHostile = std::string("<script>alert(1)</script> &amp; \"q\" 'a' \x01\x7f\x1b[0m \xff\xfe | `code` *em* _u_ [l](x) ~s~ \\ \r\n- item\n# head");

FrameRecord frame(std::string dir, std::string hex, std::string note, std::vector<Field> fields = {}) {
  FrameRecord f;
  f.dir = std::move(dir);
  f.hex = std::move(hex);
  f.note = std::move(note);
  f.fields = std::move(fields);
  if (f.dir == "tx") f.expect = f.path = "ack";
  return f;
}

VectorRecord vector(std::string id, std::string outcome) {
  return test_documents::sample_vector(std::move(id), std::move(outcome));
}

// A finished run of one vector of each outcome, recorded as sabus run does.
MemoryRecord finished_record() {
  MemoryRecord r;
  r.doc = test_documents::sample_header();
  r.doc.generator = "sabus 1.2.3";
  r.doc.options = {{"seed", 7}};
  r.doc.planned = 5;
  r.start();
  for (const char* outcome : {"pass", "fail", "skip", "known failure", "unexpected pass"}) {
    VectorRecord v = vector(std::string("3.2-") + outcome, outcome);
    r.journal += vector_json(v) + "\n";
    compact_for_reports(v);
    r.doc.vectors.push_back(v);
  }
  r.doc.status = "complete";
  r.doc.finished_at = "2024-01-01T00:00:01Z";
  r.doc.summary = Summary{1, 1, 1, 1, 1, 1, {{"motion", 1}}};
  r.doc.traffic = {{"bytes_sent", 10}, {"bytes_received", 10}, {"silence_windows", 0}, {"silence_listened_ms", 0.0},
                   {"measured_turnaround_ms", 0.0}};
  r.doc.journal.clear();
  r.journal += journal_record_json("end", r.doc) + "\n";
  return r;
}

// ---- each reader finds what breaks its format ------------------------------------

TEST(RunJsonProblems, FindWhatBreaksTheFileOrTheSchema) {
  const std::string good = json_text(finished_record().doc);
  ASSERT_EQ(joined(checks::run_json_problems(good)), "");
  auto broken = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"fields\":[]", "\"fields\":")), "not JSON")) << "the defect of issue 21";
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"hex\":\"02 32", "\"hex\":\"2 32")), "/hex"));
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"outcome\":\"fail\",\"failures\":[\"byte", "\"outcome\":\"fail\",\"failures\":[],\"x\":[\"byte")), "at /vectors/1"))
      << "a failure without its reason, and a member the schema does not have";
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"status\": \"complete\"", "\"status\": \"running\"")), "at /:"))
      << "a run that goes on has no summary";
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"passed\": 1", "\"passed\": 2")), "summary.passed is 2"));
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"id\":\"3.2-fail\"", "\"id\":\"3.2-pass\"")), "twice"));
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"first\":0,\"last\":0", "\"first\":0,\"last\":9")), "bytes 0-9 of a frame of 5"));
  EXPECT_TRUE(says(checks::run_json_problems(broken("\"skip_cause\":\"motion\"", "\"skip_cause\":\"\"")), "at /vectors/2"))
      << "a skip names its cause";
}

TEST(JournalProblems, FindALineOrARecordOutOfPlace) {
  const std::string good = finished_record().journal;
  ASSERT_EQ(joined(checks::journal_problems(good)), "");
  const auto first_end = good.find('\n') + 1;
  EXPECT_TRUE(says(checks::journal_problems(good.substr(first_end)), "not a header record"));
  EXPECT_TRUE(says(checks::journal_problems(good.substr(0, good.size() - 1)), "cut short"));
  std::string damaged = good;
  damaged.insert(first_end, "{\"id\":\"x\",\"fields\":}\n");
  EXPECT_TRUE(says(checks::journal_problems(damaged), "journal line 2: not JSON"));
  std::string vector_line_broken = good;
  vector_line_broken.replace(vector_line_broken.find("\"level\":\"must\""), 14, "\"level\":\"may\"");
  EXPECT_TRUE(says(checks::journal_problems(vector_line_broken), "journal line 2: at /level"));
  EXPECT_TRUE(says(checks::journal_problems(good + good.substr(0, first_end)), "a record that is not"));
}

TEST(JunitProblems, FindInvalidXmlAndMissingTestcases) {
  const MemoryRecord r = finished_record();
  const std::string good = junit_xml(r.doc);
  ASSERT_EQ(joined(checks::junit_problems(good, r.doc)), "");
  std::string not_xml = good;
  not_xml.insert(not_xml.find("<testcase"), "<b>&</b>");
  EXPECT_TRUE(says(checks::junit_problems(not_xml, r.doc), "JUnit line"));
  std::string invalid = good;
  invalid.replace(invalid.find(" errors=\"0\" skipped"), 11, "");
  EXPECT_FALSE(checks::junit_problems(invalid, r.doc).empty()) << "the schema refuses a testsuite without errors=";
  RunDocument more = r.doc;
  more.vectors.push_back(vector("3.2-another", "pass"));
  EXPECT_TRUE(says(checks::junit_problems(good, more), "no testcase for 3.2-another"));
  RunDocument other = r.doc;
  other.vectors[0].outcome = "fail";
  EXPECT_TRUE(says(checks::junit_problems(good, other), "testcase 3.2-pass is a pass, the vector a fail"));
}

// A run stopped before its end (exit 4) is one error in JUnit naming why,
// and the vector during which the device was lost an error, not a failure;
// the check refuses the JUnit of a stopped run without that error, with
// another reason, or with the lost vector as a failure, and a complete run
// with such an error.
TEST(JunitProblems, AStoppedRunIsAnErrorNamingWhyNotAFailure) {
  RunDocument stopped = finished_record().doc;
  VectorRecord lost = vector("3.3-lost", "fail");
  lost.failures = {std::string(harness::kDeviceLostFailure) + "tcp 127.0.0.1:9: the connection was closed"};
  stopped.vectors.push_back(lost);
  stopped.status = "aborted";
  stopped.abort_reason = "device lost during 3.3-lost: tcp 127.0.0.1:9: the connection was closed";
  stopped.summary = Summary{1, 2, 1, 1, 1, harness::kStoppedExitCode, {{"motion", 1}}};
  ASSERT_TRUE(stopped.stopped());
  EXPECT_EQ(stopped.verdict(), "STOPPED");
  const std::string xml = junit_xml(stopped);
  ASSERT_EQ(joined(checks::junit_problems(xml, stopped)), "");
  EXPECT_NE(xml.find("<testsuites name=\"sabus\" tests=\"7\" failures=\"2\" errors=\"2\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("type=\"stopped\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("type=\"lost device\""), std::string::npos) << xml;

  RunDocument by_signal = stopped;
  by_signal.abort_reason = "stopped by SIGTERM";
  EXPECT_TRUE(says(checks::junit_problems(xml, by_signal), "not why the run ended: \"stopped by SIGTERM\""));
  RunDocument complete = finished_record().doc;
  complete.vectors.push_back(lost);
  EXPECT_TRUE(says(checks::junit_problems(xml, complete), "the run is complete, but has a testcase of class sabus.run"));
  std::string no_error = xml;
  no_error.erase(no_error.find("  <testsuite name=\"run\""), no_error.find("</testsuites>") - no_error.find("  <testsuite name=\"run\""));
  EXPECT_TRUE(says(checks::junit_problems(no_error, stopped), "has 0 error(s) in 0 testcase(s) of class sabus.run"));
  std::string lost_as_failure = xml;
  const auto at = lost_as_failure.find("<error message=\"device lost: ");
  lost_as_failure.replace(at, 6, "<failure");
  lost_as_failure.replace(lost_as_failure.find("</error>", at), 8, "</failure>");
  EXPECT_TRUE(says(checks::junit_problems(lost_as_failure, stopped), "testcase 3.3-lost is a fail, the vector a error"));

  // A killed run (no end record) and one aborted by the device's silence
  // are unfinished too: an error each, of their own type.
  RunDocument killed = finished_record().doc;
  killed.status = "running";
  killed.summary.reset();
  EXPECT_EQ(joined(checks::junit_problems(junit_xml(killed), killed)), "");
  EXPECT_NE(junit_xml(killed).find("type=\"killed\""), std::string::npos);
  RunDocument silent = finished_record().doc;
  silent.status = "aborted";
  silent.abort_reason = "no answer to three liveness probes";
  EXPECT_EQ(joined(checks::junit_problems(junit_xml(silent), silent)), "");
  EXPECT_NE(junit_xml(silent).find("type=\"aborted\""), std::string::npos);
  EXPECT_EQ(silent.verdict(), "ABORTED");
}

TEST(HtmlProblems, FindMarkupFromAStringAndTextNotShown) {
  const MemoryRecord r = finished_record();
  const std::string good = html_report(r.doc);
  ASSERT_EQ(joined(checks::html_problems(good, r.doc)), "");
  auto with = [&](const std::string& html_inserted) {
    std::string text = good;
    return text.insert(text.find("<div id=\"vectors\">"), html_inserted);
  };
  EXPECT_TRUE(says(checks::html_problems(with("<script>alert(1)</script>"), r.doc), "2 scripts"));
  EXPECT_TRUE(says(checks::html_problems(with("<img src=x>"), r.doc), "<img>"));
  EXPECT_TRUE(says(checks::html_problems(with("<b onclick=\"x()\">b</b>"), r.doc), "event handler attribute onclick"));
  EXPECT_TRUE(says(checks::html_problems(with("<a href=\"http://x\">x</a>"), r.doc), "a link out of the page"));
  EXPECT_TRUE(says(checks::html_problems(with("<p>a\x01b</p></div>"), r.doc), "parse error"));
  RunDocument other = r.doc;
  other.vectors[1].failures = {"a failure the page does not show"};
  EXPECT_TRUE(says(checks::html_problems(good, other), "\"a failure the page does not show\" is not shown as text"));
}

TEST(MarkdownProblems, FindRawHtmlWrongCountsAndFailuresOtherwiseWritten) {
  const MemoryRecord r = finished_record();
  const std::string good = markdown_summary(r.doc);
  ASSERT_EQ(joined(checks::markdown_problems(good, r.doc)), "") << good;
  EXPECT_TRUE(says(checks::markdown_problems(good + "\n<div>x</div>\n", r.doc), "html_block"));
  EXPECT_TRUE(says(checks::markdown_problems(good + "\nsee *this*\n", r.doc), "emph"));
  std::string counts = good;
  counts.replace(counts.find("| must | 1 | 2 |"), 17, "| must | 1 | 3 |");
  EXPECT_TRUE(says(checks::markdown_problems(counts, r.doc), "per-level table")) << counts;
  EXPECT_TRUE(says(checks::markdown_problems(good + "- `3.2-extra` §3.2 must: x\n", r.doc), "list items"));
  RunDocument other = r.doc;
  other.vectors[1].failures = {"another reason"};
  EXPECT_TRUE(says(checks::markdown_problems(good, other), "failure item 1 reads"));
}

// ---- the inconclusive outcome (schema v4) -----------------------------------------

// finished_record with a vector that ended inconclusive (TTCN-3 inconc).
MemoryRecord inconclusive_record() {
  MemoryRecord r;
  r.doc = test_documents::sample_header();
  r.doc.generator = "sabus 1.2.3";
  r.doc.planned = 2;
  r.start();
  for (const char* outcome : {"pass", "inconclusive"}) {
    VectorRecord v = vector(std::string("3.2-") + outcome, outcome);
    r.journal += vector_json(v) + "\n";
    compact_for_reports(v);
    r.doc.vectors.push_back(v);
  }
  r.doc.status = "complete";
  r.doc.finished_at = "2024-01-01T00:00:01Z";
  r.doc.summary = Summary{1, 0, 0, 0, 0, 0, {}, 1};
  r.doc.traffic = {{"bytes_sent", 10}, {"bytes_received", 10}, {"silence_windows", 0}, {"silence_listened_ms", 0.0},
                   {"measured_turnaround_ms", 0.0}};
  r.doc.journal.clear();
  r.journal += journal_record_json("end", r.doc) + "\n";
  return r;
}

// Each reader finds an inconclusive vector recorded wrong: without its
// reason or with a failure (the schema), miscounted, in JUnit not a skip
// that says why, its reason not shown in the HTML or the Markdown.
TEST(InconclusiveProblems, EachReaderFindsAnInconclusiveVectorRecordedWrong) {
  const MemoryRecord r = inconclusive_record();
  const std::string json = json_text(r.doc);
  auto broken = [](std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
  };
  const std::string reason = "\"inconclusive_reason\":\"precondition not met";
  EXPECT_TRUE(says(checks::run_json_problems(broken(json, reason, "\"inconclusive_reason\":\"\",\"x\":\"")), "at /vectors/1"));
  EXPECT_TRUE(says(checks::run_json_problems(broken(json, "\"outcome\":\"inconclusive\",\"failures\":[]",
                                                    "\"outcome\":\"inconclusive\",\"failures\":[\"f\"]")),
                   "at /vectors/1"))
      << "an inconclusive vector has no failure";
  EXPECT_TRUE(says(checks::run_json_problems(broken(json, "\"inconclusive\": 1", "\"inconclusive\": 0")),
                   "summary.inconclusive is 0, the vectors have 1 inconclusive"));
  EXPECT_TRUE(says(checks::run_json_problems(broken(json, "\"inconclusive\": 1,", "")), "at /summary"))
      << "a v4 summary counts them";
  EXPECT_TRUE(says(checks::journal_problems(broken(r.journal, reason, "\"inconclusive_reason\":\"\",\"x\":\"")), "journal line 3"));

  const std::string xml = junit_xml(r.doc);
  EXPECT_TRUE(says(checks::junit_problems(broken(xml, "message=\"inconclusive: precondition", "message=\"precondition"), r.doc),
                   "the skipped testcase 3.2-inconclusive says \"precondition not met"));
  RunDocument failed = r.doc;
  failed.vectors[1].outcome = "fail";
  failed.vectors[1].failures = {"f"};
  EXPECT_TRUE(says(checks::junit_problems(xml, failed), "testcase 3.2-inconclusive is a skip, the vector a fail"));

  RunDocument other = r.doc;
  other.vectors[1].inconclusive_reason = "another reason";
  EXPECT_TRUE(says(checks::html_problems(html_report(r.doc), other), "\"inconclusive: another reason\" is not shown as text"));
  const std::string md = markdown_summary(r.doc);
  EXPECT_TRUE(says(checks::markdown_problems(md, other), "item 1 reads"));
  EXPECT_TRUE(says(checks::markdown_problems(broken(md, "| must | 1 | 0 | 0 | 0 | 1 | 0 |", "| must | 1 | 0 | 0 | 0 | 0 | 0 |"), r.doc),
                   "per-level table"));
}

// Then the record of a run with an inconclusive vector reads back in every
// format, also rebuilt from its JSON and its journal; each names it.
TEST(InconclusiveProblems, ARunWithAnInconclusiveVectorReadsBackInEveryFormat) {
  const MemoryRecord r = inconclusive_record();
  EXPECT_EQ(joined(checks::run_record_problems(r.doc, r.journal)), "");
  const std::string why = "precondition not met (the search is still running when the stop goes out): byte 45 current mode: "
                          "expected 0x26, got 0x20 (MANUAL_MODE)";
  std::string error;
  const auto back = from_json(json::parse(json_text(r.doc)), error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->schema_version, kSchemaVersion);
  EXPECT_EQ(back->vectors[1].outcome, "inconclusive");
  EXPECT_EQ(back->vectors[1].inconclusive_reason, why);
  EXPECT_EQ(back->summary->inconclusive, 1u);
  EXPECT_EQ(back->counts().inconclusive, 1u);
  EXPECT_NE(junit_xml(r.doc).find("<skipped message=\"inconclusive: " + why + "\"/>"), std::string::npos);
  EXPECT_NE(html_report(r.doc).find("<p class=\"inconclusive\">inconclusive: " + why + "</p>"), std::string::npos);
  EXPECT_NE(html_report(r.doc).find("1 passed, 0 failed, 0 skipped, 1 inconclusive"), std::string::npos);
  EXPECT_NE(markdown_summary(r.doc).find("1 passed, 0 failed, 0 skipped, 1 inconclusive"), std::string::npos);
  EXPECT_EQ(r.doc.verdict(), "PASS") << "an inconclusive vector fails nothing";
}

// The record of a real run on the reference controller: a vector whose
// precondition does not hold there, and one that passes.
TEST(InconclusiveProblems, ARunnersInconclusiveVectorReadsBack) {
  harness::Step mode;
  mode.command = harness::StructuredCommand{"extended_status", "", {}, std::nullopt, {}, {}};
  harness::FieldMatcher search;
  search.field = "current mode";
  search.kind = harness::FieldMatcher::Kind::kEq;
  search.values = {"0x26"};
  mode.expect.fields = {search};
  mode.precondition = "the search is still running when the stop goes out";
  harness::Vector inconclusive, pass;
  inconclusive.id = "3.7-stop";
  inconclusive.paragraph = "3.7";
  inconclusive.steps = {mode};
  pass.id = "3.17-mode";
  pass.paragraph = "3.17";
  mode.precondition.clear();
  mode.expect.fields.clear();
  pass.steps = {mode};
  const auto profile = harness::load_profile_file(harness::default_profile_path());
  ASSERT_TRUE(profile) << profile.error->text();
  auto transport = harness::make_in_process_transport(harness::bus_of(*profile.profile), {});
  MemoryRecord r;
  r.doc = test_documents::sample_header();
  r.doc.generator = "sabus test";
  r.doc.planned = 2;
  r.start();
  harness::RunOptions o;
  o.on_result = r.on_result(1.0);
  r.end(harness::Runner(*transport, *profile.profile, o).run({inconclusive, pass}), "2024-01-01T00:00:01Z");
  ASSERT_EQ(r.doc.vectors.size(), 2u);
  EXPECT_EQ(r.doc.vectors[0].outcome, "inconclusive");
  EXPECT_EQ(r.doc.summary->inconclusive, 1u);
  EXPECT_EQ(r.doc.summary->exit_code, 0);
  EXPECT_EQ(joined(checks::run_record_problems(r.doc, r.journal)), "");
}

// ---- the error outcome and the line counts (schema v5) ---------------------------

// finished_record with a vector the line left unjudged (TTCN-3 error) beside
// one that passed: no failure, so the run exits 6. The run counted more
// exchanges and faults than its vectors (liveness probes, a recovered poll).
MemoryRecord error_record() {
  MemoryRecord r;
  r.doc = test_documents::sample_header();
  r.doc.generator = "sabus 1.2.3";
  r.doc.planned = 2;
  r.start();
  for (const char* outcome : {"pass", "error"}) {
    VectorRecord v = vector(std::string("3.2-") + outcome, outcome);
    r.journal += vector_json(v) + "\n";
    compact_for_reports(v);
    r.doc.vectors.push_back(v);
  }
  r.doc.status = "complete";
  r.doc.finished_at = "2024-01-01T00:00:01Z";
  r.doc.summary = Summary{1, 0, 0, 0, 0, harness::kLineErrorExitCode, {}, 0, 1, {40, 3, 1, 1}};
  r.doc.traffic = {{"bytes_sent", 10}, {"bytes_received", 10}, {"silence_windows", 0}, {"silence_listened_ms", 0.0},
                   {"measured_turnaround_ms", 0.0}};
  r.doc.journal.clear();
  r.journal += journal_record_json("end", r.doc) + "\n";
  return r;
}

// The run JSON of `r` with `change` made to it (as another tool, or a
// broken writer, might have written it).
std::string changed(const MemoryRecord& r, const std::function<void(json&)>& change) {
  json j = json::parse(json_text(r.doc));
  change(j);
  return j.dump();
}

// Each reader of the run JSON finds a vector in error, or line counts,
// recorded wrong: an outcome no version has, an error without its reason or
// with a failure, a reason on a pass, line counts that cannot be (a fault
// that is no exchange, a recovered fault that is no fault, a repeat that is
// no exchange), the summary's counts not the vectors', an exit code 6
// without a vector in error; the journal's reader too, and the document's.
TEST(ErrorProblems, TheRunJsonsReadersFindAVectorInErrorOrLineCountsRecordedWrong) {
  const MemoryRecord r = error_record();
  ASSERT_EQ(joined(checks::run_json_problems(json_text(r.doc))), "");
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["outcome"] = "errored"; })), "at /vectors/1"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["error_reason"] = ""; })), "at /vectors/1"))
      << "an error says what the line did";
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1].erase("error_reason"); })), "at /vectors/1"))
      << "a v5 vector has its error_reason";
  EXPECT_TRUE(
      says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["failures"] = {"f"}; })), "at /vectors/1"))
      << "a vector in error has no failure (a failure is judged, and beats the error)";
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][0]["error_reason"] = "x"; })), "at /vectors/0"))
      << "a pass has no error";
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1].erase("line"); })), "at /vectors/1"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["line"]["faults"] = -1; })),
                   "at /vectors/1"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["line"]["faults"] = 3; })),
                   "vectors[1] (3.2-error): at /line: line: 3 faults in 2 exchanges: a fault is an exchange"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["line"]["recovered"] = 3; })),
                   "line: 3 recovered of 2 faults: a recovered fault is a fault"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["vectors"][1]["line"]["repeats"] = 3; })),
                   "line: 3 repeats in 2 exchanges: a repeat is an exchange"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["summary"]["errors"] = 0; })),
                   "summary.errors is 0, the vectors have 1 error"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["summary"].erase("errors"); })), "at /summary"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["summary"].erase("line"); })), "at /summary"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["summary"]["line"]["faults"] = 50; })),
                   "summary: line: 50 faults in 40 exchanges"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["summary"]["line"]["faults"] = 1; })),
                   "summary.line.faults is 1, less than the vectors' 2"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r, [](json& j) { j["summary"]["exit_code"] = 7; })), "at /summary"));
  EXPECT_TRUE(says(checks::run_json_problems(changed(r,
                                                     [](json& j) {
                                                       j["vectors"][1] = j["vectors"][0];
                                                       j["vectors"][1]["id"] = "3.2-pass-too";
                                                       j["summary"]["passed"] = 2;
                                                       j["summary"]["errors"] = 0;
                                                     })),
                   "summary.exit_code is 6 (some vector in error), but no vector ended in error"));
  // The journal: its vector lines and its end record against the same rules.
  std::string journal = r.journal;
  const std::string line = "\"line\":{\"exchanges\":2,\"faults\":2,";
  ASSERT_NE(journal.find(line), std::string::npos) << journal;
  EXPECT_TRUE(says(checks::journal_problems(journal.replace(journal.find(line), line.size(), "\"line\":{\"exchanges\":2,\"faults\":3,")),
                   "journal line 3: at /line: line: 3 faults in 2 exchanges"));
  // The document's own reader refuses such counts too, naming where.
  std::string error;
  EXPECT_FALSE(from_json(json::parse(changed(r, [](json& j) { j["vectors"][1]["line"]["faults"] = 3; })), error));
  EXPECT_NE(error.find("vectors[1] (3.2-error): "), std::string::npos) << error;
  EXPECT_NE(error.find("line: 3 faults in 2 exchanges: a fault is an exchange"), std::string::npos) << error;
  EXPECT_FALSE(from_json(json::parse(changed(r, [](json& j) { j["summary"]["line"]["recovered"] = 4; })), error));
  EXPECT_NE(error.find("summary: "), std::string::npos) << error;
  EXPECT_NE(error.find("line: 4 recovered of 3 faults"), std::string::npos) << error;
  EXPECT_FALSE(from_json(json::parse(changed(r, [](json& j) { j["summary"]["line"]["exchanges"] = -1; })), error));
  EXPECT_NE(error.find("exchanges: expected a whole number"), std::string::npos) << error;
  EXPECT_FALSE(from_json(json::parse(changed(r, [](json& j) { j["vectors"][1]["line"] = 2; })), error));
  EXPECT_NE(error.find("line: expected an object, got 2"), std::string::npos) << error;
}

// The reports' readers find a vector in error shown wrong: in JUnit not an
// <error> saying what the line did, or counted wrong; in the HTML and the
// Markdown its reason or the run's line figures not shown, the per-level
// table without it.
TEST(ErrorProblems, TheReportsReadersFindAVectorInErrorShownWrong) {
  const MemoryRecord r = error_record();
  auto broken = [](std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from << " in\n" << text;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
  };
  const std::string xml = junit_xml(r.doc);
  ASSERT_EQ(joined(checks::junit_problems(xml, r.doc)), "") << xml;
  EXPECT_TRUE(says(checks::junit_problems(broken(xml, "<error message=\"step 1", "<error message=\"step 2"), r.doc),
                   "the error of testcase 3.2-error says \"step 2 (status)"));
  EXPECT_TRUE(says(checks::junit_problems(broken(xml, "errors=\"1\" skipped=\"0\"", "errors=\"0\" skipped=\"0\""), r.doc),
                   "testsuite \"§3.2\" says errors=\"0\", its testcases have 1"));
  EXPECT_TRUE(says(checks::junit_problems(broken(xml, "failures=\"0\" errors=\"1\"", "failures=\"0\" errors=\"0\""), r.doc),
                   "testsuites says errors=\"0\", its testcases have 1"));
  EXPECT_TRUE(says(checks::junit_problems(broken(xml, "<error message=\"step 1", "<skipped message=\"step 1"), r.doc),
                   "JUnit line"))
      << "a skipped element with the error's text does not validate";
  RunDocument failed = r.doc;
  failed.vectors[1].outcome = "fail";
  failed.vectors[1].failures = {"f"};
  EXPECT_TRUE(says(checks::junit_problems(xml, failed), "testcase 3.2-error is a error, the vector a fail"));
  RunDocument skipped = r.doc;
  skipped.vectors[1].outcome = "inconclusive";
  skipped.vectors[1].inconclusive_reason = "precondition not met (x): y";
  EXPECT_TRUE(says(checks::junit_problems(junit_xml(skipped), r.doc), "testcase 3.2-error is a skip, the vector a error"));

  const std::string html = html_report(r.doc);
  ASSERT_EQ(joined(checks::html_problems(html, r.doc)), "");
  RunDocument other = r.doc;
  other.vectors[1].error_reason = "another reason";
  EXPECT_TRUE(says(checks::html_problems(html, other), "\"error: another reason\" is not shown as text"));
  RunDocument noisier = r.doc;
  noisier.summary->line = {40, 9, 9, 9};
  EXPECT_TRUE(says(checks::html_problems(html, noisier), "\"line: 9 faults in 40 exchanges, all recovered (fault rate 22.50%)\" is not shown"));

  const std::string md = markdown_summary(r.doc);
  ASSERT_EQ(joined(checks::markdown_problems(md, r.doc)), "") << md;
  EXPECT_TRUE(says(checks::markdown_problems(md, other), "failure item 1 reads"));
  EXPECT_TRUE(says(checks::markdown_problems(broken(md, "| must | 1 | 0 | 0 | 1 | 0 | 0 |", "| must | 1 | 0 | 0 | 0 | 0 | 0 |"), r.doc),
                   "per-level table"));
  EXPECT_TRUE(says(checks::markdown_problems(md, noisier), "no paragraph reads \"line: 9 faults in 40 exchanges"));
  EXPECT_TRUE(says(checks::markdown_problems(broken(md, "**Errors**", "**Errored**"), r.doc), "strong emphasis the summary does not write: Errored"));
}

// Then the record of a run with a vector in error reads back in every
// format, also rebuilt from its JSON and its journal; each names it, what
// the line did, and the run's line figures.
TEST(ErrorProblems, ARunWithAVectorInErrorReadsBackInEveryFormat) {
  const MemoryRecord r = error_record();
  EXPECT_EQ(joined(checks::run_record_problems(r.doc, r.journal)), "");
  const std::string why = "step 1 (status): no clean reply in 2 tries: bad check byte: expected 0x04, got 0x05";
  std::string error;
  const auto back = from_json(json::parse(json_text(r.doc)), error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->schema_version, kSchemaVersion);
  EXPECT_EQ(back->vectors[1].outcome, "error");
  EXPECT_EQ(back->vectors[1].error_reason, why);
  EXPECT_EQ(harness::describe(back->vectors[1].line), "line: 2 faults in 2 exchanges, 0 recovered");
  EXPECT_EQ(back->vectors[1].line.repeats, 1u);
  EXPECT_EQ(back->summary->errors, 1u);
  EXPECT_EQ(harness::describe(back->summary->line), "line: 3 faults in 40 exchanges, 1 recovered");
  EXPECT_EQ(back->counts().errors, 1u);
  EXPECT_EQ(back->verdict(), "ERROR");
  const std::string line = "line: 3 faults in 40 exchanges, 1 recovered (fault rate 7.50%)";
  const std::string xml = junit_xml(r.doc);
  EXPECT_NE(xml.find("<error message=\"" + why + "\" type=\"line error\">" + why + "\nline: 2 faults in 2 exchanges, 0 recovered\n"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<testsuites name=\"sabus\" tests=\"2\" failures=\"0\" errors=\"1\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<property name=\"line\" value=\"line: 3 faults in 40 exchanges, 1 recovered\"/>"), std::string::npos) << xml;
  const std::string html = html_report(r.doc);
  EXPECT_NE(html.find("<p class=\"error\">error: " + why + "</p>"), std::string::npos);
  EXPECT_NE(html.find("data-status=\"error\""), std::string::npos);
  EXPECT_NE(html.find("<option value=\"error\">"), std::string::npos);
  EXPECT_NE(html.find("<p id=\"summary\">1 passed, 0 failed, 0 skipped, 1 error</p>"), std::string::npos);
  EXPECT_NE(html.find("<p id=\"line\">" + line + "</p>"), std::string::npos);
  EXPECT_NE(html.find("<p id=\"line-warning\""), std::string::npos) << "7.5% is above a healthy line's 1%";
  EXPECT_NE(html.find("id=\"verdict\">ERROR<"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"error\">1 pass, 1 error</td>"), std::string::npos) << "the paragraph's tally";
  const std::string md = markdown_summary(r.doc);
  EXPECT_NE(md.find("### SAbus conformance: **ERROR**\n"), std::string::npos) << md;
  EXPECT_NE(md.find("1 passed, 0 failed, 0 skipped, 1 error\n\n" + line + "\n\n**Warning**: "), std::string::npos) << md;
  EXPECT_NE(md.find("**Line errors**: 1 vector ended in error: the line, not the firmware, left it unjudged."), std::string::npos)
      << md;
  EXPECT_NE(md.find("| must | 1 | 0 | 0 | 1 | 0 | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("**Errors**\n\n- `3.2-error` §3.2 must: " + why + "\n"), std::string::npos) << md;
}

// A run whose vectors and whole run counted no exchange (a document of
// versions 1 to 4, a transport that counts none) shows no line figures: no
// "0 faults in 0 exchanges" to read as a clean line.
TEST(ErrorProblems, NoLineFiguresWhereNoExchangeWasCounted) {
  const MemoryRecord r = finished_record();
  EXPECT_EQ(r.doc.counts().line.exchanges, 0u);
  EXPECT_EQ(html_report(r.doc).find("id=\"line\""), std::string::npos);
  EXPECT_EQ(markdown_summary(r.doc).find("line: "), std::string::npos);
  EXPECT_EQ(junit_xml(r.doc).find("name=\"line\""), std::string::npos);
}

// The record of a runner's result with a vector in error, as `sabus run`
// makes it (MemoryRecord: vector_record, finish): the engine that sets the
// verdict on a line is not this library's, so the result is made here as it
// gives it.
TEST(ErrorProblems, ARunnersResultWithAVectorInErrorIsRecordedWhole) {
  harness::VectorResult pass, erred;
  pass.id = "3.2-pass";
  pass.paragraph = "3.2";
  pass.verdict = harness::Verdict::kPass;
  pass.line = {3, 1, 1, 1};
  erred.id = "3.5-locate";
  erred.paragraph = "3.5";
  erred.verdict = harness::Verdict::kError;
  erred.error_reason = "step 2 (41h): no clean reply in 1 try: bad check byte; not sent again: a second LOCATE acts again";
  erred.line = {2, 1, 0, 0};
  harness::RunResult run;
  run.passed = 1;
  run.errors = 1;
  run.line = {9, 2, 1, 1};  // the identity query and the liveness probes too
  run.vectors = {pass, erred};
  MemoryRecord r;
  r.doc = test_documents::sample_header();
  r.doc.generator = "sabus test";
  r.doc.planned = 2;
  r.start();
  r.add(pass, 1.0);
  r.add(erred, 1.0);
  r.end(run, "2024-01-01T00:00:01Z");
  ASSERT_EQ(r.doc.vectors.size(), 2u);
  EXPECT_EQ(r.doc.vectors[1].outcome, "error");
  EXPECT_EQ(r.doc.vectors[1].error_reason, erred.error_reason);
  EXPECT_EQ(harness::describe(r.doc.vectors[0].line), "line: 1 fault in 3 exchanges, recovered");
  EXPECT_EQ(r.doc.summary->errors, 1u);
  EXPECT_EQ(r.doc.summary->exit_code, harness::kLineErrorExitCode);
  EXPECT_EQ(harness::describe(r.doc.summary->line), "line: 2 faults in 9 exchanges, 1 recovered");
  EXPECT_EQ(joined(checks::run_record_problems(r.doc, r.journal)), "");
}

// ---- the schema's two files --------------------------------------------------------

std::string read_source(const std::string& relative) {
  std::ifstream in(std::string(SABUS_SOURCE_DIR) + "/" + relative, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every property name in a JSON Schema, at any depth.
void property_names(const json& schema, std::set<std::string>& out) {
  if (schema.is_object()) {
    if (const auto p = schema.find("properties"); p != schema.end() && p->is_object())
      for (const auto& [name, _] : p->items()) out.insert(name);
    for (const auto& [key, value] : schema.items()) property_names(value, out);
  } else if (schema.is_array()) {
    for (const auto& value : schema) property_names(value, out);
  }
}

// SCHEMA.md says what each field means and run.schema.json what it may
// hold: every field in the first column of SCHEMA.md's tables (`name`, or
// `a`, `b` for fields described together) is a property of the schema, and
// every property of the schema is named in SCHEMA.md (nested ones, as the
// options' and the summary's, in the text of their field's row, or as
// `{first, last, ...}`).
TEST(RunSchema, TheSchemaAndSchemaMdNameTheSameFields) {
  std::set<std::string> in_schema, in_tables, in_text;
  property_names(json::parse(read_source("reports/run.schema.json")), in_schema);
  const std::string md_text = read_source("reports/SCHEMA.md");
  std::istringstream md(md_text);
  const std::regex row(R"(^\| (`[a-z_]+`(, `[a-z_]+`)*) \|)"), name("`([a-z_]+)`");
  for (std::string line; std::getline(md, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, row)) continue;
    const std::string cell = m[1];
    for (auto it = std::sregex_iterator(cell.begin(), cell.end(), name); it != std::sregex_iterator(); ++it) in_tables.insert((*it)[1]);
  }
  // In the text: every word of a code span (`{when, alive, detail}` too).
  const std::regex span("`([^`]+)`"), word("[a-z_]+");
  for (auto it = std::sregex_iterator(md_text.begin(), md_text.end(), span); it != std::sregex_iterator(); ++it) {
    const std::string code = (*it)[1];
    for (auto w = std::sregex_iterator(code.begin(), code.end(), word); w != std::sregex_iterator(); ++w) in_text.insert(w->str());
  }
  ASSERT_GT(in_tables.size(), 40u) << "SCHEMA.md's tables read";
  for (const auto& n : in_tables) EXPECT_TRUE(in_schema.count(n)) << "SCHEMA.md's tables name " << n << ", run.schema.json does not";
  for (const auto& n : in_schema) EXPECT_TRUE(in_text.count(n)) << "run.schema.json names " << n << ", SCHEMA.md does not";
}

// ---- records that must read back --------------------------------------------------

// Every string of the document hostile: each format keeps it as text.
TEST(RunRecordProblems, HostileTextFromTheDeviceReadsBackAsText) {
  MemoryRecord r;
  r.doc = test_documents::sample_header();
  r.doc.generator = "sabus " + kHostile;
  r.doc.device = kHostile;
  r.doc.profile = kHostile;
  r.doc.identity = {false, "", "", "", kHostile};
  r.doc.faults = {kHostile};
  r.doc.options = {{"filters", {kHostile}}, {"known_issues", kHostile}};
  r.start();
  VectorRecord v = vector("3.2-hostile", "fail");
  v.failures = {kHostile, "second " + kHostile};
  v.quote = v.comment = v.file = kHostile;
  v.transcript.push_back(frame("rx", "", kHostile));
  v.transcript[1].note = kHostile;
  v.transcript[1].fields = {{0, 0, kHostile, kHostile, kHostile, false}};
  r.journal += vector_json(v) + "\n";
  compact_for_reports(v);
  r.doc.vectors.push_back(v);
  r.doc.status = "aborted";
  r.doc.abort_reason = kHostile;
  r.doc.finished_at = "2024-01-01T00:00:01Z";
  r.doc.summary = Summary{0, 1, 0, 0, 0, 1, {}};
  r.doc.liveness = {{kHostile, false, kHostile}};
  r.doc.restore = {kHostile};
  r.doc.traffic = {{"bytes_sent", 1}, {"bytes_received", 1}, {"silence_windows", 0}, {"silence_listened_ms", 0.0},
                   {"measured_turnaround_ms", 0.0}};
  r.doc.journal.clear();
  r.journal += journal_record_json("end", r.doc) + "\n";
  EXPECT_EQ(joined(checks::run_record_problems(r.doc, r.journal)), "");
}

// The runs of issue 21 (a reply that does not decode, a NAK without its
// command, another reply address) and the clean controller: the whole suite,
// recorded as `sabus run` records it, reads back.
TEST(RunRecordProblems, TheSuiteAgainstFaultyControllersReadsBack) {
  const auto loaded = harness::load_vectors({harness::default_vectors_dir()});
  ASSERT_TRUE(loaded.ok());
  std::vector<harness::Vector> vectors;
  for (const auto& f : loaded.files) vectors.insert(vectors.end(), f.vectors.begin(), f.vectors.end());
  const auto profile = harness::load_profile_file(harness::default_profile_path());
  ASSERT_TRUE(profile) << profile.error->text();
  for (const char* fault : {"", "lrc-skips-byte0", "nak-without-command", "reply-address-0x30"}) {
    harness::FaultSet faults;
    if (*fault) {
      const auto f = harness::find_fault(fault);
      ASSERT_TRUE(f) << fault;
      faults.set(*f);
    }
    auto transport = harness::make_in_process_transport(harness::bus_of(*profile.profile), faults);
    MemoryRecord r;
    r.doc = test_documents::sample_header();
    r.doc.generator = "sabus test";
    r.doc.device = transport->describe();
    r.doc.identity = query_identity(*transport, profile.profile->address);
    r.doc.address = profile.profile->address;
    r.doc.planned = vectors.size();
    r.start();
    harness::RunOptions o;
    o.allow_motion = o.allow_destructive = true;
    o.keep_transcripts = false;
    o.on_result = r.on_result(1.0);
    r.end(harness::Runner(*transport, *profile.profile, o).run(vectors), "2024-01-01T00:00:01Z");
    const Problems p = checks::run_record_problems(r.doc, r.journal);
    EXPECT_EQ(joined(p), "") << (*fault ? fault : "clean");
    if (*fault) {
      EXPECT_NE(r.doc.verdict(), "PASS") << fault;
    }
  }
}

}  // namespace
}  // namespace sabus::reports
