// Line endpoints (pty, termios, libserialport, TCP) and the server loop.
//
// Built twice (tests/harness/line/CMakeLists.txt): as line_tests, and with
// SABUS_LINE_TESTS_UNDER_PTYSHIM as line_libserialport_tests, which ctest runs
// with LD_PRELOAD=ptyshim.so so that libserialport can open a pty
// (tests/support/ptyshim.c). Every read has a timeout; no test can hang.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "sabus/harness/line.hpp"
#include "sabus/harness/serve.hpp"

namespace sabus::harness {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// A path for a pty link, unique to this process and test.
std::string temp_link(const std::string& tag) {
  return ::testing::TempDir() + "sabus-line-" + std::to_string(::getpid()) + "-" + tag;
}

Bytes all_bytes() {
  Bytes b(256);
  for (int i = 0; i < 256; ++i) b[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  return b;
}

// Reads until `n` bytes came or `limit` passed; returns what came.
Bytes read_exactly(Line& line, std::size_t n, std::chrono::milliseconds limit = 5s) {
  Bytes got;
  const auto deadline = Clock::now() + limit;
  std::uint8_t buf[512];
  while (got.size() < n && Clock::now() < deadline) {
    const std::size_t want = std::min(sizeof buf, n - got.size());
    const std::size_t k = line.read(std::span<std::uint8_t>(buf, want), 50ms);
    got.insert(got.end(), buf, buf + k);
  }
  return got;
}

// Both directions, every byte value, in one write each.
void exchange_all_bytes(Line& a, Line& b) {
  const Bytes up = all_bytes();
  Bytes down(up.rbegin(), up.rend());
  a.write(up);
  EXPECT_EQ(read_exactly(b, up.size()), up);
  b.write(down);
  b.drain();
  EXPECT_EQ(read_exactly(a, down.size()), down);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const LineError& e) {
    return e.what();
  }
  return "(no LineError)";
}

// A LineDevice for tests: `answer` turns received bytes into reply bytes.
class ScriptDevice : public LineDevice {
 public:
  explicit ScriptDevice(std::function<void(ByteView, Bytes&)> answer) : answer_(std::move(answer)) {}
  void receive(ByteView wire, Bytes& out) override {
    answer_(wire, out);
    log_ += "received " + std::to_string(wire.size()) + " byte(s)\n";
  }
  void tick() override { ticks.fetch_add(1, std::memory_order_relaxed); }
  std::string take_log() override { return std::exchange(log_, {}); }
  std::atomic<long> ticks{0};

 private:
  std::function<void(ByteView, Bytes&)> answer_;
  std::string log_;
};

// Each byte back, inverted.
ScriptDevice inverting_device() {
  return ScriptDevice([](ByteView in, Bytes& out) {
    for (auto b : in) out.push_back(static_cast<std::uint8_t>(~b));
  });
}

// Runs serve()/serve_tcp() in a thread; stops and joins on destruction, so a
// failed assertion never leaves the thread running.
class Server {
 public:
  explicit Server(std::function<int(const std::atomic<bool>&)> run)
      : thread_([this, run] { rc_ = run(stop_); }) {}
  ~Server() { stop(); }
  int stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    return rc_;
  }
  // Waits (up to 5 s) for serve() to return by itself.
  int wait() {
    const auto deadline = Clock::now() + 5s;
    while (!done() && Clock::now() < deadline) std::this_thread::sleep_for(5ms);
    return stop();
  }

 private:
  bool done() const { return rc_ != -1; }
  std::atomic<bool> stop_{false};
  std::atomic<int> rc_{-1};
  std::thread thread_;
};

#ifndef SABUS_LINE_TESTS_UNDER_PTYSHIM

// ---- pty and termios ----

