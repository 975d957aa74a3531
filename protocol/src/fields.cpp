// The field codecs of text, fixed bytes, characters, indices and binary
// bytes (fields.hpp); the numbers and positions are fields_numeric.cpp.
#include "sabus/protocol/fields.hpp"

#include <cstdio>

#include "fields_internal.hpp"

namespace sabus::fields {

using namespace internal;

std::string_view to_string(Kind kind) {
  switch (kind) {
    case Kind::kHeader: return "header";
    case Kind::kUndescribed: return "undescribed";
#define SABUS_X(T) \
  case Kind::k##T: return #T;
      SABUS_FIELD_CODECS(SABUS_X)
#undef SABUS_X
  }
  return "?";
}

// ---- Text -----------------------------------------------------------------
void Text::encode(const value_type& v, Out out) const { put_justified(v, out, false, ' '); }
FieldStatus Text::decode(ByteView in, value_type& v) const {
  for (std::size_t i = 0; i < in.size(); ++i)
    if (!is_printable(in[i])) return error_at(i, "a printable character 0x20-0x7f");
  std::size_t end = in.size();
  while (end > 0 && in[end - 1] == ' ') --end;
  v.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(end));
  return std::nullopt;
}
std::string Text::meaning(const value_type& v) const { return v.empty() ? "(blank)" : "\"" + v + "\""; }

// ---- Fill -----------------------------------------------------------------
void Fill::encode(const value_type&, Out out) const {
  for (auto& b : out) b = ch;
}
FieldStatus Fill::decode(ByteView in, value_type&) const {
  for (std::size_t i = 0; i < in.size(); ++i)
    if (in[i] != ch) return error_at(i, describe_byte(ch));
  return std::nullopt;
}
std::string Fill::meaning(const value_type&) const {
  return ch == ' ' ? "blanks" : std::to_string(width) + " x " + describe_byte(ch);
}

// ---- Reserved -------------------------------------------------------------
void Reserved::encode(const value_type& v, Out out) const {
  if (v.empty()) {
    for (auto& b : out) b = ch;
  } else {
    put_justified(v, out, false, ch);
  }
}
FieldStatus Reserved::decode(ByteView in, value_type& v) const {
  bool as_documented = true;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (!is_printable(in[i])) return error_at(i, "a printable character 0x20-0x7f");
    as_documented &= in[i] == ch;
  }
  if (as_documented) v.clear();
  else v.assign(in.begin(), in.end());
  return std::nullopt;
}
std::string Reserved::meaning(const value_type& v) const {
  if (v.empty()) return "reserved";
  return "reserved, documented as " + describe_byte(ch) + ": \"" + v + "\"";
}

// ---- Digits ---------------------------------------------------------------
void Digits::encode(const value_type& v, Out out) const {
  std::uint32_t x = v;
  for (std::size_t i = out.size(); i-- > 0;) {
    out[i] = static_cast<std::uint8_t>('0' + x % 10);
    x /= 10;
  }
}
FieldStatus Digits::decode(ByteView in, value_type& v) const {
  std::size_t first = 0, last = in.size();
  if (blank_padded) {
    while (first < last && in[first] == ' ') ++first;
    while (last > first && in[last - 1] == ' ') --last;
    if (first == last) return error_at(0, "a digit '0'-'9' (a count padded with zeros or blanks)");
  }
  std::uint32_t x = 0;
  for (std::size_t i = first; i < last; ++i) {
    if (!is_digit(in[i])) return error_at(i, blank_padded ? "a digit '0'-'9' (a count padded with zeros or blanks)" : "a digit '0'-'9'");
    x = x * 10 + (in[i] - '0');
  }
  v = x;
  return std::nullopt;
}
std::string Digits::meaning(const value_type& v) const { return std::to_string(v); }

// ---- Bits -----------------------------------------------------------------
void Bits::encode(const value_type& v, Out out) const { out[0] = static_cast<std::uint8_t>(base | (v & mask)); }
FieldStatus Bits::decode(ByteView in, value_type& v) const {
  if ((in[0] & static_cast<std::uint8_t>(~mask)) != base) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "0x%02x | bits in 0x%02x (the bits outside 0x%02x must be 0x%02x)", base, mask,
                  mask, base);
    return error_at(0, buf);
  }
  v = in[0] & mask;
  return std::nullopt;
}
std::string Bits::meaning(const value_type& v) const {
  if (describe) return describe(v);
  return std::to_string(v);
}

// ---- TrackByte ------------------------------------------------------------
void TrackByte::encode(const value_type& v, Out out) const { out[0] = v; }
FieldStatus TrackByte::decode(ByteView in, value_type& v) const {
  if (in[0] & 0x80) return error_at(0, "bit 7 clear (BBB<<4 | SSSS)");
  if ((in[0] >> 4) == 0) return error_at(0, "BBB not 000 (§3.2 byte 40: \"not used to avoid generating a message delimiter\")");
  v = in[0];
  return std::nullopt;
}
namespace {
// §3.2 byte 40 SSSS, by code; "(… not defined)" where the list has a gap.
constexpr std::string_view kTrackSubmodes[] = {"track mode not active",
                                              "track setup submode active",
                                              "track auto mode entry",
                                              "step track submode active",
                                              "track auto search submode active",
                                              "program track submode active",
                                              "track manual search submode active",
                                              "(0111 not defined)",
                                              "track jammed error",
                                              "track limit error",
                                              "track drive error",
                                              "track peak limit error",
                                              "track geo position error",
                                              "track system error",
                                              "track checksum error",
                                              "(1111 not defined)"};
}  // namespace
std::string TrackByte::meaning(const value_type& v) const {
  static constexpr std::string_view kBands[] = {"(000 not used)", "X band", "Ka band", "S band",
                                                "C band",         "Ku band", "band not defined", "L band"};
  return std::string(kBands[(v >> 4) & 7]) + ", " + std::string(kTrackSubmodes[v & 0xF]);
}
bool TrackByte::names_active_submode(value_type v) {
  return (v & 0xF) != 0 && !kTrackSubmodes[v & 0xF].ends_with("not defined)");
}

