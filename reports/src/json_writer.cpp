// The run JSON (reports/SCHEMA.md) and its journal's records, written by
// RapidJSON's Writer from a document in memory or from a run's journal line
// by line; and writing report files safely.
#include "json_out.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "sabus/harness/files.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

using nlohmann::ordered_json;
using namespace json_out;

// ---- a vector's JSON -------------------------------------------------------------

namespace {

template <class Writer>
void put_key(Writer& w, std::string_view key) {
  w.Key(key.data(), static_cast<rapidjson::SizeType>(key.size()));
}

template <class Writer>
void put_string_member(Writer& w, std::string_view key, std::string_view value) {
  put_key(w, key);
  put_string(w, value);
}

// A frame's "fields": {first, last, name, raw, meaning, ok} each.
template <class Writer>
void put_fields(Writer& w, const std::vector<Field>& fields) {
  w.StartArray();
  for (const Field& x : fields) {
    w.StartObject();
    put_key(w, "first");
    w.Uint64(x.first);
    put_key(w, "last");
    w.Uint64(x.last);
    put_string_member(w, "name", x.name);
    put_string_member(w, "raw", x.raw);
    put_string_member(w, "meaning", x.meaning);
    put_key(w, "ok");
    w.Bool(x.ok);
    w.EndObject();
  }
  w.EndArray();
}

template <class Writer>
void put_frame(Writer& w, const FrameRecord& f) {
  w.StartObject();
  put_key(w, "t_ms");
  put_number(w, f.t_ms);
  put_string_member(w, "dir", f.dir);
  put_string_member(w, "hex", f.hex);
  put_string_member(w, "note", f.note);
  put_string_member(w, "command", f.command);
  put_key(w, "fields");
  put_fields(w, f.fields);
  if (f.dir == "tx") {
    put_string_member(w, "form", f.form);
    put_string_member(w, "expect", f.expect);
    put_string_member(w, "path", f.path);
  }
  w.EndObject();
}

// Members in the order of reports/SCHEMA.md.
template <class Writer>
void put_vector(Writer& w, const VectorRecord& v) {
  w.StartObject();
  put_string_member(w, "id", v.id);
  put_string_member(w, "paragraph", v.paragraph);
  put_string_member(w, "file", v.file);
  put_string_member(w, "level", v.level);
  put_string_member(w, "outcome", v.outcome);
  put_key(w, "failures");
  w.StartArray();
  for (const auto& f : v.failures) put_string(w, f);
  w.EndArray();
  put_string_member(w, "inconclusive_reason", v.inconclusive_reason);
  put_string_member(w, "error_reason", v.error_reason);
  put_string_member(w, "skip_reason", v.skip_reason);
  put_string_member(w, "skip_cause", v.skip_cause);
  put_string_member(w, "known_issue", v.known_issue);
  put_string_member(w, "quote", v.quote);
  put_string_member(w, "comment", v.comment);
  put_key(w, "duration_ms");
  put_number(w, v.duration_ms);
  if (v.wall_ms) {
    put_key(w, "wall_ms");
    put_number(w, *v.wall_ms);
  }
  put_key(w, "repeats");
  w.Int(v.repeats);
  put_key(w, "repeat_failures");
  w.Int(v.repeat_failures);
  // Always written, zeros when none was counted (a skipped vector sent
  // nothing): a reader never has to tell "absent" from "none".
  put_key(w, "line");
  put_json(w, line_json(v.line));
  put_key(w, "transcript");
  w.StartArray();
  for (const auto& f : v.transcript) put_frame(w, f);
  w.EndArray();
  w.EndObject();
}

// The one-line JSON text of what `put` writes.
template <class Put>
std::string one_line(Put&& put) {
  rapidjson::StringBuffer buffer;
  LineWriter w(buffer);
  put(w);
  if (!w.IsComplete()) throw std::logic_error("a JSON text left unfinished");
  return std::string(buffer.GetString(), buffer.GetSize());
}

// Reads a journal line's JSON, event by event, noting whether it is a record
// (its object has a "record" member) rather than a vector: RapidJSON's
// Reader checks the line is one JSON text of UTF-8 as it goes.
class RecordSniffer : public rapidjson::BaseReaderHandler<rapidjson::UTF8<>, RecordSniffer> {
 public:
  bool Default() { return true; }
  bool StartObject() {
    ++depth_;
    return true;
  }
  bool Key(const char* s, rapidjson::SizeType n, bool) {
    if (depth_ == 1 && std::string_view(s, n) == "record") record_ = true;
    return true;
  }
  bool EndObject(rapidjson::SizeType) {
    --depth_;
    return true;
  }
  bool StartArray() {
    ++depth_;
    return true;
  }
  bool EndArray(rapidjson::SizeType) {
    --depth_;
    return true;
  }
  bool record() const { return record_; }