TEST(PtyLine, CarriesEveryByteBothWaysWithATermiosClient) {
  const std::string link = temp_link("both-ways");
  auto server = PtyLine::create(link);
  EXPECT_EQ(server->describe(), "pty " + server->slave_name() + " (link " + link + ")");
  auto client = TermiosSerialLine::open(link, 9600);
  EXPECT_EQ(client->describe(), "serial " + link + " (" + server->slave_name() + ") 9600 8N1 (termios)");
  exchange_all_bytes(*client, *server);
}

TEST(PtyLine, NoClientIsNoBytesNotALostLine) {
  auto server = PtyLine::create("");
  std::uint8_t buf[16];
  EXPECT_EQ(server->read(buf, 20ms), 0u);
  {  // a client comes and goes
    auto client = TermiosSerialLine::open(server->slave_name(), 9600);
    client->write(Bytes{0x31});
    EXPECT_EQ(read_exactly(*server, 1), Bytes{0x31});
  }
  EXPECT_EQ(server->read(buf, 20ms), 0u);
  auto again = TermiosSerialLine::open(server->slave_name(), 9600);  // exclusive flag was cleared
  exchange_all_bytes(*again, *server);
}

TEST(PtyLine, ReplacesAStaleLinkAndRemovesItsOwn) {
  const std::string link = temp_link("stale");
  ASSERT_EQ(::symlink("/dev/pts/does-not-exist", link.c_str()), 0);
  {
    auto server = PtyLine::create(link);
    char target[256] = {};
    ASSERT_GT(::readlink(link.c_str(), target, sizeof target - 1), 0);
    EXPECT_EQ(std::string(target), server->slave_name());
  }
  EXPECT_NE(::access(link.c_str(), F_OK), 0) << "the link outlived its server";
}

TEST(PtyLine, RefusesToReplaceAFileThatIsNotALink) {
  const std::string path = temp_link("regular-file");
  { std::ofstream(path) << "keep me\n"; }
  const std::string e = error_of([&] { PtyLine::create(path); });
  EXPECT_NE(e.find("is not a symbolic link; refusing to replace it"), std::string::npos) << e;
  std::ifstream in(path);
  std::string content;
  std::getline(in, content);
  EXPECT_EQ(content, "keep me");
  ::unlink(path.c_str());
}

TEST(TermiosSerialLine, ASecondOpenIsInUse) {
  auto server = PtyLine::create(temp_link("in-use"));
  auto first = TermiosSerialLine::open(server->link_path(), 9600);
  const std::string e = error_of([&] { TermiosSerialLine::open(server->link_path(), 9600); });
  EXPECT_NE(e.find(server->link_path() + " is in use by another process"), std::string::npos) << e;
  // The other backend honours the same lock, before libserialport touches the port.
  const std::string e2 = error_of([&] { LibSerialPortLine::open(server->link_path(), 9600); });
  EXPECT_NE(e2.find("is in use by another process"), std::string::npos) << e2;
  exchange_all_bytes(*first, *server);  // the refused opens did not disturb it
}

TEST(TermiosSerialLine, RefusesBadBaudRatesAndNonTerminals) {
  auto server = PtyLine::create("");
  const std::string e = error_of([&] { TermiosSerialLine::open(server->slave_name(), 12345); });
  EXPECT_NE(e.find("unsupported baud rate 12345"), std::string::npos) << e;
  const std::string e2 = error_of([] { TermiosSerialLine::open("/dev/null", 9600); });
  EXPECT_NE(e2.find("/dev/null is not a serial port"), std::string::npos) << e2;
  const std::string e3 = error_of([] { TermiosSerialLine::open("/dev/sabus-no-such-port", 9600); });
  EXPECT_NE(e3.find("no such device"), std::string::npos) << e3;
  for (int baud : {300, 1200, 4800, 9600, 19200, 115200}) EXPECT_NO_THROW(TermiosSerialLine::open(server->slave_name(), baud));
}

