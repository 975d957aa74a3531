// The run JSON (reports/SCHEMA.md), written token by token: from a document
// in memory, or from a run's journal line by line.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <ext/stdio_filebuf.h>  // an ostream on the descriptor mkstemp opened (libstdc++, used with g++ and clang here)

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

using nlohmann::ordered_json;

// ---- JsonStreamWriter ----------------------------------------------------------

// The serializer replaces a byte that is not UTF-8 with U+FFFD instead of
// ending the write: strings from a device are 7-bit, but a damaged file may
// hold anything.
JsonStreamWriter::JsonStreamWriter(std::ostream& out, Layout layout)
    : out_(out),
      layout_(layout),
      serializer_(nlohmann::detail::output_adapter<char>(buf_), ' ', ordered_json::error_handler_t::replace) {}

JsonStreamWriter::~JsonStreamWriter() { flush(); }

void JsonStreamWriter::flush() {
  out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  buf_.clear();
}

void JsonStreamWriter::flush_when_large() {
  if (buf_.size() >= (1u << 16)) flush();
}

void JsonStreamWriter::newline(std::size_t depth) {
  if (layout_ == Layout::kLines) buf_.append(1, '\n').append(2 * depth, ' ');
}

void JsonStreamWriter::before_value() {
  if (stack_.empty()) {
    if (started_) throw std::logic_error("JsonStreamWriter: a second top-level value");
    started_ = true;
    return;
  }
  Level& top = stack_.back();
  if (top.object) {
    if (!top.has_key) throw std::logic_error("JsonStreamWriter: a value in an object without its key");
    top.has_key = false;  // the value follows its key on the same line
    return;
  }
  if (!top.empty) buf_ += ',';
  top.empty = false;
  newline(stack_.size());
}

void JsonStreamWriter::begin_object() {
  before_value();
  buf_ += '{';
  stack_.push_back({true});
}

void JsonStreamWriter::begin_array() {
  before_value();
  buf_ += '[';
  stack_.push_back({false});
}

void JsonStreamWriter::key(std::string_view name) {
  if (stack_.empty() || !stack_.back().object || stack_.back().has_key)
    throw std::logic_error("JsonStreamWriter: a key outside an object");
  Level& top = stack_.back();
  if (!top.empty) buf_ += ',';
  top.empty = false;
  top.has_key = true;
  newline(stack_.size());
  // A name of letters, digits and '_' (every name of the schema) is its own
  // JSON text between quotes; any other goes through the library.
  const bool plain = std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (plain) buf_.append(1, '"').append(name).append(1, '"');
  else serializer_.dump(ordered_json(name), false, false, 0);
  buf_ += layout_ == Layout::kLines ? ": " : ":";
}

void JsonStreamWriter::value(const ordered_json& v) {
  before_value();
  serializer_.dump(v, false, false, 0);
  flush_when_large();
}

void JsonStreamWriter::string_value(std::string_view s) {
  string_.get_ref<std::string&>().assign(s);
  value(string_);
}

void JsonStreamWriter::serialized_value(std::string_view json_text) {
  before_value();
  buf_ += json_text;
  flush_when_large();
}

void JsonStreamWriter::end() {
  if (stack_.empty() || stack_.back().has_key) throw std::logic_error("JsonStreamWriter: end without an open object or array");
  const Level closed = stack_.back();
  stack_.pop_back();
  if (!closed.empty) newline(stack_.size());
  buf_ += closed.object ? '}' : ']';
  if (stack_.empty()) {
    if (layout_ == Layout::kLines) buf_ += '\n';
    flush();
  }
}

// ---- a vector's JSON -------------------------------------------------------------

