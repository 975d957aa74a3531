// Text as the report formats carry it: valid UTF-8 (JSON, XML, HTML and
// Markdown are all read as UTF-8, and a device may send any byte), and
// escaped for XML and HTML.
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>

#include "sabus/reports/document.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

// The code point of the UTF-8 sequence at s[i] (RFC 3629: no overlong
// forms, no surrogates, nothing above U+10FFFF), advancing i past it; nullopt
// (i unchanged) when the bytes there are not one.
std::optional<char32_t> next_code_point(std::string_view s, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = byte(i);
  if (b < 0x80) {
    ++i;
    return b;
  }
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  char32_t cp = 0;
  if (b >= 0xC2 && b <= 0xDF) {
    length = 2;
    cp = b & 0x1F;
  } else if (b >= 0xE0 && b <= 0xEF) {
    length = 3;
    cp = b & 0x0F;
    if (b == 0xE0) low = 0xA0;   // overlong
    if (b == 0xED) high = 0x9F;  // surrogates
  } else if (b >= 0xF0 && b <= 0xF4) {
    length = 4;
    cp = b & 0x07;
    if (b == 0xF0) low = 0x90;   // overlong
    if (b == 0xF4) high = 0x8F;  // above U+10FFFF
  } else {
    return std::nullopt;
  }
  if (i + length > s.size()) return std::nullopt;
  for (std::size_t k = 1; k < length; ++k) {
    const unsigned char c = byte(i + k);
    if (c < (k == 1 ? low : 0x80) || c > (k == 1 ? high : 0xBF)) return std::nullopt;
    cp = cp << 6 | (c & 0x3F);
  }
  i += length;
  return cp;
}

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// Characters XML 1.0 cannot carry even as references (C0 controls other than
// tab, LF and CR; U+FFFE, U+FFFF) and those HTML5 calls parse errors in its
// input stream (DEL, the C1 controls, noncharacters): shown as text.
bool shown_as_text(char32_t cp) {
  if (cp < 0x20) return cp != '\t' && cp != '\n' && cp != '\r';
  if (cp >= 0x7F && cp <= 0x9F) return true;
  if (cp >= 0xFDD0 && cp <= 0xFDEF) return true;
  return (cp & 0xFFFE) == 0xFFFE;
}

}  // namespace

bool is_valid_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    // ASCII, nearly all there is: eight bytes at a time, no decoding.
    if (std::uint64_t word; i + 8 <= s.size() && (std::memcpy(&word, s.data() + i, 8), (word & 0x8080808080808080u) == 0)) {
      i += 8;
      continue;
    }
    if (static_cast<unsigned char>(s[i]) < 0x80) {
      ++i;
      continue;
    }
    if (!next_code_point(s, i)) return false;
  }
  return true;
}

std::string valid_utf8(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t at = i;
    if (next_code_point(s, i)) {
      out.append(s.substr(at, i - at));
    } else {
      out.append(kReplacement);
      ++i;
    }
  }
  return out;
}

nlohmann::ordered_json json_string(std::string_view s) {
  return is_valid_utf8(s) ? nlohmann::ordered_json(std::string(s)) : nlohmann::ordered_json(valid_utf8(s));
}

nlohmann::ordered_json json_value(const nlohmann::json& j) {
  if (j.is_string()) return json_string(j.get_ref<const std::string&>());
  if (j.is_array()) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const auto& item : j) out.push_back(json_value(item));
    return out;
  }
  if (j.is_object()) {
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    for (const auto& [key, value] : j.items()) out[valid_utf8(key)] = json_value(value);
    return out;
  }
  return nlohmann::ordered_json(j);
}

std::string json_value_text(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string shown_text(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t at = i;
    const std::optional<char32_t> cp = next_code_point(s, i);
    if (!cp) {
      out.append(kReplacement);
      ++i;
    } else if (!shown_as_text(*cp)) {
      out.append(s.substr(at, i - at));
    } else if (*cp <= 0xFF) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned>(*cp));
    } else {
      out += fmt::format("\\u{{{:04x}}}", static_cast<unsigned>(*cp));
    }
  }
  return out;
}

std::string xml_escape(std::string_view s) {
  const std::string text = shown_text(s);
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

// shown_text on one line: what a table cell or list item can hold.
std::string one_line(std::string_view s) {
  std::string out = shown_text(s);
  std::replace_if(out.begin(), out.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
  return out;
}

// The characters that start markup in the middle of a line: emphasis, code,
// links and images, raw HTML, entities, table cells, strikethrough, and the
// backslash itself. CommonMark lets any ASCII punctuation be escaped with a
// backslash, which then reads as the character.
constexpr std::string_view kMarkup = "\\`*_[]<>&|~!";

}  // namespace

std::string markdown_text(std::string_view s) {
  std::string out;
  for (char c : one_line(s)) {
    if (kMarkup.find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

std::string markdown_code(std::string_view s) {
  std::string out = one_line(s);
  std::replace(out.begin(), out.end(), '`', '\'');
  return out;
}

}  // namespace sabus::reports