TEST(TermiosSerialLine, IsLostWhenThePtyServerGoes) {
  auto server = PtyLine::create("");
  auto client = TermiosSerialLine::open(server->slave_name(), 9600);
  server.reset();
  std::uint8_t buf[8];
  const std::string e = error_of([&] { client->read(buf, 2s); });
  EXPECT_NE(e.find("serial " + std::string("/dev/pts/")), std::string::npos) << e;
  std::printf("lost pty, as the client sees it: %s\n", e.c_str());
}

TEST(LibSerialPortLine, RefusesAPtyWithAClearMessageWithoutTheShim) {
  auto server = PtyLine::create(temp_link("lsp-refused"));
  const std::string e = error_of([&] { LibSerialPortLine::open(server->link_path(), 9600); });
  EXPECT_NE(e.find("pseudo-terminal"), std::string::npos) << e;
  EXPECT_NE(e.find("LIBSERIALPORT_DEBUG=1"), std::string::npos) << e;
  // The refusal released the lock.
  EXPECT_NO_THROW(TermiosSerialLine::open(server->link_path(), 9600));
}

TEST(OpenSerialLine, AutoPicksTermiosForAPtyAndSaysWhy) {
  auto server = PtyLine::create(temp_link("auto"));
  EXPECT_TRUE(is_pseudo_terminal(server->link_path()));
  EXPECT_TRUE(is_pseudo_terminal(server->slave_name()));
  EXPECT_FALSE(is_pseudo_terminal("/dev/null"));
  EXPECT_FALSE(is_pseudo_terminal("/dev/sabus-no-such-port"));
  std::string note;
  auto line = open_serial_line(server->link_path(), 9600, SerialBackend::automatic, &note);
  EXPECT_EQ(note, "serial backend termios: " + server->link_path() +
                      " is a pseudo-terminal, which libserialport 0.1.1 cannot open.");
  EXPECT_NE(line->describe().find("(termios)"), std::string::npos);
  exchange_all_bytes(*line, *server);
  EXPECT_EQ(parse_serial_backend("auto"), SerialBackend::automatic);
  EXPECT_EQ(parse_serial_backend("termios"), SerialBackend::termios);
  EXPECT_EQ(parse_serial_backend("libserialport"), SerialBackend::libserialport);
  EXPECT_EQ(parse_serial_backend("serial"), std::nullopt);
}

TEST(ListSerialPorts, ListsWhatLibserialportKnows) {
  std::vector<SerialPortInfo> ports;
  ASSERT_NO_THROW(ports = list_serial_ports());
  std::printf("%zu serial port(s) on this machine\n", ports.size());
  for (const auto& p : ports) {
    EXPECT_EQ(p.name.rfind("/dev/", 0), 0u) << p.name;
    std::printf("  %s  %s  %s\n", p.name.c_str(), std::string(to_string(p.transport)).c_str(), p.description.c_str());
  }
}

// ---- TCP ----

TEST(TcpLine, CarriesEveryByteBothWaysOnLoopback) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  ASSERT_NE(listener->port(), 0);
  EXPECT_EQ(listener->describe(), "tcp 127.0.0.1:" + std::to_string(listener->port()) + " (listening)");
  auto client = TcpLine::connect("127.0.0.1", listener->port(), 2s);
  auto served = listener->accept(2s);
  ASSERT_TRUE(served);
  EXPECT_EQ(client->describe(), "tcp 127.0.0.1:" + std::to_string(listener->port()));
  EXPECT_EQ(served->describe().rfind("tcp 127.0.0.1:" + std::to_string(listener->port()) + " (client 127.0.0.1:", 0),
            0u)
      << served->describe();
  exchange_all_bytes(*client, *served);
}

