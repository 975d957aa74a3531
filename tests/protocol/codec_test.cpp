// Typed requests and replies, on the manual's own examples.
#include <gtest/gtest.h>

#include "sabus/protocol/codec.hpp"
#include "test_support.hpp"

namespace sabus {
namespace {
using test::command;

template <class T>
T request_of(const Bytes& frame_bytes) {
  auto f = decode_frame(frame_bytes);
  EXPECT_TRUE(f.ok()) << f.error().message();
  auto r = decode_request(f.value());
  EXPECT_TRUE(r.ok()) << r.error().message();
  EXPECT_TRUE(std::holds_alternative<T>(r.value()));
  return std::get<T>(r.value());
}

template <class T>
T form_of_auto_move(std::string_view data) {
  auto am = request_of<AutoMove>(command('2', 0x32, data));
  EXPECT_TRUE(std::holds_alternative<T>(am.form)) << data;
  return std::get<T>(am.form);
}

TEST(AutoMove, Form2AFromTheManual) {
  auto m = form_of_auto_move<AutoMoveAzEl>(" -152500456");
  EXPECT_EQ(m.az, -1525);
  EXPECT_EQ(m.el, 456);
  EXPECT_EQ(encode_request(AutoMove{m}, '2'), command('2', 0x32, " -152500456"));
}

TEST(AutoMove, Form2BFromTheManual) {
  auto m = form_of_auto_move<AutoMoveCounts>("C1105012152");
  EXPECT_EQ(m.az, 11050u);
  EXPECT_EQ(m.el, 12152u);
}

TEST(AutoMove, Form2CFromTheManual) {
  auto m = form_of_auto_move<AutoMoveAxis>("A-12345    ");
  EXPECT_EQ(m.axis, 'A');
  EXPECT_EQ(m.target, -12345);
  auto e = form_of_auto_move<AutoMoveAxis>("E004512    ");
  EXPECT_EQ(e.axis, 'E');
  EXPECT_EQ(e.target, 4512);
}

TEST(AutoMove, Form3FromTheManual) {
  auto m = form_of_auto_move<AutoMovePol>("P0050000000");
  EXPECT_EQ(m.pol, 500);
}

TEST(AutoMove, Form1FromTheManual) {
  auto m = form_of_auto_move<AutoMoveStored>("HSBS 6     ");
  EXPECT_EQ(m.pol, 'H');
  EXPECT_EQ(m.name, "SBS 6");
  EXPECT_EQ(form_of_auto_move<AutoMoveStored>(" SBS 6     ").pol, ' ');
  EXPECT_EQ(form_of(Request{AutoMove{m}}), "1");
}

TEST(AutoMove, MalformedTargetsDoNotDecode) {
  auto decode = [](std::string_view data) { return decode_request(decode_frame(command('2', 0x32, data)).value()); };
  // Form 3: the second sub-field must be '00000'.
  auto e = decode("P0050000001");
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().offset, 13u);
  // Form 2C: bytes 10-13 must be blanks.
  EXPECT_EQ(decode("A-12345X   ").error().offset, 10u);
  // Form 2B: digits only.
  EXPECT_EQ(decode("C11050-2152").error().offset, 9u);
  // An unknown byte 3.
  EXPECT_EQ(decode("Z1105012152").error().offset, 3u);
  // Wrong length for the catalog: 15 bytes.
  auto shortf = decode(" -15250045");
  ASSERT_FALSE(shortf.ok());
  EXPECT_EQ(shortf.error().field, "length");
  EXPECT_NE(shortf.error().message().find("16 bytes"), std::string::npos) << shortf.error().message();
}

TEST(DeviceType, ReplyFromTheManual) {
  // §3.1: "3K" + "A.BC", e.g. 3K1.59; 11 bytes.
  Bytes reply = test::frame_bytes(FrameKind::kAck, '2', 0x30, "3K1.59");
  ASSERT_EQ(reply.size(), 11u);
  auto r = decode_reply(decode_frame(reply).value());
  ASSERT_TRUE(r.ok()) << r.error().message();
  const auto& d = std::get<DeviceTypeReply>(r.value());
  EXPECT_EQ(d.controller, "3K");
  EXPECT_EQ(d.version, "1.59");
  EXPECT_EQ(encode_reply(DeviceTypeReply{"3K", "1.59"}, '2', 0x30).value(), reply);
}

TEST(Replies, OfflineAndNak) {
  auto off = decode_reply(offline_reply('2', 0x3A));
  ASSERT_TRUE(off.ok());
  EXPECT_TRUE(std::holds_alternative<OfflineReply>(off.value()));
  auto nak = decode_reply(nak_reply('2', 0x3A));
  ASSERT_TRUE(nak.ok());
  EXPECT_TRUE(std::holds_alternative<NakReply>(nak.value()));
  Frame bad_nak{FrameKind::kNak, '2', 0x3A, {'X'}};
  EXPECT_FALSE(decode_reply(bad_nak).ok());
  EXPECT_EQ(encode_reply(NakReply{}, '2', 0x3A).value(), encode_frame(nak_reply('2', 0x3A)));
}

StatusBlock example_status() {
  StatusBlock s;
  s.sat_name = "SBS 6";
  s.azimuth = {fields::AzimuthReading::Kind::kPosition, -1525, 0};
  s.elevation = 456;
  s.polarization = std::nullopt;  // no rotating feed
  s.az_limits = 0b100;            // cw limit
  s.pol_equipment = 0b01'1'000;   // single port, pol moves allowed, 'H'
  s.az_status = 0x17;             // fast, remote auto move
  s.el_status = 0x04;             // slow, down movement
  s.alarm_code = 2;               // azimuth jammed
  s.track = 0x53;                 // Ku band, step track
  s.agc = 512;
  s.agc_channel = 1;
  return s;
}

TEST(Status, ReplyLayoutByteByByte) {
  Bytes bytes = encode_reply(StatusReply{example_status(), ""}, '2', 0x31).value();
  ASSERT_EQ(bytes.size(), 52u);
  const std::string s(bytes.begin(), bytes.end());
  EXPECT_EQ(s.substr(3, 10), "SBS 6     ");
  EXPECT_EQ(bytes[13], 0x40);
  EXPECT_EQ(s.substr(14, 6), "-152.5");
  EXPECT_EQ(s.substr(20, 6), "  45.6");
  EXPECT_EQ(s.substr(26, 6), "******");
  EXPECT_EQ(bytes[32], 0x44);
  EXPECT_EQ(bytes[35], 0x58);
  EXPECT_EQ(bytes[36], 0x57);
  EXPECT_EQ(bytes[37], 0x44);
  EXPECT_EQ(bytes[39], 0x42);
  EXPECT_EQ(bytes[40], 0x53);
  EXPECT_EQ(s.substr(41, 3), "512");
  EXPECT_EQ(bytes[44], 0x41);
  EXPECT_EQ(s.substr(45, 5), "@@@@@");
  EXPECT_EQ(bytes[50], ETX);
  auto back = decode_reply(decode_frame(bytes).value());
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_EQ(std::get<StatusReply>(back.value()).status, example_status());
}

TEST(Status, AutoMoveJogPolAndMiscRepliesAreStatusReplies) {
  for (std::uint8_t code : {0x32, 0x33, 0x34, 0x36}) {
    auto bytes = encode_reply(StatusReply{example_status(), ""}, '2', code);
    ASSERT_TRUE(bytes.ok());
    EXPECT_EQ(bytes.value()[2], code);
    EXPECT_TRUE(decode_reply(decode_frame(bytes.value()).value()).ok());
  }
  // A status reply for a command whose reply is not a status reply is refused.
  EXPECT_FALSE(encode_reply(StatusReply{}, '2', 0x35).ok());
}

TEST(Status, WrongNibbleBaseAndShortReplyAreErrors) {
  Bytes bytes = encode_reply(StatusReply{example_status(), ""}, '2', 0x31).value();
  Bytes wrong = bytes;
  wrong[36] = 0x37;  // 0x30 | 7 instead of 0x40 | 0x17
  wrong[51] = lrc(ByteView(wrong).first(51));
  auto e = decode_reply(decode_frame(wrong).value());
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().offset, 36u);
  EXPECT_EQ(e.error().field, "az status");

