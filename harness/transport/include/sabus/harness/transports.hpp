// The transports the runner can use (transport.hpp is the interface): the
// in-process reference controller, and any Line (a serial port, a TCP serial
// device server). Timing helpers are in timing.hpp.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/harness/clock.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/harness/faults.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/harness/line_faults.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/harness/rfc2217.hpp"
#include "sabus/harness/transport.hpp"

namespace sabus::harness {

// The wire bytes of 7-bit `chars` with software parity (READING-NOTES 1):
// bit 7 of each byte is even parity, inverted at the indexes in
// `wrong_parity`. Throws std::invalid_argument for an index past the end.
Bytes with_software_parity(ByteView chars, std::span<const std::size_t> wrong_parity = {});

// ---- in process ---------------------------------------------------------------

// The reference controllers (a Bus: one or several addresses) on a virtual
// clock. There is no wire: replies are there as soon as the request is sent,
// and waiting for silence advances the clock instead of taking real time, so
// a whole run costs no more wall time than its computation.
class InProcessTransport final : public Transport {
 public:
  explicit InProcessTransport(std::vector<Profile> profiles, FaultSet faults = {});

  // Applies software parity (wrong where asked), feeds the bus and queues
  // its replies, which carry even parity in bit 7 as on the wire.
  void send(ByteView chars, std::span<const std::size_t> wrong_parity = {}) override;
  // Queued reply bytes at once, as on the wire (parity in bit 7). When none
  // are queued: advances the clock by `timeout`, lets the controllers move
  // (Bus::tick) and returns 0; no real time passes.
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override;
  // Advances the clock by `d` and lets the controllers move.
  void pause(std::chrono::milliseconds d) override;
  TimePoint now() const override { return clock_.now(); }

  bool in_process() const override { return true; }
  bool is_a_line() const override { return to_device_.has_value(); }
  // Over an emulated noisy line (set_line_faults) nullopt, as on a real
  // line: the line may have changed the frame the controller judged.
  std::optional<std::vector<std::string>> take_nak_rules() override {
    auto rules = bus_.take_nak_rules();
    if (to_device_) return std::nullopt;
    return rules;
  }
  bool can_send_parity_errors() const override { return true; }
  bool parity_in_bit7() const override { return true; }
  int baud() const override { return 0; }
  // "in-process reference controller rc3000-1.59 at 0x32 '2'" (+ the faults).
  std::string describe() const override { return description_; }

  // For tests and the runner's backup/restore of controller state
  // (bus().controller(i).mutable_state()). bus().take_log() has the decoded
  // transcript; it grows until taken.
  Bus& bus() { return bus_; }
  VirtualClock& clock() { return clock_; }
  std::size_t pending() const { return replies_.size(); }  // reply bytes not yet received

  // An emulated noisy line between the runner and the controllers (`sabus run
  // --sim --line-faults`): requests and replies each pass their own injector
  // (seeds spec.seed and spec.seed + 1) on their wire bytes, parity bit included.
  void set_line_faults(const LineFaultSpec& spec);
  // The faults the line injected both ways; all zero without line faults.
  LineFaultTally injected_faults() const;

 private:
  std::string description_;
  VirtualClock clock_;  // before bus_: the controllers hold a reference to it
  Bus bus_;
  std::deque<std::uint8_t> replies_;
  std::optional<LineFaultInjector> to_device_, from_device_;
};

std::unique_ptr<InProcessTransport> make_in_process_transport(std::vector<Profile> profiles, FaultSet faults = {});

// ---- lines --------------------------------------------------------------------

// How a serial port carries SAbus's 7E1 characters.
enum class LineMode : std::uint8_t {
  // The default (READING-NOTES 1): the port is opened 8N1 and the transport
  // puts the even-parity bit in bit 7 itself, so it can also send wrong
  // parity; received bytes keep their parity bit for the receiver to check.
  kSoftwareParity8N1,
  // The port is opened 7E1: the UART makes and checks the parity. Wrong
  // parity cannot be sent; received characters are 7-bit, with bit 7 set on
  // the ones the UART flagged (Transport::receive). Not possible on a pty.
  kTrue7E1,
};
std::string_view to_string(LineMode mode);                   // "software", "7e1"
std::optional<LineMode> parse_line_mode(std::string_view name);  // "software", "7e1"

// Decodes what a CharFormat::k7E1 port delivers (PARMRK marks, termios(3))
// into Transport::receive()'s bytes: FF 00 c -> c|0x80 (a character the UART
// received with a parity or framing error; a break, FF 00 00, -> 0x80);
// FF FF -> FF (an FF received as data, only possible without ISTRIP); every
// other byte unchanged. A mark split across reads is carried over to the
// next call. (FF followed by anything else is never produced; the FF is
// dropped.)
class ParityMarkDecoder {
 public:
  // Decodes in place; returns how many bytes of `bytes` are now the output
  // (never more than bytes.size()).
  std::size_t decode(std::span<std::uint8_t> bytes);
  bool inside_mark() const { return state_ != State::kPlain; }