TEST(TcpLine, AClosedPeerIsALostLine) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  auto client = TcpLine::connect("127.0.0.1", listener->port(), 2s);
  auto served = listener->accept(2s);
  ASSERT_TRUE(served);
  client.reset();
  std::uint8_t buf[8];
  const std::string e = error_of([&] { served->read(buf, 2s); });
  EXPECT_NE(e.find("closed by the other side"), std::string::npos) << e;
  // Writing to a closed connection is an error too, not SIGPIPE.
  const std::string e2 = error_of([&] {
    for (int i = 0; i < 100; ++i) served->write(all_bytes());
  });
  EXPECT_NE(e2.find("closed by the other side"), std::string::npos) << e2;
}

TEST(TcpListener, AcceptTimesOutAndConnectIsRefusedWhenNobodyListens) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  EXPECT_EQ(listener->accept(20ms), nullptr);
  const std::uint16_t port = listener->port();
  listener.reset();
  const std::string e = error_of([&] { TcpLine::connect("127.0.0.1", port, 2s); });
  EXPECT_NE(e.find("cannot connect"), std::string::npos) << e;
}

// ---- the line timing model ----

TEST(LinePacer, HoldsAReplyForTurnaroundAndTenBitsPerByte) {
  LinePacer pacer(9600, 2ms);
  const auto bt = std::chrono::nanoseconds(1'041'666);  // 10/9600 s
  EXPECT_EQ(pacer.wire_time(1), bt);
  EXPECT_EQ(pacer.wire_time(52), std::chrono::nanoseconds(54'166'666));
  const Clock::time_point t0{};
  // A 5-byte request that came in at once ends 5 byte times later.
  const auto input_end = pacer.received(5, t0);
  EXPECT_EQ(input_end, t0 + pacer.wire_time(5));
  pacer.push(Bytes(52, 0x40), input_end);
  const auto start = input_end + 2ms;
  EXPECT_EQ(pacer.next_due(), start + bt);
  Bytes out;
  EXPECT_EQ(pacer.take_due(start + bt - 1ns, out), 0u);
  EXPECT_EQ(pacer.take_due(start + bt, out), 1u);
  EXPECT_EQ(pacer.take_due(start + pacer.wire_time(10), out), 9u);
  EXPECT_EQ(pacer.next_due(), start + pacer.wire_time(11));
  // Late by a lot: everything due goes at once, nothing early.
  EXPECT_EQ(pacer.take_due(start + pacer.wire_time(52) - 1ns, out), 41u);
  EXPECT_EQ(pacer.take_due(start + pacer.wire_time(52), out), 1u);
  EXPECT_EQ(out.size(), 52u);
  EXPECT_TRUE(pacer.empty());
  EXPECT_EQ(pacer.next_due(), std::nullopt);
}

TEST(LinePacer, RepliesNeverOvertakeTheWire) {
  LinePacer pacer(9600, 2ms);
  const Clock::time_point t0{};
  // Two requests read together; both replies queue, the second starts when
  // the first has left the wire, not 2 ms after its request.
  const auto end1 = pacer.received(5, t0);
  pacer.push(Bytes(52, 1), end1);
  const auto end2 = pacer.received(5, t0);
  EXPECT_EQ(end2, t0 + pacer.wire_time(10));  // input took its wire time too
  pacer.push(Bytes(5, 2), end2);
  Bytes out;
  const auto first_end = end1 + 2ms + pacer.wire_time(52);
  EXPECT_EQ(pacer.take_due(first_end, out), 52u);
  EXPECT_EQ(pacer.next_due(), first_end + pacer.wire_time(1));
  EXPECT_EQ(pacer.take_due(first_end + pacer.wire_time(5), out), 5u);
  // An idle line: the next reply waits only for its own turnaround.
  const Clock::time_point later = t0 + 1s;
  const auto end3 = pacer.received(1, later);
  pacer.push(Bytes{3}, end3);
  EXPECT_EQ(pacer.next_due(), later + pacer.wire_time(1) + 2ms + pacer.wire_time(1));
}

// ---- serve() ----