  Frame shortf = decode_frame(bytes).value();
  shortf.data.pop_back();
  auto s = decode_reply(shortf);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().field, "length");
}

TEST(ExtendedStatus, EnumerationsAndHundredths) {
  ExtendedStatusReply x;
  x.status = example_status();
  x.mode = 0x32;       // REMOTE_MODE (READING-NOTES 27)
  x.state = 0x21;      // WAITING_FOR_USER_INPUT
  x.last_mode = 0x25;  // LOCATE_MODE
  x.exit_status = 0x38;  // LOCATE_FUNCTION_COMPLETED (READING-NOTES 28)
  x.az_hundredths = 5;
  Bytes bytes = encode_reply(x, '2', 0x40).value();
  ASSERT_EQ(bytes.size(), 58u);
  EXPECT_EQ(bytes[45], 0x32);
  EXPECT_EQ(bytes[49], '5');
  EXPECT_EQ(bytes[56], ETX);
  auto back = decode_reply(decode_frame(bytes).value());
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_EQ(std::get<ExtendedStatusReply>(back.value()), x);
  EXPECT_EQ(meanings::mode_name(0x32), "REMOTE_MODE");
  EXPECT_EQ(meanings::state_name(0x32, 0x21), "WAITING_FOR_USER_INPUT");
  EXPECT_EQ(meanings::exit_name(0x25, 0x38), "LOCATE_FUNCTION_COMPLETED");
}

