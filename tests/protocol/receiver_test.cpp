// The slave state machine (§1 State Descriptions) and every discard reason.
#include <gtest/gtest.h>

#include "sabus/protocol/receiver.hpp"
#include "test_support.hpp"

namespace sabus {
namespace {
using test::chars;
using test::command;
using test::concat;
using test::hex;
using test::receive;
using R = DiscardReason;

const ReceiverOptions kSlave50 = chars(ReceiverOptions::slave('2'));

TEST(Receiver, StatusPollWhoseCheckByteIsStx) {
  // READING-NOTES 7: 02 32 31 03 02 -- in State 4 an STX is the check byte.
  auto log = receive(kSlave50, hex("02 32 31 03 02"));
  ASSERT_EQ(log.frames().size(), 1u);
  EXPECT_EQ(log.frames()[0], hex("02 32 31 03 02"));
  EXPECT_TRUE(log.discards().empty());
}

TEST(Receiver, StatesAreNamedAsInTheSpec) {
  Receiver r(kSlave50);
  test::EventLog log;
  EXPECT_EQ(r.state(), ReceiverState::kSlaveIdle);
  r.feed(hex("02"), log);
  EXPECT_EQ(r.state(), ReceiverState::kSlaveAddressed);
  r.feed(hex("32"), log);
  EXPECT_EQ(r.state(), ReceiverState::kSlaveData);
  r.feed(hex("31 03"), log);
  EXPECT_EQ(r.state(), ReceiverState::kSlaveDataError);
  r.feed(hex("02"), log);
  EXPECT_EQ(r.state(), ReceiverState::kSlaveIdle);  // through State 5
  EXPECT_EQ(log.frames().size(), 1u);
  EXPECT_EQ(to_string(ReceiverState::kCommandExecute), "State 5 (Command Execute)");
}

TEST(Receiver, BadLrcIsDiscardedWithTheExpectedByte) {
  auto log = receive(kSlave50, hex("02 32 31 03 00"));
  ASSERT_EQ(log.discards().size(), 1u);
  const Discard d = log.discards()[0];
  EXPECT_EQ(d.reason, R::kBadLrc);
  EXPECT_EQ(d.offset, 0u);
  EXPECT_EQ(d.length, 5u);
  EXPECT_EQ(d.at, 4u);
  EXPECT_EQ(d.byte, 0x00);
  EXPECT_EQ(d.expected, 0x02);
  EXPECT_EQ(d.message(), "bytes 0-4 (5): bad LRC: check byte 0x00 at offset 4, expected 0x02 (STX)");
}

TEST(Receiver, OtherAddressGoesIdleAndTheRestIsUnknown) {
  // §1 State 2 b: the address is not ours -> State 1.
  auto log = receive(kSlave50, command('3', 0x31));
  auto ds = log.discards();
  ASSERT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds[0].reason, R::kOtherAddress);
  EXPECT_EQ(ds[0].length, 2u);
  EXPECT_EQ(ds[0].byte, '3');
  EXPECT_EQ(ds[1].reason, R::kUnknown);
  EXPECT_EQ(ds[1].offset, 2u);
  EXPECT_EQ(ds[1].length, 3u);
  EXPECT_TRUE(log.frames().empty());
}

TEST(Receiver, MultiDropAcceptsEachConfiguredAddress) {
  ReceiverOptions o = kSlave50;
  o.accept_address('3');
  auto log = receive(o, concat({command('2', 0x31), command('3', 0x31), command('4', 0x31)}));
  EXPECT_EQ(log.frames().size(), 2u);
  EXPECT_EQ(log.discards()[0].reason, R::kOtherAddress);
}

TEST(Receiver, AnyValidAddressWhenNoneIsConfigured) {
  auto o = chars(ReceiverOptions::slave_any_address());
  EXPECT_EQ(receive(o, command('1', 0x31)).frames().size(), 1u);  // 0x31
  EXPECT_EQ(receive(o, command('o', 0x31)).frames().size(), 1u);  // 0x6F
  EXPECT_EQ(receive(o, command('0', 0x31)).discards()[0].reason, R::kOtherAddress);  // 0x30
  EXPECT_EQ(receive(o, command('p', 0x31)).discards()[0].reason, R::kOtherAddress);  // 0x70
}

TEST(Receiver, ControlCharacterInTheBody) {
  for (std::uint8_t c : {0x00, 0x01, 0x05, 0x06, 0x10, 0x15, 0x1F}) {
    Bytes f = hex("02 32 36 52");
    f.push_back(c);
    f.push_back(0x41);
    f.push_back(0x03);
    f.push_back(lrc(f));
    auto log = receive(kSlave50, f);
    ASSERT_FALSE(log.discards().empty()) << int(c);
    EXPECT_EQ(log.discards()[0].reason, R::kControlCharacter) << int(c);
    EXPECT_EQ(log.discards()[0].at, 4u);
    EXPECT_TRUE(log.frames().empty());
  }
}

TEST(Receiver, ControlCharacterInTheAddressPosition) {
  auto log = receive(kSlave50, hex("02 05 31 03 00"));
  EXPECT_EQ(log.discards()[0].reason, R::kControlCharacter);
}

TEST(Receiver, EtxWhereTheCommandBelongsIsIncomplete) {
  auto log = receive(kSlave50, hex("02 32 03 33"));
  ASSERT_FALSE(log.discards().empty());
  EXPECT_EQ(log.discards()[0].reason, R::kIncomplete);
  EXPECT_NE(log.discards()[0].message().find("ETX where the command byte belongs"), std::string::npos);
}

TEST(Receiver, StxStxRestarts) {
  // §1 State 2 c: STX in State 2 stays in State 2 (READING-NOTES 7 must).
  auto log = receive(kSlave50, concat({hex("02"), command('2', 0x31)}));
  ASSERT_EQ(log.frames().size(), 1u);
  EXPECT_EQ(log.entries[1].offset, 1u);
  ASSERT_EQ(log.discards().size(), 1u);
  EXPECT_EQ(log.discards()[0].reason, R::kIncomplete);
  EXPECT_EQ(log.discards()[0].length, 1u);
}

TEST(Receiver, StxInTheMiddleOfAFrameRestartsByDefault) {
  // READING-NOTES 7: STX in State 3 resynchronises (profile switch).
  Bytes stream = concat({hex("02 32 36 52"), command('2', 0x31)});
  auto log = receive(kSlave50, stream);
  ASSERT_EQ(log.frames().size(), 1u);
  EXPECT_EQ(log.discards()[0].reason, R::kIncomplete);
  EXPECT_EQ(log.discards()[0].length, 4u);

  ReceiverOptions diagram = kSlave50;
  diagram.stx_restarts_in_data = false;  // the state diagram: invalid character -> State 1
  auto log2 = receive(diagram, stream);
  EXPECT_TRUE(log2.frames().empty());
  EXPECT_EQ(log2.discards()[0].reason, R::kControlCharacter);
}

TEST(Receiver, CheckByteEqualToEveryDelimiter) {
  // READING-NOTES 5: in State 4 any byte is the check byte.
  for (std::uint8_t want : {STX, ETX, ACK, NAK}) {
    // Choose the last data byte so that the LRC lands on `want`.
    Bytes f = hex("02 32 35 30");
    f.push_back(0x00);
    f.push_back(ETX);
    const std::uint8_t partial = lrc(f);
    f[4] = static_cast<std::uint8_t>(partial ^ want);
    if (!is_printable(f[4])) continue;
    f.push_back(lrc(f));
    ASSERT_EQ(f.back(), want);
    auto log = receive(kSlave50, concat({f, command('2', 0x31)}));
    EXPECT_EQ(log.frames().size(), 2u) << int(want);
  }
  ReceiverOptions restart = kSlave50;
  restart.check_byte_restarts_on_stx = true;  // the reading that never answers a status poll
  EXPECT_TRUE(receive(restart, hex("02 32 31 03 02")).frames().empty());
}

TEST(Receiver, OverrunAtTheLongestCommand) {
  // READING-NOTES 8: 145 bytes (Write TLE) is the longest valid frame.
  std::string body(140, 'A');
  Bytes ok = command('2', 0x3B, body);
  ASSERT_EQ(ok.size(), 145u);
  EXPECT_EQ(receive(kSlave50, ok).frames().size(), 1u);
  Bytes too_long = command('2', 0x3B, body + "A");
  auto log = receive(kSlave50, concat({too_long, command('2', 0x31)}));
  ASSERT_EQ(log.frames().size(), 1u) << "reception restarts at the next STX";
  EXPECT_EQ(log.frames()[0], command('2', 0x31));
  EXPECT_EQ(log.discards()[0].reason, R::kOverrun);
  EXPECT_EQ(log.discards()[0].at, 143u);
}

TEST(Receiver, ParityErrorOnEachPartOfTheFrame) {
  const ReceiverOptions wire = ReceiverOptions::slave('2');  // default: even parity in bit 7
  const Bytes good = add_even_parity(command('2', 0x36, "RA"));
  EXPECT_EQ(receive(wire, good).frames().size(), 1u);
  for (std::size_t i : {1u, 2u, 3u, 6u}) {  // address, command, data byte, check byte
    Bytes bad = good;
    bad[i] ^= 0x80;
    auto log = receive(wire, bad);
    EXPECT_TRUE(log.frames().empty()) << i;
    ASSERT_FALSE(log.discards().empty()) << i;
    EXPECT_EQ(log.discards()[0].reason, R::kParityError) << i;
    EXPECT_EQ(log.discards()[0].at, i);
  }
  // The frame's characters come out without the parity bit.
  EXPECT_EQ(receive(wire, good).frames()[0], command('2', 0x36, "RA"));
}

// A master set to 8N1 sends no parity bit: outside a frame its bytes with an
// odd number of ones are parity errors, not unknown bytes, one run per kind.
TEST(Receiver, ParityErrorsOutsideAFrameAreNamedAsSuch) {
  const ReceiverOptions wire = ReceiverOptions::slave('2');
  // 02 32 31 03 00 as 7-bit characters: STX, '2' and '1' have odd parity.
  auto log = receive(wire, hex("02 32 31 03 00 41 c3"));
  const auto ds = log.discards();
  ASSERT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds[0].reason, R::kParityError);
  EXPECT_EQ(ds[0].offset, 0u);
  EXPECT_EQ(ds[0].length, 3u);
  EXPECT_EQ(ds[0].message(), "bytes 0-2 (3): parity error: 0x02 (STX) at offset 0");
  EXPECT_EQ(ds[1].reason, R::kUnknown) << "ETX, NUL, 'A' and 'C' (C3h, with its parity bit) have even parity";
  EXPECT_EQ(ds[1].offset, 3u);
  EXPECT_EQ(ds[1].length, 4u);
  // Without parity checking, bit 7 outside a frame is an 8-bit character.
  const auto seven = receive(kSlave50, hex("41 c1 c2 42"));
  ASSERT_EQ(seven.discards().size(), 3u);
  EXPECT_EQ(seven.discards()[1].reason, R::kNotAscii);
  EXPECT_EQ(seven.discards()[1].length, 2u);
}

