// The server loop of `sabus sim` and the line timing model (LinePacer).
#include "sabus/harness/serve.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <iostream>
#include <string>
#include <string_view>

namespace sabus::harness {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// The --log transcript: one line per event, "  12.345 text", seconds since
// the server started.
class Transcript {
 public:
  explicit Transcript(std::ostream* out) : out_(out), start_(Clock::now()) {}

  void device_log(const std::string& text) {
    if (out_ == nullptr || text.empty()) return;
    std::string_view rest = text;
    while (!rest.empty()) {
      const auto nl = rest.find('\n');
      const std::string_view one = rest.substr(0, nl);
      if (!one.empty()) note(one);
      rest = nl == std::string_view::npos ? std::string_view{} : rest.substr(nl + 1);
    }
  }

  void note(std::string_view line) {
    if (out_ == nullptr) return;
    const double s = std::chrono::duration<double>(Clock::now() - start_).count();
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%8.3f ", s);
    *out_ << stamp << line << '\n';
    out_->flush();  // a transcript is read while the server runs (tail -f)
  }

 private:
  std::ostream* out_;
  Clock::time_point start_;
};

struct SessionEnd {
  bool lost = false;
  std::string message;  // why the line was lost
};

SessionEnd run_session(Line& line, LineDevice& device, const ServeOptions& options, const std::atomic<bool>& stop,
                       Transcript& transcript) {
  const milliseconds tick = std::max(options.tick, milliseconds{1});
  LinePacer pacer(options.baud, std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::duration<double, std::milli>(std::max(options.turnaround_ms, 0.0))));
  std::array<std::uint8_t, 256> buf{};
  Bytes reply, due;
  try {
    while (!stop.load(std::memory_order_relaxed)) {
      milliseconds timeout = tick;
      if (options.emulate_line) {
        due.clear();
        if (pacer.take_due(Clock::now(), due) > 0) line.write(due);
        if (const auto next = pacer.next_due()) {
          // Wake for the next reply byte; input that comes first is read at once.
          const auto wait = std::chrono::ceil<milliseconds>(*next - Clock::now());
          timeout = std::clamp(wait, milliseconds{0}, tick);
        }
      }
      const std::size_t n = line.read(buf, timeout);
      if (n > 0) {
        const auto at = Clock::now();
        reply.clear();
        device.receive(ByteView(buf.data(), n), reply);
        if (options.emulate_line) {
          const auto input_end = pacer.received(n, at);
          if (!reply.empty()) pacer.push(reply, input_end);
        } else if (!reply.empty()) {
          line.write(reply);
        }
      }
      device.tick();
      transcript.device_log(device.take_log());
    }
  } catch (const LineError& e) {
    transcript.device_log(device.take_log());
    return {true, e.what()};
  }
  return {};
}

}  // namespace

int serve(Line& line, LineDevice& device, const ServeOptions& options, const std::atomic<bool>& stop) {
  Transcript transcript(options.log);
  const SessionEnd end = run_session(line, device, options, stop, transcript);
  if (!end.lost) return 0;
  transcript.note("line lost: " + end.message);
  std::cerr << "sabus: the line was lost, stopping: " << end.message << "\n";
  return 1;
}

int serve_tcp(TcpListener& listener, LineDevice& device, const ServeOptions& options,
              const std::atomic<bool>& stop) {
  Transcript transcript(options.log);
  const milliseconds tick = std::max(options.tick, milliseconds{1});
  while (!stop.load(std::memory_order_relaxed)) {
    std::unique_ptr<TcpLine> client;
    try {
      client = listener.accept(tick);
    } catch (const LineError& e) {
      transcript.note(std::string("listener failed: ") + e.what());
      std::cerr << "sabus: " << e.what() << "\n";
      return 1;
    }
    if (!client) {
      device.tick();  // the controller keeps running with nobody connected
      transcript.device_log(device.take_log());
      continue;
    }
    transcript.note("client connected: " + client->describe());
    const SessionEnd end = run_session(*client, device, options, stop, transcript);
    if (!end.lost) break;
    transcript.note("client gone: " + end.message);
  }
  return 0;
}

LinePacer::LinePacer(int baud, std::chrono::nanoseconds turnaround)
    : baud_(std::max(baud, 1)), turnaround_(std::max(turnaround, std::chrono::nanoseconds{0})) {}

std::chrono::nanoseconds LinePacer::wire_time(std::size_t count) const {
  // 10 bits per byte (7E1: start, 7 data, parity, stop).
  return std::chrono::nanoseconds(static_cast<std::int64_t>(count) * 10'000'000'000LL / baud_);
}

LinePacer::Clock::time_point LinePacer::received(std::size_t n, Clock::time_point t) {
  const Clock::time_point from = rx_end_ && *rx_end_ > t ? *rx_end_ : t;
  rx_end_ = from + wire_time(n);
  return *rx_end_;
}

void LinePacer::push(ByteView reply, Clock::time_point input_end) {
  if (reply.empty()) return;
  Clock::time_point start = input_end + turnaround_;
  if (tx_end_ && *tx_end_ > start) start = *tx_end_;
  runs_.push_back(Run{start, reply.size(), 0});
  bytes_.insert(bytes_.end(), reply.begin(), reply.end());
  tx_end_ = start + wire_time(reply.size());
}

std::size_t LinePacer::take_due(Clock::time_point now, Bytes& out) {
  std::size_t taken = 0;
  while (!runs_.empty()) {
    Run& run = runs_.front();
    if (now < run.start) break;
    // The most bytes k whose end, start + wire_time(k), is not after now.
    const auto elapsed = std::min(std::chrono::nanoseconds(now - run.start), wire_time(run.size));
    auto k = static_cast<std::size_t>(elapsed.count() * baud_ / 10'000'000'000LL);
    while (k < run.size && wire_time(k + 1) <= elapsed) ++k;
    while (k > 0 && wire_time(k) > elapsed) --k;
    k = std::min(k, run.size);
    if (k <= run.sent) break;
    const std::size_t n = k - run.sent;
    out.insert(out.end(), bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(n));
    bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(n));
    run.sent = k;
    taken += n;
    if (run.sent < run.size) break;
    runs_.pop_front();
  }
  return taken;
}

std::optional<LinePacer::Clock::time_point> LinePacer::next_due() const {
  if (runs_.empty()) return std::nullopt;
  const Run& run = runs_.front();
  return run.start + wire_time(run.sent + 1);
}

}  // namespace sabus::harness
