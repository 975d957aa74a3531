// The slave's byte-at-a-time receive state machine (§1 Slave State Diagram,
// states 1-5), fed any chunking of a byte stream. It does no I/O and no heap
// allocation: complete frames and discarded runs are reported to a sink, with
// stream offsets, so splitting the input anywhere gives the same events.
//
// Configured for ACK/NAK starts and no address filter it reads replies on the
// master side (ReceiverOptions::master()).
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <string>
#include <string_view>

#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus {

// Named as in §1 "State Descriptions".
enum class ReceiverState : std::uint8_t {
  kSlaveIdle = 1,        // State 1: waiting for STX
  kSlaveAddressed = 2,   // State 2: waiting for the address byte
  kSlaveData = 3,        // State 3: command and data bytes, until ETX
  kSlaveDataError = 4,   // State 4 ("Slave Data Error State"): waiting for the check byte
  kCommandExecute = 5,   // State 5: a frame is complete; passes at once to State 1
};
std::string_view to_string(ReceiverState s);

// Why a run of bytes was discarded. One table: enum, short name, description.
#define SABUS_DISCARD_REASONS(X)                                                                            \
  X(kBadLrc, "bad LRC", "the check byte is not the XOR of byte 0 through ETX (§1 Check Character)")         \
  X(kOtherAddress, "other address", "the address byte is not an address this receiver accepts (§1 State 2 b)") \
  X(kControlCharacter, "control character in the body",                                                     \
    "a control character 00h-1Fh other than ETX inside the frame (§1 Data Format, READING-NOTES 6)")        \
  X(kOverrun, "overrun", "the frame is longer than the longest valid frame (READING-NOTES 8)")             \
  X(kParityError, "parity error",                                                                          \
    "bit 7 of the byte does not give even parity (§1 Data Format); outside a frame, a run of such bytes")  \
  X(kNotAscii, "8-bit character",                                                                          \
    "bit 7 set where characters are 7-bit (parity checking off); outside a frame, a run of such bytes")   \
  X(kUnknownCommand, "unknown command", "state-diagram reading: an unknown command code is ignored (E-9)")  \
  X(kWrongLength, "wrong length", "state-diagram reading: a length that does not fit the command is ignored (E-9)") \
  X(kIncomplete, "incomplete", "the frame was cut short by a new start byte or the end of the input")      \
  X(kUnknown, "unknown bytes", "well-formed characters outside any frame (State 1 waits for a start byte)")

enum class DiscardReason : std::uint8_t {
#define SABUS_X(id, name, description) id,
  SABUS_DISCARD_REASONS(SABUS_X)
#undef SABUS_X
};
std::string_view to_string(DiscardReason r);
std::string_view description(DiscardReason r);

// A run of discarded bytes. Offsets count bytes from the start of the stream.
struct Discard {
  DiscardReason reason;
  std::uint64_t offset = 0;   // first byte of the run
  std::uint64_t length = 0;   // bytes in the run
  std::uint64_t at = 0;       // the byte that decided it (for kIncomplete at end of input: one past the run)
  std::uint8_t byte = 0;      // that byte as received
  std::uint8_t expected = 0;  // kBadLrc: the computed check byte
  std::string message() const;
  bool operator==(const Discard&) const = default;
};

// A complete frame. The spans point into the receiver and are valid only
// during the callback; to_frame() copies.
struct FrameView {
  FrameKind kind;
  std::uint8_t address;
  std::uint8_t command;
  ByteView data;           // bytes 3 .. ETX-1, 7-bit characters
  ByteView bytes;          // byte 0 through the check byte, 7-bit characters
  std::uint64_t offset;    // stream offset of byte 0
  Frame to_frame() const { return {kind, address, command, Bytes(data.begin(), data.end())}; }
};

class ReceiverSink {
 public:
  virtual ~ReceiverSink() = default;
  virtual void on_frame(const FrameView& frame) = 0;
  virtual void on_discard(const Discard& discard) = 0;
};

enum class Parity : std::uint8_t {
  kEvenBit7,  // default (E-1): bit 7 of each byte carries even parity; checked and stripped
  kNone,      // 7-bit characters, as a true 7E1 UART delivers them
  kUnchecked, // lenient: bit 7 is stripped and never checked (a device that ignores parity)
};

enum class StartBytes : std::uint8_t {
  kCommand,  // STX: the slave side
  kReply,    // ACK, NAK: the master side
  kAny,      // STX, ACK, NAK: both directions of one line
};

