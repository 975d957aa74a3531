// describe_frame: every byte of a frame as a field with its meaning.
#include <gtest/gtest.h>

#include "sabus/protocol/codec.hpp"
#include "test_support.hpp"

namespace sabus {
namespace {

const FieldDescription* field(const FrameDescription& d, std::string_view name) {
  for (const auto& f : d.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// The fields cover every byte of the frame exactly once, in order.
void expect_covers(const FrameDescription& d, std::size_t size) {
  std::size_t next = 0;
  for (const auto& f : d.fields) {
    EXPECT_EQ(f.first, next) << f.name;
    next = f.last + 1;
  }
  EXPECT_EQ(next, size);
}

TEST(Describe, StatusReplyFieldByField) {
  StatusReply r;
  r.status.azimuth = {fields::AzimuthReading::Kind::kPosition, -1525, 0};
  r.status.az_status = 0x05;  // slow, cw automatic movement
  r.status.alarm_code = 22;
  Bytes bytes = encode_reply(r, '2', 0x31).value();
  FrameDescription d = describe_frame(bytes);
  EXPECT_FALSE(d.error.has_value());
  expect_covers(d, 52);
  const auto* az = field(d, "az status");
  ASSERT_NE(az, nullptr);
  EXPECT_EQ(az->first, 36u);
  EXPECT_EQ(az->raw, "0x45");
  EXPECT_EQ(az->meaning, "slow, cw automatic movement in progress");
  EXPECT_EQ(az->line().substr(0, 6), "byte 3");
  EXPECT_NE(az->line().find("az status"), std::string::npos);
  EXPECT_EQ(field(d, "azimuth")->meaning, "-152.5 deg");
  EXPECT_EQ(field(d, "azimuth")->first, 14u);
  EXPECT_EQ(field(d, "azimuth")->last, 19u);
  EXPECT_EQ(field(d, "alarm code")->meaning, "polarization jammed");
  EXPECT_EQ(field(d, "check byte")->meaning, "LRC ok");
  EXPECT_NE(d.summary.find("status reply"), std::string::npos);
}

TEST(Describe, ExtendedStatusNamesTheStateOfTheCurrentMode) {
  ExtendedStatusReply x;
  x.mode = 0x28;   // TRACK_MODE
  x.state = 0x27;  // TRACK_STEP_PEAKING
  Bytes bytes = encode_reply(x, '2', 0x40).value();
  FrameDescription d = describe_frame(bytes);
  expect_covers(d, 58);
  EXPECT_EQ(field(d, "current mode")->meaning, "TRACK_MODE");
  EXPECT_EQ(field(d, "current state")->meaning, "TRACK_STEP_PEAKING");
}

TEST(Describe, BadFieldIsMarkedAndTheErrorNamesItsByte) {
  Bytes bytes = encode_reply(StatusReply{}, '2', 0x31).value();
  bytes[37] = 0x30;
  bytes[51] = lrc(ByteView(bytes).first(51));
  FrameDescription d = describe_frame(bytes);
  ASSERT_TRUE(d.error.has_value());
  EXPECT_EQ(d.error->offset, 37u);
  const auto* el = field(d, "el status");
  EXPECT_FALSE(el->ok);
  EXPECT_NE(el->line().find("!!"), std::string::npos);
}

TEST(Describe, AutoMoveRequestShowsItsForm) {
  FrameDescription d = describe_frame(test::command('2', 0x32, " -152500456"));
  expect_covers(d, 16);
  EXPECT_EQ(field(d, "azimuth")->meaning, "-152.5 deg");
  EXPECT_EQ(field(d, "elevation")->meaning, "45.6 deg");
  FrameDescription bad = describe_frame(test::command('2', 0x32, "P0050000001"));
  ASSERT_TRUE(bad.error.has_value());
  EXPECT_EQ(bad.error->offset, 13u);
}

TEST(Describe, OfflineNakWrongLengthUnknownAndBadLrc) {
  auto off = describe_frame(encode_frame(offline_reply('2', 0x31)));
  EXPECT_NE(off.summary.find("offline"), std::string::npos);
  EXPECT_FALSE(off.error.has_value());
  expect_covers(off, 6);
  auto nak = describe_frame(encode_frame(nak_reply('2', 0x31)));
  EXPECT_NE(nak.summary.find("NAK"), std::string::npos);
  EXPECT_FALSE(nak.error.has_value());
  auto wrong = describe_frame(test::command('2', 0x31, "X"));
  ASSERT_TRUE(wrong.error.has_value());
  EXPECT_EQ(wrong.error->field, "length");
  expect_covers(wrong, 6);
  auto unknown = describe_frame(test::command('2', 0x5A, "AB"));
  EXPECT_FALSE(field(unknown, "command")->ok);
  auto bad_lrc = describe_frame(test::hex("02 32 31 03 00"));
  ASSERT_TRUE(bad_lrc.error.has_value());
  EXPECT_EQ(bad_lrc.error->offset, 4u);
  EXPECT_FALSE(field(bad_lrc, "check byte")->ok);
}

TEST(Describe, ReplyShorterThanItsFirstFieldStopsCleanly) {
  // Found by fuzz_reply_decoders: a 3Eh reply (length TBD) with no index.
  Bytes bytes = encode_frame({FrameKind::kAck, '2', 0x3E, {}});
  FrameDescription d = describe_frame(bytes);
  ASSERT_TRUE(d.error.has_value());
  EXPECT_EQ(d.error->field, "index");
  expect_covers(d, 5);
  Bytes one = encode_frame({FrameKind::kAck, '2', 0x3E, {'0'}});
  EXPECT_TRUE(describe_frame(one).error.has_value());
  expect_covers(describe_frame(one), 6);
  EXPECT_FALSE(decode_reply(decode_frame(one).value()).ok());
}

}  // namespace
}  // namespace sabus
