// The command catalog: ONE row per SAbus command code 30h-48h (§3 Command Set).
// This is the only place a command's code, paragraph, lengths, forms, reply
// kind and effects live; codecs, the receiver's overrun limit, the reference
// controller, the vector linter and the reports all read it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace sabus {

// What a command is answered with when it is accepted (§3.x "Reply").
enum class ReplyKind : std::uint8_t {
  kDeviceType,      // §3.1  11 bytes
  kStatus,          // §3.2  52 bytes (also 32h, 33h, 34h, 36h)
  kQueryName,       // §3.6  19 bytes
  kDisplay,         // §3.8  169 bytes
  kSignalStrength,  // §3.9  6 bytes, '0' = online
  kAckOnly,         // ACK A CC ETX LRC, 5 bytes
  kSatelliteData,   // §3.11 32 bytes
  kTleData,         // §3.13 145 bytes
  kIessData,        // §3.15 not specified (TBD)
  kPulseCount,      // §3.16 15 bytes
  kExtendedStatus,  // §3.17 58 bytes (ERRATA E-21)
  kSignpostData,    // §3.21 36 bytes
  kNavigationData,  // §3.22 72 bytes
  kJogPosition,     // §3.24 12 bytes
};
std::string_view to_string(ReplyKind kind);

// What executing a command can do on a real bench (READING-NOTES 26).
struct Effects {
  bool moves_antenna = false;
  bool changes_stored_data = false;
  // A second identical frame acts again rather than leaving the device as
  // the first did: a jog restarts its duration (§3.4), a LOCATE, a search or
  // a peak starts over, a key is pressed twice. After a line fault the runner sends a command again only when
  // this is false (RunOptions::retries).
  bool acts_again = false;
};

// A form of a command: the variants the spec describes, told apart by a
// selector byte (auto move byte 3, jog direction, misc sub-command, ...).
struct FormInfo {
  std::string_view id;          // "2A", "E", "R", "preset"
  std::string_view selectors;   // the selector byte values that choose this form, "" if none
  std::string_view description;
  Effects effects;
};

struct CommandInfo {
  std::uint8_t code;
  std::string_view name;        // "Auto Move"
  std::string_view key;         // "auto_move": how vectors and the CLI name it
  std::string_view paragraph;   // "3.3"
  // Whole frame, STX through check byte. nullopt: the spec leaves it TBD.
  std::optional<std::uint8_t> request_length;
  std::optional<std::uint8_t> reply_length;
  ReplyKind reply;
  std::span<const FormInfo> forms;
  bool implemented;             // implemented by RC3000 software 1.59 (§3 table '*')
  bool needs_dvb_option;        // §3.20, §3.21
  // Offset of the byte that selects the form, if the command has forms.
  std::optional<std::uint8_t> form_selector_offset;

  // Effects of the command in any of its forms.
  Effects effects() const;
  // Request/reply data bytes (between the command byte and ETX).
  std::optional<std::size_t> request_data_length() const;
  std::optional<std::size_t> reply_data_length() const;
  // The form chosen by a selector byte, or nullptr.
  const FormInfo* form_for_selector(std::uint8_t selector) const;
  const FormInfo* form_by_id(std::string_view id) const;
};

inline constexpr std::uint8_t kFirstCommand = 0x30;
inline constexpr std::uint8_t kLastCommand = 0x48;
inline constexpr std::size_t kCommandCount = kLastCommand - kFirstCommand + 1;
// Frame overhead: byte 0, address, command, ETX, check byte.
inline constexpr std::size_t kFrameOverhead = 5;
// The two reply frames every command can get instead of its normal reply.
inline constexpr std::size_t kNakReplyLength = 5;      // §3 NAK Reply
inline constexpr std::size_t kOfflineReplyLength = 6;  // §3 Online/Offline Reply

std::span<const CommandInfo> catalog();
const CommandInfo* find_command(std::uint8_t code);
// By key ("auto_move"), by name ("Auto Move", case-insensitive) or by code text ("32h", "0x32").
const CommandInfo* find_command(std::string_view name_or_code);

// Longest command and reply frame in the catalog (READING-NOTES 8: overrun limit).
std::size_t max_request_length();
std::size_t max_reply_length();

}  // namespace sabus
