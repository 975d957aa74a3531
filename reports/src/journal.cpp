// The run journal: JSON Lines, a header record, one line per finished vector,
// an end record (reports/SCHEMA.md, "The journal").
#include "sabus/reports/journal.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace sabus::reports {

using nlohmann::json;
using nlohmann::ordered_json;

std::string journal_path_for(const std::string& json_path) {
  std::filesystem::path p(json_path);
  if (p.extension() == ".json") p.replace_extension();
  p += ".journal.jsonl";
  return p.string();
}

// ---- writing ---------------------------------------------------------------------

JournalWriter::~JournalWriter() {
  if (fd_ >= 0) ::close(fd_);
}

bool JournalWriter::open(const std::string& path, const RunDocument& header) {
  path_ = path;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    error_ = path + ": cannot write: " + std::strerror(errno);
    return false;
  }
  return write_text(journal_record_json("header", header));
}

bool JournalWriter::open(const std::string& path, const RunDocument& header, const std::vector<VectorRecord>& earlier,
                         const std::string& backup_file) {
  const std::string tmp = path + ".tmp";
  if (!open(tmp, header)) return false;
  // In the file before it replaces the killed run's journal: a resumed run
  // killed in turn still names the backup its restore needs.
  if (!backup_file.empty() && !backup(backup_file)) return false;
  for (const auto& v : earlier)
    if (!append(v)) return false;
  if (::fsync(fd_) != 0 || ::rename(tmp.c_str(), path.c_str()) != 0) {
    error_ = path + ": cannot write: " + std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    ::unlink(tmp.c_str());
    return false;
  }
  path_ = path;  // the descriptor follows the rename
  return true;
}

bool JournalWriter::append(const VectorRecord& v) { return write_text(vector_json(v)); }

bool JournalWriter::backup(const std::string& file) { return write_text(journal_backup_json(file)); }

bool JournalWriter::close(const RunDocument& finished) {
  if (fd_ < 0) return false;
  bool ok = write_text(journal_record_json("end", finished));
  if (ok && ::fsync(fd_) != 0) {
    error_ = path_ + ": fsync: " + std::strerror(errno);
    ok = false;
  }
  ::close(fd_);
  fd_ = -1;
  return ok;
}

