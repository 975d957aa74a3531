// What yaml-cpp's Emitter leaves to its caller, and the double-quoted text of
// the profile writer (yaml_writer.hpp).
#include "sabus/harness/yaml_writer.hpp"

#include <cstdint>
#include <stdexcept>

namespace sabus::harness::yaml_writer {
namespace {

// The length of the well-formed UTF-8 sequence at s[i] (Unicode 15, table
// 3-7: no overlong forms, no surrogates, nothing past U+10FFFF), or 0.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0u; };
  const unsigned b0 = byte(0);
  const auto trail = [](unsigned b) { return b >= 0x80 && b <= 0xBF; };
  if (b0 < 0x80) return 1;
  if (b0 >= 0xC2 && b0 <= 0xDF) return trail(byte(1)) ? 2 : 0;
  if (b0 >= 0xE0 && b0 <= 0xEF) {
    const unsigned lo = b0 == 0xE0 ? 0xA0 : 0x80, hi = b0 == 0xED ? 0x9F : 0xBF;
    return byte(1) >= lo && byte(1) <= hi && trail(byte(2)) ? 3 : 0;
  }
  if (b0 >= 0xF0 && b0 <= 0xF4) {
    const unsigned lo = b0 == 0xF0 ? 0x90 : 0x80, hi = b0 == 0xF4 ? 0x8F : 0xBF;
    return byte(1) >= lo && byte(1) <= hi && trail(byte(2)) && trail(byte(3)) ? 4 : 0;
  }
  return 0;
}

std::uint32_t code_point(std::string_view seq) {
  const auto b = [&](std::size_t k) { return static_cast<std::uint32_t>(static_cast<unsigned char>(seq[k])); };
  switch (seq.size()) {
    case 1: return b(0);
    case 2: return (b(0) & 0x1F) << 6 | (b(1) & 0x3F);
    case 3: return (b(0) & 0x0F) << 12 | (b(1) & 0x3F) << 6 | (b(2) & 0x3F);
    default: return (b(0) & 0x07) << 18 | (b(1) & 0x3F) << 12 | (b(2) & 0x3F) << 6 | (b(3) & 0x3F);
  }
}

// Printable on one comment line: YAML 1.2 nb-char (c-printable without the
// breaks and the byte order mark), without tab, NEL and the separators a
// YAML 1.1 reader takes for line breaks, and without the noncharacters
// yaml-cpp replaces.
bool printable_on_a_line(std::uint32_t c) {
  if (c < 0x20 || c == 0x7F) return false;
  if (c >= 0x80 && c <= 0x9F) return false;
  if (c == 0x2028 || c == 0x2029 || c == 0xFEFF) return false;
  if ((c >= 0xFDD0 && c <= 0xFDEF) || (c & 0xFFFE) == 0xFFFE) return false;
  return true;
}

void append_escaped(std::string& out, std::string_view bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  for (char ch : bytes) {
    const auto u = static_cast<unsigned char>(ch);
    out += "\\x";
    out += kHex[u >> 4];
    out += kHex[u & 0xF];
  }
}

}  // namespace

std::string printable_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_length(text, i);
    if (n == 0) {  // one byte that is not UTF-8; what follows is read afresh
      append_escaped(out, text.substr(i, 1));
      ++i;
      continue;
    }
    const std::string_view seq = text.substr(i, n);
    if (seq == "\n" || printable_on_a_line(code_point(seq))) out += seq;
    else append_escaped(out, seq);
    i += n;
  }
  return out;
}

std::string comment_lines(std::string_view text) {
  if (text.empty()) return "";
  YAML::Emitter e;
  e << YAML::Comment(printable_text(text));
  return document(e);
}

std::string double_quoted(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u > 0x7E) {
      append_escaped(out, std::string_view(&c, 1));
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string document(const YAML::Emitter& emitter) {
  if (!emitter.good()) throw std::logic_error("YAML writer: " + emitter.GetLastError());
  return std::string(emitter.c_str(), emitter.size()) + "\n";
}

}  // namespace sabus::harness::yaml_writer
