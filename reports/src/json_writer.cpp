// The JSON report, rewritten atomically after every vector (reports/SCHEMA.md).
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

std::string assemble(const RunDocument& doc, const std::vector<std::string>& vectors) {
  std::string out = header_json(doc).dump(2);
  out.resize(out.size() - 2);  // "\n}"; "vectors" comes last so a reader sees the header first
  out += ",\n  \"vectors\": [";
  for (std::size_t i = 0; i < vectors.size(); ++i) out += (i ? ",\n    " : "\n    ") + vectors[i];
  out += vectors.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

}  // namespace

std::string json_text(const RunDocument& doc) {
  std::vector<std::string> vectors;
  for (const auto& v : doc.vectors) vectors.push_back(to_json(v).dump());
  return assemble(doc, vectors);
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

bool JsonWriter::start(const RunDocument& doc) {
  vectors_.clear();
  for (const auto& v : doc.vectors) vectors_.push_back(to_json(v).dump());
  return write(doc);
}

bool JsonWriter::add(const RunDocument& doc) {
  while (vectors_.size() < doc.vectors.size()) vectors_.push_back(to_json(doc.vectors[vectors_.size()]).dump());
  return write(doc);
}

bool JsonWriter::finish(const RunDocument& doc) { return add(doc); }

bool JsonWriter::write(const RunDocument& doc) {
  if (path_.empty()) return true;
  const std::string tmp = path_ + ".tmp";
  if (!write_file(tmp, assemble(doc, vectors_), error_)) return false;
  std::error_code ec;
  std::filesystem::rename(tmp, path_, ec);
  if (ec) {
    error_ = path_ + ": cannot replace: " + ec.message();
    return false;
  }
  return true;
}

}  // namespace sabus::reports
