// The vector data model's own functions (vector.hpp).
#include "sabus/harness/vector.hpp"

#include "vector_loader_internal.hpp"

namespace sabus::harness {

using namespace vector_loader_internal;

std::string SourceLocation::text() const {
  return line > 0 ? file + ":" + std::to_string(line) + ":" + std::to_string(column) : file;
}

std::string_view to_string(Level level) {
  for (const auto& [name, l] : kLevels)
    if (l == level) return name;
  return "?";
}

bool Vector::has_tag(std::string_view tag) const { return contains(tags, tag); }

std::string LoadError::text() const {
  std::string out = where.text() + ": ";
  if (!vector_id.empty()) out += "[" + vector_id + "] ";
  if (!key.empty()) out += key + ": ";
  return out + message;
}

std::string matcher_text(const FieldDescription& f) {
  std::string text = f.raw;
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"') {
    text = text.substr(1, text.size() - 2);
    while (!text.empty() && text.back() == ' ') text.pop_back();
  }
  return text;
}

}  // namespace sabus::harness
