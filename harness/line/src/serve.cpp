// The server loop of `sabus sim` and the line timing model (LinePacer).
#include "sabus/harness/serve.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <string_view>

#include "sabus/harness/rfc2217.hpp"

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

// What a session asks its server between reads: whether to end it (another
// client takes over), and a baud rate the client set (RFC 2217).
struct SessionHooks {
  std::function<bool()> end_now;
  std::function<std::optional<int>()> baud_change;
};

SessionEnd run_session(Line& line, LineDevice& device, const ServeOptions& options, const std::atomic<bool>& stop,
                       Transcript& transcript, const SessionHooks& hooks = {}) {
  const milliseconds tick = std::max(options.tick, milliseconds{1});
  const auto turnaround = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::duration<double, std::milli>(std::max(options.turnaround_ms, 0.0)));
  LinePacer pacer(options.baud, turnaround);
  std::optional<LineFaultInjector> to_device, from_device;
  if (options.line_faults) {
    to_device.emplace(*options.line_faults);
    LineFaultSpec back = *options.line_faults;
    back.seed += 1;
    from_device.emplace(back);
  }
  // What the noisy line did, said when the session ends.
  struct SayFaults {
    Transcript& transcript;
    std::optional<LineFaultInjector>& in;
    std::optional<LineFaultInjector>& out;
    ~SayFaults() {
      if (in) transcript.note("line faults made: requests " + describe(in->tally()) + "; replies " + describe(out->tally()));
    }
  } say{transcript, to_device, from_device};
  std::array<std::uint8_t, 256> buf{};
  Bytes reply, due;
  std::optional<int> new_baud;
  try {
    while (!stop.load(std::memory_order_relaxed)) {
      if (hooks.end_now && hooks.end_now()) return {};
      if (hooks.baud_change)
        if (const auto baud = hooks.baud_change()) {
          new_baud = baud;
          transcript.note(fmt::format("client set {} baud{}", *baud,
                                      options.emulate_line ? ": the line is emulated at that rate" : ""));
        }
      // Replies already queued keep their times; the next ones take the new rate.
      if (new_baud && pacer.empty()) pacer = LinePacer(*std::exchange(new_baud, std::nullopt), turnaround);
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
        if (to_device) {
          const Bytes noisy = to_device->pass(ByteView(buf.data(), n));
          device.receive(noisy, reply);
        } else {
          device.receive(ByteView(buf.data(), n), reply);
        }
        if (from_device && !reply.empty()) reply = from_device->pass(reply);
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
  std::unique_ptr<TcpLine> next;  // a client that took over, served next
  std::string listener_error;
  while (!stop.load(std::memory_order_relaxed)) {
    std::unique_ptr<TcpLine> client = std::move(next);
    try {
      if (!client) client = listener.accept(tick);
    } catch (const LineError& e) {
      listener_error = e.what();
      break;
    }
    if (!client) {
      device.tick();  // the controller keeps running with nobody connected
      transcript.device_log(device.take_log());
      continue;
    }
    const std::string who = client->describe();
    const TcpLine* socket = client.get();  // still owned by `line` below
    transcript.note("client connected: " + who);
    std::unique_ptr<Line> line;
    Rfc2217ServerLine* telnet = nullptr;
    try {
      if (options.rfc2217) {
        auto server = std::make_unique<Rfc2217ServerLine>(
            std::move(client), options.baud,
            [&transcript](const std::string& text, bool) { transcript.note(text); });
        telnet = server.get();
        line = std::move(server);
      } else {
        line = std::move(client);
      }
    } catch (const LineError& e) {
      transcript.note(std::string("client gone: ") + e.what());
      continue;
    }
    SessionHooks hooks;
    // A newcomer while this client is served: refused at once, or served
    // instead (--takeover). Checked between reads, so never kept waiting.
    hooks.end_now = [&]() {
      std::unique_ptr<TcpLine> other;
      try {
        other = listener.accept(milliseconds{0});
      } catch (const LineError& e) {
        listener_error = e.what();
        return true;
      }
      if (!other) return false;
      if (socket->peer_closed()) {
        // The client before it left and its close is not read yet: the port
        // is free, so the newcomer is served, not refused.
        transcript.note("client gone: " + who + " closed the connection");
        next = std::move(other);
        return true;
      }
      if (options.takeover) {
        transcript.note("client " + other->describe() + " takes over from " + who + " (--takeover): " + who +
                        " disconnected");
        next = std::move(other);
        return true;
      }
      transcript.note("client refused: " + other->describe() + ": the port is in use by " + who);
      try {
        other->write(ByteView(reinterpret_cast<const std::uint8_t*>(kPortInUse.data()), kPortInUse.size()));
      } catch (const LineError&) {
        // it left already: nothing to tell it
      }
      return false;  // `other` is closed here
    };
    if (telnet != nullptr) hooks.baud_change = [telnet] { return telnet->take_baud_change(); };
    const SessionEnd end = run_session(*line, device, options, stop, transcript, hooks);
    if (!listener_error.empty()) break;
    if (end.lost) transcript.note("client gone: " + end.message);
    else if (!next) break;  // stopped
  }
  if (!listener_error.empty()) {
    transcript.note("listener failed: " + listener_error);
    std::cerr << "sabus: " << listener_error << "\n";
    return 1;
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
