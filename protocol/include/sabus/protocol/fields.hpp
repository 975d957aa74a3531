// Fixed-width field types of SAbus frames. Each is a small codec with
//   value_type, width, encode(value, out), decode(in, value) -> FieldStatus,
//   meaning(value) -> human text
// so message layouts (messages.hpp) are lists of (name, field type, member)
// and encoding, decoding and describing are generic walks over them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "sabus/protocol/bytes.hpp"

namespace sabus::fields {

// Why a field did not decode: `index` is relative to the field's first byte.
struct FieldError {
  std::size_t index = 0;
  std::string expected;
};
using FieldStatus = std::optional<FieldError>;
using Out = std::span<std::uint8_t>;

// A field with no value of its own (literal bytes).
struct Unit {
  bool operator==(const Unit&) const = default;
};

// Printable text, left-justified and blank-padded (§3.2 sat_name). The value
// has its trailing blanks removed; encode pads them back.
struct Text {
  using value_type = std::string;
  std::size_t width;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// Bytes the spec fixes ("00000" in auto move form 3, blanks in form 2C).
// Anything else does not decode.
struct Fill {
  using value_type = Unit;
  std::size_t width;
  std::uint8_t ch;
  void encode(const value_type&, Out out) const;
  FieldStatus decode(ByteView in, value_type&) const;
  std::string meaning(const value_type&) const;
};

// Reserved or spare bytes with a documented fill (§3.2 bytes 45-49: 40h).
// Lenient: any printable bytes decode; the value is "" when they are the
// documented fill and the bytes themselves otherwise.
struct Reserved {
  using value_type = std::string;
  std::size_t width;
  std::uint8_t ch;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// Unsigned decimal digits, zero-padded ("01", "11050"). With
// `blank_padded` (a count in a reply, ERRATA E-33) blanks may pad the digits
// on either side instead ("  123", "123  "); encode still zero-pads.
struct Digits {
  using value_type = std::uint32_t;
  std::size_t width;
  bool blank_padded = false;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// How a scaled integer is shown to people.
enum class Quantity : std::uint8_t { kNumber, kDegrees, kCounts, kLatitude, kLongitude };

// A signed value, right-justified and left-padded with zeros, sign first
// (§3.3 "-152500456": az -152.5; ERRATA E-45). `decimals` scales the value
// (1: tenths, 2: hundredths); there is no decimal point on the wire.
struct SignedDigits {
  using value_type = std::int32_t;
  std::size_t width;
  int decimals;
  Quantity quantity = Quantity::kDegrees;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// "ddd.d": zero-padded with a decimal point (§3.23 heading "123.4",
// §3.22 true heading; READING-NOTES 33). nullopt = all blanks, if allowed.
// With `blank_padded` (a reply's heading, ERRATA E-33) blanks may pad the
// number on either side instead (" 12.3", "12.3 "); encode still zero-pads.
struct ZeroPaddedDecimal {
  using value_type = std::optional<std::int32_t>;
  std::size_t width;
  int decimals;
  bool blank_allowed = false;
  bool blank_padded = false;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// A position in a reply: right-justified, blank-padded, one decimal
// ("-180.0".."180.0"); on an A/D error 5 or 6 '*' (§3.2, ERRATA E-42).
// nullopt = the '*' error field. §3.2 says only "formatted": decode also
// takes a left-justified or zero-padded position ("-12.3 ", "0045.0",
// ERRATA E-33); which justification a device uses is judged by vectors.
struct Position {
  using value_type = std::optional<std::int32_t>;  // tenths of a degree
  std::size_t width = 6;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// §3.2 bytes 14-19: an azimuth position, or with a fluxgate compass a heading
// 0.0-359.9 in bytes 14-18 and 'M' or 'T' in byte 19.
struct AzimuthReading {
  enum class Kind : std::uint8_t { kPosition, kHeading, kError } kind = Kind::kPosition;
  std::int32_t tenths = 0;
  char reference = 0;  // 'M' or 'T' for a heading
  bool operator==(const AzimuthReading&) const = default;
};
struct Azimuth {
  using value_type = AzimuthReading;
  static constexpr std::size_t width = 6;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// A decimal number right-justified and blank-padded (§3.2 AGC "  0".."999";
// §3.22 magnetic variation). nullopt = all blanks, if allowed.
struct RightDecimal {
  using value_type = std::optional<std::int32_t>;
  std::size_t width;
  int decimals;
  bool blank_allowed = false;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// A decimal number left-justified and blank-padded (§3.10 longitude
// "-179.9", inclination "19"; READING-NOTES 33, ERRATA E-41: the decimal
// digit is optional on decode). nullopt = all blanks, if allowed.
struct LeftDecimal {
  using value_type = std::optional<std::int32_t>;
  std::size_t width;
  int decimals;
  bool blank_allowed = false;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// A binary byte: `base` in the bits outside `mask`, data in the bits inside
// (§3.2: "binary data will be placed in the lower nibble of a byte whose
// higher nibble will be initialized to a value which will make the result an
// ASCII character"). The value is the data bits.
using BitsMeaning = std::string (*)(std::uint8_t bits);
struct Bits {
  using value_type = std::uint8_t;
  std::uint8_t base;
  std::uint8_t mask;
  BitsMeaning describe = nullptr;
  static constexpr std::size_t width = 1;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// §3.2 byte 40: BBB<<4 | SSSS with bit 7 clear and BBB never 000.
struct TrackByte {
  using value_type = std::uint8_t;  // the whole byte
  static constexpr std::size_t width = 1;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
  // Whether SSSS (the low four bits) names a submode of an active TRACK:
  // one of §3.2's listed codes but 0000 "track mode not active".
  static bool names_active_submode(value_type v);
};

// One character out of a documented set, each with its meaning.
struct ChoiceItem {
  char ch;
  std::string_view meaning;
};
struct Choice {
  using value_type = char;
  std::span<const ChoiceItem> items;
  static constexpr std::size_t width = 1;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
  std::string allowed() const;  // "'H', 'V'"
};

// Any printable character; the meaning may come from a table function.
using CharMeaning = std::string (*)(char c);
struct AnyChar {
  using value_type = char;
  CharMeaning describe = nullptr;
  static constexpr std::size_t width = 1;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// Two index digits, or 7Fh 7Fh for an empty slot (§3.11, §3.13, §3.21 NOTE;
// READING-NOTES 18). nullopt = empty.
struct SlotIndex {
  using value_type = std::optional<std::uint8_t>;
  static constexpr std::size_t width = 2;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};
inline constexpr std::uint8_t kEmptySlot = 0x7F;

// §3.18/§3.19 bytes 3-4: 0x40 | A<<4 | tens, then the ones digit
// (READING-NOTES 22, 29).
struct PresetRef {
  bool preset = false;
  std::uint8_t index = 0;
  bool operator==(const PresetRef&) const = default;
};
struct PresetIndex {
  using value_type = PresetRef;
  static constexpr std::size_t width = 2;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// §3.17 bytes 45-48: an enumeration value 20h-7Fh.
struct EnumByte {
  using value_type = std::uint8_t;
  static constexpr std::size_t width = 1;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// §3.22 latitude "dd.mm(N/S)" (6) and longitude "ddd.mm(E/W)" (7); the value
// is signed minutes (south and west negative); nullopt = blanks (no data).
struct NavAngle {
  using value_type = std::optional<std::int32_t>;
  std::size_t width;  // 6: latitude, 7: longitude
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// §3.1 version "A.BC".
struct Version {
  using value_type = std::string;
  static constexpr std::size_t width = 4;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// Printable bytes of a layout the spec leaves TBD (§3.14/§3.15, ERRATA E-37).
// Width 0: the rest of the frame's data.
struct Opaque {
  using value_type = std::string;
  std::size_t width = 0;
  void encode(const value_type& v, Out out) const;
  FieldStatus decode(ByteView in, value_type& v) const;
  std::string meaning(const value_type& v) const;
};

// The kind of each field codec above, so that tools can treat a described
// field by what it is (`sabus record` masks positions, AGC and the display by
// kind: vectors/README.md "Recorded regression vectors"). One row per codec.
#define SABUS_FIELD_CODECS(X)                                                                              \
  X(Text) X(Fill) X(Reserved) X(Digits) X(SignedDigits) X(ZeroPaddedDecimal) X(Position) X(Azimuth)        \
  X(RightDecimal) X(LeftDecimal) X(Bits) X(TrackByte) X(Choice) X(AnyChar) X(SlotIndex) X(PresetIndex)    \
  X(EnumByte) X(NavAngle) X(Version) X(Opaque)

enum class Kind : std::uint8_t {
  kHeader,       // start, address, command, ETX, check byte, the offline 'F'
  kUndescribed,  // bytes no layout describes (a frame of the wrong length)
#define SABUS_X(T) k##T,
  SABUS_FIELD_CODECS(SABUS_X)
#undef SABUS_X
};
std::string_view to_string(Kind kind);  // "header", "undescribed", "Position", ...

template <class C>
struct KindOf;
#define SABUS_X(T)                                 \
  template <>                                      \
  struct KindOf<T> {                               \
    static constexpr Kind value = Kind::k##T;      \
  };
SABUS_FIELD_CODECS(SABUS_X)
#undef SABUS_X

// Shared formatting: 1234 with 1 decimal -> "123.4"; -5 -> "-0.5".
std::string format_scaled(std::int64_t value, int decimals);

}  // namespace sabus::fields