// The readings of READING-NOTES 1 and 5-9 (ERRATA E-1, E-5..E-9) are options,
// each with the notes' decision as its default.
struct ReceiverOptions {
  StartBytes starts = StartBytes::kCommand;
  // Accepted addresses (§1 State 2). None set: any address 31h-6Fh.
  std::bitset<128> addresses;
  Parity parity = Parity::kEvenBit7;                // E-1
  LrcRule lrc_rule = LrcRule::kFromByte0;           // E-5
  bool check_byte_restarts_on_stx = false;          // E-5, E-7: in State 4 an STX is the check byte
  bool reject_control_in_body = true;               // E-6 (master side: false, E-35)
  // No reading (fault accepts-control-in-body): a control character in
  // State 3 is left out of the frame, the check byte still covering it.
  bool skip_control_in_body = false;
  bool stx_restarts_in_data = true;                 // E-7: a start byte in State 3 restarts reception
  bool stx_restarts_in_address = true;              // §1 State 2 c (must); false: State 2 -> State 1
  std::size_t max_frame_length = 0;                 // E-8: 0 = the catalog's longest frame for `starts`;
                                                    // the other side reads to ETX (kBufferSize at most)
  bool validate_command_in_receiver = false;        // E-9: true = state-diagram reading (silence)

  static ReceiverOptions slave(std::uint8_t address);
  static ReceiverOptions slave_any_address();
  static ReceiverOptions master();
  ReceiverOptions& accept_address(std::uint8_t address);
  bool operator==(const ReceiverOptions&) const = default;
};

class Receiver {
 public:
  static constexpr std::size_t kBufferSize = 256;

  explicit Receiver(const ReceiverOptions& options = ReceiverOptions::slave_any_address());

  // Feeds a chunk. Every complete frame and every discarded run is reported.
  void feed(ByteView chunk, ReceiverSink& sink);
  // End of input: a partial frame is reported as incomplete, a pending run of
  // bytes outside a frame is reported. The receiver is back in State 1.
  void finish(ReceiverSink& sink);
  // Back to State 1 without reporting; the stream offset continues.
  void reset();
  // New options from the next byte on (a reading taken late, ERRATA E-6,
  // E-8): the state, a frame under way and the stream offset are kept.
  void reconfigure(const ReceiverOptions& options);

  ReceiverState state() const { return state_; }
  std::uint64_t offset() const { return pos_; }
  const ReceiverOptions& options() const { return options_; }

 private:
  enum ByteClass : std::uint8_t { kData, kEtx, kStart, kControl, kBadParity, kNotAscii };

  void begin_frame(std::uint8_t c, std::uint64_t at);
  void discard_frame(DiscardReason reason, std::uint64_t end, std::uint64_t at, std::uint8_t byte,
                     ReceiverSink& sink, std::uint8_t expected = 0);
  void flush_unknown(ReceiverSink& sink);
  // A byte outside any frame (State 1): it joins the run of its kind, or ends
  // the run of another kind and starts its own.
  void idle_byte(std::uint8_t wire, std::uint64_t at, ReceiverSink& sink);
  static DiscardReason idle_reason(std::uint8_t byte_class);
  void complete_frame(std::uint64_t at, std::uint8_t wire, ReceiverSink& sink);
  void step_slow(std::uint8_t wire, std::uint64_t at, ReceiverSink& sink);
  bool all_data(std::uint64_t w) const;

  ReceiverOptions options_;
  std::array<std::uint8_t, 256> class_{};   // ByteClass of each received byte value
  std::array<bool, 128> address_ok_{};
  std::size_t data_limit_ = 0;              // len_ at which a further data byte overruns
  bool swar_ = false;                       // all_data() is valid for these options

  ReceiverState state_ = ReceiverState::kSlaveIdle;
  std::array<std::uint8_t, kBufferSize> buf_{};
  std::size_t len_ = 0;
  std::uint8_t lrc_ = 0;
  std::uint64_t pos_ = 0;          // stream offset of the next byte
  std::uint64_t frame_start_ = 0;
  // The run of bytes outside any frame: well-formed characters (kUnknown),
  // bytes with a wrong parity bit (kParityError) or 8-bit characters
  // (kNotAscii), one kind a run, so that a master sending with the wrong
  // parity shows as parity errors, not as noise.
  std::uint64_t unknown_start_ = 0;
  std::uint64_t unknown_len_ = 0;
  std::uint8_t unknown_first_ = 0;
  DiscardReason unknown_reason_ = DiscardReason::kUnknown;
};

}  // namespace sabus