TEST(Serve, AnswersOverAPtyAndLogsWithTimestamps) {
  auto pty = PtyLine::create(temp_link("serve"));
  ScriptDevice device = inverting_device();
  std::ostringstream log;
  ServeOptions options;
  options.log = &log;
  Server server([&](const std::atomic<bool>& stop) { return serve(*pty, device, options, stop); });
  auto client = TermiosSerialLine::open(pty->link_path(), 9600);
  const Bytes request = all_bytes();
  client->write(request);
  const Bytes reply = read_exactly(*client, request.size());
  ASSERT_EQ(reply.size(), request.size());
  for (std::size_t i = 0; i < reply.size(); ++i) EXPECT_EQ(reply[i], static_cast<std::uint8_t>(~request[i]));
  EXPECT_EQ(server.stop(), 0);
  EXPECT_GT(device.ticks.load(), 0);
  // "   0.012 received 256 byte(s)" (possibly in several chunks)
  std::istringstream lines(log.str());
  std::string first;
  ASSERT_TRUE(std::getline(lines, first)) << log.str();
  EXPECT_TRUE(std::regex_match(first, std::regex(R"( *[0-9]+\.[0-9]{3} received [0-9]+ byte\(s\))"))) << first;
}

TEST(Serve, AnEmulatedLineTakesTheWireTime) {
  auto pty = PtyLine::create("");
  const Bytes request{0x02, 0x32, 0x31, 0x03, 0x02};
  ScriptDevice device([](ByteView in, Bytes& out) {
    static_cast<void>(in);
    out.assign(52, 0x40);
  });
  ServeOptions options;
  options.emulate_line = true;
  options.baud = 9600;
  options.turnaround_ms = 2.0;
  Server server([&](const std::atomic<bool>& stop) { return serve(*pty, device, options, stop); });
  auto client = TermiosSerialLine::open(pty->slave_name(), 9600);
  const auto t0 = Clock::now();
  client->write(request);
  const Bytes reply = read_exactly(*client, 52);
  const auto elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(reply, Bytes(52, 0x40));
  // Physics, a lower bound only: 52 bytes of 10 bits at 9600 baud after a
  // 2 ms turnaround cannot arrive sooner (the model also counts the request's
  // own 5 bytes). No upper bound: the machine may be slow.
  const double floor_s = 52 * 10.0 / 9600 + 0.002;
  std::printf("52-byte reply at 9600 baud: %.1f ms after the request (wire floor %.1f ms, model %.1f ms)\n",
              elapsed * 1e3, floor_s * 1e3, (57 * 10.0 / 9600 + 0.002) * 1e3);
  EXPECT_GE(elapsed, floor_s);
  EXPECT_EQ(server.stop(), 0);
}

TEST(Serve, ReturnsOneWhenTheLineIsLost) {
  auto pty = PtyLine::create("");
  auto line = TermiosSerialLine::open(pty->slave_name(), 9600);
  ScriptDevice device = inverting_device();
  Server server([&](const std::atomic<bool>& stop) { return serve(*line, device, ServeOptions{}, stop); });
  pty.reset();  // the other side goes away
  EXPECT_EQ(server.wait(), 1);
}

TEST(ServeTcp, ServesClientsOneAfterAnother) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  ScriptDevice device = inverting_device();
  std::ostringstream log;
  ServeOptions options;
  options.log = &log;
  Server server([&](const std::atomic<bool>& stop) { return serve_tcp(*listener, device, options, stop); });
  for (int round = 0; round < 3; ++round) {
    auto client = TcpLine::connect("127.0.0.1", listener->port(), 2s);
    client->write(Bytes{0x00, 0x0F, 0xF0});
    EXPECT_EQ(read_exactly(*client, 3), (Bytes{0xFF, 0xF0, 0x0F})) << "round " << round;
  }
  EXPECT_EQ(server.stop(), 0);
  const std::string text = log.str();
  std::size_t connected = 0;
  for (auto at = text.find("client connected"); at != std::string::npos; at = text.find("client connected", at + 1))
    ++connected;
  EXPECT_EQ(connected, 3u) << text;
  EXPECT_NE(text.find("client gone: "), std::string::npos) << text;
}

