// `sabus proxy`: a man-in-the-middle between an M&C system and the controller.
// Bytes pass through unchanged in both directions (poll() on both sides, no
// pacing of its own); every chunk, and every frame or ignored run the §1
// receiver finds in it, is logged as one JSON line (tools/PROXY-LOG.md).
#include <fmt/format.h>
#include <poll.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <deque>
#include <fstream>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "device.hpp"
#include "sabus/harness/capture.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/protocol/lrc.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;

std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int) { g_stop = true; }

struct ProxyOptions {
  std::string listen_pty, listen_tcp, port, tcp, log;
  std::string line = "8N1", serial_backend = "auto";
  int baud = 9600;
};

// The log: one JSON object a line, flushed as it is written so that a
// killed proxy leaves every exchange it forwarded.
class ProxyLogger {
 public:
  ProxyLogger(std::ostream& out, Parity device_parity)
      : out_(out), start_(std::chrono::steady_clock::now()) {
    ReceiverOptions req = ReceiverOptions::slave_any_address();  // every address on the line
    ReceiverOptions rep = ReceiverOptions::master();
    rep.parity = device_parity;
    sides_[0].rx = Receiver(req);
    sides_[1].rx = Receiver(rep);
  }
  // A log that cannot be written (a full disk) is said once; the bytes go on
  // being forwarded: the M&C system and the controller are not the log's.
  void write(const nlohmann::json& record) {
    out_ << proxy_log_line(record) << std::flush;
    if (!out_ && !lost_) {
      lost_ = true;
      std::cerr << "sabus proxy: the log cannot be written (" << std::strerror(errno)
                << "); forwarding goes on, unlogged\n";
    }
  }
  double now_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  // A chunk read from one side (as read, before it is forwarded).
  void chunk(Direction d, ByteView wire) {
    const double t = now_ms();
    write(proxy_chunk(t, d, wire));
    Side& s = side(d);
    s.history.insert(s.history.end(), wire.begin(), wire.end());
    Sink sink;
    s.rx.feed(wire, sink);
    emit(d, t, sink);
    trim(s);
  }
  void event(std::string_view what, const std::string& detail) { write(proxy_event(now_ms(), what, detail)); }
  // End of the session: a partial frame is logged as incomplete.
  void finish() {
    for (Direction d : {Direction::kToDevice, Direction::kFromDevice}) {
      Sink sink;
      side(d).rx.finish(sink);
      emit(d, now_ms(), sink);
    }
  }

 private:
  struct Event {
    bool frame;
    Bytes chars;
    Discard discard{};
  };
  struct Sink : ReceiverSink {
    std::vector<Event> events;
    void on_frame(const FrameView& f) override { events.push_back({true, Bytes(f.bytes.begin(), f.bytes.end())}); }
    void on_discard(const Discard& d) override { events.push_back({false, {}, d}); }
  };
  struct Side {
    Receiver rx;
    std::deque<std::uint8_t> history;  // the last bytes of the stream, for the hex of a discarded run
    std::uint64_t history_start = 0;   // stream offset of history.front()
  };
  static constexpr std::size_t kHistory = 4096;

  Side& side(Direction d) { return sides_[d == Direction::kToDevice ? 0 : 1]; }
  static void trim(Side& s) {
    while (s.history.size() > kHistory) {
      s.history.pop_front();
      ++s.history_start;
    }
  }
  Bytes slice(const Side& s, std::uint64_t offset, std::uint64_t length) const {
    Bytes out;
    for (std::uint64_t i = std::max(offset, s.history_start); i < offset + length && i - s.history_start < s.history.size(); ++i)
      out.push_back(s.history[i - s.history_start]);
    return out;
  }
  void emit(Direction d, double t, const Sink& sink) {
    for (const auto& e : sink.events) {
      if (!e.frame) {
        write(proxy_discard(t, d, e.discard, slice(side(d), e.discard.offset, e.discard.length)));
      } else if (d == Direction::kToDevice) {
        // §1: the addressed device answers each command; a reply belongs to
        // the last command before it.
        last_request_ = ++seq_;
        write(proxy_frame(t, d, e.chars, seq_, std::nullopt));
      } else {
        write(proxy_frame(t, d, e.chars, std::nullopt, last_request_));
      }
    }
  }