TEST(Receiver, UncheckedParityStripsBit7) {
  ReceiverOptions lenient = ReceiverOptions::slave('2');
  lenient.parity = Parity::kUnchecked;
  Bytes wire = add_even_parity(command('2', 0x36, "RA"));
  wire[3] ^= 0x80;  // a parity error on a data byte
  auto log = receive(lenient, wire);
  ASSERT_EQ(log.frames().size(), 1u);
  EXPECT_EQ(log.frames()[0], command('2', 0x36, "RA"));
}

TEST(Receiver, StxInTheAddressPositionCanBeAnOtherAddress) {
  ReceiverOptions o = kSlave50;
  o.stx_restarts_in_address = false;  // not the spec: State 2 c says remain in State 2
  auto log = receive(o, concat({hex("02"), command('2', 0x31)}));
  EXPECT_TRUE(log.frames().empty());
  EXPECT_EQ(log.discards()[0].reason, R::kOtherAddress);
}

TEST(Receiver, EightBitCharacterWithoutParity) {
  auto log = receive(kSlave50, hex("02 32 b1 03 00"));
  EXPECT_EQ(log.discards()[0].reason, R::kNotAscii);
}

TEST(Receiver, IncompleteAtTheEndOfInput) {
  auto log = receive(kSlave50, hex("02 32 31"));
  ASSERT_EQ(log.discards().size(), 1u);
  EXPECT_EQ(log.discards()[0].reason, R::kIncomplete);
  EXPECT_NE(log.discards()[0].message().find("the input ended"), std::string::npos);
}

