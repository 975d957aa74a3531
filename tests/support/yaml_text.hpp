// What a YAML file sabus writes may hold, checked without the writers' own
// code: UTF-8 as iconv reads it, and only characters YAML 1.2 calls
// printable (c-printable), with '\n' the only line break. So no control
// character (tab and '\r' included), no DEL, no C1 control, no U+2028 or
// U+2029 (line breaks to a YAML 1.1 reader), no byte order mark and no
// noncharacter: what a strict YAML reader would refuse or split.
#pragma once

#include <iconv.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace sabus::test {

// "" when `text` is such a file's text, else what is wrong and where.
inline std::string yaml_text_problem(std::string_view text) {
  iconv_t cd = ::iconv_open("UTF-32LE", "UTF-8");
  if (cd == reinterpret_cast<iconv_t>(-1)) return "iconv cannot convert UTF-8";
  std::vector<char> out(4 * text.size() + 4);
  char* in = const_cast<char*>(text.data());
  std::size_t in_left = text.size();
  char* to = out.data();
  std::size_t to_left = out.size();
  const std::size_t r = ::iconv(cd, &in, &in_left, &to, &to_left);
  ::iconv_close(cd);
  if (r == static_cast<std::size_t>(-1))
    return "not UTF-8 at byte " + std::to_string(in - text.data()) + " (0x" +
           [&] {
             char hex[8];
             std::snprintf(hex, sizeof hex, "%02x", static_cast<unsigned char>(*in));
             return std::string(hex);
           }() +
           ")";
  const std::size_t n = (out.size() - to_left) / 4;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t c = 0;
    for (int k = 3; k >= 0; --k) c = c << 8 | static_cast<unsigned char>(out[4 * i + static_cast<std::size_t>(k)]);
    const bool printable = c == '\n' || (c >= 0x20 && c <= 0x7E) || (c >= 0xA0 && c <= 0xD7FF && c != 0x2028 && c != 0x2029) ||
                           (c >= 0xE000 && c <= 0xFFFD && c != 0xFEFF && !(c >= 0xFDD0 && c <= 0xFDEF)) ||
                           (c >= 0x10000 && c <= 0x10FFFF && (c & 0xFFFE) != 0xFFFE);
    if (!printable) {
      char u[16];
      std::snprintf(u, sizeof u, "U+%04X", c);
      return "character " + std::to_string(i) + " is " + u + ", which a YAML file sabus writes does not hold";
    }
  }
  return "";
}

}  // namespace sabus::test
