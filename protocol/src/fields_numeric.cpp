// The field codecs of numbers and positions (fields.hpp): signed digits,
// zero-padded and justified decimals, positions with their '*' error fields,
// the azimuth or heading of §3.2, navigation angles.
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "fields_internal.hpp"
#include "sabus/protocol/fields.hpp"

namespace sabus::fields {

using namespace internal;

namespace {

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

// Writes an optional number's field all blanks when it has no value (§3.2,
// §3.22: a field without data is spaces); returns whether it did.
bool blank_when_empty(const std::optional<std::int32_t>& v, Out out) {
  if (v) return false;
  std::fill(out.begin(), out.end(), std::uint8_t{' '});
  return true;
}

std::string decimal_meaning(const std::optional<std::int32_t>& v, int decimals) {
  return v ? format_scaled(*v, decimals) : "(blank)";
}

}  // namespace

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
  if (blank_when_empty(v, out)) return;
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
  if (blank_padded) {
    // E-33: blanks on either side of a number with its decimals ("  0.5").
    std::size_t first = 0, last = in.size();
    while (first < last && in[first] == ' ') ++first;
    while (last > first && in[last - 1] == ' ') --last;
    std::int32_t x = 0;
    if (auto e = parse_decimal(in, first, last, decimals, true, x)) {
      e->expected += " (\"ddd.d\", padded with zeros or blanks)";
      return e;
    }
    if (x < 0) return error_at(first, "a digit (a heading has no sign)");
    v = x;
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
  // Blanks before (right-justified) or after (left-justified) the number,
  // or neither (zero-padded): ERRATA E-33.
  std::size_t first = 0, last = in.size();
  while (first < last && in[first] == ' ') ++first;
  while (last > first && in[last - 1] == ' ') --last;
  if (first == last) return error_at(0, "a position \"-180.0\"..\"180.0\"");
  std::int32_t x = 0;
  if (auto e = parse_decimal(in, first, last, 1, true, x)) {
    e->expected += " (a position with one decimal, padded with blanks or zeros)";
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
  if (blank_when_empty(v, out)) return;
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
  return decimal_meaning(v, decimals);
}

// ---- LeftDecimal ----------------------------------------------------------
void LeftDecimal::encode(const value_type& v, Out out) const {
  if (blank_when_empty(v, out)) return;
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
  return decimal_meaning(v, decimals);
}

// ---- NavAngle -------------------------------------------------------------
void NavAngle::encode(const value_type& v, Out out) const {
  if (blank_when_empty(v, out)) return;
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

}  // namespace sabus::fields