TEST(Receiver, UnknownBytesBetweenFramesAreOneRun) {
  auto log = receive(kSlave50, concat({hex("41 42 43"), command('2', 0x31), hex("44")}));
  auto ds = log.discards();
  ASSERT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds[0].reason, R::kUnknown);
  EXPECT_EQ(ds[0].length, 3u);
  EXPECT_EQ(ds[1].offset, 8u);
}

TEST(Receiver, UnknownCodeAndWrongLengthReachTheControllerByDefault) {
  // READING-NOTES 9: §3 wins, the controller NAKs them.
  EXPECT_EQ(receive(kSlave50, command('2', 0x5A)).frames().size(), 1u);
  EXPECT_EQ(receive(kSlave50, command('2', 0x31, "X")).frames().size(), 1u);
  ReceiverOptions diagram = kSlave50;
  diagram.validate_command_in_receiver = true;
  EXPECT_EQ(receive(diagram, command('2', 0x5A)).discards()[0].reason, R::kUnknownCommand);
  EXPECT_EQ(receive(diagram, command('2', 0x31, "X")).discards()[0].reason, R::kWrongLength);
  EXPECT_EQ(receive(diagram, command('2', 0x31)).frames().size(), 1u);
}

TEST(Receiver, LrcFromAddressOption) {
  ReceiverOptions o = kSlave50;
  o.lrc_rule = LrcRule::kFromAddress;
  Bytes f = encode_frame({FrameKind::kCommand, '2', 0x31, {}}, LrcRule::kFromAddress);
  EXPECT_EQ(receive(o, f).frames().size(), 1u);
  EXPECT_EQ(receive(kSlave50, f).discards()[0].reason, R::kBadLrc);
}

