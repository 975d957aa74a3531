// The run JSON on disk, and the run's journal (reports/SCHEMA.md).
//
// `sabus run` appends each finished vector to the journal, one JSON Lines
// record each, written through to the kernel at once; the run JSON is written
// once at the start (status "running", naming the journal) and once at the
// end or on abort, from the journal. A journal left by a killed run becomes
// a run JSON with `sabus report JOURNAL --json F`. Writing is linear in the
// number of vectors: nothing is rewritten, and no vector's JSON is held in
// memory longer than it takes to write it.
#pragma once

#include <functional>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/reports/document.hpp"

namespace sabus::reports {

// ---- the run JSON ----------------------------------------------------------------
// Written by RapidJSON's Writer (reports/src/json_out.hpp): every bracket,
// comma, quote and escape is the library's; strings that are not valid UTF-8
// are repaired (valid_utf8) and non-finite numbers written as null.

// One member of the run JSON's "vectors" (a journal's vector record), on one
// line, members in the order of reports/SCHEMA.md.
std::string vector_json(const VectorRecord& v);
// A journal's header or end record on one line: {"record": RECORD, "run":
// the header members of `run`}.
std::string journal_record_json(std::string_view record, const RunDocument& run);
// A journal's backup record on one line: {"record": "backup", "file": FILE},
// the stored-data backup file the run wrote before its first destructive
// vector (RunDocument::backup).
std::string journal_backup_json(std::string_view file);

// The run JSON of a document held in memory: the header members one a line,
// then "vectors" last (a reader sees the header first), one vector a line.
void write_run_json(std::ostream& out, const RunDocument& doc);
std::string json_text(const RunDocument& doc);
// The run JSON with the header of `header` (less its "journal") and the
// vectors of a journal (JournalWriter, each line the serializer's text of one
// vector), one line at a time: each line is read through by RapidJSON's
// Reader before the Writer places it, so a line that is not one JSON text of
// UTF-8 stops the copy (false, `error` names the line) rather than reach the
// file; records are left out, and so is a last line without its newline (cut
// short by a kill). Nothing but the line being copied is held in memory.
bool write_run_json_from_journal(std::istream& journal, std::ostream& out, const RunDocument& header, std::string& error);

// Writes the run JSON to a new temporary file beside PATH, fsyncs it and
// renames it over PATH, so PATH is always a whole document; "-" writes it to
// standard output. A PATH that is not a regular file (or a link to one) is
// refused (output_path_problem), and never replaced.
bool write_run_json(const std::string& path, const RunDocument& doc, std::string& error);
// The same from a journal file that this process wrote (JournalWriter),
// with write_run_json_from_journal. A journal from elsewhere is read with
// read_journal and written from the document.
bool write_run_json(const std::string& path, const RunDocument& header, const std::string& journal, std::string& error);

// ---- the journal -----------------------------------------------------------------

// "out/run.json" -> "out/run.journal.jsonl": the journal beside a run JSON.
std::string journal_path_for(const std::string& json_path);

// Appends records to a journal file (JSON Lines): a header record, each
// vector as run.json's "vectors" holds it, the backup record once the
// stored-data backup is written, an end record. Each line is
// written with one write(2), so a killed process leaves every finished
// record; the file is fsynced when the run ends (complete or aborted).
class JournalWriter {
 public:
  JournalWriter() = default;
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;
  ~JournalWriter();
  // Creates (or truncates) the file and writes the header record.
  bool open(const std::string& path, const RunDocument& header);
  // The journal of a resumed run (`sabus run --resume`): the header record
  // and the vectors the stopped run finished, written to PATH.tmp, fsynced
  // and renamed over PATH, so that a journal already at PATH (a killed
  // run's, which may be where those vectors come from) is replaced only by
  // one that holds them all. `backup`: the stopped run's stored-data backup
  // file, which the resumed run restores from and takes no other: its backup
  // record follows the header ("": none). The file stays open for append.
  bool open(const std::string& path, const RunDocument& header, const std::vector<VectorRecord>& earlier,
            const std::string& backup = "");
  bool append(const VectorRecord& v);
  // The backup record: the stored-data backup is written to `file`. Written
  // before the destructive vector it was taken for runs, so that the journal
  // of a run killed after it names the backup (the end record, which names it
  // too, is never written then).
  bool backup(const std::string& file);
  // Writes the end record (the finished header: status, summary, ...),
  // fsyncs and closes the file.
  bool close(const RunDocument& finished);
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  const std::string& error() const { return error_; }

 private:
  bool write_text(std::string line);  // a record's JSON, without its newline
  int fd_ = -1;
  std::string path_, error_;
};

// A run recorded in memory as `sabus run` records it on disk: each finished
// vector whole to the journal, and compacted for the reports
// (compact_for_reports) to the document. For what checks a run's record
// without files: the suite gate, fuzz_record, the tests.
struct MemoryRecord {
  RunDocument doc;      // filled by the caller before start()
  std::string journal;  // the journal's text

  // The header record: `doc` as it is now, naming a journal.
  void start();
  void add(const harness::VectorResult& r, std::optional<double> wall_ms);
  // finish(doc, ...), then the end record.
  void end(const harness::RunResult& run, std::string finished_at);
  // RunOptions::on_result for add (wall_ms as given).
  std::function<void(const harness::VectorResult&)> on_result(std::optional<double> wall_ms = std::nullopt);
};

// What reading a journal found besides its records.
struct JournalNotes {
  bool journal = false;                // the file read is a journal (read_run_or_journal)
  bool ended = false;                  // it has an end record: the run ended (complete or aborted)
  std::size_t vectors = 0;             // vector records read
  std::vector<std::string> notes;      // e.g. a last line cut short, ignored
};

// Reads a journal record by record: `on_vector` gets each vector, in order. Returns the run header (the end record's when the run
// ended, the header record's otherwise, with no vectors; its `backup` the
// backup record's file when the header has none), or nullopt with
// `error` set (file:line and why) when the file is not a journal or a line
// other than the last is not a record. A last line without its newline is a
// record cut short by a kill and is left out with a note.
std::optional<RunDocument> scan_journal(const std::string& path, const std::function<void(const nlohmann::ordered_json&)>& on_vector,
                                        JournalNotes& notes, std::string& error);
// The same from a stream; `name` is what errors call it.
std::optional<RunDocument> scan_journal(std::istream& in, const std::string& name,
                                        const std::function<void(const nlohmann::ordered_json&)>& on_vector, JournalNotes& notes,
                                        std::string& error);
// The whole document of a journal, every vector with its transcript.
std::optional<RunDocument> read_journal(const std::string& path, JournalNotes& notes, std::string& error);
std::optional<RunDocument> read_journal(std::istream& in, const std::string& name, JournalNotes& notes, std::string& error);
// Whether a file starts with a journal's header record.
bool is_journal(const std::string& path);
// A run JSON or a journal, whichever the file is (`notes.journal` says which).
std::optional<RunDocument> read_run_or_journal(const std::string& path, JournalNotes& notes, std::string& error);

}  // namespace sabus::reports
