// How the runner reaches a device: one interface for the in-process reference
// controller, a serial port and a TCP serial server. The runner never touches
// a port; transports move bytes and keep time.
#pragma once

#include <chrono>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "sabus/harness/clock.hpp"
#include "sabus/protocol/bytes.hpp"

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
  // cannot be honoured (the runner skips such vectors).
  virtual void send(ByteView chars, std::span<const std::size_t> wrong_parity = {}) = 0;
  // Bytes received within `timeout` (0 when none came), as 7-bit characters
  // when parity is checked in software: a byte with a parity error is passed
  // with bit 7 set so the receiver reports it. Throws TransportLost.
  virtual std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) = 0;
  // Lets time pass: sleeps on a real line, advances the clock in-process.
  virtual void pause(std::chrono::milliseconds d) = 0;
  virtual TimePoint now() const = 0;

  virtual bool in_process() const { return false; }
  virtual bool can_send_parity_errors() const = 0;
  virtual int baud() const = 0;  // 0 in-process
  virtual std::string describe() const = 0;
};

// Wire time of `bytes` characters at `baud`: 10 bit times each (READING-NOTES 2).
constexpr std::chrono::microseconds wire_time(std::size_t bytes, int baud) {
  return baud <= 0 ? std::chrono::microseconds{0}
                   : std::chrono::microseconds{static_cast<std::int64_t>(bytes) * 10 * 1000000 / baud};
}

}  // namespace sabus::harness