  std::ostream& out_;
  bool lost_ = false;  // the log failed to be written; said once
  std::chrono::steady_clock::time_point start_;
  Side sides_[2] = {{Receiver(ReceiverOptions::slave_any_address()), {}, 0}, {Receiver(ReceiverOptions::master()), {}, 0}};
  std::uint64_t seq_ = 0;
  std::optional<std::uint64_t> last_request_;
};

std::unique_ptr<Line> open_device(const ProxyOptions& o) {
  if (!o.tcp.empty()) {
    auto hp = parse_host_port(o.tcp);
    return TcpLine::connect(hp->host, hp->port, std::chrono::seconds(5));
  }
  if (is_rfc2217_url(o.port)) {
    std::string error;
    const auto url = parse_rfc2217_url(o.port, error);
    if (!url) throw LineError("--port " + error);
    return Rfc2217Line::connect(url->host, url->port, o.baud, o.line == "7E1" ? CharFormat::k7E1 : CharFormat::k8N1,
                                std::chrono::seconds(5), telnet_note("proxy"));
  }
  std::string note;
  const auto backend = parse_serial_backend(o.serial_backend).value_or(SerialBackend::automatic);
  auto line = open_serial_line(o.port, o.baud, backend, o.line == "7E1" ? CharFormat::k7E1 : CharFormat::k8N1, &note);
  if (!note.empty() && verbose()) std::cerr << "sabus proxy: " << note << "\n";
  return line;
}

// The option combinations proxy takes; false after saying what is wrong.
bool check_options(const ProxyOptions& o, std::optional<HostPort>& listen_tcp) {
  if ((o.listen_pty.empty() ? 0 : 1) + (o.listen_tcp.empty() ? 0 : 1) != 1) {
    std::cerr << "sabus proxy: choose one M&C side: --listen-pty LINK or --listen-tcp HOST:PORT\n";
    return false;
  }
  if ((o.port.empty() ? 0 : 1) + (o.tcp.empty() ? 0 : 1) != 1) {
    std::cerr << "sabus proxy: choose one device side: --port DEV or --tcp HOST:PORT\n";
    return false;
  }
  if (!o.listen_tcp.empty() && !(listen_tcp = parse_host_port(o.listen_tcp))) {
    std::cerr << "sabus proxy: --listen-tcp HOST:PORT, with a port 0-65535\n";
    return false;
  }
  if (!o.tcp.empty() && !parse_host_port(o.tcp)) {
    std::cerr << "sabus proxy: --tcp HOST:PORT, with a port 0-65535\n";
    return false;
  }
  if (o.line == "7E1" && o.port.empty()) {
    std::cerr << "sabus proxy: --line 7E1 needs --port (a serial port)\n";
    return false;
  }
  return true;
}

// Forwards bytes both ways until a signal or a lost line; the exit status.
int forward(Line& device_line, PtyLine* pty, TcpListener* listener, ProxyLogger& log, bool true_7e1) {
  Line* device = &device_line;
  std::unique_ptr<TcpLine> client;
  Line* mc = pty;
  std::uint8_t buf[4096];
  int status = kExitOk;
  while (!g_stop) {
    pollfd fds[2] = {{device->poll_fd(), POLLIN, 0}, {-1, POLLIN, 0}};
    fds[1].fd = mc ? mc->poll_fd() : -1;
    // The listener's fd is not exposed: with no client, accept() waits
    // instead of poll(), a few ms at a time.
    const int timeout = (!mc && listener) ? 0 : 50;
    const int ready = poll(fds, 2, timeout);
    if (ready < 0 && errno != EINTR) {
      log.event("error", std::string("poll: ") + std::strerror(errno));
      status = kExitFailed;
      break;
    }
    try {
      if (fds[0].revents != 0) {
        const std::size_t n = device->read(buf, std::chrono::milliseconds(0));
        if (n > 0) {
          const ByteView in(buf, n);
          log.chunk(Direction::kFromDevice, in);
          if (mc) {
            try {
              mc->write(true_7e1 ? ByteView(add_even_parity(in)) : in);
            } catch (const LineError& e) {
              if (pty) throw;  // a pty with its slave held open does not go away
              log.event("client lost", e.what());
              client.reset();
              mc = nullptr;
            }
          }
        }
      }
    } catch (const LineError& e) {
      log.event("device lost", e.what());
      std::cerr << "sabus proxy: device lost: " << e.what() << "\n";
      status = kExitStopped;
      break;
    }
    if (mc && fds[1].revents != 0) {
      std::size_t n = 0;
      try {
        n = mc->read(buf, std::chrono::milliseconds(0));
      } catch (const LineError& e) {
        if (pty) {
          log.event("error", e.what());
          status = kExitFailed;
          break;
        }
        log.event("client lost", e.what());
        client.reset();
        mc = nullptr;
      }
      if (n > 0) {
        log.chunk(Direction::kToDevice, ByteView(buf, n));
        try {
          device->write(ByteView(buf, n));
        } catch (const LineError& e) {
          log.event("device lost", e.what());
          std::cerr << "sabus proxy: device lost: " << e.what() << "\n";
          status = kExitStopped;
          break;
        }
      }
    }
    if (!mc && listener) {
      try {
        client = listener->accept(std::chrono::milliseconds(20));
      } catch (const LineError& e) {
        log.event("error", e.what());
        status = kExitFailed;
        break;
      }
      if (client) {
        mc = client.get();
        log.event("client connected", client->describe());
      }
    }
  }
  return status;
}

