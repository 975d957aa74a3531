#include "sabus/protocol/fields.hpp"

#include <cstdio>
#include <cstdlib>

namespace sabus::fields {
namespace {

bool is_digit(std::uint8_t c) { return c >= '0' && c <= '9'; }

FieldError error_at(std::size_t i, std::string expected) { return FieldError{i, std::move(expected)}; }

// Writes `text` right- or left-justified into `out`, padded with `pad`.
void put_justified(std::string_view text, Out out, bool right, std::uint8_t pad) {
  const std::size_t n = std::min(text.size(), out.size());
  const std::size_t lead = right ? out.size() - n : 0;
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = pad;
  for (std::size_t i = 0; i < n; ++i) out[lead + i] = static_cast<std::uint8_t>(text[i]);
}

// Parses "-12.3" / "45" / "0.05" strictly from in[first, last): optional '-',
// digits, and if decimals > 0 an optional '.' followed by exactly `decimals`
// digits (required when `need_fraction`). Returns the scaled value.
FieldStatus parse_decimal(ByteView in, std::size_t first, std::size_t last, int decimals, bool need_fraction,
                          std::int32_t& out) {
  std::size_t i = first;
  bool negative = false;
  if (i < last && in[i] == '-') {
    negative = true;
    ++i;
  }
  std::int64_t v = 0;
  std::size_t int_digits = 0;
  while (i < last && is_digit(in[i])) {
    v = v * 10 + (in[i] - '0');
    ++i;
    ++int_digits;
  }
  if (int_digits == 0) return error_at(i, "a digit");
  int frac = 0;
  if (i < last && in[i] == '.' && decimals > 0) {
    ++i;
    while (i < last && is_digit(in[i]) && frac < decimals) {
      v = v * 10 + (in[i] - '0');
      ++i;
      ++frac;
    }
    if (frac != decimals) return error_at(i, std::to_string(decimals) + " digit(s) after the decimal point");
  } else if (need_fraction && decimals > 0) {
    return error_at(i, "a decimal point");
  }
  for (; frac < decimals; ++frac) v *= 10;
  if (i != last) return error_at(i, "the end of the number");
  out = static_cast<std::int32_t>(negative ? -v : v);
  return std::nullopt;
}

std::string quantity_text(std::int32_t v, int decimals, Quantity q) {
  std::string s = format_scaled(v, decimals);
  switch (q) {
    case Quantity::kDegrees: return s + " deg";
    case Quantity::kCounts: return s + " counts";
    case Quantity::kLatitude:
    case Quantity::kLongitude: {
      // sddmm / sdddmm: degrees and minutes in one integer (§3.23).
      const std::int32_t a = std::abs(v);
      char buf[48];
      const char hemi = q == Quantity::kLatitude ? (v < 0 ? 'S' : 'N') : (v < 0 ? 'W' : 'E');
      std::snprintf(buf, sizeof buf, "%d deg %02d min %c", a / 100, a % 100, hemi);
      return buf;
    }
    case Quantity::kNumber: break;
  }
  return s;
}

}  // namespace

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

std::string format_scaled(std::int64_t value, int decimals) {
  const bool negative = value < 0;
  std::uint64_t a = negative ? static_cast<std::uint64_t>(-value) : static_cast<std::uint64_t>(value);
  std::uint64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  std::string s = std::to_string(a / scale);
  if (decimals > 0) {
    std::string frac = std::to_string(a % scale);
    s.push_back('.');
    s.append(static_cast<std::size_t>(decimals) - frac.size(), '0');
    s.append(frac);
  }
  if (negative) s.insert(s.begin(), '-');
  return s;
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
  std::uint32_t x = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (!is_digit(in[i])) return error_at(i, "a digit '0'-'9'");
    x = x * 10 + (in[i] - '0');
  }
  v = x;
  return std::nullopt;
}
std::string Digits::meaning(const value_type& v) const { return std::to_string(v); }

// ---- SignedDigits ---------------------------------------------------------
void SignedDigits::encode(const value_type& v, Out out) const {
  std::uint32_t a = static_cast<std::uint32_t>(v < 0 ? -static_cast<std::int64_t>(v) : v);
  std::size_t first = 0;
  if (v < 0) {
    out[0] = '-';
    first = 1;
  }
  for (std::size_t i = out.size(); i-- > first;) {
    out[i] = static_cast<std::uint8_t>('0' + a % 10);
    a /= 10;
  }
}
FieldStatus SignedDigits::decode(ByteView in, value_type& v) const {
  std::size_t i = 0;
  bool negative = false;
  if (in[0] == '-') {
    negative = true;
    i = 1;
  }
  std::int64_t x = 0;
  for (; i < in.size(); ++i) {
    if (!is_digit(in[i]))
      return error_at(i, i == 0 ? "'-' or a digit (right-justified, left-padded with zeros)" : "a digit '0'-'9'");
    x = x * 10 + (in[i] - '0');
  }
  v = static_cast<std::int32_t>(negative ? -x : x);
  return std::nullopt;
}
std::string SignedDigits::meaning(const value_type& v) const { return quantity_text(v, decimals, quantity); }