 private:
  enum class State : std::uint8_t { kPlain, kAfterFF, kAfterFF00 };
  State state_ = State::kPlain;
};

// A Transport over any Line. Real time: now() is a steady clock, pause()
// sleeps. A LineError from the line (an unplugged adapter, a closed socket,
// a hung-up pty) becomes TransportLost with the same message.
class LineTransport final : public Transport {
 public:
  // `baud`: the line's rate (for a TCP device server, its serial side's);
  // the transport only reports it, for the runner's timeouts.
  LineTransport(std::unique_ptr<Line> line, LineMode mode, int baud);

  void send(ByteView chars, std::span<const std::size_t> wrong_parity = {}) override;
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override;
  void pause(std::chrono::milliseconds d) override;
  TimePoint now() const override { return clock_.now(); }

  bool can_send_parity_errors() const override { return mode_ == LineMode::kSoftwareParity8N1; }
  bool parity_in_bit7() const override { return mode_ == LineMode::kSoftwareParity8N1; }
  int baud() const override { return baud_; }
  // The line's describe() and the mode: "serial /dev/ttyUSB0 9600 8N1
  // (libserialport), software even parity in bit 7".
  std::string describe() const override;
  std::chrono::microseconds network_round_trip() const override { return line_->round_trip(); }

  Line& line() { return *line_; }
  LineMode mode() const { return mode_; }

 private:
  std::unique_ptr<Line> line_;
  LineMode mode_;
  int baud_;
  ParityMarkDecoder marks_;
  SteadyClock clock_;
};

// A serial port (open_serial_line: exclusive, so a second runner on the same
// port fails with "... is in use by another process"). kTrue7E1 opens it 7E1,
// which fails on a pseudo-terminal with a message that says so. `note`, when
// given, receives which backend was used and why. Throws LineError when the
// port cannot be opened (the device was never reached).
std::unique_ptr<LineTransport> make_serial_transport(const std::string& path, int baud,
                                                     SerialBackend backend = SerialBackend::automatic,
                                                     LineMode mode = LineMode::kSoftwareParity8N1,
                                                     std::string* note = nullptr);

// Raw TCP to a serial device server, which passes bytes through both ways: its
// serial port must be set 8N1 at the device's baud rate (`baud`, reported for
// timeouts), so the transport uses software parity, bit 7 included, exactly
// as on a port opened 8N1. Throws LineError when it cannot connect.
std::unique_ptr<LineTransport> make_tcp_transport(const std::string& host, std::uint16_t port,
                                                  std::chrono::milliseconds timeout, int baud = 9600);

// A terminal server's RFC 2217 port (rfc2217://HOST:PORT): its serial side
// set to `baud` 8N1 for software parity (the default) or 7E1 for
// LineMode::kTrue7E1, where the server's UART makes the parity (its 7-bit
// characters come back with bit 7 clear; a parity error there is only seen
// as the server's NOTIFY-LINESTATE, passed to `note`). Throws LineError when
// it cannot connect or the server does not negotiate within `timeout`.
std::unique_ptr<LineTransport> make_rfc2217_transport(const std::string& host, std::uint16_t port, int baud,
                                                      LineMode mode, std::chrono::milliseconds timeout,
                                                      TelnetNote note = {});

}  // namespace sabus::harness