 private:
  int depth_ = 0;
  bool record_ = false;
};

}  // namespace

std::string vector_json(const VectorRecord& v) {
  return one_line([&](LineWriter& w) { put_vector(w, v); });
}

std::string journal_record_json(std::string_view record, const RunDocument& run) {
  return one_line([&](LineWriter& w) {
    w.StartObject();
    put_string_member(w, "record", record);
    put_key(w, "run");
    put_json(w, header_json(run));
    w.EndObject();
  });
}

std::string journal_backup_json(std::string_view file) {
  return one_line([&](LineWriter& w) {
    w.StartObject();
    put_string_member(w, "record", "backup");
    put_string_member(w, "file", file);
    w.EndObject();
  });
}

// ---- the run JSON ----------------------------------------------------------------

namespace {

// The header members in schema order, then "vectors": each vector that
// `vectors` gives (its one-line JSON text, made by a LineWriter, read by a
// Reader) on a line of its own, placed by the writer (RawValue). "vectors" comes last so a reader sees the header
// first. `vectors(put)` calls put(text) for each vector and returns false
// (with `error` set) when it could not read them all.
template <class Vectors>
bool write_run(std::ostream& out, const ordered_json& header, std::string& error, Vectors&& vectors) {
  OStreamBuffer os(out);
  FileWriter w(os);
  w.SetIndent(' ', 2);
  w.StartObject();
  for (const auto& [name, value] : header.items()) {
    put_key(w, name);
    put_json(w, value);
  }
  put_key(w, "vectors");
  w.StartArray();
  const bool ok = vectors([&](const std::string& text) {
    w.RawValue(text.data(), text.size(), rapidjson::kObjectType);
  }, error);
  w.EndArray();
  w.EndObject();
  if (!w.IsComplete()) throw std::logic_error("the run JSON left unfinished");
  os.Put('\n');
  os.Flush();
  return ok;
}

ordered_json header_without_journal(const RunDocument& doc) {
  ordered_json h = header_json(doc);
  h.erase("journal");  // the file now holds every vector
  return h;
}

}  // namespace

void write_run_json(std::ostream& out, const RunDocument& doc) {
  std::string unused;
  write_run(out, header_json(doc), unused, [&](auto&& put, std::string&) {
    for (const auto& v : doc.vectors) put(vector_json(v));
    return true;
  });
}

std::string json_text(const RunDocument& doc) {
  std::ostringstream out;
  write_run_json(out, doc);
  return std::move(out).str();
}

bool write_run_json_from_journal(std::istream& journal, std::ostream& out, const RunDocument& header, std::string& error) {
  return write_run(out, header_without_journal(header), error, [&](auto&& put, std::string& why) {
    // A last line without its newline was cut short by a failed write: left
    // out, as read_journal leaves it out.
    std::size_t line_no = 0;
    std::vector<char> scratch;
    for (std::string line; std::getline(journal, line) && !journal.eof();) {
      ++line_no;
      if (line.empty()) continue;
      // Read in place in a copy (RapidJSON's in-situ parse writes the strings
      // it unescapes over the text, which the file must get as it is), with
      // the UTF-8 checked apart: RapidJSON's check, and its copy of each
      // string, cost five times the parse.
      RecordSniffer sniffer;
      scratch.assign(line.begin(), line.end());
      scratch.push_back('\0');
      rapidjson::InsituStringStream in(scratch.data());
      rapidjson::Reader reader;
      const auto parsed = reader.Parse<rapidjson::kParseInsituFlag>(in, sniffer);
      if (parsed.IsError() || in.Tell() != line.size() || !is_valid_utf8(line)) {
        why = "journal line " + std::to_string(line_no) + " is not one JSON text (offset " +
              std::to_string(parsed.IsError() ? parsed.Offset() : in.Tell()) + ")";
        return false;
      }
      if (!sniffer.record()) put(line);
    }
    if (journal.bad()) {
      why = "the journal could not be read";
      return false;
    }
    return true;
  });
}

