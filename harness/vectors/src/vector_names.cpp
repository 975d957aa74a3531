// What the names in a vector file look like: ids, flags, tags, capture
// names, profile key segments, and the spec paragraphs a vector may cite.
#include <algorithm>

#include "vector_loader_internal.hpp"

namespace sabus::harness::vector_loader_internal {
namespace {

bool is_lower_alnum(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }

// first character, then the rest, at most `max` characters.
bool is_name(std::string_view s, std::size_t max, bool (*first)(char), bool (*rest)(char)) {
  return !s.empty() && s.size() <= max && first(s[0]) && std::all_of(s.begin() + 1, s.end(), rest);
}
bool is_letter(char c) { return is_alnum(c) && !(c >= '0' && c <= '9'); }
bool is_ident_char(char c) { return is_alnum(c) || c == '_'; }

}  // namespace

bool is_alnum(char c) { return is_lower_alnum(c) || (c >= 'A' && c <= 'Z'); }

bool is_flag_name(std::string_view s) { return is_name(s, 64, is_letter, is_ident_char); }
// "motion", "option:dvb", "pol:single_port".
bool is_tag_text(std::string_view s) {
  return is_name(s, 32, [](char c) { return c >= 'a' && c <= 'z'; },
                 [](char c) { return is_lower_alnum(c) || c == '_' || c == ':' || c == '-'; });
}
// "3.2-status-reserved-bytes".
bool is_id_text(std::string_view s) {
  return is_name(s, 100, is_alnum, [](char c) { return is_alnum(c) || c == '.' || c == '-' || c == '_' || c == ':'; });
}
// "$track".
bool is_capture_name(std::string_view s) {
  return s.size() >= 2 && s[0] == '$' && is_name(s.substr(1), 32, [](char c) { return is_letter(c) || c == '_'; }, is_ident_char);
}
// A profile key path segment: "errata", "implements_iess".
bool is_key_segment(std::string_view s) {
  return is_name(s, 40, [](char c) { return (c >= 'a' && c <= 'z') || c == '_'; },
                 [](char c) { return is_lower_alnum(c) || c == '_'; });
}

// §1, §2, §3 (the RC3000 command set, NAK and offline replies), §4, and the
// catalog's §3.1-§3.25: one table of paragraphs, the catalog.
bool is_spec_paragraph(std::string_view p) {
  if (p == "1" || p == "2" || p == "3" || p == "4") return true;
  for (const auto& c : catalog())
    if (c.paragraph == p) return true;
  return false;
}

}  // namespace sabus::harness::vector_loader_internal