#else  // SABUS_LINE_TESTS_UNDER_PTYSHIM: libserialport on a pty, ptyshim.so preloaded

class LibSerialPortOverPty : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    ASSERT_TRUE(preload != nullptr && std::string(preload).find("ptyshim") != std::string::npos)
        << "run through ctest (harness.line.libserialport_over_pty): needs LD_PRELOAD=ptyshim.so";
  }
};

TEST_F(LibSerialPortOverPty, CarriesEveryByteBothWays) {
  auto server = PtyLine::create(temp_link("lsp-both-ways"));
  // Through the link: LibSerialPortLine resolves it to /dev/pts/N first.
  auto client = LibSerialPortLine::open(server->link_path(), 9600);
  EXPECT_EQ(client->describe(),
            "serial " + server->link_path() + " (" + server->slave_name() + ") 9600 8N1 (libserialport)");
  exchange_all_bytes(*client, *server);
  exchange_all_bytes(*server, *client);
}

TEST_F(LibSerialPortOverPty, ASecondOpenIsInUseWhicheverBackend) {
  auto server = PtyLine::create("");
  auto first = LibSerialPortLine::open(server->slave_name(), 9600);
  const std::string e = error_of([&] { LibSerialPortLine::open(server->slave_name(), 9600); });
  EXPECT_NE(e.find("is in use by another process"), std::string::npos) << e;
  const std::string e2 = error_of([&] { TermiosSerialLine::open(server->slave_name(), 9600); });
  EXPECT_NE(e2.find("is in use by another process"), std::string::npos) << e2;
  exchange_all_bytes(*first, *server);
}

TEST_F(LibSerialPortOverPty, IsLostWhenThePtyServerGoes) {
  auto server = PtyLine::create("");
  auto client = LibSerialPortLine::open(server->slave_name(), 9600);
  server.reset();
  std::uint8_t buf[8];
  const std::string e = error_of([&] { client->read(buf, 2s); });
  EXPECT_NE(e.find("(libserialport)"), std::string::npos) << e;
  std::printf("lost pty, as the libserialport client sees it: %s\n", e.c_str());
}

TEST_F(LibSerialPortOverPty, TheShimForwardsEverythingElse) {
  auto server = PtyLine::create("");
  // The port list walks /sys/class/tty through the forwarded calls; ptys
  // are still not in it.
  std::vector<SerialPortInfo> ports;
  ASSERT_NO_THROW(ports = list_serial_ports());
  for (const auto& p : ports) EXPECT_EQ(p.name.find("/dev/pts/"), std::string::npos) << p.name;
  // Other ioctls and other files are untouched: a plain termios client works.
  auto client = TermiosSerialLine::open(server->slave_name(), 9600);
  exchange_all_bytes(*client, *server);
}

TEST_F(LibSerialPortOverPty, ChosenExplicitlyItServesAndIsServed) {
  auto pty = PtyLine::create(temp_link("lsp-serve"));
  ScriptDevice device = inverting_device();
  Server server([&](const std::atomic<bool>& stop) { return serve(*pty, device, ServeOptions{}, stop); });
  std::string note;
  auto client = open_serial_line(pty->link_path(), 19200, SerialBackend::libserialport, &note);
  EXPECT_EQ(note, "serial backend libserialport, as asked.");
  const Bytes request = all_bytes();
  client->write(request);
  client->drain();
  const Bytes reply = read_exactly(*client, request.size());
  ASSERT_EQ(reply.size(), request.size());
  for (std::size_t i = 0; i < reply.size(); ++i) EXPECT_EQ(reply[i], static_cast<std::uint8_t>(~request[i]));
  EXPECT_EQ(server.stop(), 0);
}

#endif

}  // namespace
}  // namespace sabus::harness