int run_proxy(const ProxyOptions& o) {
  std::optional<HostPort> listen_tcp;
  if (!check_options(o, listen_tcp)) return kExitUsage;
  std::ofstream log_file;
  if (!o.log.empty()) {
    log_file.open(o.log, std::ios::trunc);
    if (!log_file) {
      std::cerr << "sabus proxy: cannot write " << o.log << "\n";
      return kExitUsage;
    }
  }
  std::ostream& log_out = o.log.empty() ? std::cout : log_file;

  std::unique_ptr<Line> device;
  try {
    device = open_device(o);
  } catch (const LineError& e) {
    std::cerr << "sabus proxy: cannot reach the device: " << e.what() << "\n";
    return kExitUnreachable;
  }
  std::unique_ptr<PtyLine> pty;
  std::unique_ptr<TcpListener> listener;
  try {
    if (listen_tcp) listener = TcpListener::listen(listen_tcp->host, listen_tcp->port);
    else pty = PtyLine::create(o.listen_pty);
  } catch (const LineError& e) {
    std::cerr << "sabus proxy: " << e.what() << "\n";
    return kExitFailed;
  }
  const std::string mc_side = pty ? pty->describe() : listener->describe();

  // A true 7E1 port hands over 7-bit characters; the M&C side (a pty or a
  // socket) carries 8 bits, where SAbus's parity travels in bit 7 (line.hpp).
  const bool true_7e1 = o.line == "7E1";
  ProxyLogger log(log_out, true_7e1 ? Parity::kNone : Parity::kEvenBit7);
  log.write(proxy_header(mc_side, device->describe(), true_7e1 ? "7E1" : "8N1"));
  if (!o.log.empty())
    std::cout << (pty ? "READY " + o.listen_pty : fmt::format("READY tcp {}:{}", listen_tcp->host, listener->port()))
              << std::endl;

  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);  // no SA_RESTART: poll() returns at once
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  int status = forward(*device, pty.get(), listener.get(), log, true_7e1);
  log.finish();
  if (status == kExitOk) log.event("stop", "signal");
  return status;
}

}  // namespace

Command add_proxy_command(CLI::App& app) {
  auto o = std::make_shared<ProxyOptions>();
  CLI::App* sub = app.add_subcommand(
      "proxy", "Forward bytes between an M&C system and the controller unchanged, logging every exchange decoded");
  sub->add_option("--listen-pty", o->listen_pty, "M&C side: create a pseudo-terminal and link LINK to it");
  sub->add_option("--listen-tcp", o->listen_tcp, "M&C side: accept one TCP client at a time on HOST:PORT (port 0: any)");
  sub->add_option("--port", o->port, "Device side: a serial port (a pty works too), or rfc2217://HOST:PORT (a terminal server)");
  sub->add_option("--tcp", o->tcp, "Device side: a TCP serial server HOST:PORT");
  sub->add_option("--baud", o->baud, "Device side baud rate")->check(kBaudRange);
  sub->add_option("--line", o->line, "8N1 (default: parity in bit 7, forwarded as is) or 7E1 (a true 7E1 port)")
      ->check(CLI::IsMember({"8N1", "7E1"}));
  add_serial_backend_option(sub, o->serial_backend);
  sub->add_option("--log", o->log, "Write the log (JSON Lines, tools/PROXY-LOG.md) to FILE (default: stdout)");
  return {sub, [o] { return run_proxy(*o); }};
}

}  // namespace sabus::cli
