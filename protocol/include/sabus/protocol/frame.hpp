// Whole frames: `STX|ACK|NAK addr cmd data... ETX LRC` (§1 Message Format).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus {

enum class FrameKind : std::uint8_t { kCommand, kAck, kNak };
std::string_view to_string(FrameKind kind);
std::uint8_t start_byte(FrameKind kind);

struct Frame {
  FrameKind kind = FrameKind::kCommand;
  std::uint8_t address = 0;
  std::uint8_t command = 0;
  Bytes data;
  bool operator==(const Frame&) const = default;
};

// Bytes 0-2 are the header (start, address, command); byte 3 is the first
// data byte of every frame (§1 Message Format).
inline constexpr std::size_t kFrameDataStart = 3;

// 7-bit characters, STX/ACK/NAK through the check byte.
Bytes encode_frame(const Frame& frame, LrcRule rule = LrcRule::kFromByte0);

// How strictly decode_frame reads a complete byte string.
struct FrameCheck {
  LrcRule lrc = LrcRule::kFromByte0;
  // §3.2 byte 40 can be 10h-1Fh (ERRATA E-35): a reply body may hold control
  // characters other than ETX; a command body may not (READING-NOTES 6).
  bool allow_control_in_reply_body = true;
};

// Decodes exactly one complete frame of 7-bit characters; the error names the
// byte offset and what was expected there.
Expected<Frame> decode_frame(ByteView bytes, const FrameCheck& check = {});

// §3 RC3000 Unrecognized Commands - NAK Reply: NAK A CC ETX LRC.
Frame nak_reply(std::uint8_t address, std::uint8_t command);
// §3 RC3000 Online/Offline Reply: ACK A CC 'F' ETX LRC.
Frame offline_reply(std::uint8_t address, std::uint8_t command);
bool is_offline_reply(const Frame& frame);
inline constexpr std::uint8_t kOfflineMarker = 'F';

// Byte 0 of the last frame in a byte sequence (READING-NOTES 7): the last
// STX, ACK or NAK that is followed by an address byte (31h-6Fh), so a send
// that restarts a frame (02 02 A 31 03 LRC) has its second STX; nullopt when
// there is none. The vector linter, `{lrc}` and the recorders read sends so.
std::optional<std::size_t> last_frame_start(ByteView bytes);

}  // namespace sabus

namespace sabus {
// A device address as the tools accept it (READING-NOTES 4): the decimal
// setting "50" (49-111), the address character "2", or "0x32".
Expected<std::uint8_t> parse_address(std::string_view text);
}  // namespace sabus
