// LRC, parity and whole-frame encode/decode (§1 Message Format, Check Character).
#include <gtest/gtest.h>

#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/frame.hpp"
#include "test_support.hpp"

namespace sabus {
namespace {
using test::hex;

TEST(Lrc, XorOfByte0ThroughEtx) {
  // READING-NOTES 7: at address 50 the status poll's check byte is 0x02.
  EXPECT_EQ(lrc(hex("02 32 31 03")), 0x02);
  EXPECT_EQ(lrc(hex("06 32 30 33 4b 31 2e 35 39 03")), 0x06 ^ 0x32 ^ 0x30 ^ 0x33 ^ 0x4b ^ 0x31 ^ 0x2e ^ 0x35 ^ 0x39 ^ 0x03);
  EXPECT_EQ(lrc(hex("02 32 31 03"), LrcRule::kFromAddress), 0x32 ^ 0x31 ^ 0x03);
}

TEST(Parity, EvenParityInBit7) {
  EXPECT_EQ(with_even_parity(0x02), 0x82);  // one bit set -> parity bit set
  EXPECT_EQ(with_even_parity(0x03), 0x03);
  EXPECT_EQ(with_even_parity(0x31), 0xB1);
  EXPECT_EQ(with_even_parity(0x33), 0x33);
  EXPECT_EQ(with_even_parity(0x7F), 0xFF);
  EXPECT_TRUE(has_even_parity(0x82));
  EXPECT_FALSE(has_even_parity(0x02));
  EXPECT_EQ(add_even_parity(hex("02 32 31 03 02")), hex("82 b2 b1 03 82"));
}

TEST(Frame, EncodeStatusPoll) {
  EXPECT_EQ(encode_frame({FrameKind::kCommand, '2', 0x31, {}}), hex("02 32 31 03 02"));
}

TEST(Frame, OfflineAndNakFormats) {
  // §3 Online/Offline Reply: ACK A CC 'F' ETX LRC.
  Bytes off = encode_frame(offline_reply('2', 0x32));
  EXPECT_EQ(off, test::concat({hex("06 32 32 46 03"), Bytes{static_cast<std::uint8_t>(0x06 ^ 0x32 ^ 0x32 ^ 0x46 ^ 0x03)}}));
  EXPECT_TRUE(is_offline_reply(decode_frame(off).value()));
  // §3 NAK Reply: NAK A CC ETX LRC.
  Bytes nak = encode_frame(nak_reply('2', 0x3A));
  EXPECT_EQ(nak, test::concat({hex("15 32 3a 03"), Bytes{static_cast<std::uint8_t>(0x15 ^ 0x32 ^ 0x3a ^ 0x03)}}));
  EXPECT_EQ(nak.size(), kNakReplyLength);
  EXPECT_EQ(off.size(), kOfflineReplyLength);
}

TEST(Frame, DecodeRoundTrip) {
  Frame f{FrameKind::kAck, 'o', 0x30, {'3', 'K', '1', '.', '5', '9'}};
  auto d = decode_frame(encode_frame(f));
  ASSERT_TRUE(d.ok()) << d.error().message();
  EXPECT_EQ(d.value(), f);
}

TEST(Frame, DecodeErrorsNameTheByte) {
  auto e = decode_frame(hex("02 32 31 03 00"));
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().offset, 4u);
  EXPECT_EQ(e.error().field, "check byte");
  EXPECT_NE(e.error().message().find("expected 0x02"), std::string::npos) << e.error().message();

  e = decode_frame(hex("07 32 31 03 07"));
  EXPECT_EQ(e.error().offset, 0u);
  e = decode_frame(hex("02 70 31 03 40"));  // address outside 31h-6Fh
  EXPECT_EQ(e.error().offset, 1u);
  e = decode_frame(hex("02 32 31 05 03 00"));  // control character in a command body
  EXPECT_EQ(e.error().offset, 3u);
  e = decode_frame(hex("02 32 31 41 00"));  // no ETX before the check byte
  EXPECT_EQ(e.error().offset, 3u);
  e = decode_frame(hex("02 32 03"));
  EXPECT_EQ(e.error().field, "frame");
}

TEST(Frame, ReplyBodyMayCarryControlCharactersOtherThanEtx) {
  // ERRATA E-35: status byte 40 can be 10h-1Fh.
  Frame f{FrameKind::kAck, '2', 0x31, {0x41, 0x15, 0x42}};
  EXPECT_TRUE(decode_frame(encode_frame(f)).ok());
  Frame c{FrameKind::kCommand, '2', 0x31, {0x41, 0x15, 0x42}};
  EXPECT_FALSE(decode_frame(encode_frame(c)).ok());
}

TEST(Address, DecimalCharacterOrHex) {
  // READING-NOTES 4: the decimal setting and the address character.
  EXPECT_EQ(parse_address("50").value(), 0x32);
  EXPECT_EQ(parse_address("2").value(), 0x32);
  EXPECT_EQ(parse_address("0x32").value(), 0x32);
  EXPECT_EQ(parse_address("49").value(), 0x31);
  EXPECT_EQ(parse_address("111").value(), 0x6F);
  EXPECT_FALSE(parse_address("48").ok());
  EXPECT_FALSE(parse_address("112").ok());
  EXPECT_FALSE(parse_address("p").ok());
  EXPECT_FALSE(parse_address("").ok());
  EXPECT_FALSE(parse_address("5x").ok());
}

TEST(Hex, ParsesCommonSpellings) {
  EXPECT_EQ(parse_hex("0232310302").value(), hex("02 32 31 03 02"));
  EXPECT_EQ(parse_hex("0x02 0x32").value(), hex("02 32"));
  EXPECT_EQ(parse_hex("02:32:31").value(), hex("02 32 31"));
  EXPECT_FALSE(parse_hex("023").ok());
  EXPECT_FALSE(parse_hex("0g").ok());
  EXPECT_EQ(to_hex(hex("02 ab")), "02 ab");
}

TEST(Frame, LastFrameStartIsTheLastStartByteBeforeAnAddress) {
  EXPECT_EQ(last_frame_start(hex("02 32 31 03 02")), 0u) << "a check byte of 02h starts nothing";
  EXPECT_EQ(last_frame_start(hex("02 02 32 31 03 00")), 1u) << "STX STX: the second one (READING-NOTES 7)";
  EXPECT_EQ(last_frame_start(hex("02 32 31 03 02 15 33 30 03 00")), 5u) << "an ACK or NAK starts a reply frame";
  EXPECT_EQ(last_frame_start(hex("02 20 31 03 11")), std::nullopt) << "20h is no address";
  EXPECT_EQ(last_frame_start(hex("")), std::nullopt);
}

}  // namespace
}  // namespace sabus
