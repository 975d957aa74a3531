// The Telnet layer a terminal server puts on a serial line (RFC 854, 855,
// 1143) and the COM-PORT-OPTION of RFC 2217, with no I/O: bytes in, data and
// telnet events out. Used by the RFC 2217 client line (line_rfc2217.cpp) and
// by `sabus sim --rfc2217` (serve.cpp).
//
// On a Telnet connection 0xFF (IAC) starts a command, so a 0xFF data byte is
// sent doubled. SAbus puts even parity in bit 7 (READING-NOTES 1), so 0xFF is
// ordinary data here: the 7Fh no-data marker of an empty slot (§3.11, §3.13,
// §3.21) is 0xFF on the wire.
//
// The Decoder is fed any chunking and keeps its place between calls (inside
// IAC IAC, inside IAC SB ... IAC SE), like llhttp's execute(); what it cannot
// make sense of is an Event of kind error with a one-line reason, never an
// exception, and it goes on decoding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sabus/protocol/bytes.hpp"

namespace sabus::harness::telnet {

// Command bytes (RFC 854).
inline constexpr std::uint8_t kSE = 240, kNOP = 241, kSB = 250, kWILL = 251, kWONT = 252, kDO = 253,
                              kDONT = 254, kIAC = 255;
// Options: BINARY (RFC 856), ECHO (857), SUPPRESS-GO-AHEAD (858),
// COM-PORT-OPTION (RFC 2217).
inline constexpr std::uint8_t kBinary = 0, kEcho = 1, kSuppressGoAhead = 3, kComPortOption = 44;

// The longest subnegotiation payload kept; RFC 2217's longest is SIGNATURE
// text. A longer one is dropped with an error event.
inline constexpr std::size_t kMaxSubnegotiation = 512;

// `data` with every 0xFF doubled, appended to `out`.
void append_escaped(ByteView data, Bytes& out);
Bytes escaped(ByteView data);
// IAC verb option, e.g. IAC WILL BINARY.
Bytes negotiation(std::uint8_t verb, std::uint8_t option);
// IAC SB option payload IAC SE, the payload escaped.
Bytes subnegotiation(std::uint8_t option, ByteView payload);

struct Event {
  enum class Kind : std::uint8_t {
    negotiation,     // verb (WILL/WONT/DO/DONT) and option
    subnegotiation,  // option and payload (unescaped, without IAC SB option ... IAC SE)
    command,         // any other IAC command (NOP, GA, BRK, ...): verb
    error,           // reason; decoding goes on
  };
  Kind kind;
  std::uint8_t verb = 0;
  std::uint8_t option = 0;
  Bytes payload;
  std::string reason;
};
std::string describe(const Event& e);  // "DO BINARY", "SB COM-PORT-OPTION 101 00 00 25 80"
std::string option_name(std::uint8_t option);  // "BINARY", "option 24"

class Decoder {
 public:
  // Appends the data bytes of `in` to `data` and the telnet events to `events`.
  void feed(ByteView in, Bytes& data, std::vector<Event>& events);
  // True inside an unfinished command or subnegotiation (a stream that ends
  // here was cut short).
  bool mid_sequence() const { return state_ != State::data; }

 private:
  enum class State : std::uint8_t {
    data, after_iac, after_verb, sb_option, sb_payload, sb_after_iac, sb_discard, sb_discard_after_iac
  };
  // The byte after an IAC outside a subnegotiation.
  void after_iac(std::uint8_t b, Bytes& data, std::vector<Event>& events);
  State state_ = State::data;
  std::uint8_t verb_ = 0;
  std::uint8_t sb_option_ = 0;
  Bytes sb_;
};

// Which options each side has on (RFC 1143's rule without its queue: answer
// only a request that changes the state, never an acknowledgement, so two
// peers cannot loop). `local` is what we do (WILL/WONT, asked by DO/DONT),
// `remote` what the peer does (DO/DONT, asked by WILL/WONT).
class Options {
 public:
  // The options we agree to do and want the peer to do.
  Options(std::vector<std::uint8_t> local_allowed, std::vector<std::uint8_t> remote_allowed);
  // Asks to turn on: IAC WILL opt (local) or IAC DO opt (remote).
  Bytes request_local(std::uint8_t option);
  Bytes request_remote(std::uint8_t option);
  // Handles a received negotiation; returns the reply to send (maybe none).
  Bytes receive(std::uint8_t verb, std::uint8_t option);
  bool local_on(std::uint8_t option) const { return local_[option] == State::on; }
  bool remote_on(std::uint8_t option) const { return remote_[option] == State::on; }
  // True while our request for the option has had no answer.
  bool local_pending(std::uint8_t option) const { return local_[option] == State::requested; }
  bool remote_pending(std::uint8_t option) const { return remote_[option] == State::requested; }

 private:
  enum class State : std::uint8_t { off, requested, on };
  static bool has(const std::vector<std::uint8_t>& list, std::uint8_t option);
  std::vector<std::uint8_t> local_allowed_, remote_allowed_;
  State local_[256] = {};
  State remote_[256] = {};
};

// RFC 2217 COM-PORT-OPTION commands (client to server); the server's answer
// to each is the same code + 100 (kServerOffset).
namespace com_port {
inline constexpr std::uint8_t kSignature = 0, kSetBaudrate = 1, kSetDatasize = 2, kSetParity = 3, kSetStopsize = 4,
                              kSetControl = 5, kNotifyLinestate = 6, kNotifyModemstate = 7, kFlowcontrolSuspend = 8,
                              kFlowcontrolResume = 9, kSetLinestateMask = 10, kSetModemstateMask = 11,
                              kPurgeData = 12;
inline constexpr std::uint8_t kServerOffset = 100;
// SET-PARITY values; SET-STOPSIZE 1 = one stop bit; SET-CONTROL 1 = no flow control.
inline constexpr std::uint8_t kParityNone = 1, kParityOdd = 2, kParityEven = 3;
inline constexpr std::uint8_t kOneStopBit = 1, kNoFlowControl = 1;
// SET-BAUDRATE's payload: the code and the rate as four bytes, network order.
Bytes set_baudrate(std::uint8_t code, std::uint32_t baud);
// The rate of a SET-BAUDRATE payload (code + 4 bytes); nullopt when short.
std::optional<std::uint32_t> baudrate_of(ByteView payload);
// "parity error", "break", ... for the bits of a NOTIFY-LINESTATE value.
std::string linestate_text(std::uint8_t state);
std::string modemstate_text(std::uint8_t state);
// The name of a command code (client or server form): "SET-BAUDRATE".
std::string command_name(std::uint8_t code);
}  // namespace com_port

}  // namespace sabus::harness::telnet