// ---- Choice ---------------------------------------------------------------
void Choice::encode(const value_type& v, Out out) const { out[0] = static_cast<std::uint8_t>(v); }
FieldStatus Choice::decode(ByteView in, value_type& v) const {
  for (const auto& item : items)
    if (static_cast<std::uint8_t>(item.ch) == in[0]) {
      v = item.ch;
      return std::nullopt;
    }
  return error_at(0, "one of " + allowed());
}
std::string Choice::meaning(const value_type& v) const {
  for (const auto& item : items)
    if (item.ch == v) return std::string(item.meaning);
  return "?";
}
std::string Choice::allowed() const {
  std::string s;
  for (const auto& item : items) {
    if (!s.empty()) s += ", ";
    s += "'";
    s += item.ch;
    s += "'";
  }
  return s;
}

// ---- AnyChar --------------------------------------------------------------
void AnyChar::encode(const value_type& v, Out out) const { out[0] = static_cast<std::uint8_t>(v); }
FieldStatus AnyChar::decode(ByteView in, value_type& v) const {
  if (!is_printable(in[0])) return error_at(0, "a printable character 0x20-0x7f");
  v = static_cast<char>(in[0]);
  return std::nullopt;
}
std::string AnyChar::meaning(const value_type& v) const {
  if (describe) return describe(v);
  return describe_byte(static_cast<std::uint8_t>(v));
}

// ---- SlotIndex ------------------------------------------------------------
void SlotIndex::encode(const value_type& v, Out out) const {
  if (!v) {
    out[0] = out[1] = kEmptySlot;
    return;
  }
  Digits{2}.encode(*v, out);
}
FieldStatus SlotIndex::decode(ByteView in, value_type& v) const {
  if (in[0] == kEmptySlot || in[1] == kEmptySlot) {
    if (in[0] != in[1]) return error_at(in[0] == kEmptySlot ? 1 : 0, "0x7f in both index bytes (empty slot)");
    v.reset();
    return std::nullopt;
  }
  std::uint32_t x = 0;
  if (auto e = Digits{2}.decode(in, x)) {
    e->expected += " or 0x7f 0x7f (empty slot)";
    return e;
  }
  v = static_cast<std::uint8_t>(x);
  return std::nullopt;
}
std::string SlotIndex::meaning(const value_type& v) const {
  return v ? "index " + std::to_string(*v) : "no data stored for this index (0x7f 0x7f)";
}

// ---- PresetIndex ----------------------------------------------------------
void PresetIndex::encode(const value_type& v, Out out) const {
  out[0] = static_cast<std::uint8_t>(0x40 | (v.preset ? 0x10 : 0) | (v.index / 10));
  out[1] = static_cast<std::uint8_t>('0' + v.index % 10);
}
FieldStatus PresetIndex::decode(ByteView in, value_type& v) const {
  if ((in[0] & 0xE0) != 0x40 || (in[0] & 0x0F) > 9)
    return error_at(0, "0x40 | A<<4 | tens digit (READING-NOTES 22, 29)");
  if (!is_digit(in[1])) return error_at(1, "the ones digit '0'-'9'");
  v.preset = (in[0] & 0x10) != 0;
  v.index = static_cast<std::uint8_t>((in[0] & 0x0F) * 10 + (in[1] - '0'));
  return std::nullopt;
}
std::string PresetIndex::meaning(const value_type& v) const {
  return v.preset ? "preset satellite " + std::to_string(v.index) : "satellite data in this command (A=0)";
}

// ---- EnumByte -------------------------------------------------------------
void EnumByte::encode(const value_type& v, Out out) const { out[0] = v; }
FieldStatus EnumByte::decode(ByteView in, value_type& v) const {
  if (in[0] < 0x20 || in[0] > 0x7F) return error_at(0, "an enumeration value 0x20-0x7f (§3.17)");
  v = in[0];
  return std::nullopt;
}
std::string EnumByte::meaning(const value_type& v) const { return std::to_string(v); }

// ---- Version --------------------------------------------------------------
void Version::encode(const value_type& v, Out out) const { put_justified(v, out, false, ' '); }
FieldStatus Version::decode(ByteView in, value_type& v) const {
  if (!is_digit(in[0])) return error_at(0, "a digit (\"A.BC\")");
  if (in[1] != '.') return error_at(1, "'.' (\"A.BC\")");
  if (!is_digit(in[2])) return error_at(2, "a digit (\"A.BC\")");
  if (!is_digit(in[3])) return error_at(3, "a digit (\"A.BC\")");
  v.assign(in.begin(), in.end());
  return std::nullopt;
}
std::string Version::meaning(const value_type& v) const { return "software " + v; }

// ---- Opaque ---------------------------------------------------------------
void Opaque::encode(const value_type& v, Out out) const { put_justified(v, out, false, ' '); }
FieldStatus Opaque::decode(ByteView in, value_type& v) const {
  for (std::size_t i = 0; i < in.size(); ++i)
    if (!is_printable(in[i])) return error_at(i, "a printable character 0x20-0x7f");
  v.assign(in.begin(), in.end());
  return std::nullopt;
}
std::string Opaque::meaning(const value_type& v) const {
  return std::to_string(v.size()) + " bytes, layout not specified (TBD)";
}

}  // namespace sabus::fields