TEST(Receiver, MasterSideReadsRepliesWithControlCharactersInTheBody) {
  // ERRATA E-35: byte 40 = 15h (X band, program track) inside a status reply.
  Bytes reply = test::frame_bytes(FrameKind::kAck, '2', 0x31, std::string("AB\x15" "C", 4));
  auto log = receive(chars(ReceiverOptions::master()), reply);
  ASSERT_EQ(log.frames().size(), 1u);
  EXPECT_EQ(log.frames()[0], reply);
  auto nak = test::frame_bytes(FrameKind::kNak, '2', 0x3A, "");
  EXPECT_EQ(receive(chars(ReceiverOptions::master()), nak).frames().size(), 1u);
  // A command frame is noise to the master side.
  EXPECT_EQ(receive(chars(ReceiverOptions::master()), command('2', 0x31)).discards()[0].reason, R::kUnknown);
}

TEST(Receiver, MasterSideOverrunAtTheLongestReply) {
  Bytes display = test::frame_bytes(FrameKind::kAck, '2', 0x37, std::string(164, ' '));
  ASSERT_EQ(display.size(), 169u);
  EXPECT_EQ(receive(chars(ReceiverOptions::master()), display).frames().size(), 1u);
  Bytes longer = test::frame_bytes(FrameKind::kAck, '2', 0x37, std::string(165, ' '));
  EXPECT_EQ(receive(chars(ReceiverOptions::master()), longer).discards()[0].reason, R::kOverrun);
}

TEST(Receiver, ByteAtATimeGivesTheSameEvents) {
  Bytes stream = concat({hex("41"), command('2', 0x31), hex("02 32 31 03 00"), hex("02 02"), command('2', 0x35, "01"),
                         hex("02 32")});
  auto whole = receive(kSlave50, stream);
  Receiver r(kSlave50);
  test::EventLog log;
  for (auto b : stream) r.feed(ByteView(&b, 1), log);
  r.finish(log);
  EXPECT_EQ(log.entries, whole.entries);
  EXPECT_EQ(whole.frames().size(), 2u);
}

}  // namespace
}  // namespace sabus