bool JournalWriter::write_text(std::string line) {
  if (fd_ < 0) return false;
  // One write(2) a record: a process killed after it leaves the whole line
  // in the file, one killed during it at worst a last line cut short.
  line += '\n';
  for (std::size_t done = 0; done < line.size();) {
    const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;  // SIGINT stops the run, not the record
    if (n <= 0) {
      error_ = path_ + ": write failed: " + std::strerror(errno);
      ::close(fd_);
      fd_ = -1;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// ---- in memory -------------------------------------------------------------------

void MemoryRecord::start() {
  if (doc.journal.empty()) doc.journal = "run.journal.jsonl";
  journal = journal_record_json("header", doc) + "\n";
}

void MemoryRecord::add(const harness::VectorResult& r, std::optional<double> wall_ms) {
  VectorRecord record = vector_record(r);
  record.wall_ms = wall_ms;
  journal += vector_json(record) + "\n";
  compact_for_reports(record);
  doc.vectors.push_back(std::move(record));
}

void MemoryRecord::end(const harness::RunResult& run, std::string finished_at) {
  finish(doc, run, std::move(finished_at));
  doc.journal.clear();
  journal += journal_record_json("end", doc) + "\n";
}

std::function<void(const harness::VectorResult&)> MemoryRecord::on_result(std::optional<double> wall_ms) {
  return [this, wall_ms](const harness::VectorResult& r) { add(r, wall_ms); };
}

// ---- reading ---------------------------------------------------------------------

namespace {

std::string record_type(const ordered_json& r) {
  const auto it = r.find("record");
  return it != r.end() && it->is_string() ? it->get<std::string>() : "";
}

}  // namespace

bool is_journal(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string first;
  if (!in || !std::getline(in, first)) return false;
  const auto r = ordered_json::parse(first, nullptr, false);
  return r.is_object() && record_type(r) == "header";
}

std::optional<RunDocument> scan_journal(const std::string& path, const std::function<void(const ordered_json&)>& on_vector,
                                        JournalNotes& notes, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot read";
    return std::nullopt;
  }
  return scan_journal(in, path, on_vector, notes, error);
}

std::optional<RunDocument> scan_journal(std::istream& in, const std::string& path,
                                        const std::function<void(const ordered_json&)>& on_vector, JournalNotes& notes,
                                        std::string& error) {
  std::optional<RunDocument> header;
  std::string backup_file;  // the backup record's
  std::size_t line_no = 0;
  auto fail = [&](const std::string& why) {
    error = path + ":" + std::to_string(line_no) + ": " + why;
    return std::nullopt;
  };
  auto run_of = [&](const ordered_json& r) {
    std::optional<RunDocument> doc;
    std::string why = "a record without its run";
    if (const auto run = r.find("run"); run != r.end()) doc = from_json(json(*run), why);
    if (!doc) error = path + ":" + std::to_string(line_no) + ": " + why;
    return doc;
  };
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    const bool cut_short = in.eof();  // no newline after it: the writer was killed during the write
    if (line.empty()) continue;
    ordered_json r;
    try {
      r = ordered_json::parse(line);
    } catch (const json::parse_error& e) {
      if (cut_short && header) {
        notes.notes.push_back("line " + std::to_string(line_no) + " is cut short (" + std::to_string(line.size()) +
                              " bytes): left out");
        break;
      }
      return fail(line_no == 1 ? "not a run journal (the first line is not JSON)" : std::string("not JSON: ") + e.what());
    }
    const std::string type = r.is_object() ? record_type(r) : "";
    if (!header) {
      if (type != "header") return fail("not a run journal (the first line is not a header record)");
      if (!(header = run_of(r))) return std::nullopt;
      header->vectors.clear();
      continue;
    }
    if (type.empty()) {
      if (!r.is_object()) return fail("not a vector or a record");
      try {
        on_vector(r);
      } catch (const json::exception& e) {
        return fail(std::string("vector: ") + e.what());
      }
      ++notes.vectors;
    } else if (type == "backup") {
      const auto file = r.find("file");
      if (file == r.end() || !file->is_string() || file->get<std::string>().empty())
        return fail("a backup record without its file (\"file\": the stored-data backup file, a string)");
      if (!backup_file.empty() && *file != backup_file)
        return fail("a second backup record, naming " + file->get<std::string>() + " after " + backup_file +
                    ": a run takes one stored-data backup");
      backup_file = file->get<std::string>();
    } else if (type == "end") {
      auto finished = run_of(r);
      if (!finished) return std::nullopt;
      finished->vectors.clear();
      header = std::move(finished);
      notes.ended = true;
    } else {
      return fail("unknown record \"" + type + "\"");
    }
  }
  if (!header) {
    error = path + ": empty: not a run journal";
    return std::nullopt;
  }
  // The header record was written before the backup was taken; the end
  // record, when there is one, names it itself.
  if (header->backup.empty()) header->backup = std::move(backup_file);
  return header;
}

std::optional<RunDocument> read_journal(const std::string& path, JournalNotes& notes, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot read";
    return std::nullopt;
  }
  return read_journal(in, path, notes, error);
}

std::optional<RunDocument> read_journal(std::istream& in, const std::string& name, JournalNotes& notes, std::string& error) {
  std::vector<VectorRecord> vectors;
  auto doc = scan_journal(in, name, [&](const ordered_json& v) { vectors.push_back(vector_from_json(json(v))); }, notes, error);
  if (doc) {
    doc->vectors = std::move(vectors);
    doc->journal.clear();  // the document holds the vectors itself
  }
  return doc;
}

std::optional<RunDocument> read_run_or_journal(const std::string& path, JournalNotes& notes, std::string& error) {
  notes.journal = is_journal(path);
  return notes.journal ? read_journal(path, notes, error) : read_run_file(path, error);
}

}  // namespace sabus::reports