// ---- files -----------------------------------------------------------------------

namespace {

bool same_file(const struct stat& st, int fd) {
  struct stat other {};
  return ::fstat(fd, &other) == 0 && other.st_dev == st.st_dev && other.st_ino == st.st_ino;
}

// A report written whole or not at all (harness/files: a new file beside
// PATH, flushed to the disk and renamed over it; a link is written through
// and stays a link), after output_path_problem's refusals, which name what
// the path is; "-" is standard output.
bool replace_file(const std::string& path, std::string& error, const harness::Fill& fill) {
  if (path == kStandardOutput) {
    const bool ok = fill(std::cout, error);
    std::cout.flush();
    if (ok && !std::cout) error = "standard output: write failed";
    return ok && std::cout;
  }
  if (std::string why = output_path_problem(path); !why.empty()) {
    error = why;
    return false;
  }
  return harness::replace_file(path, fill, error);
}

}  // namespace

bool write_run_json(const std::string& path, const RunDocument& doc, std::string& error) {
  return replace_file(path, error, [&](std::ostream& out, std::string&) {
    write_run_json(out, doc);
    return true;
  });
}

bool write_run_json(const std::string& path, const RunDocument& header, const std::string& journal, std::string& error) {
  return replace_file(path, error, [&](std::ostream& out, std::string& why) {
    std::ifstream in(journal, std::ios::binary);
    if (!in) {
      why = journal + ": cannot read";
      return false;
    }
    if (write_run_json_from_journal(in, out, header, why)) return true;
    why = journal + ": " + why;
    return false;
  });
}

std::string output_path_problem(const std::string& path) {
  if (path.empty()) return "no file name given";
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) return path + ": " + std::strerror(errno);
    // A new file: its folder must be there.
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    struct stat dir {};
    if (!parent.empty() && (::stat(parent.c_str(), &dir) != 0 || !S_ISDIR(dir.st_mode)))
      return path + ": cannot write: no such directory " + parent.string();
    return "";
  }
  std::string via;
  if (S_ISLNK(st.st_mode)) {
    std::error_code ec;
    const auto target = std::filesystem::read_symlink(path, ec);
    via = " through the symbolic link to " + (ec ? std::string("?") : target.string());
    if (::stat(path.c_str(), &st) != 0)
      return path + " is a symbolic link to " + (ec ? std::string("?") : target.string()) +
             ", which does not exist; not written through it";
  }
  if (!S_ISREG(st.st_mode))
    return path + " is " + harness::kind_of_file(st.st_mode) + via + ": reports are written to regular files only (- for standard output)";
  // `--json /dev/stdout > out.json`: the rename would replace the file the
  // shell opened, and what else goes to standard output would be lost.
  if (same_file(st, STDOUT_FILENO) || same_file(st, STDERR_FILENO))
    return path + " is this process's own standard output or error" + via + ": give - for standard output";
  return "";
}

std::string report_paths_problem(const std::vector<std::pair<std::string, std::string>>& reports) {
  std::map<std::string, std::string> seen;  // a file (or "-") -> the option that named it first
  for (const auto& [option, path] : reports) {
    if (path.empty()) continue;
    std::error_code ec;
    const std::string key = path == kStandardOutput ? path : std::filesystem::weakly_canonical(path, ec).string();
    if (const auto it = seen.find(key); it != seen.end())
      return path == kStandardOutput ? it->second + " - and " + option + " -: only one report can go to standard output"
                                     : it->second + " and " + option + " both name " + path;
    seen[key] = option;
    if (path == kStandardOutput) continue;
    if (const std::string why = output_path_problem(path); !why.empty()) return option + " " + why;
  }
  return "";
}

// The same way as the run JSON: a report is whole or not there, never cut
// short by a full disk or a kill, and never written through a device or a
// link to one.
bool write_file(const std::string& path, const std::string& text, std::string& error) {
  return replace_file(path, error, [&](std::ostream& out, std::string&) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    return true;
  });
}

}  // namespace sabus::reports
