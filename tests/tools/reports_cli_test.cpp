// `sabus run`, `sabus report` and `sabus diff` as processes: every report
// from one run and from its JSON, a run interrupted half-way, a regression
// between two runs of the in-process controller.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "process.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/reports/checks.hpp"
#include "sabus/reports/document.hpp"
#include "sabus/reports/journal.hpp"
#include "temp_dir.hpp"

namespace sabus::reports {
namespace {

using test::Process;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

using Output = test::ShellResult;
using test::shell;

using test::slurp;

class ReportsCli : public test::TempDirTest {
 protected:
  ReportsCli() : TempDirTest("sabus-reports-test") {}
};

const std::string kSabus = SABUS_BIN;

TEST_F(ReportsCli, EveryReportFromOneRunAndFromItsJson) {
  const std::string known = path("known.txt");
  std::ofstream(known) << "3.2-status-track-byte: short status reply in this release\n";
  const Output run = shell(kSabus + " run --sim --fault short-status --known-issues " + known + " --report-dir " +
                           path("run") + " 2>/dev/null");
  EXPECT_EQ(run.status, 1);
  for (const char* f : {"run.json", "junit.xml", "report.html", "summary.md"})
    ASSERT_TRUE(fs::exists(dir_ / "run" / f)) << f;
  const Output again = shell(kSabus + " report " + path("run/run.json") + " --html " + path("again.html") + " --junit " +
                             path("again.xml") + " --md " + path("again.md"));
  EXPECT_EQ(again.status, 0) << again.out;
  EXPECT_EQ(slurp(dir_ / "run/report.html"), slurp(path("again.html")));
  EXPECT_EQ(slurp(dir_ / "run/junit.xml"), slurp(path("again.xml")));
  EXPECT_EQ(slurp(dir_ / "run/summary.md"), slurp(path("again.md")));
  EXPECT_NE(slurp(path("again.html")).find("3.2-status-track-byte"), std::string::npos);

  EXPECT_FALSE(fs::exists(dir_ / "run" / "run.journal.jsonl")) << "the JSON holds every vector: the journal is gone";
  const auto doc = nlohmann::json::parse(slurp(dir_ / "run/run.json"));
  EXPECT_EQ(doc["schema_version"], kSchemaVersion);
  EXPECT_EQ(doc["status"], "complete");
  EXPECT_FALSE(doc.contains("journal"));
  EXPECT_EQ(doc["identity"]["controller_type"], "3K");
  EXPECT_EQ(doc["identity"]["firmware_version"], "1.59");
  bool known_failure = false, has_fields = false, has_quote = false;
  for (const auto& v : doc["vectors"]) {
    known_failure |= v["id"] == "3.2-status-track-byte" && v["outcome"] == "known failure";
    EXPECT_GE(v["wall_ms"].get<double>(), 0) << v["id"];
    has_quote |= !v["quote"].get<std::string>().empty();
    for (const auto& t : v["transcript"]) {
      for (const char* key : {"t_ms", "dir", "hex", "note"}) EXPECT_TRUE(t.contains(key)) << key;
      has_fields |= !t["fields"].empty();
    }
  }
  EXPECT_TRUE(known_failure);
  EXPECT_TRUE(has_fields);
  EXPECT_TRUE(has_quote);
}

TEST_F(ReportsCli, ReportRejectsABadFile) {
  std::ofstream(path("bad.json")) << "{\"schema\": \"sabus-run\", \"schema_version\": 2, \"vectors\": [{}]}";
  EXPECT_EQ(shell(kSabus + " report " + path("bad.json") + " --md " + path("x.md") + " 2>/dev/null").status, 2);
  EXPECT_EQ(shell(kSabus + " report " + path("none.json") + " --md " + path("x.md") + " 2>/dev/null").status, 2);
  EXPECT_EQ(shell(kSabus + " report " + path("bad.json") + " 2>/dev/null").status, 2) << "no report asked for";
}

TEST_F(ReportsCli, PlainConsoleLinesWhenNotATerminal) {
  const Output run = shell(kSabus + " run --sim --fault short-status --json " + path("plain.json") + " 2>/dev/null");
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.out.find('\r'), std::string::npos);
  EXPECT_EQ(run.out.find('\033'), std::string::npos);
  EXPECT_NE(run.out.find("\nFAIL 3.2-status-track-byte §3.2 must: "), std::string::npos) << run.out;
  // One verdict line a vector, in the JSON's order.
  const auto doc = nlohmann::json::parse(slurp(path("plain.json")));
  std::size_t at = 0;
  for (const auto& v : doc["vectors"]) {
    const std::string word = v["outcome"] == "pass" ? "PASS " : v["outcome"] == "skip" ? "SKIP " : "FAIL ";
    at = run.out.find("\n" + word + v["id"].get<std::string>() + " ", at);
    ASSERT_NE(at, std::string::npos) << v["id"];
  }
  // The closing line counts what the JSON of the same run counts, the skips by cause.
  const auto summary = doc["summary"];
  ASSERT_GT(summary["failed"].get<int>(), 0);
  const auto causes = summary["skipped_by_cause"];
  const std::string last = run.out.substr(run.out.rfind('\n', run.out.size() - 2) + 1);
  EXPECT_EQ(last, std::to_string(summary["passed"].get<int>()) + " passed, " + std::to_string(summary["failed"].get<int>()) +
                      " failed, " + std::to_string(summary["skipped"].get<int>()) + " skipped (" +
                      std::to_string(causes["profile"].get<int>()) + " need another profile, " +
                      std::to_string(causes["motion"].get<int>()) + " need --allow-motion, " +
                      std::to_string(causes["destructive"].get<int>()) + " need --allow-destructive)\n");
}

TEST_F(ReportsCli, DiffNamesAnInjectedFaultAsARegression) {
  ASSERT_EQ(shell(kSabus + " run --sim --json " + path("good.json") + " >/dev/null 2>&1").status, 0);
  ASSERT_EQ(shell(kSabus + " run --sim --fault short-status --json " + path("bad.json") + " >/dev/null 2>&1").status, 1);
  const Output diff = shell(kSabus + " diff " + path("good.json") + " " + path("bad.json"));
  EXPECT_EQ(diff.status, 1);
  EXPECT_NE(diff.out.find("REGRESSION New failures"), std::string::npos) << diff.out;
  EXPECT_NE(diff.out.find("3.2-status-reply-length §3.2 must: pass → fail"), std::string::npos) << diff.out;
  const Output md = shell(kSabus + " diff --md " + path("good.json") + " " + path("bad.json"));
  EXPECT_EQ(md.status, 1);
  EXPECT_NE(md.out.find("| `3.2-status-reply-length` |"), std::string::npos) << md.out;
  const Output back = shell(kSabus + " diff " + path("bad.json") + " " + path("good.json"));
  EXPECT_EQ(back.status, 0) << back.out;
  const int failed = nlohmann::json::parse(slurp(path("bad.json")))["summary"]["failed"].get<int>();
  EXPECT_NE(back.out.find("Fixed (" + std::to_string(failed) + ")"), std::string::npos) << back.out;
  const Output same = shell(kSabus + " diff " + path("good.json") + " " + path("good.json"));
  EXPECT_EQ(same.status, 0);
  EXPECT_EQ(same.out.find("WARNING"), std::string::npos) << same.out;
  // A filtered run against a full one: said before anything else.
  ASSERT_EQ(shell(kSabus + " run --sim --filter '3.2-*' --json " + path("filtered.json") + " >/dev/null 2>&1").status, 0);
  const Output filtered = shell(kSabus + " diff " + path("good.json") + " " + path("filtered.json"));
  EXPECT_EQ(filtered.out.rfind("WARNING option filters: [] -> [\"3.2-*\"]\nWARNING selection: OLD ran ", 0), 0u) << filtered.out;
  EXPECT_EQ(shell(kSabus + " diff --timing-threshold soon " + path("good.json") + " " + path("good.json") + " 2>/dev/null").status, 2);
}

// A §3.17 vector file: a 40h whose current mode is a precondition, then a
// status poll that expects `reply`.
std::string precondition_vector(const std::string& mode, const std::string& reply = "ack") {
  return "paragraph: \"3.17\"\ntitle: t\nvectors:\n  - id: 3.17-search-stop\n    comment: c\n"
         "    spec: {paragraph: \"3.17\", quote: \"31-127 (20h - 7Fh) current mode value as defined by the mode_name "
         "enumeration list at the end of this definition\"}\n    level: must\n    steps:\n"
         "      - send: {command: extended_status}\n        expect: {reply: ack, fields: {current mode: " + mode + "}}\n"
         "        precondition: \"the search is still running when the stop goes out\"\n"
         "      - send: {command: status}\n        expect: " + reply + "\n";
}

// A precondition the reference controller at rest does not meet (no search
// runs): the vector is inconclusive on the console, in every report (each
// read back by its parser) and exits 5, having checked nothing; `sabus
// diff` shows pass -> inconclusive as a change, not a regression, and
// inconclusive -> fail as a new failure.
TEST_F(ReportsCli, AnInconclusiveVectorInEveryReportAndInADiff) {
  std::ofstream(path("holds.yaml")) << precondition_vector("{regex: \"^0x(?!26$)([2-4][0-9a-f]|5[0-9a-c])$\"}");
  std::ofstream(path("unmet.yaml")) << precondition_vector("0x26");
  std::ofstream(path("fails.yaml")) << precondition_vector("{regex: \"^0x(?!26$)([2-4][0-9a-f]|5[0-9a-c])$\"}", "nak");
  const Output pass = shell(kSabus + " run --sim --vectors " + path("holds.yaml") + " --json " + path("pass.json") + " 2>&1");
  ASSERT_EQ(pass.status, 0) << pass.out;
  const Output unmet = shell(kSabus + " run --sim --vectors " + path("unmet.yaml") + " --report-dir " + path("inc") + " 2>&1");
  EXPECT_EQ(unmet.status, 5) << unmet.out;
  const std::string why = "precondition not met (the search is still running when the stop goes out): byte ";
  EXPECT_NE(unmet.out.find("INCONCLUSIVE 3.17-search-stop §3.17 must: " + why), std::string::npos) << unmet.out;
  EXPECT_NE(unmet.out.find("0 passed, 0 failed, 0 skipped, 1 inconclusive\n"), std::string::npos) << unmet.out;
  EXPECT_NE(unmet.out.find("NOTHING RAN: the one vector that ran ended inconclusive"), std::string::npos) << unmet.out;

  const std::string json = slurp(dir_ / "inc/run.json");
  EXPECT_EQ(checks::run_json_problems(json), checks::Problems{});
  const auto j = nlohmann::json::parse(json);
  EXPECT_EQ(j["schema_version"], kSchemaVersion);
  EXPECT_EQ(j["summary"]["inconclusive"], 1);
  EXPECT_EQ(j["summary"]["exit_code"], harness::kNothingRanExitCode);
  EXPECT_EQ(j["vectors"][0]["outcome"], "inconclusive");
  EXPECT_EQ(j["vectors"][0]["inconclusive_reason"].get<std::string>().rfind(why, 0), 0u) << j["vectors"][0];
  std::string error;
  const auto doc = read_run_file(path("inc/run.json"), error);
  ASSERT_TRUE(doc) << error;
  ASSERT_EQ(doc->vectors.size(), 1u);
  EXPECT_EQ(doc->counts().inconclusive, 1u);
  const std::string xml = slurp(dir_ / "inc/junit.xml"), html = slurp(dir_ / "inc/report.html"), md = slurp(dir_ / "inc/summary.md");
  EXPECT_EQ(checks::junit_problems(xml, *doc), checks::Problems{});
  EXPECT_NE(xml.find("<skipped message=\"inconclusive: " + why), std::string::npos) << xml;
  EXPECT_EQ(checks::html_problems(html, *doc), checks::Problems{});
  EXPECT_NE(html.find("<p class=\"inconclusive\">inconclusive: " + why), std::string::npos);
  EXPECT_EQ(checks::markdown_problems(md, *doc), checks::Problems{});
  EXPECT_NE(md.find("| must | 0 | 0 | 0 | 0 | 1 | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("**Inconclusive**\n\n- `3.17-search-stop` §3.17 must: " + why), std::string::npos) << md;

  const Output diff = shell(kSabus + " diff " + path("pass.json") + " " + path("inc/run.json"));
  EXPECT_EQ(diff.status, 0) << diff.out;
  EXPECT_NE(diff.out.find("Other outcome changes (1):\n  3.17-search-stop §3.17 must: pass → inconclusive  inconclusive: " + why),
            std::string::npos)
      << diff.out;
  const Output fails = shell(kSabus + " run --sim --vectors " + path("fails.yaml") + " --json " + path("fail.json") + " 2>&1");
  ASSERT_EQ(fails.status, 1) << fails.out;
  const Output worse = shell(kSabus + " diff " + path("inc/run.json") + " " + path("fail.json"));
  EXPECT_EQ(worse.status, 1) << worse.out;
  EXPECT_NE(worse.out.find("REGRESSION New failures (1):\n  3.17-search-stop §3.17 must: inconclusive → fail"), std::string::npos)
      << worse.out;
  const Output back = shell(kSabus + " diff " + path("fail.json") + " " + path("inc/run.json"));
  EXPECT_EQ(back.out.find("Fixed"), std::string::npos) << "a failure now inconclusive is not fixed:\n" << back.out;
  EXPECT_NE(back.out.find("3.17-search-stop §3.17 must: fail → inconclusive"), std::string::npos) << back.out;
}

// A run of §3.2 on the reference controller whose two vectors that the
// short-status fault fails are recorded as the line leaving them unjudged
// (as the runner records a reply a repeat could not get clean; the engine is
// tested on its own): the reports `sabus report` makes from that JSON name
// them and the line figures, each read back by its parser; `sabus diff`
// shows pass -> error as a change and error -> fail as a new failure;
// `sabus run --last-failed` runs exactly those two again.
TEST_F(ReportsCli, VectorsInErrorInEveryReportInADiffAndInALastFailedRun) {
  const Output clean = shell(kSabus + " run --sim --paragraph 3.2 --json " + path("pass.json") + " 2>&1");
  ASSERT_EQ(clean.status, 0) << clean.out;
  const Output faulty = shell(kSabus + " run --sim --fault short-status --paragraph 3.2 --json " + path("fail.json") + " 2>&1");
  ASSERT_EQ(faulty.status, 1) << faulty.out;
  std::string error;
  const auto failed = read_run_file(path("fail.json"), error);
  ASSERT_TRUE(failed) << error;
  auto doc = read_run_file(path("pass.json"), error);
  ASSERT_TRUE(doc) << error;
  std::vector<std::string> erred;
  for (const auto& f : failed->vectors)
    if (f.is_failure() && erred.size() < 2) erred.push_back(f.id);
  ASSERT_EQ(erred.size(), 2u) << "the fault fails two vectors of §3.2 at least";
  const std::string why = "step 1 (status): no clean reply in 2 tries: bad check byte: expected 0x04, got 0x05";
  for (auto& v : doc->vectors)
    if (std::find(erred.begin(), erred.end(), v.id) != erred.end()) {
      v.outcome = "error";
      v.error_reason = why;
      v.line = {2, 2, 0, 1};
      --doc->summary->passed;
      ++doc->summary->errors;
    }
  // The run's figures: its vectors' (on a clean line, the exchanges the
  // runner counted, none faulty, and the two above) and 200 exchanges of no
  // vector (liveness, backup) with one fault; 3 of the 5 faults recovered.
  harness::LineFaultCounts vectors_line;
  for (const auto& v : doc->vectors) vectors_line += v.line;
  ASSERT_EQ(vectors_line.faults, 4u) << "a clean in-process line has no fault";
  doc->summary->line = vectors_line;
  doc->summary->line += harness::LineFaultCounts{200, 1, 3, 1};
  doc->summary->exit_code = harness::kLineErrorExitCode;
  ASSERT_TRUE(write_run_json(path("err.json"), *doc, error)) << error;
  ASSERT_EQ(checks::run_json_problems(slurp(dir_ / "err.json")), checks::Problems{});

  const Output report = shell(kSabus + " report " + path("err.json") + " --html " + path("err.html") + " --junit " +
                              path("err.xml") + " --md " + path("err.md"));
  EXPECT_EQ(report.status, 0) << report.out;
  EXPECT_EQ(report.out.rfind("ERROR: ", 0), 0u) << report.out;
  EXPECT_NE(report.out.find(", 2 errors (complete)\n" + harness::describe(doc->summary->line) + " (fault rate "), std::string::npos)
      << report.out;
  EXPECT_EQ(harness::describe(doc->summary->line).rfind("line: 5 faults in ", 0), 0u);
  EXPECT_NE(harness::describe(doc->summary->line).find(" exchanges, 3 recovered"), std::string::npos);
  const std::string xml = slurp(dir_ / "err.xml"), html = slurp(dir_ / "err.html"), md = slurp(dir_ / "err.md");
  EXPECT_EQ(checks::junit_problems(xml, *doc), checks::Problems{});
  EXPECT_NE(xml.find("<error message=\"" + why + "\" type=\"line error\">"), std::string::npos) << xml;
  EXPECT_EQ(checks::html_problems(html, *doc), checks::Problems{});
  EXPECT_NE(html.find("<p class=\"error\">error: " + why + "</p>"), std::string::npos);
  EXPECT_NE(html.find("<p id=\"line\">" + harness::describe(doc->summary->line) + " (fault rate "), std::string::npos);
  EXPECT_EQ(checks::markdown_problems(md, *doc), checks::Problems{});
  EXPECT_NE(md.find("**Errors**\n\n- `" + erred[0] + "` §3.2 must: " + why + "\n"), std::string::npos) << md;
  EXPECT_NE(md.find("**Line errors**: 2 vectors ended in error"), std::string::npos) << md;

  const Output diff = shell(kSabus + " diff " + path("pass.json") + " " + path("err.json"));
  EXPECT_EQ(diff.status, 0) << diff.out;
  EXPECT_NE(diff.out.find("Other outcome changes (2):\n  " + erred[0] + " §3.2 must: pass → error  error: " + why),
            std::string::npos)
      << diff.out;
  const Output worse = shell(kSabus + " diff " + path("err.json") + " " + path("fail.json"));
  EXPECT_EQ(worse.status, 1) << worse.out;
  EXPECT_NE(worse.out.find("  " + erred[0] + " §3.2 must: error → fail"), std::string::npos) << worse.out;
  // The failures the fault made that passed now are fixed; the two now in
  // error are not: an other change, with what the line did.
  const Output back = shell(kSabus + " diff " + path("fail.json") + " " + path("err.json"));
  const auto other = back.out.find("Other outcome changes (2):\n");
  ASSERT_NE(other, std::string::npos) << back.out;
  for (const auto& id : erred) {
    EXPECT_NE(back.out.find("  " + id + " §3.2 must: fail → error  error: " + why, other), std::string::npos) << back.out;
    EXPECT_EQ(back.out.find("  " + id + " §3.2 must: fail → pass"), std::string::npos) << "not fixed:\n" << back.out;
  }

  const Output again = shell(kSabus + " run --sim --last-failed " + path("err.json") + " --json " + path("again.json") + " 2>&1");
  EXPECT_EQ(again.status, 0) << again.out;
  const auto rerun = read_run_file(path("again.json"), error);
  ASSERT_TRUE(rerun) << error;
  std::vector<std::string> ran;
  for (const auto& v : rerun->vectors) ran.push_back(v.id);
  std::sort(ran.begin(), ran.end());
  std::sort(erred.begin(), erred.end());
  EXPECT_EQ(ran, erred) << "only the vectors in error ran again";
}

// The vector records in a run's journal so far.
std::size_t journaled_vectors(const fs::path& journal) {
  std::ifstream in(journal);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) {
    const auto r = nlohmann::json::parse(line, nullptr, false);
    n += r.is_object() && !r.contains("record");  // a vector; the header and end records say what they are
  }
  return n;
}

// `sabus run` over TCP with pacing against `sabus sim`: seconds, time enough
// to interrupt it half-way.
class InterruptedRun : public ReportsCli {
 protected:
  void SetUp() override {
    ReportsCli::SetUp();
    sim_ = std::make_unique<Process>(std::vector<std::string>{kSabus, "sim", "--tcp", "127.0.0.1:0"});
    const std::string ready = sim_->line(5s);
    ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
    port_ = ready.substr(ready.rfind(':') + 1);
  }
  void TearDown() override {
    if (sim_) {
      EXPECT_EQ(sim_->interrupt(), 0);
    }
    ReportsCli::TearDown();
  }
  std::unique_ptr<Process> start_run() {
    return std::make_unique<Process>(
        std::vector<std::string>{kSabus, "run", "--tcp", "127.0.0.1:" + port_, "--pace", "150", "--json", path("run.json"),
                                 "--junit", path("junit.xml"), "--md", path("summary.md"),
                                 // The power-on vectors run first (as-found), several of them
                                 // skipped on the default profile: these runs want passes.
                                 "--exclude", "*power-on*", "--exclude", "*block-tracking"});
  }
  // The files of a run the bench stopped, read back: the run JSON through its
  // schema, the JUnit through reports/junit.xsd and the checks (one error
  // naming `why`, of type "stopped"; no vector a failure but the one the
  // device was lost in, an error), the summary's verdict STOPPED.
  void expect_stopped_files(const std::string& why) {
    const std::string json = slurp(path("run.json"));
    EXPECT_EQ(checks::run_json_problems(json), checks::Problems{});
    std::string error;
    const auto doc = read_run_file(path("run.json"), error);
    ASSERT_TRUE(doc) << error;
    EXPECT_EQ(doc->status, "aborted");
    EXPECT_EQ(doc->abort_reason.rfind(why, 0), 0u) << doc->abort_reason;
    ASSERT_TRUE(doc->summary);
    EXPECT_EQ(doc->summary->exit_code, harness::kStoppedExitCode);
    const std::string junit = slurp(path("junit.xml"));
    EXPECT_EQ(checks::junit_problems(junit, *doc), checks::Problems{});
    EXPECT_NE(junit.find("<error message=\"" + why), std::string::npos) << "the error names why";
    EXPECT_NE(junit.find("type=\"stopped\""), std::string::npos);
    EXPECT_EQ(junit.find("<failure"), std::string::npos) << "a stopped run is not a failure of the firmware";
    EXPECT_EQ(checks::markdown_problems(slurp(path("summary.md")), *doc), checks::Problems{});
    EXPECT_EQ(slurp(path("summary.md")).rfind("### SAbus conformance: **STOPPED**", 0), 0u);
  }
  // Waits until the journal holds `n` vectors; the JSON meanwhile says the
  // run goes on and names the journal. Returns the vectors planned.
  std::size_t wait_for(std::size_t n) {
    std::size_t planned = 0;
    for (int i = 0; i < 600 && journaled_vectors(dir_ / "run.journal.jsonl") < n; ++i) std::this_thread::sleep_for(50ms);
    const auto doc = nlohmann::json::parse(slurp(dir_ / "run.json"), nullptr, false);
    EXPECT_FALSE(doc.is_discarded()) << "the JSON is whole while the run goes on";
    if (doc.is_discarded()) return 0;
    EXPECT_EQ(doc["status"], "running");
    EXPECT_EQ(doc["journal"], "run.journal.jsonl");
    EXPECT_TRUE(doc["vectors"].empty()) << "the vectors are in the journal until the end";
    planned = doc["planned"].get<std::size_t>();
    return planned;
  }
  std::unique_ptr<Process> sim_;
  std::string port_;
};

// SIGINT half-way leaves a JSON marked aborted with every finished vector,
// written from the journal once.
TEST_F(InterruptedRun, SigintHalfWayLeavesAnAbortedJsonWithEveryFinishedVector) {
  auto run = start_run();
  const std::size_t planned = wait_for(2);
  const std::size_t seen = journaled_vectors(dir_ / "run.journal.jsonl");
  ASSERT_GE(seen, 2u) << "the run did not get going";
  ASSERT_GT(planned, seen + 2) << "the run is too fast to interrupt half-way";
  EXPECT_EQ(run->interrupt(), harness::kStoppedExitCode) << "stopped, not failed (1)";
  const auto doc = nlohmann::json::parse(slurp(path("run.json")));
  EXPECT_EQ(doc["status"], "aborted");
  EXPECT_EQ(doc["abort_reason"], "stopped by SIGINT");
  expect_stopped_files("stopped by SIGINT");
  EXPECT_GE(doc["vectors"].size(), seen) << "every vector finished before the SIGINT is kept";
  EXPECT_LT(doc["vectors"].size(), planned);
  for (const auto& v : doc["vectors"]) {
    EXPECT_EQ(v["outcome"], "pass") << v["id"];
    EXPECT_FALSE(v["transcript"].empty()) << v["id"];
  }
  EXPECT_EQ(doc["summary"]["passed"].get<std::size_t>(), doc["vectors"].size());
  EXPECT_FALSE(doc.contains("journal"));
  EXPECT_FALSE(fs::exists(dir_ / "run.journal.jsonl"));
}

// SIGTERM (what a CI job's timeout or `kill` sends) stops the run as SIGINT
// does, and the reports name it.
TEST_F(InterruptedRun, SigtermStopsTheRunWithItsOwnExitCodeAndAJunitError) {
  auto run = start_run();
  const std::size_t planned = wait_for(2);
  ASSERT_GT(planned, journaled_vectors(dir_ / "run.journal.jsonl") + 2) << "the run is too fast to stop half-way";
  EXPECT_EQ(run->stop_with(SIGTERM), harness::kStoppedExitCode);
  expect_stopped_files("stopped by SIGTERM");
  const auto doc = nlohmann::json::parse(slurp(path("run.json")));
  EXPECT_GE(doc["vectors"].size(), 2u);
  EXPECT_LT(doc["vectors"].size(), planned);
}

// The device goes away half-way (the simulator killed: its socket closes):
// the run stops with the code of a stopped run, not 1 or 3, its reports
// saved; the vector it was in is an error in JUnit.
TEST_F(InterruptedRun, ALostDeviceStopsTheRunWithItsOwnExitCode) {
  auto run = start_run();
  const std::size_t planned = wait_for(2);
  ASSERT_GT(planned, journaled_vectors(dir_ / "run.journal.jsonl") + 2);
  sim_.reset();  // SIGKILL
  EXPECT_EQ(run->wait_exit_for(30s), harness::kStoppedExitCode);
  expect_stopped_files("device lost during ");
  const std::string junit = slurp(path("junit.xml"));
  EXPECT_NE(junit.find("type=\"lost device\""), std::string::npos) << "the vector it was lost in is an error";
}

// A run killed outright (SIGKILL: no end record, no final JSON) leaves its
// journal; `sabus report` makes the run JSON and the reports from it.
TEST_F(InterruptedRun, AKilledRunsJournalBecomesItsJsonThroughSabusReport) {
  auto run = start_run();
  const std::size_t planned = wait_for(3);
  run.reset();  // SIGKILL
  const std::size_t journaled = journaled_vectors(dir_ / "run.journal.jsonl");
  ASSERT_GE(journaled, 3u);
  ASSERT_LT(journaled, planned);
  const Output report = shell(kSabus + " report " + path("run.journal.jsonl") + " --json " + path("run.json") + " --html " +
                              path("report.html") + " --junit " + path("junit.xml") + " 2>" + path("stderr.txt"));
  EXPECT_EQ(report.status, 0) << report.out << slurp(path("stderr.txt"));
  // The summary, then the line figures of a run over a line (TCP here).
  EXPECT_EQ(report.out.substr(0, report.out.find('\n') + 1),
            "INCOMPLETE: " + std::to_string(journaled) + " passed, 0 failed, 0 skipped (running)\n");
  EXPECT_TRUE(std::regex_search(report.out, std::regex(R"(\nline: 0 faults in \d+ exchanges \(fault rate 0\.00%\)\n$)")))
      << report.out;
  EXPECT_NE(slurp(path("stderr.txt")).find("has no end record: the run was killed"), std::string::npos) << slurp(path("stderr.txt"));
  const auto doc = nlohmann::json::parse(slurp(path("run.json")));
  EXPECT_EQ(doc["status"], "running") << "the run never ended";
  EXPECT_FALSE(doc.contains("journal"));
  ASSERT_EQ(doc["vectors"].size(), journaled);
  EXPECT_FALSE(doc["vectors"][0]["transcript"][0]["fields"].empty()) << "every field, as the run recorded it";
  EXPECT_NE(slurp(path("report.html")).find("id=\"verdict\">INCOMPLETE<"), std::string::npos);
  // The recovered JSON reads back, and reports from it are the journal's.
  const Output again = shell(kSabus + " report " + path("run.json") + " --html " + path("again.html"));
  EXPECT_EQ(again.status, 0);
  EXPECT_EQ(slurp(path("again.html")), slurp(path("report.html")));
}

}  // namespace
}  // namespace sabus::reports
