// Byte-level vocabulary shared by every part of the protocol library:
// the SAbus delimiters, byte views, and the error value every decoder returns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace sabus {

using Bytes = std::vector<std::uint8_t>;
using ByteView = std::span<const std::uint8_t>;

// §1 Message Delimiters / §3 Message Delimiters table.
inline constexpr std::uint8_t STX = 0x02;
inline constexpr std::uint8_t ETX = 0x03;
inline constexpr std::uint8_t ACK = 0x06;
inline constexpr std::uint8_t NAK = 0x15;

// §1 Address Character: 31h..6Fh (49..111 decimal).
inline constexpr std::uint8_t kMinAddress = 0x31;
inline constexpr std::uint8_t kMaxAddress = 0x6F;
constexpr bool is_valid_address(std::uint8_t a) { return a >= kMinAddress && a <= kMaxAddress; }

// §1 Data Format: 00h-1Fh are reserved for message control, 20h-7Fh carry
// address, command and data (READING-NOTES 6: 7Fh is the empty-slot marker).
constexpr bool is_control(std::uint8_t c) { return c < 0x20; }
constexpr bool is_printable(std::uint8_t c) { return c >= 0x20 && c <= 0x7F; }

// Where and why a byte string failed to decode. `offset` is the byte index in
// the frame (byte 0 = STX/ACK/NAK), as the spec numbers bytes.
struct DecodeError {
  std::size_t offset = 0;
  std::string field;     // e.g. "az status", "check byte"
  std::string expected;  // e.g. "0x40|bits (high bits 010)"
  std::string got;       // e.g. "0x45 'E'"
  std::string message() const;
};

// A minimal expected<T, DecodeError> (std::expected is C++23).
template <class T>
class Expected {
 public:
  Expected(T value) : v_(std::move(value)) {}                 // NOLINT: implicit by design
  Expected(DecodeError error) : v_(std::move(error)) {}       // NOLINT: implicit by design
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  const T& value() const& { return std::get<0>(v_); }
  T& value() & { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const T& operator*() const& { return value(); }
  const T* operator->() const { return &value(); }
  const DecodeError& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, DecodeError> v_;
};

// "0x45 'E'" for printable bytes, "0x15 (NAK)" for delimiters, "0x9a" otherwise.
std::string describe_byte(std::uint8_t b);
// "02 32 31 03 02"
std::string to_hex(ByteView bytes);
// Parses "02 32 31 03 02", "0232310302", "02:32", "0x02 0x32"; nullopt-style error via ok flag.
Expected<Bytes> parse_hex(std::string_view text);

}  // namespace sabus