// ERRATA E-30: on a mount without 0.01 deg feedback bytes 49-50 may hold a
// blank ("no digit") instead of '0'; it decodes to no value and encodes back
// as a blank. A letter or a control byte there is still no digit and fails.
TEST(ExtendedStatus, AHundredthsByteMayBeBlankButNothingElse) {
  ExtendedStatusReply x;
  x.status = example_status();
  x.az_hundredths = std::nullopt;
  x.el_hundredths = std::nullopt;
  Bytes bytes = encode_reply(x, '2', 0x40).value();
  EXPECT_EQ(bytes[49], ' ');
  EXPECT_EQ(bytes[50], ' ');
  auto back = decode_reply(decode_frame(bytes).value());
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_EQ(std::get<ExtendedStatusReply>(back.value()), x);

  for (std::uint8_t wrong : {std::uint8_t{'A'}, std::uint8_t{'-'}, std::uint8_t{0x01}, std::uint8_t{0x7F}}) {
    for (std::size_t at : {std::size_t{49}, std::size_t{50}}) {
      Bytes bad = bytes;
      bad[at] = wrong;
      bad.back() = lrc(ByteView(bad).first(bad.size() - 1));
      auto frame = decode_frame(bad);
      ASSERT_TRUE(frame.ok()) << frame.error().message();
      auto r = decode_reply(frame.value());
      ASSERT_FALSE(r.ok()) << "byte " << at << " = " << int(wrong);
      EXPECT_EQ(r.error().offset, at);
      EXPECT_EQ(r.error().field, at == 49 ? "az hundredths" : "el hundredths");
    }
  }
}

TEST(Jog, RequestAndMinimalReply) {
  auto j = request_of<Jog>(command('2', 0x33, "EF0050"));
  EXPECT_EQ(j.direction, 'E');
  EXPECT_EQ(j.speed, 'F');
  EXPECT_EQ(j.duration_ms, 50u);
  EXPECT_EQ(form_of(Request{j}), "E");
  auto jm = request_of<JogMinimal>(command('2', 0x47, "XS9999"));
  EXPECT_EQ(jm.duration_ms, 9999u);
  // READING-NOTES 14: speed and duration are required even for X.
  EXPECT_FALSE(decode_request(decode_frame(command('2', 0x33, "X 0000")).value()).ok());
  EXPECT_FALSE(decode_request(decode_frame(command('2', 0x33, "CF0050")).value()).ok());
  Bytes reply = encode_reply(JogPositionReply{'A', -1525}, '2', 0x47).value();
  EXPECT_EQ(reply.size(), 12u);
  EXPECT_EQ(std::string(reply.begin() + 3, reply.begin() + 10), "A-152.5");
}

TEST(QueryName, RequestAndReply) {
  EXPECT_EQ(request_of<QueryName>(command('2', 0x35, "01")).index, 1u);
  Bytes reply = encode_reply(QueryNameReply{1, 12, "SBS 6"}, '2', 0x35).value();
  EXPECT_EQ(reply.size(), 19u);
  EXPECT_EQ(std::string(reply.begin() + 3, reply.begin() + 17), "0112SBS 6     ");
}

TEST(Misc, SubCommandsAndParameters) {
  auto m = request_of<Misc>(command('2', 0x36, "RA"));
  EXPECT_EQ(m.sub, 'R');
  EXPECT_EQ(m.param, 'A');
  EXPECT_EQ(form_of(Request{m}), "R");
  EXPECT_EQ(meanings::misc_parameter('K', 'G'), "Mode Group Change");
  EXPECT_FALSE(decode_request(decode_frame(command('2', 0x36, "QA")).value()).ok());
}

