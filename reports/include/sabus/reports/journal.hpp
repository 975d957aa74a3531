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

// ---- an incremental JSON writer --------------------------------------------------

// Writes one JSON text token by token to a stream: nlohmann serializes every
// key and value, this class places the brackets, commas and line breaks (one
// member or element a line, indented by depth; or, kOneLine, none at all, as
// nlohmann's dump() without indent writes). nlohmann has no writer that
// streams a document it does not hold whole; a run JSON of thousands of
// vectors is written without holding it.
class JsonStreamWriter {
 public:
  enum class Layout { kLines, kOneLine };
  explicit JsonStreamWriter(std::ostream& out, Layout layout = Layout::kLines);
  JsonStreamWriter(const JsonStreamWriter&) = delete;
  JsonStreamWriter& operator=(const JsonStreamWriter&) = delete;
  ~JsonStreamWriter();                           // writes out what is buffered
  void begin_object();
  void begin_array();
  void end();                                    // closes the innermost object or array
  void key(std::string_view name);               // in an object, before its value
  void value(const nlohmann::ordered_json& v);   // one value, on one line
  void string_value(std::string_view s);         // the same for a string, without a json value made for it
  // One value nlohmann serialized earlier on one line (a journal's vector
  // line), copied as it is.
  void serialized_value(std::string_view json_text);
  bool done() const { return stack_.empty() && started_; }

 private:
  void before_value();
  void newline(std::size_t depth);
  struct Level {
    bool object = false, empty = true, has_key = false;
  };
  void flush();
  void flush_when_large();
  std::ostream& out_;
  Layout layout_;
  std::vector<Level> stack_;
  bool started_ = false;
  // What is written goes to buf_ and from it to out_ in large pieces; the
  // library's serializer (the one dump() uses, made once) writes into buf_,
  // and one string value is reused for string_value.
  std::string buf_;
  nlohmann::detail::serializer<nlohmann::ordered_json> serializer_;
  nlohmann::ordered_json string_ = nlohmann::ordered_json::value_t::string;
};

// ---- a vector's JSON ------------------------------------------------------------

// The JSON text of transcript frames' "fields" arrays, serialized once a
// distinct frame: the frames of a run repeat (the same poll, the same reply),
// and their fields are most of a run JSON (4.3 of 4.9 MB for the suite), so
// building, writing and freeing a tree of them for every frame was most of
// what the reports cost a run. Found by the frame's hex and used only when
// the fields are equal too, so a document whose fields differ (one read from
// a file) is never written with another frame's. A table of 4096 slots, a
// newer frame taking an older one's: bounded in a run of any length.
class FieldsJsonCache {
 public:
  const std::string& text(const FrameRecord& f);

 private:
  struct Slot {
    std::string hex, text;
    std::vector<Field> fields;
  };
  std::vector<Slot> slots_ = std::vector<Slot>(4096);
};

// One member of the run JSON's "vectors" (a journal's vector record), on one
// line, members in the order of reports/SCHEMA.md. `cache`: where the
// frames' fields text is kept between calls (none: each serialized anew).
std::string vector_json(const VectorRecord& v, FieldsJsonCache* cache = nullptr);

// ---- the run JSON ----------------------------------------------------------------

// The run JSON of a document held in memory: the header members, then
// "vectors" last (a reader sees the header first), one vector a line.
std::string json_text(const RunDocument& doc);

// Writes the run JSON to a new temporary file beside PATH, fsyncs it and
// renames it over PATH, so PATH is always a whole document; "-" writes it to
// standard output. A PATH that is not a regular file (or a link to one) is
// refused (output_path_problem), and never replaced.
bool write_run_json(const std::string& path, const RunDocument& doc, std::string& error);
// The same with the header of `header` and the vectors of a journal that
// this process wrote (JournalWriter), copied line by line as they were
// serialized: no vector is parsed again or held in memory. A journal from
// elsewhere is read with read_journal and written from the document.
bool write_run_json(const std::string& path, const RunDocument& header, const std::string& journal, std::string& error);

// ---- the journal -----------------------------------------------------------------

// "out/run.json" -> "out/run.journal.jsonl": the journal beside a run JSON.
std::string journal_path_for(const std::string& json_path);

// Appends records to a journal file (JSON Lines): a header record, each
// vector as run.json's "vectors" holds it, an end record. Each line is
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
  bool append(const VectorRecord& v);
  // Writes the end record (the finished header: status, summary, ...),
  // fsyncs and closes the file.
  bool close(const RunDocument& finished);
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  const std::string& error() const { return error_; }

 private:
  bool write_line(const nlohmann::ordered_json& record);
  bool write_text(std::string line);  // a record's JSON, without its newline
  int fd_ = -1;
  std::string path_, error_;
  FieldsJsonCache fields_;
};

// What reading a journal found besides its records.
struct JournalNotes {
  bool journal = false;                // the file read is a journal (read_run_or_journal)
  bool ended = false;                  // it has an end record: the run ended (complete or aborted)
  std::size_t vectors = 0;             // vector records read
  std::vector<std::string> notes;      // e.g. a last line cut short, ignored
};

// Reads a journal record by record: `on_vector` gets each vector, in order. Returns the run header (the end record's when the run
// ended, the header record's otherwise, with no vectors), or nullopt with
// `error` set (file:line and why) when the file is not a journal or a line
// other than the last is not a record. A last line without its newline is a
// record cut short by a kill and is left out with a note.
std::optional<RunDocument> scan_journal(const std::string& path, const std::function<void(const nlohmann::ordered_json&)>& on_vector,
                                        JournalNotes& notes, std::string& error);
// The whole document of a journal, every vector with its transcript.
std::optional<RunDocument> read_journal(const std::string& path, JournalNotes& notes, std::string& error);
// Whether a file starts with a journal's header record.
bool is_journal(const std::string& path);
// A run JSON or a journal, whichever the file is (`notes.journal` says which).
std::optional<RunDocument> read_run_or_journal(const std::string& path, JournalNotes& notes, std::string& error);

}  // namespace sabus::reports
