// How the runner reaches a device: one interface for the in-process reference
// controller, a serial port and a TCP serial server. The runner never touches
// a port; transports move bytes and keep time.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "sabus/harness/clock.hpp"
#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness {

// The device is gone: unplugged adapter, closed socket, I/O error.
struct TransportLost : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Puts 7-bit characters on the line. With software parity (the default, a
  // port opened 8N1: READING-NOTES 1) the transport sets bit 7 of each byte to
  // even parity, except at the indexes in `wrong_parity`, which get the wrong
  // bit. With a true 7E1 port the UART makes the parity and `wrong_parity`
  // cannot be honoured (the runner skips such vectors; send() throws
  // std::invalid_argument when asked). An index past the end of `chars` is a
  // caller's bug: std::invalid_argument too. Throws TransportLost.
  virtual void send(ByteView chars, std::span<const std::size_t> wrong_parity = {}) = 0;
  // Bytes received within `timeout` (0 when none came; at most buf.size()),
  // as they came off the wire, never stripped or checked here:
  // - parity_in_bit7() true (software parity, the default, and TCP): each
  //   byte is a 7-bit character with its parity bit in bit 7, right or wrong.
  //   Feed them to a receiver with Parity::kEvenBit7, which checks and strips
  //   the bit and reports a wrong one as a parity error.
  // - parity_in_bit7() false (a true 7E1 port): each byte is a 7-bit
  //   character whose parity the UART has checked; a character the UART
  //   received with a parity or framing error comes with bit 7 set (a break
  //   as 0x80). Feed them to a receiver with Parity::kNone, which reports
  //   such a byte as an 8-bit character.
  // receiver_parity() below picks the receiver setting. Throws TransportLost.
  virtual std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) = 0;
  // Lets time pass: sleeps on a real line, advances the clock in-process.
  virtual void pause(std::chrono::milliseconds d) = 0;
  virtual TimePoint now() const = 0;

  virtual bool in_process() const { return false; }
  // Whether bytes cross a line that can garble them: every real line, and
  // the in-process controller behind an emulated noisy one. Without a line
  // every fault of a reply is the device's own: the runner gives no line
  // figures (RunResult::line all zero).
  virtual bool is_a_line() const { return !in_process(); }
  // The names of the NAK rules (nak_rules.hpp) the device applied since the
  // last call, oldest first; nullopt when the device cannot tell (every real
  // line). The reference controller knows why it NAKs.
  virtual std::optional<std::vector<std::string>> take_nak_rules() { return std::nullopt; }
  virtual bool can_send_parity_errors() const = 0;
  // Whether bit 7 of received bytes carries the even-parity bit (see
  // receive()). True for software parity, the project's default.
  virtual bool parity_in_bit7() const { return true; }
  virtual int baud() const = 0;  // 0 in-process
  virtual std::string describe() const = 0;
  // The network round trip to a device server in front of the device
  // (Line::round_trip(), measured when it was opened); 0 with no network or
  // none measured. The runner adds it to the turnaround it waits for.
  virtual std::chrono::microseconds network_round_trip() const { return {}; }
};

// How a receiver reads what `t.receive()` returns.
inline Parity receiver_parity(const Transport& t) { return t.parity_in_bit7() ? Parity::kEvenBit7 : Parity::kNone; }

// Wire time of `bytes` characters at `baud`: 10 bit times each (READING-NOTES 2).
constexpr std::chrono::microseconds wire_time(std::size_t bytes, int baud) {
  return baud <= 0 ? std::chrono::microseconds{0}
                   : std::chrono::microseconds{static_cast<std::int64_t>(bytes) * 10 * 1000000 / baud};
}

}  // namespace sabus::harness