TEST(SatelliteData, WriteAndReadWithEmptySlot) {
  WriteSatellite w;
  w.index = 20;
  w.sat = {"GALAXY 19", -971, 0, '1', '0', -125};
  Bytes frame = encode_request(w, '2');
  ASSERT_EQ(frame.size(), 32u);
  EXPECT_EQ(std::string(frame.begin() + 3, frame.begin() + 30), "20GALAXY 19 -97.1 0 10-12.5");
  EXPECT_EQ(request_of<WriteSatellite>(frame), w);
  // §3.11 NOTE: 7Fh in both index bytes when the slot is empty.
  SatelliteDataReply empty;
  empty.index = std::nullopt;
  Bytes reply = encode_reply(empty, '2', 0x3A).value();
  ASSERT_EQ(reply.size(), 32u);
  EXPECT_EQ(reply[3], 0x7F);
  EXPECT_EQ(reply[4], 0x7F);
  auto back = decode_reply(decode_frame(reply).value());
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_FALSE(std::get<SatelliteDataReply>(back.value()).index.has_value());
}

TEST(Tle, WriteIs145Bytes) {
  WriteTle t;
  t.index = 10;
  t.line1 = "1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927";
  t.line2 = "2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537";
  Bytes frame = encode_request(t, '2');
  ASSERT_EQ(frame.size(), 145u);
  EXPECT_EQ(request_of<WriteTle>(frame), t);
}

TEST(RemoteLocateAndStore, PresetFlagForms) {
  RemoteLocate preset;
  preset.preset = {true, 20};
  Bytes f = encode_request(preset, '2');
  ASSERT_EQ(f.size(), 37u);
  EXPECT_EQ(f[3], 0x52);
  EXPECT_EQ(form_of(Request{request_of<RemoteLocate>(f)}), "preset");

  RemoteStore data;
  data.preset = {false, 0};
  data.sat = {"SBS 6", -740, 0, '0', '0', 0};
  data.pol_selection = 'S';
  data.h_pos = 125;
  data.v_pos = -775;
  Bytes s = encode_request(data, '2');
  ASSERT_EQ(s.size(), 48u);
  EXPECT_EQ(request_of<RemoteStore>(s), data);
  EXPECT_EQ(form_of(Request{data}), "data");
}

TEST(Navigation, WriteFromTheManualAndRead) {
  auto w = request_of<WriteNavigation>(command('2', 0x46, "01234-01234123.4            "));
  EXPECT_EQ(w.latitude, 1234);
  EXPECT_EQ(w.longitude, -1234);
  EXPECT_EQ(w.heading, 1234);
  NavigationDataReply r;
  r.latlon_source = 7;
  r.latitude = 12 * 60 + 34;
  r.longitude = -(123 * 60 + 45);
  r.heading_source = 7;
  r.heading = 1234;
  r.magvar_status = 1;
  r.magvar = -35;
  Bytes reply = encode_reply(r, '2', 0x45).value();
  ASSERT_EQ(reply.size(), 72u);
  const std::string s(reply.begin(), reply.end());
  EXPECT_EQ(s.substr(4, 6), "12.34N");
  EXPECT_EQ(s.substr(13, 7), "123.45W");
  EXPECT_EQ(s.substr(30, 5), "123.4");
  EXPECT_EQ(s.substr(36, 6), "  -3.5");
  EXPECT_EQ(std::get<NavigationDataReply>(decode_reply(decode_frame(reply).value()).value()), r);
}

// §3.20 byte 21 "1 - 9": the codec reads the whole range, 4 and 8 too
// (whether a controller takes them is ERRATA E-32's reading); 0 is outside.
TEST(Signpost, FecCodesOfTheRangeOneToNine) {
  WriteSignpost w;
  for (char fec : {'1', '4', '8', '9'}) {
    w.signpost.fec = fec;
    const auto d = decode_request(decode_frame(encode_request(w, '2')).value());
    ASSERT_TRUE(d.ok()) << fec;
    EXPECT_EQ(std::get<WriteSignpost>(d.value()).signpost.fec, fec);
  }
  w.signpost.fec = '9';
  Bytes f = encode_request(w, '2');
  ASSERT_EQ(f.size(), 36u);
  f[21] = '0';
  f.back() = lrc(ByteView(f).first(f.size() - 1));
  auto e = decode_request(decode_frame(f).value());
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().field, "fec");
  w.signpost.fec = '8';
  const FrameDescription d = describe_frame(encode_request(w, '2'));
  const auto fec = std::find_if(d.fields.begin(), d.fields.end(), [](const FieldDescription& x) { return x.name == "fec"; });
  ASSERT_NE(fec, d.fields.end());
  EXPECT_TRUE(fec->ok);
  EXPECT_NE(fec->meaning.find("not defined (E-32)"), std::string::npos) << fec->meaning;
}