// ---- ZeroPaddedDecimal ------------------------------------------------------
void ZeroPaddedDecimal::encode(const value_type& v, Out out) const {
  if (!v) {
    for (auto& b : out) b = ' ';
    return;
  }
  std::string s = format_scaled(*v, decimals);
  while (s.size() < out.size()) s.insert(s.begin(), '0');
  put_justified(s, out, true, '0');
}
FieldStatus ZeroPaddedDecimal::decode(ByteView in, value_type& v) const {
  bool blank = true;
  for (auto c : in) blank &= c == ' ';
  if (blank && blank_allowed) {
    v.reset();
    return std::nullopt;
  }
  // Exactly width-decimals-1 integer digits, '.', `decimals` digits.
  const std::size_t point = in.size() - static_cast<std::size_t>(decimals) - 1;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (i == point) {
      if (in[i] != '.') return error_at(i, "'.'");
    } else if (!is_digit(in[i])) {
      return error_at(i, "a digit (zero-padded, \"ddd.d\")");
    }
  }
  std::int32_t x = 0;
  if (auto e = parse_decimal(in, 0, in.size(), decimals, true, x)) return e;
  v = x;
  return std::nullopt;
}
std::string ZeroPaddedDecimal::meaning(const value_type& v) const {
  return v ? format_scaled(*v, decimals) + " deg" : "(no data)";
}

// ---- Position -------------------------------------------------------------
void Position::encode(const value_type& v, Out out) const {
  if (!v) {
    for (auto& b : out) b = '*';
    return;
  }
  put_justified(format_scaled(*v, 1), out, true, ' ');
}
FieldStatus Position::decode(ByteView in, value_type& v) const {
  // E-42: 5 or 6 '*' padded with blanks is the A/D error field.
  std::size_t stars = 0, blanks = 0;
  for (auto c : in) {
    stars += c == '*';
    blanks += c == ' ';
  }
  if (stars > 0) {
    if (stars + blanks != in.size() || stars < in.size() - 1)
      return error_at(0, "'*' in every position, or 5 '*' and a blank (A/D error)");
    v.reset();
    return std::nullopt;
  }
  std::size_t first = 0;
  while (first < in.size() && in[first] == ' ') ++first;
  if (first == in.size()) return error_at(0, "a right-justified position \"-180.0\"..\"180.0\"");
  std::int32_t x = 0;
  if (auto e = parse_decimal(in, first, in.size(), 1, true, x)) {
    e->expected += " (right-justified position with one decimal)";
    return e;
  }
  v = x;
  return std::nullopt;
}
std::string Position::meaning(const value_type& v) const {
  return v ? format_scaled(*v, 1) + " deg" : "A/D error or no sensor (******)";
}

// ---- Azimuth --------------------------------------------------------------
void Azimuth::encode(const value_type& v, Out out) const {
  switch (v.kind) {
    case AzimuthReading::Kind::kError:
      for (auto& b : out) b = '*';
      return;
    case AzimuthReading::Kind::kPosition:
      put_justified(format_scaled(v.tenths, 1), out, true, ' ');
      return;
    case AzimuthReading::Kind::kHeading:
      put_justified(format_scaled(v.tenths, 1), out.first(5), true, ' ');
      out[5] = static_cast<std::uint8_t>(v.reference);
      return;
  }
}
FieldStatus Azimuth::decode(ByteView in, value_type& v) const {
  if (in[5] == 'M' || in[5] == 'T') {
    // Fluxgate compass: bytes 14-18 heading, byte 19 'M' or 'T' (§3.2 NOTE).
    std::size_t first = 0;
    while (first < 5 && in[first] == ' ') ++first;
    std::int32_t x = 0;
    if (auto e = parse_decimal(in, first, 5, 1, true, x)) {
      e->expected += " (heading 0.0-359.9 before 'M'/'T')";
      return e;
    }
    v = {AzimuthReading::Kind::kHeading, x, static_cast<char>(in[5])};
    return std::nullopt;
  }
  Position::value_type p;
  if (auto e = Position{}.decode(in, p)) return e;
  v = p ? AzimuthReading{AzimuthReading::Kind::kPosition, *p, 0} : AzimuthReading{AzimuthReading::Kind::kError, 0, 0};
  return std::nullopt;
}
std::string Azimuth::meaning(const value_type& v) const {
  switch (v.kind) {
    case AzimuthReading::Kind::kError: return "A/D error (******)";
    case AzimuthReading::Kind::kPosition: return format_scaled(v.tenths, 1) + " deg";
    case AzimuthReading::Kind::kHeading:
      return "heading " + format_scaled(v.tenths, 1) + (v.reference == 'M' ? " deg magnetic" : " deg true");
  }
  return "";
}

