// The check character (§1 Check Character; READING-NOTES 5, ERRATA E-5).
#pragma once

#include <cstdint>

#include "sabus/protocol/bytes.hpp"

namespace sabus {

// Which bytes the longitudinal redundancy check covers.
enum class LrcRule : std::uint8_t {
  kFromByte0,    // default (E-5): XOR of byte 0 (STX, ACK or NAK) through ETX
  kFromAddress,  // XOR of byte 1 through ETX: the variant some SAbus devices use
};

// XOR of every byte of `frame_without_check` (byte 0 through ETX) under `rule`.
constexpr std::uint8_t lrc(ByteView frame_without_check, LrcRule rule = LrcRule::kFromByte0) {
  std::uint8_t x = 0;
  std::size_t first = rule == LrcRule::kFromByte0 ? 0 : 1;
  for (std::size_t i = first; i < frame_without_check.size(); ++i) x ^= frame_without_check[i];
  return x;
}

// Even parity in bit 7 (§1 Data Format: "7-bit ASCII with the 8th bit sent as
// even parity"; READING-NOTES 1): the byte a master opened 8N1 puts on the wire.
constexpr std::uint8_t with_even_parity(std::uint8_t c7) {
  std::uint8_t c = c7 & 0x7F;
  std::uint8_t ones = 0;
  for (std::uint8_t b = c; b; b &= static_cast<std::uint8_t>(b - 1)) ++ones;
  return static_cast<std::uint8_t>(c | ((ones & 1) << 7));
}
constexpr bool has_even_parity(std::uint8_t wire) { return with_even_parity(wire) == wire; }

Bytes add_even_parity(ByteView chars7);

}  // namespace sabus