namespace {

void member(JsonStreamWriter& w, std::string_view key, const ordered_json& value) {
  w.key(key);
  w.value(value);
}
// String members, in order.
void members(JsonStreamWriter& w, std::initializer_list<std::pair<std::string_view, const std::string*>> list) {
  for (const auto& [key, value] : list) {
    w.key(key);
    w.string_value(*value);
  }
}

// A frame's "fields" array.
void write_fields(JsonStreamWriter& w, const std::vector<Field>& fields) {
  w.begin_array();
  for (const auto& x : fields) {
    w.begin_object();
    member(w, "first", x.first);
    member(w, "last", x.last);
    members(w, {{"name", &x.name}, {"raw", &x.raw}, {"meaning", &x.meaning}});
    member(w, "ok", x.ok);
    w.end();
  }
  w.end();
}

void write_frame(JsonStreamWriter& w, const FrameRecord& f, FieldsJsonCache* cache) {
  w.begin_object();
  member(w, "t_ms", f.t_ms);
  members(w, {{"dir", &f.dir}, {"hex", &f.hex}, {"note", &f.note}, {"command", &f.command}});
  w.key("fields");
  if (cache) w.serialized_value(cache->text(f));
  else write_fields(w, f.fields);
  if (f.dir == "tx") members(w, {{"form", &f.form}, {"expect", &f.expect}, {"path", &f.path}});
  w.end();
}

void write_vector(JsonStreamWriter& w, const VectorRecord& v, FieldsJsonCache* cache) {
  w.begin_object();
  members(w, {{"id", &v.id}, {"paragraph", &v.paragraph}, {"file", &v.file}, {"level", &v.level}, {"outcome", &v.outcome}});
  member(w, "failures", v.failures);
  members(w, {{"skip_reason", &v.skip_reason},
              {"skip_cause", &v.skip_cause},
              {"known_issue", &v.known_issue},
              {"quote", &v.quote},
              {"comment", &v.comment}});
  member(w, "duration_ms", v.duration_ms);
  if (v.wall_ms) member(w, "wall_ms", *v.wall_ms);
  member(w, "repeats", v.repeats);
  member(w, "repeat_failures", v.repeat_failures);
  w.key("transcript");
  w.begin_array();
  for (const auto& f : v.transcript) write_frame(w, f, cache);
  w.end();
  w.end();
}

// The text `write` writes with a one-line writer.
template <class Write>
std::string one_line(Write&& write) {
  std::ostringstream out;
  JsonStreamWriter w(out, JsonStreamWriter::Layout::kOneLine);
  write(w);  // its last end() writes the text out
  return std::move(out).str();
}

}  // namespace

const std::string& FieldsJsonCache::text(const FrameRecord& f) {
  Slot& slot = slots_[std::hash<std::string>{}(f.hex) % slots_.size()];
  if (slot.hex != f.hex || slot.fields != f.fields) {
    slot.hex = f.hex;
    slot.fields = f.fields;
    slot.text = one_line([&](JsonStreamWriter& w) { write_fields(w, f.fields); });
  }
  return slot.text;
}

std::string vector_json(const VectorRecord& v, FieldsJsonCache* cache) {
  return one_line([&](JsonStreamWriter& w) { write_vector(w, v, cache); });
}

// ---- the run JSON ----------------------------------------------------------------