// ---- RightDecimal ---------------------------------------------------------
void RightDecimal::encode(const value_type& v, Out out) const {
  if (!v) {
    for (auto& b : out) b = ' ';
    return;
  }
  put_justified(format_scaled(*v, decimals), out, true, ' ');
}
FieldStatus RightDecimal::decode(ByteView in, value_type& v) const {
  std::size_t first = 0;
  while (first < in.size() && in[first] == ' ') ++first;
  if (first == in.size()) {
    if (!blank_allowed) return error_at(0, "a right-justified number");
    v.reset();
    return std::nullopt;
  }
  // ERRATA E-40: trailing blanks are tolerated on decode.
  std::size_t last = in.size();
  while (last > first && in[last - 1] == ' ') --last;
  std::int32_t x = 0;
  if (auto e = parse_decimal(in, first, last, decimals, true, x)) return e;
  v = x;
  return std::nullopt;
}
std::string RightDecimal::meaning(const value_type& v) const {
  return v ? format_scaled(*v, decimals) : "(blank)";
}

// ---- LeftDecimal ----------------------------------------------------------
void LeftDecimal::encode(const value_type& v, Out out) const {
  if (!v) {
    for (auto& b : out) b = ' ';
    return;
  }
  std::string text = format_scaled(*v, decimals);
  // E-41: a whole value read without its decimal digit ("7655" in 5 bytes)
  // is written back the same way when "7655.0" would not fit.
  std::int64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  if (text.size() > out.size() && *v % scale == 0) text = format_scaled(*v / scale, 0);
  put_justified(text, out, false, ' ');
}
FieldStatus LeftDecimal::decode(ByteView in, value_type& v) const {
  std::size_t last = in.size();
  while (last > 0 && in[last - 1] == ' ') --last;
  if (last == 0) {
    if (!blank_allowed) return error_at(0, "a left-justified number");
    v.reset();
    return std::nullopt;
  }
  std::int32_t x = 0;
  // E-41: "45" and "45.0" are the same value.
  if (auto e = parse_decimal(in, 0, last, decimals, false, x)) {
    e->expected += " (left-justified, blank-padded)";
    return e;
  }
  v = x;
  return std::nullopt;
}
std::string LeftDecimal::meaning(const value_type& v) const {
  return v ? format_scaled(*v, decimals) : "(blank)";
}

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
std::string TrackByte::meaning(const value_type& v) const {
  static constexpr std::string_view kBands[] = {"(000 not used)", "X band", "Ka band", "S band",
                                                "C band",         "Ku band", "band not defined", "L band"};
  static constexpr std::string_view kSub[] = {"track mode not active",
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
  return std::string(kBands[(v >> 4) & 7]) + ", " + std::string(kSub[v & 0xF]);
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

// ---- NavAngle -------------------------------------------------------------
void NavAngle::encode(const value_type& v, Out out) const {
  if (!v) {
    for (auto& b : out) b = ' ';
    return;
  }
  const std::int32_t a = std::abs(*v);
  const bool lat = width == 6;
  char buf[16];
  std::snprintf(buf, sizeof buf, lat ? "%02d.%02d%c" : "%03d.%02d%c", a / 60, a % 60,
                lat ? (*v < 0 ? 'S' : 'N') : (*v < 0 ? 'W' : 'E'));
  put_justified(buf, out, false, ' ');
}
FieldStatus NavAngle::decode(ByteView in, value_type& v) const {
  bool blank = true;
  for (auto c : in) blank &= c == ' ';
  if (blank) {
    v.reset();
    return std::nullopt;
  }
  const bool lat = width == 6;
  const std::size_t deg_digits = lat ? 2 : 3;
  for (std::size_t i = 0; i < deg_digits; ++i)
    if (!is_digit(in[i])) return error_at(i, lat ? "dd.mm(N/S)" : "ddd.mm(E/W)");
  if (in[deg_digits] != '.') return error_at(deg_digits, "'.'");
  for (std::size_t i = deg_digits + 1; i < deg_digits + 3; ++i)
    if (!is_digit(in[i])) return error_at(i, "minutes digits");
  const std::uint8_t h = in[deg_digits + 3];
  const bool ok = lat ? (h == 'N' || h == 'S') : (h == 'E' || h == 'W');
  if (!ok) return error_at(deg_digits + 3, lat ? "'N' or 'S'" : "'E' or 'W'");
  std::int32_t deg = 0;
  for (std::size_t i = 0; i < deg_digits; ++i) deg = deg * 10 + (in[i] - '0');
  const std::int32_t min = (in[deg_digits + 1] - '0') * 10 + (in[deg_digits + 2] - '0');
  if (min > 59) return error_at(deg_digits + 1, "minutes 00-59");
  const std::int32_t total = deg * 60 + min;
  v = (h == 'S' || h == 'W') ? -total : total;
  return std::nullopt;
}
std::string NavAngle::meaning(const value_type& v) const {
  if (!v) return "(no data)";
  const std::int32_t a = std::abs(*v);
  const bool lat = width == 6;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%d deg %02d min %c", a / 60, a % 60, lat ? (*v < 0 ? 'S' : 'N') : (*v < 0 ? 'W' : 'E'));
  return buf;
}

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
