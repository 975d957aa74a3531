// How long the runner waits: for a reply, and before it concludes that the
// device stays silent. Pure functions of the baud rate and byte counts (the
// catalog's lengths), and a meter of the device's measured turnaround; no
// clock of their own, so tests check them with numbers.
//
// Times on a line (READING-NOTES 2): one character is 10 bit times, start + 7
// data + parity + stop (7E1), the same as 8N1; 1.042 ms at 9600 baud.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "sabus/harness/clock.hpp"
#include "sabus/harness/transport.hpp"

namespace sabus::harness {

// What a reply can pick up between the wire and the runner: a USB serial
// adapter holds received bytes until its latency timer fires (16 ms by
// default on FTDI chips) and the OS schedules the reader.
inline constexpr std::chrono::milliseconds kHostLatency{20};

// How long to wait for a whole reply to a request, counted from when send()
// was called (send() does not wait for the UART to drain):
//   wire(request) + turnaround_allowance + wire(reply) + margin,
//   margin = kHostLatency + 10% of the two wire times,
// the 10% for UART clocks a few percent apart and for gaps a device may leave
// between characters. Rounded up to whole milliseconds. At 9600 baud a status
// poll (5 bytes out, 52 back) with a 50 ms allowance: 59.4 ms of wire time +
// 50 + 20 + 5.9 = 136 ms. With baud 0 (in-process, no wire): allowance + 20 ms.
constexpr std::chrono::milliseconds reply_timeout(int baud, std::size_t request_bytes, std::size_t reply_bytes,
                                                  std::chrono::milliseconds turnaround_allowance) {
  const std::chrono::microseconds wire = wire_time(request_bytes, baud) + wire_time(reply_bytes, baud);
  const std::chrono::microseconds margin = kHostLatency + wire / 10;
  return std::chrono::ceil<std::chrono::milliseconds>(wire + turnaround_allowance + margin);
}

// A device is slower on some commands than on the ones its turnaround was
// measured with, so the window assumes up to kSilenceFactor times the
// measured turnaround, and never less than kSilenceFloor (also what a run
// uses before it has measured anything).
inline constexpr int kSilenceFactor = 3;
inline constexpr std::chrono::milliseconds kSilenceFloor{100};

// How long to listen, counted from the end of the request on the wire (the
// time send() was called + wire_time(request bytes, baud)), before concluding
// that the device stays silent, as it must after a frame it ignores (§1;
// READING-NOTES 9: bad LRC, other address, parity error, ...):
//   max(kSilenceFloor, kSilenceFactor * measured_turnaround)
//     + wire_time(longest_reply, baud) + kHostLatency.
// `measured_turnaround` is TurnaroundMeter::max(): request end to the first
// reply byte as the runner saw it. A reply the device would have started
// within the first term shows its first byte well inside the window; the
// window also spans the longest reply the request could draw, so that an
// unexpected reply is read whole (and reported as the frame it is) instead of
// spilling into the next step's receive. §4 asks a master to pace its
// requests anyway (READING-NOTES 3), so this costs little. At 9600 baud, a
// 5 ms turnaround and a 52-byte reply: 100 + 54.2 + 20 = 175 ms (rounded up).
constexpr std::chrono::milliseconds silence_window(std::chrono::microseconds measured_turnaround, int baud,
                                                   std::size_t longest_reply) {
  const std::chrono::microseconds start =
      std::max<std::chrono::microseconds>(kSilenceFloor, kSilenceFactor * measured_turnaround);
  return std::chrono::ceil<std::chrono::milliseconds>(start + wire_time(longest_reply, baud) + kHostLatency);
}

// The device's turnaround, from request/reply pairs of a run.
class TurnaroundMeter {
 public:
  // `request_end`: when the last request byte left the wire (the time send()
  // was called + wire_time(request bytes, baud)); `first_reply_byte`: when
  // receive() first returned bytes of the reply. A reply seen before the
  // estimated request end (bytes faster than the estimate) counts as 0.
  void record(TimePoint request_end, TimePoint first_reply_byte) {
    const Duration d = std::max(Duration{0}, first_reply_byte - request_end);
    max_ = std::max(max_, d);
    total_ += d;
    ++count_;
  }
  std::size_t count() const { return count_; }
  // The longest and the mean turnaround; 0 before anything was recorded.
  Duration max() const { return max_; }
  Duration mean() const { return count_ == 0 ? Duration{0} : total_ / static_cast<std::int64_t>(count_); }
  void reset() { *this = TurnaroundMeter{}; }

 private:
  std::size_t count_ = 0;
  Duration max_{0};
  Duration total_{0};
};

}  // namespace sabus::harness
