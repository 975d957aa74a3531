// The server loop of `sabus sim`: bytes from a Line into a LineDevice (the
// reference controller), its replies back onto the Line.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <optional>

#include "sabus/harness/line.hpp"
#include "sabus/harness/line_faults.hpp"
#include "sabus/harness/line_device.hpp"
#include "sabus/protocol/bytes.hpp"

namespace sabus::harness {

struct ServeOptions {
  // Hold replies back so that a pty or TCP line behaves like a real one at
  // `baud`: see LinePacer. Meant for lines that are themselves instant; on a
  // real port the UART already takes that time.
  bool emulate_line = false;
  int baud = 9600;
  double turnaround_ms = 2.0;  // from the end of the last request byte to the first reply byte
  // When set, every line of device.take_log() (and TCP client changes) is
  // written here, prefixed by seconds since the server started ("  12.345 ").
  std::ostream* log = nullptr;
  // The longest wait for input before device.tick() runs again.
  std::chrono::milliseconds tick{5};
  // serve_tcp only. rfc2217: each client gets Telnet with RFC 2217's
  // COM-PORT-OPTION (Rfc2217ServerLine), not raw bytes; the baud rate it
  // sets is the one emulate_line emulates from then on. takeover: a client
  // that connects while another is served replaces it (the first is
  // disconnected); without it the newcomer is refused at once with
  // kPortInUse and closed, as ser2net and commercial device servers do.
  bool rfc2217 = false;
  bool takeover = false;
  // A noisy line on purpose (line_faults.hpp): each request's bytes and each
  // reply's pass an injector (seeds spec.seed and spec.seed + 1) before the
  // device reads them or the line carries them. The log says how many faults
  // were made when the server stops.
  std::optional<LineFaultSpec> line_faults;
};

// What a refused second client reads before its connection is closed
// (ser2net says "Port already in use").
inline constexpr std::string_view kPortInUse = "Port already in use: sabus sim serves one client at a time\r\n";

// Serves `device` on `line` until `stop` is set (by the caller's SIGINT /
// SIGTERM handler; it is checked at least every `tick`) or the line is lost.
// Returns 0 on stop, 1 when the line is lost (after a message on stderr).
int serve(Line& line, LineDevice& device, const ServeOptions& options, const std::atomic<bool>& stop);

// TcpServe: like a serial device server, accepts one client, serves it until
// it disconnects, accepts the next, until `stop`. The device keeps running
// (tick) between clients. A client that comes while one is served is refused
// or takes over (ServeOptions::takeover); the log says which. Returns 0 on
// stop, 1 when the listener fails.
int serve_tcp(TcpListener& listener, LineDevice& device, const ServeOptions& options,
              const std::atomic<bool>& stop);

// The timing model of ServeOptions::emulate_line, with no clock of its own
// (tests drive it with made-up times).
//
// A byte takes 10 bit times (start, 7 data, parity, stop: 7E1) = 10/baud s.
// Input is handed to the device at once, but it is counted as having taken
// its wire time: a chunk of n bytes that came in at t (instantly, over a pty
// or TCP) ends at max(t, end of the previous chunk) + n byte times. A reply
// starts `turnaround` after the end of the input that caused it, and not
// before the previous reply has left the wire (replies never overtake the
// wire rate, however fast requests come). Reply byte k (0-based) is due when
// its stop bit ends: start + (k + 1) byte times. Deadlines are computed from
// these absolute times, so a late write does not shift later bytes.
class LinePacer {
 public:
  using Clock = std::chrono::steady_clock;
  LinePacer(int baud, std::chrono::nanoseconds turnaround);

  // n bytes were read at `t`; returns when the last of them ended on the
  // emulated wire.
  Clock::time_point received(std::size_t n, Clock::time_point t);
  // Queues a reply to input that ended at `input_end` (from received()).
  void push(ByteView reply, Clock::time_point input_end);
  // Moves the bytes due by `now` to the end of `out`; returns how many.
  std::size_t take_due(Clock::time_point now, Bytes& out);
  // When the next queued byte is due; nullopt when nothing is queued.
  std::optional<Clock::time_point> next_due() const;
  bool empty() const { return bytes_.empty(); }
  // The end of byte `count - 1` of a run starting at 0: count byte times.
  std::chrono::nanoseconds wire_time(std::size_t count) const;

 private:
  struct Run {
    Clock::time_point start;  // when the first bit of byte 0 starts
    std::size_t size;         // bytes in the run
    std::size_t sent;         // bytes already taken
  };
  int baud_;
  std::chrono::nanoseconds turnaround_;
  std::optional<Clock::time_point> rx_end_, tx_end_;
  std::deque<Run> runs_;
  std::deque<std::uint8_t> bytes_;
};

}  // namespace sabus::harness