TEST(Display, ReplyIs169Bytes) {
  DisplayReply d;
  d.rows = {"MANUAL", "AZ -152.5", "EL   45.6", ""};
  d.cursor_row = 2;
  d.cursor_column = 13;
  d.blinking = '1';
  Bytes reply = encode_reply(d, '2', 0x37).value();
  ASSERT_EQ(reply.size(), 169u);
  EXPECT_EQ(reply[163], '2');
  EXPECT_EQ(reply[164], '1');
  EXPECT_EQ(reply[165], '3');
  EXPECT_EQ(reply[166], '1');
}

TEST(NotImplemented, SignalStrengthAndIessHaveCodecs) {
  auto s = request_of<SignalStrength>(command('2', 0x38, "\x7f\x5f"));
  EXPECT_EQ(s.low, 0x3F);
  EXPECT_EQ(s.high, 0x1F);
  auto i = request_of<WriteIess>(command('2', 0x3D, "01PAYLOAD"));
  EXPECT_EQ(i.payload, "PAYLOAD");
  EXPECT_EQ(encode_reply(SignalStrengthReply{}, '2', 0x38).value().size(), 6u);
}

TEST(Requests, UnknownCodeIsAnError) {
  auto e = decode_request(decode_frame(command('2', 0x5A)).value());
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().offset, 2u);
}

}  // namespace
}  // namespace sabus

namespace sabus {
namespace {
TEST(Replies, FieldErrorAtTheEndOfAFieldNamesItsLastByte) {
  // Found by fuzz_reply_decoders: longitude "-" then blanks, the error is
  // "a digit" just past the '-' -- it must not read past the data.
  SatelliteDataReply r;
  Bytes bytes = encode_reply(r, '2', 0x3A).value();
  bytes[15] = '-';
  for (int i = 16; i < 21; ++i) bytes[i] = '-';  // "------": no digit anywhere
  bytes[31] = lrc(ByteView(bytes).first(31));
  auto e = decode_reply(decode_frame(bytes).value());
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().field, "longitude");
  EXPECT_GE(e.error().offset, 15u);
  EXPECT_LE(e.error().offset, 20u);
  Bytes end = encode_reply(r, '2', 0x3A).value();
  const char lon[] = "12345-";  // a digit is expected after the final '-'? no: junk at the end
  for (int i = 0; i < 6; ++i) end[15 + i] = static_cast<std::uint8_t>(lon[i]);
  end[31] = lrc(ByteView(end).first(31));
  auto e2 = decode_reply(decode_frame(end).value());
  ASSERT_FALSE(e2.ok());
  EXPECT_LE(e2.error().offset, 20u);
}

// classify_command reads the frame a slave would be reading when the bytes
// end (READING-NOTES 7), complete or damaged.
std::string classified(const Bytes& bytes) {
  const CommandForm cf = classify_command(bytes);
  if (!cf.info) return "none";
  if (!cf.form) return std::string(cf.info->key) + " (form unknown)";
  return std::string(cf.info->key) + (cf.form->id.empty() ? "" : " " + std::string(cf.form->id));
}

TEST(ClassifyCommand, TheLastFrameAStxBegins) {
  EXPECT_EQ(classified(test::hex("02 32 31 03 02")), "status") << "a check byte of 02h starts nothing";
  EXPECT_EQ(classified(test::concat({test::hex("02"), command('2', 0x31)})), "status") << "STX STX: the second one";
  EXPECT_EQ(classified(test::concat({command('2', 0x30), command('2', 0x31)})), "status");
  EXPECT_EQ(classified(command('2', 0x32, " -152500456")), "auto_move 2A");
  EXPECT_EQ(classified(command('2', 0x33, "EF0050")), "jog E");
}

TEST(ClassifyCommand, DamagedFramesByTheirSelectorByte) {
  Bytes bad_lrc = command('2', 0x33, "WF0050");
  bad_lrc.back() ^= 0x01;
  EXPECT_EQ(classified(bad_lrc), "jog W");
  EXPECT_EQ(classified(command('2', 0x33, "UFxx50")), "jog U") << "the duration does not decode";
  EXPECT_EQ(classified(test::hex("02 32 33 51")), "jog (form unknown)") << "cut short, no such selector";
  EXPECT_EQ(classified(test::hex("02 12 31 03 22")), "status") << "an address no device has (§1 State 2 b)";
}

TEST(ClassifyCommand, NoCommandFrame) {
  EXPECT_EQ(classified(test::hex("")), "none");
  EXPECT_EQ(classified(test::hex("32 31 03")), "none") << "no STX";
  EXPECT_EQ(classified(test::hex("02 32")), "none") << "no command byte";
  EXPECT_EQ(classified(command('2', 0x5A)), "none") << "not a catalog code";
}
}  // namespace
}  // namespace sabus
