// The run JSON (reports/SCHEMA.md), written token by token: from a document
// in memory, or from a run's journal line by line.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

using nlohmann::ordered_json;

namespace {

// Strings from a device are 7-bit, but a damaged file may hold anything: a
// byte that is not UTF-8 becomes U+FFFD instead of ending the write.
std::string dump_line(const ordered_json& v) { return v.dump(-1, ' ', false, ordered_json::error_handler_t::replace); }

}  // namespace

// ---- JsonStreamWriter ----------------------------------------------------------

void JsonStreamWriter::newline(std::size_t depth) { out_ << '\n' << std::string(2 * depth, ' '); }

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
  if (!top.empty) out_ << ',';
  top.empty = false;
  newline(stack_.size());
}

void JsonStreamWriter::begin_object() {
  before_value();
  out_ << '{';
  stack_.push_back({true});
}

void JsonStreamWriter::begin_array() {
  before_value();
  out_ << '[';
  stack_.push_back({false});
}

void JsonStreamWriter::key(std::string_view name) {
  if (stack_.empty() || !stack_.back().object || stack_.back().has_key)
    throw std::logic_error("JsonStreamWriter: a key outside an object");
  Level& top = stack_.back();
  if (!top.empty) out_ << ',';
  top.empty = false;
  top.has_key = true;
  newline(stack_.size());
  out_ << dump_line(ordered_json(name)) << ": ";
}

void JsonStreamWriter::value(const ordered_json& v) {
  before_value();
  out_ << dump_line(v);
}

void JsonStreamWriter::serialized_value(std::string_view json_text) {
  before_value();
  out_ << json_text;
}

void JsonStreamWriter::end() {
  if (stack_.empty() || stack_.back().has_key) throw std::logic_error("JsonStreamWriter: end without an open object or array");
  const Level closed = stack_.back();
  stack_.pop_back();
  if (!closed.empty) newline(stack_.size());
  out_ << (closed.object ? '}' : ']');
  if (stack_.empty()) out_ << '\n';
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

// Writes PATH.tmp with `fill`, fsyncs it and renames it over PATH.
template <class Fill>
bool replace_file(const std::string& path, std::string& error, Fill&& fill) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc | std::ios::binary);
    if (!out) {
      error = tmp + ": cannot write: " + std::strerror(errno);
      return false;
    }
    if (!fill(out, error)) {
      out.close();
      std::filesystem::remove(tmp);
      return false;
    }
    out.close();
    if (!out) {
      error = tmp + ": write failed";
      return false;
    }
  }
  // The data reaches the disk before the name does: a power cut leaves the
  // old file or the new one, never an empty one. (Linux syncs a file through
  // any descriptor, a read-only one too.)
  if (const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC); fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    error = path + ": cannot replace: " + ec.message();
    return false;
  }
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
  write_run(out, header_json(doc), [&](JsonStreamWriter& w) {
    for (const auto& v : doc.vectors) w.value(to_json(v));
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

bool write_file(const std::string& path, const std::string& text, std::string& error) {
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
