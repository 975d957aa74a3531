#include <cctype>
#include <cstdio>

#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus {

std::string DecodeError::message() const {
  std::string m = "byte " + std::to_string(offset);
  if (!field.empty()) m += " " + field;
  m += ": expected " + expected;
  if (!got.empty()) m += ", got " + got;
  return m;
}

std::string describe_byte(std::uint8_t b) {
  static constexpr char kDigits[] = "0123456789abcdef";
  switch (b) {
    case STX: return "0x02 (STX)";
    case ETX: return "0x03 (ETX)";
    case ACK: return "0x06 (ACK)";
    case NAK: return "0x15 (NAK)";
    default: break;
  }
  // Built by hand, not by snprintf: `sabus decode` describes a byte in
  // every discarded run's message, and random input has one every two bytes.
  std::string out = {'0', 'x', kDigits[b >> 4], kDigits[b & 0xF]};
  if (b >= 0x20 && b < 0x7F) out += {' ', '\'', static_cast<char>(b), '\''};
  return out;
}

std::string to_hex(ByteView bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  s.reserve(bytes.size() * 3);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i) s += ' ';
    s += kDigits[bytes[i] >> 4];
    s += kDigits[bytes[i] & 0xF];
  }
  return s;
}

Expected<Bytes> parse_hex(std::string_view text) {
  Bytes out;
  int high = -1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '0' && i + 1 < text.size() && (text[i + 1] == 'x' || text[i + 1] == 'X') && high < 0) {
      ++i;  // "0x" prefix of a byte
      continue;
    }
    if (std::isspace(static_cast<unsigned char>(c)) || c == ':' || c == ',' || c == '-') {
      if (high >= 0) return DecodeError{i, "hex text", "two hex digits per byte", std::string(1, c)};
      continue;
    }
    int v = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
            : (c >= 'a' && c <= 'f')                    ? c - 'a' + 10
            : (c >= 'A' && c <= 'F')                    ? c - 'A' + 10
                                                        : -1;
    if (v < 0) return DecodeError{i, "hex text", "a hex digit", std::string(1, c)};
    if (high < 0) {
      high = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(high << 4 | v));
      high = -1;
    }
  }
  if (high >= 0) return DecodeError{text.size(), "hex text", "an even number of hex digits", ""};
  return out;
}

Bytes add_even_parity(ByteView chars7) {
  Bytes out(chars7.size());
  for (std::size_t i = 0; i < chars7.size(); ++i) out[i] = with_even_parity(chars7[i]);
  return out;
}

}  // namespace sabus