namespace {

// The header members in schema order, then "vectors": each vector that
// `vectors` writes, one a line. "vectors" comes last so a reader sees the
// header first.
template <class WriteVectors>
bool write_run(std::ostream& out, const ordered_json& header, WriteVectors&& vectors) {
  JsonStreamWriter w(out);
  w.begin_object();
  for (const auto& [name, value] : header.items()) {
    w.key(name);
    w.value(value);
  }
  w.key("vectors");
  w.begin_array();
  const bool ok = vectors(w);
  w.end();
  w.end();
  return ok;
}

// What a path names, for the refusals of output_path_problem: "a directory",
// "a character device", ...
std::string kind_of(const struct stat& st) {
  if (S_ISDIR(st.st_mode)) return "a directory";
  if (S_ISCHR(st.st_mode)) return "a character device";
  if (S_ISBLK(st.st_mode)) return "a block device";
  if (S_ISFIFO(st.st_mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return "not a regular file";
}

bool same_file(const struct stat& st, int fd) {
  struct stat other {};
  return ::fstat(fd, &other) == 0 && other.st_dev == st.st_dev && other.st_ino == st.st_ino;
}

// Where a report at `path` is written: the path itself, or for a symbolic
// link to a regular file the file it names (the link stays a link).
std::string write_target(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return path;
  std::error_code ec;
  const auto resolved = std::filesystem::canonical(path, ec);
  return ec ? path : resolved.string();
}

// Writes `fill` into a new file beside PATH (created exclusively, so no
// link or device planted at a guessed name is written through), fsyncs it
// and renames it over PATH, which must be a regular file or not exist: the
// rename never replaces a link, a device, a pipe or a directory.
template <class Fill>
bool replace_file(const std::string& path, std::string& error, Fill&& fill) {
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
  const std::string target = write_target(path);
  std::string tmp = target + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) {
    error = target + ": cannot write a temporary file beside it: " + std::strerror(errno);
    return false;
  }
  // mkstemp makes the file 0600; a report gets the mode any new file would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  (void)::fchmod(fd, 0666 & ~mask);
  auto fail = [&](std::string why) {
    std::filesystem::remove(tmp);
    error = std::move(why);
    return false;
  };
  {
    __gnu_cxx::stdio_filebuf<char> buf(fd, std::ios::out | std::ios::binary);  // closes fd
    std::ostream out(&buf);
    if (!fill(out, error)) return fail(error);
    out.flush();
    if (!out) return fail(tmp + ": write failed");
    // The data reaches the disk before the name does: a power cut leaves the
    // old file or the new one, never an empty one.
    if (::fsync(fd) != 0) return fail(tmp + ": fsync failed: " + std::strerror(errno));
  }
  // Checked again just before the rename: the run may have lasted an hour.
  struct stat st {};
  if (::lstat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    return fail(target + " is " + kind_of(st) + " now; not replaced (the report is lost)");
  if (::rename(tmp.c_str(), target.c_str()) != 0) return fail(target + ": cannot replace: " + std::strerror(errno));
  return true;
}

ordered_json header_without_journal(const RunDocument& doc) {
  ordered_json h = header_json(doc);
  h.erase("journal");  // the file now holds every vector
  return h;
}

}  // namespace

std::string json_text(const RunDocument& doc) {
  std::ostringstream out;
  FieldsJsonCache cache;
  write_run(out, header_json(doc), [&](JsonStreamWriter& w) {
    for (const auto& v : doc.vectors) w.serialized_value(vector_json(v, &cache));
    return true;
  });
  return out.str();
}

bool write_run_json(const std::string& path, const RunDocument& doc, std::string& error) {
  return replace_file(path, error, [&](std::ostream& out, std::string&) {
    out << json_text(doc);
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
    return write_run(out, header_without_journal(header), [&](JsonStreamWriter& w) {
      // JournalWriter's lines: the header and end records start so; every
      // other line is one vector as to_json made it.
      // A last line without its newline was cut short by a failed write.
      for (std::string line; std::getline(in, line) && !in.eof();)
        if (!line.empty() && !line.starts_with("{\"record\":")) w.serialized_value(line);
      return !in.bad();
    });
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
    return path + " is " + kind_of(st) + via + ": reports are written to regular files only (- for standard output)";
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

bool write_file(const std::string& path, const std::string& text, std::string& error) {
  if (path == kStandardOutput) {
    std::cout << text << std::flush;
    if (!std::cout) error = "standard output: write failed";
    return static_cast<bool>(std::cout);
  }
  if (std::string why = output_path_problem(path); !why.empty()) {
    error = why;
    return false;
  }
  std::ofstream out(path, std::ios::trunc | std::ios::binary);
  if (!out) {
    error = path + ": cannot write: " + std::strerror(errno);
    return false;
  }
  out << text;
  out.close();
  if (!out) {
    error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace sabus::reports
