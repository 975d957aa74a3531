// The run JSON written token by token, and the run journal: what a finished
// run, a killed run and a damaged file leave, and the JSON made from each.
#include "sabus/reports/journal.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "sabus/reports/checks.hpp"
#include "sample_run.hpp"
#include "temp_dir.hpp"

namespace sabus::reports {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

// A status poll vector whose reply field's meaning has JSON's special
// characters and a control character.
VectorRecord vector(std::string id, std::string outcome) {
  VectorRecord v = test_documents::sample_vector(std::move(id), std::move(outcome));
  v.transcript[1].fields[0].meaning = "ACK \"quoted\" \\ and \x01";
  return v;
}

RunDocument header() {
  RunDocument d = test_documents::sample_header();
  d.generator = "sabus 1.2.3";
  d.options = {{"seed", 7}};
  d.planned = 3;
  d.journal = "run.journal.jsonl";
  return d;
}

using test::slurp;

class Journal : public test::TempDirTest {
 protected:
  Journal() : TempDirTest("sabus-journal-test") {}
  // A journal of three vectors; `end` writes the end record of a finished run.
  RunDocument write_journal(const std::string& file, bool end) {
    RunDocument d = header();
    JournalWriter w;
    EXPECT_TRUE(w.open(file, d)) << w.error();
    for (const auto& v : {vector("a", "pass"), vector("b", "fail"), vector("c", "pass")}) {
      EXPECT_TRUE(w.append(v)) << w.error();
      d.vectors.push_back(v);
    }
    if (end) {
      d.status = "complete";
      d.finished_at = "2024-01-01T00:00:01Z";
      d.summary = Summary{2, 1, 0, 0, 0, 1};
      d.journal.clear();
      EXPECT_TRUE(w.close(d)) << w.error();
    }
    return d;
  }
};

// The defect of issue 21: a reply that does not decode is a note without
// bytes or fields, and the run JSON held `"fields":}` for it (a cache of
// fields text answered an empty frame with an empty text). Every frame's
// fields are an array, written by the serializer, whatever the frame.
TEST(VectorJson, AFrameWithoutBytesOrFieldsHasAnEmptyFieldsArray) {
  VectorRecord v = vector("3.2-status-reply-length", "fail");
  FrameRecord ignored;
  ignored.dir = "rx";
  ignored.t_ms = 4;
  ignored.note = "discarded bytes 0-10 (11): bad LRC: check byte 0x6a 'j' at offset 10, expected 0x6c 'l'";
  v.transcript.push_back(ignored);
  for (int round = 0; round < 2; ++round) {  // the same frame twice: nothing is kept from the first
    const std::string text = vector_json(v);
    const auto parsed = json::parse(text);
    EXPECT_EQ(parsed["transcript"][2]["fields"], json::array()) << text;
    EXPECT_EQ(parsed["transcript"][2]["hex"], "");
    EXPECT_EQ(parsed["transcript"][2]["note"], ignored.note);
    EXPECT_FALSE(parsed["transcript"][2].contains("expect")) << "a received frame has no expectation";
  }
}

// A device may send any byte, and a note or a field's raw text may carry it:
// the JSON holds UTF-8 (U+FFFD for a byte that is not), control characters
// escaped, and no number JSON cannot carry.
TEST(VectorJson, StringsThatAreNotUtf8AndNumbersThatAreNotFinite) {
  VectorRecord v = vector("x", "fail");
  v.failures = {std::string("got \"\xff\x80\x01\x7f\" (\xc3\xa9 stays)")};
  v.transcript[1].fields[0].raw = std::string("\"\xfe\"");
  v.duration_ms = std::numeric_limits<double>::quiet_NaN();
  const std::string text = vector_json(v);
  EXPECT_EQ(text.find('\x01'), std::string::npos) << "control characters escaped";
  const auto parsed = json::parse(text);  // throws on a byte that is not UTF-8
  EXPECT_EQ(parsed["failures"][0], "got \"\xEF\xBF\xBD\xEF\xBF\xBD\x01\x7f\" (\xc3\xa9 stays)");
  EXPECT_EQ(parsed["transcript"][1]["fields"][0]["raw"], "\"\xEF\xBF\xBD\"");
  EXPECT_TRUE(parsed["duration_ms"].is_null());
}

// The run JSON is made from the journal line by line, each line read by a
// JSON parser and written again: a damaged line stops it, naming the line,
// instead of reaching the file.
TEST(RunJsonFromJournal, ALineThatIsNotJsonStopsTheCopy) {
  RunDocument d = header();
  std::string journal = journal_record_json("header", d) + "\n" + vector_json(vector("a", "pass")) + "\n";
  std::ostringstream out;
  std::string error;
  std::istringstream good(journal);
  ASSERT_TRUE(write_run_json_from_journal(good, out, d, error)) << error;
  EXPECT_EQ(json::parse(out.str())["vectors"][0]["id"], "a");
  for (const std::string damaged : {"{\"id\":\"b\",\"fields\":}", "{\"id\":\"b\"} {\"id\":\"c\"}", "{\"id\":\"\xff\"}"}) {
    std::istringstream bad(journal + damaged + "\n" + vector_json(vector("c", "pass")) + "\n");
    std::ostringstream ignored;
    EXPECT_FALSE(write_run_json_from_journal(bad, ignored, d, error)) << damaged;
    EXPECT_NE(error.find("journal line 3 is not one JSON text"), std::string::npos) << error;
  }
  // Records are left out by what they are, not by how their line starts.
  std::istringstream reordered(journal + "{\"run\":{},\"record\":\"end\"}\n");
  std::ostringstream kept;
  ASSERT_TRUE(write_run_json_from_journal(reordered, kept, d, error)) << error;
  EXPECT_EQ(json::parse(kept.str())["vectors"].size(), 1u);
}

TEST(JsonText, HeaderInSchemaOrderAndVectorsLastOneALine) {
  RunDocument d = header();
  d.vectors = {vector("a", "pass"), vector("b", "fail")};
  const std::string text = json_text(d);
  EXPECT_EQ(text.rfind("{\n  \"schema\": \"sabus-run\",\n  \"schema_version\": 7,\n  \"generator\": \"sabus 1.2.3\",\n", 0), 0u) << text;
  const auto vectors = text.find("  \"vectors\": [\n    {\"id\":\"a\",");
  ASSERT_NE(vectors, std::string::npos) << text;
  EXPECT_EQ(text.find("\"planned\""), text.rfind("\"planned\"")) << "each header member once";
  EXPECT_LT(text.find("\"planned\""), vectors);
  EXPECT_EQ(std::count(text.begin() + static_cast<long>(vectors), text.end(), '\n'), 5) << "a line per vector";
  std::string error;
  const auto back = from_json(json::parse(text), error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(json_text(*back), text);
  EXPECT_EQ(back->vectors[1].wall_ms, 0.5);
}

TEST_F(Journal, AFinishedRunsJournalGivesTheSameJsonAsTheDocument) {
  const RunDocument d = write_journal(path("run.journal.jsonl"), true);
  JournalNotes notes;
  std::string error;
  const auto back = read_journal(path("run.journal.jsonl"), notes, error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(notes.ended);
  EXPECT_EQ(notes.vectors, 3u);
  EXPECT_TRUE(notes.notes.empty());
  EXPECT_EQ(json_text(*back), json_text(d)) << "header from the end record, every vector with its fields";
  ASSERT_TRUE(write_run_json(path("run.json"), *back, path("run.journal.jsonl"), error)) << error;
  EXPECT_EQ(slurp(dir_ / "run.json"), json_text(d));
  EXPECT_FALSE(fs::exists(path("run.json.tmp")));
  // Every line is one record, and the file ends with a newline.
  const std::string raw = slurp(dir_ / "run.journal.jsonl");
  EXPECT_EQ(std::count(raw.begin(), raw.end(), '\n'), 5);
  EXPECT_EQ(raw.back(), '\n');
  EXPECT_EQ(raw.rfind("{\"record\":\"header\",\"run\":{\"schema\":\"sabus-run\"", 0), 0u) << raw.substr(0, 80);
  EXPECT_NE(raw.find("\n{\"id\":\"b\",\"paragraph\":\"3.2\","), std::string::npos) << "a vector a line, as run.json holds it";
  // An unknown record is an error, not a vector.
  std::ofstream(path("run.journal.jsonl"), std::ios::app) << "{\"record\":\"later\"}\n";
  EXPECT_FALSE(read_journal(path("run.journal.jsonl"), notes, error));
  EXPECT_NE(error.find("run.journal.jsonl:6: unknown record \"later\""), std::string::npos) << error;
}

TEST_F(Journal, AKilledRunsJournalHasEveryFinishedVectorAndSaysItNeverEnded) {
  write_journal(path("killed.journal.jsonl"), false);
  JournalNotes notes;
  std::string error;
  const auto back = read_run_or_journal(path("killed.journal.jsonl"), notes, error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(notes.journal);
  EXPECT_FALSE(notes.ended);
  EXPECT_EQ(back->status, "running");
  EXPECT_EQ(back->verdict(), "INCOMPLETE");
  ASSERT_EQ(back->vectors.size(), 3u);
  EXPECT_EQ(back->vectors[1].failures.at(0), "byte 3: expected 0x57, got 0x44");
  ASSERT_TRUE(write_run_json(path("run.json"), *back, path("killed.journal.jsonl"), error)) << error;
  const auto doc = json::parse(slurp(dir_ / "run.json"));
  EXPECT_EQ(doc["status"], "running");
  EXPECT_FALSE(doc.contains("journal")) << "the JSON holds the vectors itself now";
  EXPECT_EQ(doc["vectors"].size(), 3u);
  EXPECT_EQ(doc["vectors"][2]["transcript"][1]["fields"][0]["meaning"], "ACK \"quoted\" \\ and \x01");
}

TEST_F(Journal, ALastLineCutShortIsLeftOutWithANote) {
  write_journal(path("cut.journal.jsonl"), false);
  std::string raw = slurp(dir_ / "cut.journal.jsonl");
  raw.resize(raw.size() - 40);  // the last vector record, half written
  std::ofstream(path("cut.journal.jsonl"), std::ios::binary | std::ios::trunc) << raw;
  JournalNotes notes;
  std::string error;
  const auto back = read_journal(path("cut.journal.jsonl"), notes, error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->vectors.size(), 2u);
  ASSERT_EQ(notes.notes.size(), 1u);
  EXPECT_NE(notes.notes[0].find("line 4 is cut short"), std::string::npos) << notes.notes[0];
}

TEST_F(Journal, ADamagedLineOrAnotherFileIsAnErrorWithFileAndLine) {
  write_journal(path("bad.journal.jsonl"), true);
  std::string raw = slurp(dir_ / "bad.journal.jsonl");
  const auto third = raw.find('\n', raw.find('\n') + 1) + 1;
  raw.insert(third, "{\"id\":\"x\"}\n");  // a vector without its outcome
  std::ofstream(path("bad.journal.jsonl"), std::ios::binary | std::ios::trunc) << raw;
  JournalNotes notes;
  std::string error;
  EXPECT_FALSE(read_journal(path("bad.journal.jsonl"), notes, error));
  EXPECT_NE(error.find("bad.journal.jsonl:3: vector: "), std::string::npos) << error;
  EXPECT_NE(error.find("outcome"), std::string::npos) << error;

  std::ofstream(path("run.json")) << json_text(header());
  EXPECT_FALSE(is_journal(path("run.json")));
  EXPECT_FALSE(scan_journal(path("run.json"), [](const ordered_json&) {}, notes, error));
  EXPECT_NE(error.find("not a run journal"), std::string::npos) << error;
  const auto doc = read_run_or_journal(path("run.json"), notes, error);
  ASSERT_TRUE(doc) << error << " (a run JSON reads as one)";
  EXPECT_FALSE(notes.journal);
  EXPECT_FALSE(read_run_or_journal(path("none.jsonl"), notes, error));
}

// The backup record names the stored-data backup file: a malformed one is
// an error naming the line and what is wrong, not a vector or a note.
TEST_F(Journal, AMalformedBackupRecordIsAnErrorNamingItsLine) {
  write_journal(path("run.journal.jsonl"), false);
  const std::string raw = slurp(dir_ / "run.journal.jsonl");
  const auto second = raw.find('\n') + 1;  // after the header: line 2
  for (const std::string record : {R"({"record":"backup"})", R"({"record":"backup","file":3})",
                                   R"({"record":"backup","file":""})"}) {
    std::string damaged = raw;
    damaged.insert(second, record + "\n");
    std::ofstream(path("bad.journal.jsonl"), std::ios::binary | std::ios::trunc) << damaged;
    JournalNotes notes;
    std::string error;
    EXPECT_FALSE(read_journal(path("bad.journal.jsonl"), notes, error)) << record;
    EXPECT_NE(error.find("bad.journal.jsonl:2: a backup record without its file (\"file\": the stored-data backup file, a "
                         "string)"),
              std::string::npos)
        << record << ": " << error;
    EXPECT_EQ(checks::journal_problems(damaged),
              checks::Problems{"journal line 2: a backup record that is not {\"record\": \"backup\", \"file\": FILE} once, "
                               "after the header and before the end"})
        << record;
  }
  // A run takes one backup: a second record naming another file.
  std::string twice = raw;
  twice.insert(second, "{\"record\":\"backup\",\"file\":\"out/backup.json\"}\n");
  twice += "{\"record\":\"backup\",\"file\":\"out/backup-2.json\"}\n";
  std::ofstream(path("bad.journal.jsonl"), std::ios::binary | std::ios::trunc) << twice;
  JournalNotes notes;
  std::string error;
  EXPECT_FALSE(read_journal(path("bad.journal.jsonl"), notes, error));
  EXPECT_NE(error.find("bad.journal.jsonl:6: a second backup record, naming out/backup-2.json after out/backup.json"),
            std::string::npos)
      << error;
  EXPECT_EQ(checks::journal_problems(twice),
            checks::Problems{"journal line 6: a backup record that is not {\"record\": \"backup\", \"file\": FILE} once, "
                             "after the header and before the end"});
}

// A killed run's journal names its backup in the backup record (the end
// record that would name it is never written): read back, the document's
// `backup` is that file, and so is the run JSON's made from the journal.
TEST_F(Journal, AKilledRunsBackupRecordIsTheDocumentsBackup) {
  RunDocument d = header();
  {
    JournalWriter w;
    ASSERT_TRUE(w.open(path("run.journal.jsonl"), d)) << w.error();
    ASSERT_TRUE(w.append(vector("a", "pass"))) << w.error();
    ASSERT_TRUE(w.backup("out/backup \"1\".json")) << w.error();
    ASSERT_TRUE(w.append(vector("b", "fail"))) << w.error();
  }  // killed: no end record
  const std::string raw = slurp(dir_ / "run.journal.jsonl");
  EXPECT_NE(raw.find("\n{\"record\":\"backup\",\"file\":\"out/backup \\\"1\\\".json\"}\n"), std::string::npos) << raw;
  EXPECT_EQ(checks::journal_problems(raw), checks::Problems{});
  JournalNotes notes;
  std::string error;
  const auto back = read_journal(path("run.journal.jsonl"), notes, error);
  ASSERT_TRUE(back) << error;
  EXPECT_FALSE(notes.ended);
  EXPECT_EQ(notes.vectors, 2u) << "the backup record is not a vector";
  EXPECT_EQ(back->backup, "out/backup \"1\".json");
  ASSERT_TRUE(write_run_json(path("run.json"), *back, path("run.journal.jsonl"), error)) << error;
  EXPECT_EQ(checks::run_json_problems(slurp(dir_ / "run.json")), checks::Problems{});
  const auto doc = read_run_file(path("run.json"), error);
  ASSERT_TRUE(doc) << error;
  EXPECT_EQ(doc->backup, "out/backup \"1\".json");
  EXPECT_EQ(doc->vectors.size(), 2u);
  // The journal of a run that ended names the backup in its end record too;
  // the checks hold the two to the same file.
  d.vectors = {vector("a", "pass"), vector("b", "fail")};
  d.status = "complete";
  d.finished_at = "2024-01-01T00:00:01Z";
  d.summary = Summary{1, 1, 0, 0, 0, 1};
  d.journal.clear();
  d.backup = "out/backup \"1\".json";
  d.traffic = {{"bytes_sent", 10}, {"bytes_received", 10}, {"silence_windows", 0}, {"silence_listened_ms", 0.0},
               {"measured_turnaround_ms", 1.0}};
  const std::string ended = raw + journal_record_json("end", d) + "\n";
  EXPECT_EQ(checks::journal_problems(ended), checks::Problems{});
  d.backup = "out/other.json";
  EXPECT_EQ(checks::journal_problems(raw + journal_record_json("end", d) + "\n"),
            checks::Problems{"journal end record: backup out/other.json, not the backup record's out/backup \"1\".json"});
}

TEST(JournalPath, BesideItsJson) {
  EXPECT_EQ(journal_path_for("out/run.json"), "out/run.journal.jsonl");
  EXPECT_EQ(journal_path_for("out/run"), "out/run.journal.jsonl");
  EXPECT_EQ(journal_path_for("run.v2.json"), "run.v2.journal.jsonl");
}

TEST(JournalWriter, AFileThatCannotBeWrittenSaysWhy) {
  JournalWriter w;
  EXPECT_FALSE(w.open("/nonexistent-dir/run.journal.jsonl", header()));
  EXPECT_NE(w.error().find("/nonexistent-dir/run.journal.jsonl: cannot write"), std::string::npos) << w.error();
  EXPECT_FALSE(w.append(vector("a", "pass")));
  std::string error;
  EXPECT_FALSE(write_run_json("/nonexistent-dir/run.json", header(), error));
  EXPECT_NE(error.find("cannot write"), std::string::npos) << error;
}

}  // namespace
}  // namespace sabus::reports
