// The field types, on the spec's own example values.
#include <gtest/gtest.h>

#include "sabus/protocol/fields.hpp"

namespace sabus::fields {
namespace {

ByteView view(std::string_view s) { return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}; }

template <class C>
std::string encode(const C& c, const typename C::value_type& v, std::size_t width) {
  Bytes out(width);
  c.encode(v, out);
  return std::string(out.begin(), out.end());
}

template <class C>
typename C::value_type decode_ok(const C& c, std::string_view s) {
  typename C::value_type v{};
  auto e = c.decode(view(s), v);
  EXPECT_FALSE(e.has_value()) << "\"" << s << "\": " << (e ? e->expected : "");
  return v;
}

template <class C>
FieldError decode_err(const C& c, std::string_view s) {
  typename C::value_type v{};
  auto e = c.decode(view(s), v);
  EXPECT_TRUE(e.has_value()) << "\"" << s << "\" should not decode";
  return e.value_or(FieldError{});
}

TEST(Fields, SignedDigitsAsInAutoMove2A) {
  // §3.3 form 2A: '-152500456' = az -152.5, el 45.6.
  SignedDigits tenths{5, 1};
  EXPECT_EQ(decode_ok(tenths, "-1525"), -1525);
  EXPECT_EQ(decode_ok(tenths, "00456"), 456);
  EXPECT_EQ(encode(tenths, -1525, 5), "-1525");
  EXPECT_EQ(encode(tenths, 456, 5), "00456");
  EXPECT_EQ(encode(tenths, -123, 5), "-0123");  // ERRATA E-45
  EXPECT_EQ(tenths.meaning(-1525), "-152.5 deg");
  EXPECT_EQ(decode_err(tenths, " 1525").index, 0u);
  EXPECT_EQ(decode_err(tenths, "+1525").index, 0u);
  EXPECT_EQ(decode_err(tenths, "15-25").index, 2u);
  // §3.3 form 2C: '-12345' with 'A' = -123.45.
  SignedDigits hundredths{6, 2};
  EXPECT_EQ(decode_ok(hundredths, "-12345"), -12345);
  EXPECT_EQ(hundredths.meaning(-12345), "-123.45 deg");
  EXPECT_EQ(hundredths.meaning(-5), "-0.05 deg");
}

TEST(Fields, Digits) {
  // §3.3 form 2B: '1105012152' = counts 11050 and 12152.
  EXPECT_EQ(decode_ok(Digits{5}, "11050"), 11050u);
  EXPECT_EQ(decode_ok(Digits{5}, "12152"), 12152u);
  EXPECT_EQ(encode(Digits{2}, 7, 2), "07");
  EXPECT_EQ(decode_err(Digits{2}, "1 ").index, 1u);
  // A reply's count (§3.16, ERRATA E-33): zeros or blanks pad it, on either
  // side; a blank inside it, a sign or no digit at all does not read.
  const Digits count{5, true};
  EXPECT_EQ(decode_ok(count, "00123"), 123u);
  EXPECT_EQ(decode_ok(count, "  123"), 123u);
  EXPECT_EQ(decode_ok(count, "123  "), 123u);
  EXPECT_EQ(encode(count, 123, 5), "00123");
  EXPECT_EQ(decode_err(count, "1 23 ").index, 1u);
  decode_err(count, " -123");
  decode_err(count, "     ");
}

TEST(Fields, HeadingZeroPaddedOrBlankPadded) {
  // §3.22 bytes 30-34 "0.0 - 359.9"; ERRATA E-33: zeros or blanks pad it.
  const ZeroPaddedDecimal strict{5, 1, true}, either{5, 1, true, true};
  EXPECT_EQ(decode_ok(strict, "001.5"), 15);
  decode_err(strict, "  1.5");
  EXPECT_EQ(decode_ok(either, "001.5"), 15);
  EXPECT_EQ(decode_ok(either, "  1.5"), 15);
  EXPECT_EQ(decode_ok(either, "1.5  "), 15);
  EXPECT_FALSE(decode_ok(either, "     ").has_value()) << "blank: no heading data";
  EXPECT_EQ(encode(either, 15, 5), "001.5");
  decode_err(either, " -1.5");
  decode_err(either, "  1 5");
}

TEST(Fields, TextIsLeftJustifiedBlankPadded) {
  // §3.3 form 1: 'SBS 6     '.
  EXPECT_EQ(decode_ok(Text{10}, "SBS 6     "), "SBS 6");
  EXPECT_EQ(encode(Text{10}, "SBS 6", 10), "SBS 6     ");
  EXPECT_EQ(decode_ok(Text{10}, "          "), "");
  EXPECT_EQ(decode_ok(Text{10}, "  USER    "), "  USER");  // §3.6: leading blanks are kept
  EXPECT_EQ(decode_err(Text{3}, std::string_view("A\x02" "B", 3)).index, 1u);
}

TEST(Fields, PositionRightJustifiedWithStarsForAnError) {
  Position p;
  EXPECT_EQ(decode_ok(p, "-180.0"), -1800);
  EXPECT_EQ(decode_ok(p, "  45.6"), 456);
  EXPECT_EQ(decode_ok(p, "   0.0"), 0);
  EXPECT_EQ(encode(p, 456, 6), "  45.6");
  EXPECT_EQ(encode(p, -1800, 6), "-180.0");
  // ERRATA E-42: 6 '*', or 5 '*' and a blank.
  EXPECT_FALSE(decode_ok(p, "******").has_value());
  EXPECT_FALSE(decode_ok(p, "***** ").has_value());
  EXPECT_FALSE(decode_ok(p, " *****").has_value());
  EXPECT_EQ(encode(p, std::nullopt, 6), "******");
  // ERRATA E-33: a left-justified or zero-padded position reads the same;
  // a blank inside the number or a missing decimal does not read.
  EXPECT_EQ(decode_ok(p, "45.6  "), 456);
  EXPECT_EQ(decode_ok(p, "-12.3 "), -123);
  EXPECT_EQ(decode_ok(p, "0045.6"), 456);
  EXPECT_EQ(decode_ok(p, "-012.3"), -123);
  decode_err(p, " 4 5.6");
  decode_err(p, "- 12.3");
  decode_err(p, "      ");
  decode_err(p, "  4a.6");
  decode_err(p, "   456");   // no decimal point
  decode_err(p, "  ***4");
}

TEST(Fields, AzimuthPositionOrFluxgateHeading) {
  Azimuth az;
  auto v = decode_ok(az, "359.9T");
  EXPECT_EQ(v.kind, AzimuthReading::Kind::kHeading);
  EXPECT_EQ(v.tenths, 3599);
  EXPECT_EQ(v.reference, 'T');
  EXPECT_EQ(az.meaning(v), "heading 359.9 deg true");
  v = decode_ok(az, "  0.0M");
  EXPECT_EQ(v.reference, 'M');
  v = decode_ok(az, "-152.5");
  EXPECT_EQ(v.kind, AzimuthReading::Kind::kPosition);
  EXPECT_EQ(v.tenths, -1525);
  EXPECT_EQ(decode_ok(az, "******").kind, AzimuthReading::Kind::kError);
  EXPECT_EQ(encode(az, AzimuthReading{AzimuthReading::Kind::kHeading, 12, 'M'}, 6), "  1.2M");
}

TEST(Fields, BitsCheckTheHighBits) {
  Bits status{0x40, 0x1F, nullptr};
  std::string ok = "\x45";
  EXPECT_EQ(decode_ok(status, ok), 0x05);
  std::string wrong_base = "\x35";  // a wrong nibble base: 0x30 | bits
  EXPECT_NE(decode_err(status, wrong_base).expected.find("0x40"), std::string::npos);
  EXPECT_EQ(encode(status, 0x15, 1), "\x55");
}

TEST(Fields, TrackByteNeverHasBbbZero) {
  TrackByte t;
  EXPECT_EQ(decode_ok(t, "\x53"), 0x53);
  EXPECT_EQ(t.meaning(0x53), "Ku band, step track submode active");
  decode_err(t, std::string_view("\x03", 1));
  decode_err(t, "\x83");
}

// §3.2 byte 40 SSSS: 0001-0110 and 1000-1110 name a submode of an active
// TRACK; 0000 is "track mode not active", 0111 and 1111 are not listed. The
// band BBB does not matter.
TEST(Fields, TrackByteNamesAnActiveSubmodeForTheListedCodesButZero) {
  for (std::uint8_t ssss = 0; ssss < 16; ++ssss) {
    const bool listed = ssss != 0 && ssss != 0b0111 && ssss != 0b1111;
    EXPECT_EQ(TrackByte::names_active_submode(static_cast<std::uint8_t>(0x40 | ssss)), listed) << int(ssss);
    EXPECT_EQ(TrackByte::names_active_submode(static_cast<std::uint8_t>(0x10 | ssss)), listed) << int(ssss);
  }
}

TEST(Fields, LeftDecimalAcceptsAMissingDecimalDigit) {
  LeftDecimal lon{6, 1};
  EXPECT_EQ(decode_ok(lon, "-179.9"), -1799);
  EXPECT_EQ(decode_ok(lon, "45    "), 450);  // ERRATA E-41
  EXPECT_EQ(decode_ok(lon, "45.0  "), 450);
  EXPECT_EQ(encode(lon, 450, 6), "45.0  ");
  // Found by fuzz_reply_decoders: "07655" in a 5-byte pol offset is 7655.0,
  // which is written back without its decimal digit so that it fits.
  LeftDecimal pol{5, 1};
  EXPECT_EQ(decode_ok(pol, "07655"), 76550);
  EXPECT_EQ(encode(pol, 76550, 5), "7655 ");
  EXPECT_EQ(decode_ok(pol, "7655 "), 76550);
  decode_err(lon, "  45.0");  // right-justified
  decode_err(lon, "      ");
  EXPECT_FALSE(decode_ok(LeftDecimal{5, 1, true}, "     ").has_value());
  EXPECT_EQ(decode_ok(LeftDecimal{2, 0}, "19"), 19);
  decode_err(LeftDecimal{2, 0}, "1.");
}

TEST(Fields, ZeroPaddedHeading) {
  ZeroPaddedDecimal h{5, 1};
  EXPECT_EQ(decode_ok(h, "123.4"), 1234);
  EXPECT_EQ(decode_ok(h, "000.0"), 0);
  EXPECT_EQ(encode(h, 59, 5), "005.9");
  decode_err(h, " 12.3");
  decode_err(h, "1234.");
}

TEST(Fields, SlotIndexEmptyMarker) {
  SlotIndex s;
  EXPECT_EQ(decode_ok(s, "20"), 20);
  EXPECT_FALSE(decode_ok(s, "\x7f\x7f").has_value());
  decode_err(s, "\x7f" "1");
  EXPECT_EQ(encode(s, std::nullopt, 2), "\x7f\x7f");
}

TEST(Fields, PresetIndex) {
  PresetIndex p;
  auto v = decode_ok(p, "\x51" "9");  // A=1, tens 1 -> index 19
  EXPECT_TRUE(v.preset);
  EXPECT_EQ(v.index, 19);
  v = decode_ok(p, "\x42" "0");  // READING-NOTES 29: tens 2 for index 20
  EXPECT_FALSE(v.preset);
  EXPECT_EQ(v.index, 20);
  EXPECT_EQ(encode(p, PresetRef{true, 20}, 2), "\x52" "0");
  decode_err(p, "\x31" "0");
}

TEST(Fields, NavigationAngles) {
  NavAngle lat{6}, lon{7};
  EXPECT_EQ(decode_ok(lat, "12.34N"), 12 * 60 + 34);
  EXPECT_EQ(decode_ok(lat, "12.34S"), -(12 * 60 + 34));
  EXPECT_EQ(decode_ok(lon, "123.45W"), -(123 * 60 + 45));
  EXPECT_EQ(encode(lon, 123 * 60 + 45, 7), "123.45E");
  EXPECT_FALSE(decode_ok(lat, "      ").has_value());
  decode_err(lat, "12.34X");
  decode_err(lat, "12.64N");
  EXPECT_EQ(lat.meaning(-(12 * 60 + 34)), "12 deg 34 min S");
}

TEST(Fields, NavigationSignedDegreesMinutes) {
  // §3.23: 01234 = 12 deg 34 min N, -1234 = 12 deg 34 min S, 00123 = 1 deg 23 min.
  SignedDigits lat{5, 0, Quantity::kLatitude};
  EXPECT_EQ(lat.meaning(decode_ok(lat, "01234")), "12 deg 34 min N");
  EXPECT_EQ(lat.meaning(decode_ok(lat, "-1234")), "12 deg 34 min S");
  EXPECT_EQ(lat.meaning(decode_ok(lat, "00123")), "1 deg 23 min N");
  SignedDigits lon{6, 0, Quantity::kLongitude};
  EXPECT_EQ(lon.meaning(decode_ok(lon, "-01234")), "12 deg 34 min W");
}

TEST(Fields, VersionAndReserved) {
  EXPECT_EQ(decode_ok(Version{}, "1.59"), "1.59");
  decode_err(Version{}, "159 ");
  Reserved r{5, 0x40};
  EXPECT_EQ(decode_ok(r, "@@@@@"), "");
  EXPECT_EQ(decode_ok(r, "@@A@@"), "@@A@@");
  EXPECT_EQ(encode(r, "", 5), "@@@@@");
  EXPECT_NE(r.meaning("@@A@@").find("documented as 0x40"), std::string::npos);
}

TEST(Fields, FormatScaled) {
  EXPECT_EQ(format_scaled(0, 1), "0.0");
  EXPECT_EQ(format_scaled(-5, 1), "-0.5");
  EXPECT_EQ(format_scaled(12345, 2), "123.45");
  EXPECT_EQ(format_scaled(7, 0), "7");
}

}  // namespace
}  // namespace sabus::fields
