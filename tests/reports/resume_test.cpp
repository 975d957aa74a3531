// A stopped run read back for `sabus run --resume`: the failing paths first
// (a missing, malformed or finished run, one ended by what it found, one
// that does not say how it was run), then a stopped run's JSON and a killed
// run's journal, the vector the device was lost in left out to run again;
// the new fields of the run JSON through the schema and back; a resumed
// run's journal written over a killed run's; a kept vector read back as the
// runner's result.
#include "sabus/reports/resume.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "sabus/reports/checks.hpp"
#include "sabus/reports/journal.hpp"
#include "sample_run.hpp"
#include "temp_dir.hpp"

namespace sabus::reports {
namespace {

namespace fs = std::filesystem;
using test_documents::sample_header;
using test_documents::sample_vector;

class StoppedRunFile : public test::TempDirTest {
 protected:
  StoppedRunFile() : TempDirTest("sabus-resume-test") {}
  // A run of three vectors that the bench stopped (SIGINT) after two of them.
  RunDocument stopped() {
    RunDocument d = sample_header();
    d.options = {{"seed", 7}, {"level", "informative"}};
    d.invocation.emplace();
    d.invocation->tcp = "127.0.0.1:2000";
    d.invocation->line = "8N1";
    d.invocation->serial_backend = "auto";
    d.invocation->report_dir = "out";
    d.planned = 3;
    d.vectors = {sample_vector("a", "pass"), sample_vector("b", "fail")};
    d.status = "aborted";
    d.abort_reason = "stopped by SIGINT";
    d.stopped_by = "SIGINT";
    d.finished_at = "2024-01-01T00:20:00Z";
    d.summary = d.counts();
    d.summary->exit_code = harness::kStoppedExitCode;
    d.restore = {"preset satellite 2 restored"};
    d.backup = "out/backup.json";
    d.traffic = {{"bytes_sent", 10}, {"bytes_received", 20}, {"silence_windows", 1}, {"silence_listened_ms", 5.0},
                 {"measured_turnaround_ms", 2.0}};
    return d;
  }
  // The header a killed run left: its JSON says "running", names its journal,
  // and has no end (no summary, restore or backup).
  RunDocument killed_header() {
    RunDocument header = stopped();
    header.status = "running";
    header.abort_reason.clear();
    header.stopped_by.clear();
    header.finished_at.clear();
    header.summary.reset();
    header.restore.clear();
    header.backup.clear();
    header.vectors.clear();
    header.journal = "run.journal.jsonl";
    return header;
  }
  void write(const std::string& name, const RunDocument& d) {
    std::string error;
    ASSERT_TRUE(write_run_json(path(name), d, error)) << error;
  }
  std::string refused(const std::string& given) {
    std::string error;
    EXPECT_FALSE(read_stopped_run(given, error)) << given;
    return error;
  }
};

TEST_F(StoppedRunFile, AMissingOrMalformedFileIsAnErrorNamingIt) {
  EXPECT_EQ(refused(path("none.json")),
            path("none.json") + ": no such file (give the run.json of a stopped `sabus run`, or its journal)");
  EXPECT_EQ(refused(dir_.string()).rfind(path("run.json") + ": no such file", 0), 0u) << "a folder means its run.json";
  std::ofstream(path("bad.json")) << "{\"schema\": ";
  EXPECT_EQ(refused(path("bad.json")).rfind(path("bad.json") + ": not JSON", 0), 0u);
  std::ofstream(path("other.json")) << "{\"schema\": \"something-else\"}";
  EXPECT_EQ(refused(path("other.json")).rfind(path("other.json") + ": schema: ", 0), 0u);
}

TEST_F(StoppedRunFile, ARunThatRanToItsEndIsNotResumed) {
  RunDocument d = stopped();
  d.status = "complete";
  d.abort_reason.clear();
  d.stopped_by.clear();
  d.summary->exit_code = 1;
  write("run.json", d);
  EXPECT_EQ(refused(path("run.json")),
            path("run.json") + ": the run ran to its end (exit 1): there is nothing to resume (`sabus run --last-failed " +
                path("run.json") + "` runs its failures again)");
}

TEST_F(StoppedRunFile, ARunEndedByWhatItFoundIsNotResumed) {
  RunDocument d = stopped();
  d.abort_reason = "no answer to three liveness probes";
  d.stopped_by.clear();
  d.summary->exit_code = 1;
  write("run.json", d);
  EXPECT_EQ(refused(path("run.json")),
            path("run.json") + ": the run was ended by what it found, not stopped by the bench (no answer to three liveness "
                               "probes; exit 1): only a run stopped by SIGINT, SIGTERM or a lost device (exit 4), or killed, "
                               "is resumed");
}

TEST_F(StoppedRunFile, ARunThatDoesNotSayHowItWasRunIsNotResumed) {
  RunDocument d = stopped();
  d.invocation.reset();
  write("run.json", d);
  EXPECT_NE(refused(path("run.json")).find("does not record how it was run"), std::string::npos);
}

// The stopped run's JSON: every finished vector kept, whole; the stop as
// the resumed run records it.
TEST_F(StoppedRunFile, AStoppedRunsJsonIsReadWithItsVectorsAndItsStop) {
  write("run.json", stopped());
  for (const std::string& given : {path("run.json"), dir_.string()}) {
    std::string error;
    const auto s = read_stopped_run(given, error);
    ASSERT_TRUE(s) << error;
    EXPECT_EQ(s->json, path("run.json"));
    ASSERT_EQ(s->doc.vectors.size(), 2u);
    EXPECT_EQ(s->doc.vectors[1].id, "b");
    EXPECT_FALSE(s->doc.vectors[0].transcript[0].fields.empty()) << "whole: the journal of the resumed run holds them";
    EXPECT_TRUE(s->rerun.empty());
    EXPECT_EQ(s->stop.stopped_by, "SIGINT");
    EXPECT_EQ(s->stop.stopped_at, "2024-01-01T00:20:00Z");
    EXPECT_EQ(s->stop.abort_reason, "stopped by SIGINT");
    EXPECT_EQ(s->stop.kept, 2u);
    EXPECT_EQ(s->stop.restore, std::vector<std::string>{"preset satellite 2 restored"});
    EXPECT_EQ(s->doc.backup, "out/backup.json");
    ASSERT_TRUE(s->doc.invocation);
    EXPECT_EQ(s->doc.invocation->tcp, "127.0.0.1:2000");
  }
}

// The vector the device was lost in did not finish: it runs again.
TEST_F(StoppedRunFile, TheVectorTheDeviceWasLostInIsLeftOutToRunAgain) {
  RunDocument d = stopped();
  d.vectors[1].failures = {std::string(harness::kDeviceLostFailure) + "the socket closed"};
  d.abort_reason = "device lost during b: the socket closed";
  d.stopped_by = "lost device";
  write("run.json", d);
  std::string error;
  const auto s = read_stopped_run(path("run.json"), error);
  ASSERT_TRUE(s) << error;
  ASSERT_EQ(s->doc.vectors.size(), 1u);
  EXPECT_EQ(s->doc.vectors[0].id, "a");
  EXPECT_EQ(s->rerun, std::vector<std::string>{"b"});
  EXPECT_EQ(s->stop.stopped_by, "lost device");
  EXPECT_EQ(s->stop.kept, 1u);
}

// A killed run: its JSON says "running" and names the journal, which holds
// the vectors; the journal named instead gives the same, and the JSON beside
// it is the file the resumed run writes.
TEST_F(StoppedRunFile, AKilledRunIsReadFromItsJournal) {
  const RunDocument header = killed_header();
  write("run.json", header);
  {
    JournalWriter w;
    ASSERT_TRUE(w.open(path("run.journal.jsonl"), header)) << w.error();
    for (const auto& v : stopped().vectors) ASSERT_TRUE(w.append(v));
  }  // no end record
  for (const std::string& given : {path("run.json"), path("run.journal.jsonl")}) {
    std::string error;
    const auto s = read_stopped_run(given, error);
    ASSERT_TRUE(s) << error;
    EXPECT_EQ(s->json, path("run.json"));
    EXPECT_EQ(s->doc.vectors.size(), 2u);
    EXPECT_EQ(s->stop.stopped_by, "killed");
    EXPECT_EQ(s->stop.stopped_at.size(), std::string("2024-01-01T00:20:00Z").size()) << "the journal's last write";
  }
  fs::remove(path("run.journal.jsonl"));
  EXPECT_NE(refused(path("run.json")).find("its journal, " + path("run.journal.jsonl") + ", is not there"), std::string::npos);
}

// A killed run after its backup: the journal's backup record is the
// stopped run's `backup`, which the resumed run restores from. A malformed
// one refuses the resume, naming the journal's line.
TEST_F(StoppedRunFile, AKilledRunsBackupIsTheOneItsJournalNames) {
  const RunDocument header = killed_header();
  write("run.json", header);
  {
    JournalWriter w;
    ASSERT_TRUE(w.open(path("run.journal.jsonl"), header)) << w.error();
    ASSERT_TRUE(w.append(stopped().vectors[0]));
    ASSERT_TRUE(w.backup("out/backup.json")) << w.error();
    ASSERT_TRUE(w.append(stopped().vectors[1]));
  }  // no end record
  EXPECT_EQ(checks::journal_problems(test::slurp(dir_ / "run.journal.jsonl")), checks::Problems{});
  std::string error;
  const auto s = read_stopped_run(path("run.json"), error);
  ASSERT_TRUE(s) << error;
  EXPECT_EQ(s->stop.stopped_by, "killed");
  EXPECT_EQ(s->doc.backup, "out/backup.json");
  EXPECT_EQ(s->doc.vectors.size(), 2u);

  std::string text = test::slurp(dir_ / "run.journal.jsonl");
  const std::string record = "{\"record\":\"backup\",\"file\":\"out/backup.json\"}";
  ASSERT_NE(text.find(record), std::string::npos) << text;
  text.replace(text.find(record), record.size(), "{\"record\":\"backup\",\"file\":[\"out/backup.json\"]}");
  std::ofstream(path("run.journal.jsonl"), std::ios::binary | std::ios::trunc) << text;
  EXPECT_EQ(refused(path("run.json")), path("run.journal.jsonl") +
                                           ":3: a backup record without its file (\"file\": the stored-data backup file, a "
                                           "string)");
}

// The journal of a run resumed from a stopped run's backup names it, after
// its header and before the kept vectors: killed in turn, it is resumed
// from the same backup.
TEST_F(StoppedRunFile, AResumedRunsJournalNamesTheStoppedRunsBackup) {
  RunDocument d = stopped();
  const std::vector<VectorRecord> kept = d.vectors;
  d.status = "running";
  d.abort_reason.clear();
  d.stopped_by.clear();
  d.finished_at.clear();
  d.summary.reset();
  d.restore.clear();
  d.backup.clear();  // the resumed run's header: it has taken no backup of its own
  d.vectors.clear();
  {
    JournalWriter w;
    ASSERT_TRUE(w.open(path("run.journal.jsonl"), d, kept, "out/backup.json")) << w.error();
    ASSERT_TRUE(w.append(sample_vector("c", "pass")));
  }  // killed: no end record
  const std::string text = test::slurp(dir_ / "run.journal.jsonl");
  EXPECT_EQ(checks::journal_problems(text), checks::Problems{});
  const std::size_t second = text.find('\n') + 1;
  EXPECT_EQ(text.substr(second, text.find('\n', second) - second), "{\"record\":\"backup\",\"file\":\"out/backup.json\"}");
  JournalNotes notes;
  std::string error;
  const auto back = read_journal(path("run.journal.jsonl"), notes, error);
  ASSERT_TRUE(back) << error;
  EXPECT_FALSE(notes.ended);
  EXPECT_EQ(back->backup, "out/backup.json");
  ASSERT_EQ(back->vectors.size(), 3u);
  EXPECT_EQ(back->vectors[0].id, "a");
  EXPECT_EQ(back->vectors[2].id, "c");
}

TEST_F(StoppedRunFile, AJournalWithoutItsJsonIsNotResumed) {
  JournalWriter w;
  ASSERT_TRUE(w.open(path("run.journal.jsonl"), sample_header())) << w.error();
  EXPECT_EQ(refused(path("run.journal.jsonl")),
            path("run.journal.jsonl") + ": the run JSON of this journal, " + path("run.json") + ", is not there");
}

// The resumed run's journal replaces a killed run's with the header and the
// kept vectors, and goes on from there; read back, it is one run.
TEST_F(StoppedRunFile, AResumedRunsJournalHoldsTheKeptVectorsFirst) {
  std::ofstream(path("run.journal.jsonl")) << "the killed run's journal\n";
  RunDocument d = stopped();
  const std::vector<VectorRecord> kept = d.vectors;
  d.status = "running";
  d.vectors.clear();
  JournalWriter w;
  ASSERT_TRUE(w.open(path("run.journal.jsonl"), d, kept)) << w.error();
  EXPECT_EQ(w.path(), path("run.journal.jsonl"));
  EXPECT_FALSE(fs::exists(path("run.journal.jsonl.tmp")));
  ASSERT_TRUE(w.append(sample_vector("c", "pass")));
  d.status = "complete";
  d.abort_reason.clear();
  d.stopped_by.clear();
  ASSERT_TRUE(w.close(d)) << w.error();
  JournalNotes notes;
  std::string error;
  const auto back = read_journal(path("run.journal.jsonl"), notes, error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->vectors.size(), 3u);
  EXPECT_EQ(back->vectors[0].id, "a");
  EXPECT_EQ(back->vectors[2].id, "c");
  EXPECT_TRUE(notes.ended);
}

// The fields --resume reads and writes: through the schema and back.
TEST_F(StoppedRunFile, TheResumptionFieldsPassTheSchemaAndReadBack) {
  RunDocument d = stopped();
  d.vectors.push_back(sample_vector("c", "pass"));
  d.status = "complete";
  d.abort_reason.clear();
  d.stopped_by.clear();
  d.summary = d.counts();
  d.summary->exit_code = 1;
  d.resumptions = {{"2024-01-01T00:20:00Z", "SIGINT", "stopped by SIGINT", "2024-01-01T00:30:00Z", 2, {"navigation data restored"}}};
  const std::string text = json_text(d);
  EXPECT_EQ(checks::run_json_problems(text), checks::Problems{});
  std::string error;
  const auto back = from_json(nlohmann::json::parse(text), error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->resumptions.size(), 1u);
  EXPECT_EQ(back->resumptions[0].resumed_at, "2024-01-01T00:30:00Z");
  EXPECT_EQ(back->resumptions[0].kept, 2u);
  EXPECT_EQ(back->resumptions[0].restore, std::vector<std::string>{"navigation data restored"});
  EXPECT_EQ(back->invocation, d.invocation);
  EXPECT_EQ(back->backup, "out/backup.json");
  EXPECT_EQ(json_text(*back), text);
  // A stopped run says by what; a complete one cannot.
  RunDocument s = stopped();
  EXPECT_EQ(checks::run_json_problems(json_text(s)), checks::Problems{});
  EXPECT_EQ(from_json(nlohmann::json::parse(json_text(s)), error)->stopped_by, "SIGINT");
  d.stopped_by = "SIGINT";
  EXPECT_NE(checks::run_json_problems(json_text(d)), checks::Problems{});
}

// Each outcome, level and skip cause the runner names reads back as itself.
TEST(KeptResult, EveryOutcomeReadsBackAsTheRunnersVerdict) {
  for (const auto verdict : {harness::Verdict::kPass, harness::Verdict::kFail, harness::Verdict::kSkip,
                             harness::Verdict::kKnownFailure, harness::Verdict::kUnexpectedPass, harness::Verdict::kInconclusive}) {
    harness::VectorResult r;
    r.id = "x";
    r.level = harness::Level::kShould;
    r.verdict = verdict;
    if (verdict == harness::Verdict::kSkip) r.skip_cause = harness::SkipCause::kDestructive;
    const harness::VectorResult back = kept_result(vector_record(r));
    EXPECT_EQ(back.verdict, verdict) << harness::to_string(verdict);
    EXPECT_EQ(back.level, harness::Level::kShould);
    EXPECT_EQ(back.skip_cause, r.skip_cause);
  }
}

}  // namespace
}  // namespace sabus::reports
