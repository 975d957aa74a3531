// The runner's transports: in-process (virtual clock), a serial port over a
// pty served by serve() with the reference controllers, TCP against
// serve_tcp(), lost lines, exclusive open, true 7E1, and the timing helpers.
//
// Built twice (tests/harness/transport/CMakeLists.txt): as transport_tests, and with
// SABUS_TRANSPORT_TESTS_UNDER_PTYSHIM as transport_libserialport_tests, which
// ctest runs with LD_PRELOAD=ptyshim.so so that the libserialport backend can
// open a pty. Every read has a timeout; no test can hang.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/harness/serve.hpp"
#include "sabus/harness/timing.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/lrc.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness {
namespace {

using namespace std::chrono_literals;
using Steady = std::chrono::steady_clock;

// ---- helpers ----------------------------------------------------------------------

std::string temp_link(const std::string& tag) {
  return ::testing::TempDir() + "sabus-transport-" + std::to_string(::getpid()) + "-" + tag;
}

const Bytes kStatusPoll = encode_request(StatusPoll{}, '2');  // 02 32 31 03 02

// Receives until `n` bytes came or `limit` passed (in the transport's own
// time: virtual in-process); returns what came.
Bytes receive_bytes(Transport& t, std::size_t n, std::chrono::milliseconds limit = 5s) {
  Bytes got;
  const TimePoint deadline = t.now() + limit;
  std::uint8_t buf[512];
  while (got.size() < n && t.now() < deadline) {
    const std::size_t want = std::min(sizeof buf, n - got.size());
    const std::size_t k = t.receive(std::span<std::uint8_t>(buf, want), 50ms);
    got.insert(got.end(), buf, buf + k);
  }
  return got;
}

// Frames and discards of a receive stream, read as the runner reads replies.
struct Replies : ReceiverSink {
  std::vector<Frame> frames;
  std::vector<Discard> discards;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard& d) override { discards.push_back(d); }
};

Replies read_replies(const Transport& t, ByteView wire) {
  ReceiverOptions o = ReceiverOptions::master();
  o.parity = receiver_parity(t);
  Receiver r(o);
  Replies out;
  r.feed(wire, out);
  r.finish(out);
  return out;
}

// A 52-byte status reply from address '2' with even parity on every byte.
void expect_status_reply_on_the_wire(const Transport& t, const Bytes& wire) {
  ASSERT_EQ(wire.size(), 52u) << to_hex(wire);
  for (std::size_t i = 0; i < wire.size(); ++i) EXPECT_TRUE(has_even_parity(wire[i])) << "byte " << i;
  const Replies r = read_replies(t, wire);
  ASSERT_EQ(r.frames.size(), 1u);
  EXPECT_TRUE(r.discards.empty()) << r.discards.front().message();
  EXPECT_EQ(r.frames[0].kind, FrameKind::kAck);
  EXPECT_EQ(r.frames[0].address, '2');
  EXPECT_EQ(r.frames[0].command, 0x31);
  auto reply = decode_reply(r.frames[0]);
  ASSERT_TRUE(reply.ok()) << reply.error().message();
  EXPECT_TRUE(std::holds_alternative<StatusReply>(reply.value()));
}

template <class E>
std::string error_of_type(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("(other exception: ") + e.what() + ")";
  }
  return "(no exception)";
}

// Runs serve()/serve_tcp() in a thread; stops and joins on destruction.
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

 private:
  std::atomic<bool> stop_{false};
  std::atomic<int> rc_{-1};
  std::thread thread_;
};

// The reference controllers as served by `sabus sim`, recording the wire
// bytes both ways (read them after the server has stopped, or under lock).
class RecordingBus : public LineDevice {
 public:
  RecordingBus() : bus_({Profile{}}, clock_, {}, Parity::kEvenBit7) {}
  void receive(ByteView wire, Bytes& out) override {
    const std::size_t before = out.size();
    bus_.receive(wire, out);
    std::lock_guard lock(mutex_);
    heard_.insert(heard_.end(), wire.begin(), wire.end());
    said_.insert(said_.end(), out.begin() + static_cast<std::ptrdiff_t>(before), out.end());
  }
  void tick() override { bus_.tick(); }
  std::string take_log() override { return bus_.take_log(); }
  Bytes heard() {
    std::lock_guard lock(mutex_);
    return heard_;
  }
  Bytes said() {
    std::lock_guard lock(mutex_);
    return said_;
  }

 private:
  SteadyClock clock_;
  Bus bus_;
  std::mutex mutex_;
  Bytes heard_, said_;
};

// ---- software parity and the 7E1 marks (pure) ----------------------------------

TEST(SoftwareParity, SetsEvenParityAndInvertsItWhereAsked) {
  // 02 32 31 03 02: bits set 1, 3, 3, 2, 1.
  EXPECT_EQ(with_software_parity(kStatusPoll), (Bytes{0x82, 0xB2, 0xB1, 0x03, 0x82}));
  const std::size_t wrong[] = {1, 3};
  EXPECT_EQ(with_software_parity(kStatusPoll, wrong), (Bytes{0x82, 0x32, 0xB1, 0x83, 0x82}));
  const std::size_t past_end[] = {5};
  const std::string e = error_of_type<std::invalid_argument>([&] { with_software_parity(kStatusPoll, past_end); });
  EXPECT_EQ(e, "wrong parity asked for byte 5 of a 5-byte message");
}

TEST(ParityMarkDecoder, TurnsMarkedCharactersIntoBit7) {
  ParityMarkDecoder d;
  Bytes b{0x06, 0x32, 0xFF, 0x00, 0x41, 0x03, 0xFF, 0x00, 0x00, 0xFF, 0xFF};
  const std::size_t n = d.decode(b);
  b.resize(n);
  // 'A' with a parity error, a break (FF 00 00), an FF received as data.
  EXPECT_EQ(b, (Bytes{0x06, 0x32, 0xC1, 0x03, 0x80, 0xFF}));
  EXPECT_FALSE(d.inside_mark());
}

TEST(ParityMarkDecoder, CarriesAMarkAcrossReads) {
  for (std::size_t split = 1; split <= 2; ++split) {
    ParityMarkDecoder d;
    const Bytes all{0x31, 0xFF, 0x00, 0x32, 0x33};
    Bytes first(all.begin(), all.begin() + 1 + static_cast<std::ptrdiff_t>(split));
    Bytes second(all.begin() + 1 + static_cast<std::ptrdiff_t>(split), all.end());
    first.resize(d.decode(first));
    EXPECT_TRUE(d.inside_mark()) << "split " << split;
    second.resize(d.decode(second));
    EXPECT_EQ(first, Bytes{0x31}) << "split " << split;
    EXPECT_EQ(second, (Bytes{0xB2, 0x33})) << "split " << split;
  }
}

TEST(LineMode, NamesRoundTrip) {
  for (LineMode m : {LineMode::kSoftwareParity8N1, LineMode::kTrue7E1}) EXPECT_EQ(parse_line_mode(to_string(m)), m);
  EXPECT_EQ(to_string(LineMode::kSoftwareParity8N1), "software");
  EXPECT_EQ(to_string(LineMode::kTrue7E1), "7e1");
  EXPECT_EQ(parse_line_mode("8n1"), std::nullopt);
  EXPECT_EQ(to_string(CharFormat::k8N1), "8N1");
  EXPECT_EQ(to_string(CharFormat::k7E1), "7E1");
}

// ---- timing (pure, numbers only) ------------------------------------------------------

TEST(TransportTiming, ReplyTimeoutIsWireTimeTurnaroundAndAMargin) {
  // 9600 baud, status poll: (5 + 52) * 1041.67 us = 59374 us of wire time,
  // + 50 ms allowance + 20 ms host latency + 5937 us (10%) = 135.3 -> 136 ms.
  EXPECT_EQ(reply_timeout(9600, 5, 52, 50ms), 136ms);
  // 300 baud: 1900 ms of wire, + 50 + 20 + 190 = 2160 ms.
  EXPECT_EQ(reply_timeout(300, 5, 52, 50ms), 2160ms);
  // The longest reply (37h display, 169 bytes) at 9600 with no allowance:
  // 174 bytes = 181250 us, + 20 ms + 18125 us = 219.4 -> 220 ms.
  EXPECT_EQ(reply_timeout(9600, 5, 169, 0ms), 220ms);
  // In-process: no wire.
  EXPECT_EQ(reply_timeout(0, 5, 52, 50ms), 70ms);
  static_assert(reply_timeout(9600, 5, 52, 50ms) == 136ms, "a constant expression");
}

TEST(TransportTiming, SilenceWindowCoversTheTurnaroundAndTheLongestReply) {
  // A fast device: the floor holds. 100 ms + 52 bytes (54167 us) + 20 ms.
  EXPECT_EQ(silence_window(5ms, 9600, 52), 175ms);
  // A slow one: 3 x 50 ms + 169 bytes (176042 us) + 20 ms = 346.04 -> 347 ms.
  EXPECT_EQ(silence_window(50ms, 9600, 169), 347ms);
  // Exactly at the floor: 3 x 33334 us = 100.002 ms.
  EXPECT_EQ(silence_window(33334us, 9600, 0), 121ms);
  // Nothing measured yet, in-process: the floor and the latency.
  EXPECT_EQ(silence_window(0us, 0, 52), 120ms);
  // 300 baud, 58-byte extended status: 100 + 1933.3 + 20 = 2053.3 -> 2054 ms.
  EXPECT_EQ(silence_window(10ms, 300, 58), 2054ms);
}

TEST(TransportTiming, TurnaroundMeterKeepsTheMaxAndTheMean) {
  TurnaroundMeter m;
  EXPECT_EQ(m.count(), 0u);
  EXPECT_EQ(m.max(), 0us);
  EXPECT_EQ(m.mean(), 0us);
  const TimePoint t0{};
  m.record(t0, t0 + 2ms);
  m.record(t0 + 1s, t0 + 1s + 4ms);
  m.record(t0 + 2s, t0 + 2s + 9ms);
  m.record(t0 + 3s, t0 + 3s - 1ms);  // bytes before the estimated request end: 0
  EXPECT_EQ(m.count(), 4u);
  EXPECT_EQ(m.max(), 9ms);
  EXPECT_EQ(m.mean(), 3750us);  // (2 + 4 + 9 + 0) / 4 ms
  m.reset();
  EXPECT_EQ(m.count(), 0u);
  EXPECT_EQ(m.max(), 0us);
}

#ifndef SABUS_TRANSPORT_TESTS_UNDER_PTYSHIM

// ---- in process ---------------------------------------------------------------------

TEST(InProcessTransport, StatusPollRoundTripWithEvenParity) {
  auto t = make_in_process_transport({Profile{}});
  EXPECT_TRUE(t->in_process());
  EXPECT_TRUE(t->can_send_parity_errors());
  EXPECT_TRUE(t->parity_in_bit7());
  EXPECT_EQ(t->baud(), 0);
  EXPECT_EQ(t->describe(), "in-process reference controller rc3000-1.59 at 0x32 '2'");
  const TimePoint t0 = t->now();
  t->send(kStatusPoll);
  EXPECT_EQ(t->pending(), 52u);
  std::uint8_t buf[64];
  const std::size_t n = t->receive(buf, 1s);
  expect_status_reply_on_the_wire(*t, Bytes(buf, buf + n));
  EXPECT_EQ(t->now(), t0) << "a queued reply costs no time";
  EXPECT_EQ(t->pending(), 0u);
}

TEST(InProcessTransport, ReceiveHandsOutQueuedBytesInPieces) {
  auto t = make_in_process_transport({Profile{}});
  t->send(kStatusPoll);
  std::uint8_t buf[10];
  EXPECT_EQ(t->receive(buf, 1s), 10u);
  EXPECT_EQ(buf[0], with_even_parity(ACK));
  EXPECT_EQ(t->pending(), 42u);
}

TEST(InProcessTransport, AParityErrorIsIgnoredByTheController) {
  auto t = make_in_process_transport({Profile{}});
  const std::size_t wrong[] = {2};  // the command byte
  t->send(kStatusPoll, wrong);
  std::uint8_t buf[64];
  const TimePoint t0 = t->now();
  EXPECT_EQ(t->receive(buf, 500ms), 0u);
  EXPECT_EQ(t->now() - t0, 500ms);
  EXPECT_NE(t->bus().take_log().find("parity error"), std::string::npos);
  // The controller is not wedged: the next poll is answered.
  t->send(kStatusPoll);
  expect_status_reply_on_the_wire(*t, receive_bytes(*t, 52));
}

TEST(InProcessTransport, SilenceCostsNoWallTime) {
  auto t = make_in_process_transport({Profile{}});
  std::uint8_t buf[8];
  const auto wall0 = Steady::now();
  const TimePoint t0 = t->now();
  EXPECT_EQ(t->receive(buf, 10s), 0u);
  EXPECT_EQ(t->now() - t0, 10s);
  t->pause(2500ms);
  EXPECT_EQ(t->now() - t0, 12500ms);
  EXPECT_EQ(t->clock().now(), t->now());
  const auto wall = Steady::now() - wall0;
  EXPECT_LT(wall, 1s) << "12.5 s of virtual silence took "
                      << std::chrono::duration_cast<std::chrono::milliseconds>(wall).count() << " ms";
}

TEST(InProcessTransport, AMultiDropBusAnswersOnlyTheAddressedController) {
  auto t = make_in_process_transport(multi_drop(Profile{}, {'2', '3'}), FaultSet{Fault::kShortStatus});
  EXPECT_EQ(t->describe(), "in-process reference controllers rc3000-1.59-50 at 0x32 '2', rc3000-1.59-51 at 0x33 '3', "
            "faults: short-status");
  EXPECT_EQ(t->bus().size(), 2u);
  t->send(encode_request(StatusPoll{}, '3'));
  const Bytes wire = receive_bytes(*t, 51, 1s);
  ASSERT_EQ(wire.size(), 51u) << "one reply, one byte short (fault short-status)";
  EXPECT_EQ(wire[1] & 0x7F, '3');
  EXPECT_EQ(t->pending(), 0u);
}

TEST(InProcessTransport, PauseLetsTheControllerMove) {
  auto t = make_in_process_transport({Profile{}});
  t->send(encode_request(Jog{{'U', 'F', 1000}}, '2'));  // §3.4: up, fast, 1000 ms
  ASSERT_EQ(receive_bytes(*t, 52, 1s).size(), 52u);
  const double before = t->bus().controller(0).state().el.position;
  t->pause(500ms);
  const double after = t->bus().controller(0).state().el.position;
  EXPECT_NEAR(after - before, 0.5, 1e-6) << "1 deg/s fast for 0.5 s of virtual time";
}

// ---- serial port over a pty, served by serve() -------------------------------------

class SerialTransportOverPty : public ::testing::Test {
 protected:
  void SetUp() override {
    pty = PtyLine::create(temp_link(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    server = std::make_unique<Server>([this](const std::atomic<bool>& stop) { return serve(*pty, bus, {}, stop); });
  }
  void TearDown() override { server.reset(); }

  std::unique_ptr<PtyLine> pty;
  RecordingBus bus;
  std::unique_ptr<Server> server;
};

TEST_F(SerialTransportOverPty, StatusPollRoundTrip) {
  std::string note;
  auto t = make_serial_transport(pty->link_path(), 9600, SerialBackend::automatic, LineMode::kSoftwareParity8N1, &note);
  EXPECT_NE(note.find("serial backend termios"), std::string::npos) << note;
  EXPECT_FALSE(t->in_process());
  EXPECT_TRUE(t->can_send_parity_errors());
  EXPECT_TRUE(t->parity_in_bit7());
  EXPECT_EQ(t->baud(), 9600);
  EXPECT_EQ(t->describe(), "serial " + pty->link_path() + " (" + pty->slave_name() +
                               ") 9600 8N1 (termios), software even parity in bit 7");
  const TimePoint t0 = t->now();
  t->send(kStatusPoll);
  expect_status_reply_on_the_wire(*t, receive_bytes(*t, 52));
  const double ms = std::chrono::duration<double, std::milli>(t->now() - t0).count();
  std::printf("status poll round trip over a pty (no line emulation): %.2f ms\n", ms);
}

TEST_F(SerialTransportOverPty, SoftwareParityOnTheWireBothWays) {
  auto t = make_serial_transport(pty->link_path(), 9600);
  const std::size_t wrong[] = {2};
  t->send(kStatusPoll, wrong);  // ignored by the controller (§1: parity error)
  std::uint8_t buf[64];
  EXPECT_EQ(t->receive(buf, 300ms), 0u);
  t->send(kStatusPoll);
  const Bytes reply = receive_bytes(*t, 52);
  expect_status_reply_on_the_wire(*t, reply);
  server->stop();
  // What the controller heard: the parity bit in bit 7, wrong where asked.
  EXPECT_EQ(bus.heard(), (Bytes{0x82, 0xB2, 0x31, 0x03, 0x82, 0x82, 0xB2, 0xB1, 0x03, 0x82}));
  // What it said is what the transport returned, parity bit included.
  EXPECT_EQ(bus.said(), reply);
  EXPECT_EQ(reply[0], 0x06) << "ACK has two bits set: parity 0";
  EXPECT_EQ(reply[1], 0xB2) << "'2' has three bits set: parity 1";
}

TEST_F(SerialTransportOverPty, ASecondTransportOnThePortIsInUse) {
  auto first = make_serial_transport(pty->link_path(), 9600);
  const std::string e = error_of_type<LineError>([&] { make_serial_transport(pty->link_path(), 9600); });
  EXPECT_NE(e.find(pty->link_path() + " is in use by another process"), std::string::npos) << e;
  const std::string e2 = error_of_type<LineError>(
      [&] { make_serial_transport(pty->link_path(), 9600, SerialBackend::libserialport); });
  EXPECT_NE(e2.find("is in use by another process"), std::string::npos) << e2;
  first->send(kStatusPoll);  // the refused opens did not disturb the first
  expect_status_reply_on_the_wire(*first, receive_bytes(*first, 52));
}

TEST_F(SerialTransportOverPty, True7E1OnAPtyFailsWithAClearMessage) {
  for (SerialBackend b : {SerialBackend::automatic, SerialBackend::termios, SerialBackend::libserialport}) {
    const std::string e = error_of_type<LineError>(
        [&] { make_serial_transport(pty->link_path(), 9600, b, LineMode::kTrue7E1); });
    EXPECT_NE(e.find(pty->link_path() + " is a pseudo-terminal, which carries 8 data bits and no parity: it "
                                        "cannot be opened 7E1"),
              std::string::npos)
        << to_string(b) << ": " << e;
  }
  // The refusals released nothing they did not take: software parity opens.
  auto t = make_serial_transport(pty->link_path(), 9600);
  t->send(kStatusPoll);
  expect_status_reply_on_the_wire(*t, receive_bytes(*t, 52));
}

TEST_F(SerialTransportOverPty, ALostLineIsTransportLost) {
  auto t = make_serial_transport(pty->link_path(), 9600);
  server->stop();
  pty.reset();  // the other side goes away
  std::uint8_t buf[8];
  const std::string e = error_of_type<TransportLost>([&] { t->receive(buf, 2s); });
  EXPECT_EQ(e.rfind("serial ", 0), 0u) << e;
  std::printf("lost pty, as the transport reports it: %s\n", e.c_str());
}

TEST(Set7E1, APtyDoesNotTakeItEvenWhenAsked) {
  // Below check_char_format: the read-back catches a port that keeps 8N1.
  auto server = PtyLine::create("");
  auto client = TermiosSerialLine::open(server->slave_name(), 9600);
  const std::string e = error_of_type<LineError>([&] {
    // Through a second fd on the same slave (the client's is private).
    UniqueFd fd(::open(server->slave_name().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
    ASSERT_TRUE(fd);
    posix::set_7e1(fd.get(), "pty " + server->slave_name());
  });
  EXPECT_NE(e.find("the port did not accept 7E1 (7 data bits, even parity)"), std::string::npos) << e;
}

// ---- the 7E1 transport's own logic, over an 8N1 pty standing in for the UART ----

TEST(LineTransport, True7E1SendsSevenBitsAndDecodesTheUartsMarks) {
  auto server = PtyLine::create("");
  LineTransport t(TermiosSerialLine::open(server->slave_name(), 9600), LineMode::kTrue7E1, 9600);
  EXPECT_FALSE(t.can_send_parity_errors());
  EXPECT_FALSE(t.parity_in_bit7());
  EXPECT_NE(t.describe().find(", parity by the UART (true 7E1)"), std::string::npos) << t.describe();
  t.send(kStatusPoll);
  std::uint8_t buf[64];
  std::size_t n = 0;
  for (int i = 0; i < 20 && n < kStatusPoll.size(); ++i) n += server->read(std::span(buf + n, 64 - n), 50ms);
  EXPECT_EQ(Bytes(buf, buf + n), kStatusPoll) << "no parity bit: the UART makes it";
  const std::size_t wrong[] = {1};
  const std::string e = error_of_type<std::invalid_argument>([&] { t.send(kStatusPoll, wrong); });
  EXPECT_NE(e.find("cannot send wrong parity"), std::string::npos) << e;

  // What a 7E1 port with PARMRK delivers: 'A' with a parity error as FF 00 41.
  server->write(Bytes{0x06, 0x32, 0xFF, 0x00, 0x41, 0x03});
  Bytes got;
  for (int i = 0; i < 20 && got.size() < 4; ++i) {
    const std::size_t k = t.receive(buf, 50ms);
    got.insert(got.end(), buf, buf + k);
  }
  EXPECT_EQ(got, (Bytes{0x06, 0x32, 0xC1, 0x03}));
  // The receiver the transport asks for reports that byte.
  const Replies r = read_replies(t, got);
  ASSERT_FALSE(r.discards.empty());
  EXPECT_EQ(r.discards.front().reason, DiscardReason::kNotAscii);

  // A mark split across reads: its first byte alone gives nothing yet.
  server->write(Bytes{0xFF});
  EXPECT_EQ(t.receive(buf, 50ms), 0u);
  server->write(Bytes{0x00, 0x31});
  Bytes rest;
  for (int i = 0; i < 20 && rest.empty(); ++i) {
    const std::size_t k = t.receive(buf, 50ms);
    rest.insert(rest.end(), buf, buf + k);
  }
  EXPECT_EQ(rest, Bytes{0xB1});
}

// ---- TCP ------------------------------------------------------------------------

TEST(TcpTransport, StatusPollRoundTripAgainstServeTcp) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  RecordingBus bus;
  Server server([&](const std::atomic<bool>& stop) { return serve_tcp(*listener, bus, {}, stop); });
  auto t = make_tcp_transport("127.0.0.1", listener->port(), 2s);
  EXPECT_TRUE(t->can_send_parity_errors());
  EXPECT_TRUE(t->parity_in_bit7());
  EXPECT_EQ(t->baud(), 9600);
  EXPECT_EQ(t->describe(), "tcp 127.0.0.1:" + std::to_string(listener->port()) + ", software even parity in bit 7");
  const std::size_t wrong[] = {0};
  t->send(kStatusPoll, wrong);
  std::uint8_t buf[64];
  EXPECT_EQ(t->receive(buf, 300ms), 0u);
  t->send(kStatusPoll);
  expect_status_reply_on_the_wire(*t, receive_bytes(*t, 52));
  EXPECT_EQ(server.stop(), 0);
  EXPECT_EQ(bus.heard().front(), 0x02) << "STX with its parity bit inverted";
}

TEST(TcpTransport, AClosedServerIsTransportLost) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  RecordingBus bus;
  auto server = std::make_unique<Server>(
      [&](const std::atomic<bool>& stop) { return serve_tcp(*listener, bus, {}, stop); });
  auto t = make_tcp_transport("127.0.0.1", listener->port(), 2s);
  t->send(kStatusPoll);  // a round trip: the server has accepted the connection
  ASSERT_EQ(receive_bytes(*t, 52).size(), 52u);
  server.reset();  // serve_tcp returns and closes the connection
  std::uint8_t buf[8];
  const std::string e = error_of_type<TransportLost>([&] { t->receive(buf, 2s); });
  EXPECT_NE(e.find("closed by the other side"), std::string::npos) << e;
  // Sending on it fails the same way (no SIGPIPE).
  const std::string e2 = error_of_type<TransportLost>([&] {
    for (int i = 0; i < 100; ++i) t->send(kStatusPoll);
  });
  EXPECT_NE(e2.find("closed by the other side"), std::string::npos) << e2;
}

TEST(TcpTransport, NobodyListeningIsALineErrorAtConnect) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  const std::uint16_t port = listener->port();
  listener.reset();
  const std::string e = error_of_type<LineError>([&] { make_tcp_transport("127.0.0.1", port, 2s); });
  EXPECT_NE(e.find("cannot connect"), std::string::npos) << e;
}

#else  // SABUS_TRANSPORT_TESTS_UNDER_PTYSHIM: libserialport on a pty, ptyshim.so preloaded

class LibSerialPortTransport : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    ASSERT_TRUE(preload != nullptr && std::string(preload).find("ptyshim") != std::string::npos)
        << "run through ctest (transport_libserialport_tests): needs LD_PRELOAD=ptyshim.so";
  }
};

TEST_F(LibSerialPortTransport, StatusPollRoundTripAndParityOnTheWire) {
  auto pty = PtyLine::create(temp_link("lsp"));
  RecordingBus bus;
  Server server([&](const std::atomic<bool>& stop) { return serve(*pty, bus, {}, stop); });
  std::string note;
  auto t = make_serial_transport(pty->link_path(), 9600, SerialBackend::libserialport,
                                 LineMode::kSoftwareParity8N1, &note);
  EXPECT_EQ(note, "serial backend libserialport, as asked.");
  EXPECT_NE(t->describe().find("9600 8N1 (libserialport), software even parity in bit 7"), std::string::npos)
      << t->describe();
  const std::size_t wrong[] = {4};
  t->send(kStatusPoll, wrong);
  std::uint8_t buf[64];
  EXPECT_EQ(t->receive(buf, 300ms), 0u);
  t->send(kStatusPoll);
  expect_status_reply_on_the_wire(*t, receive_bytes(*t, 52));
  EXPECT_EQ(server.stop(), 0);
  EXPECT_EQ(bus.heard(), (Bytes{0x82, 0xB2, 0xB1, 0x03, 0x02, 0x82, 0xB2, 0xB1, 0x03, 0x82}));
}

TEST_F(LibSerialPortTransport, SecondOpenIsInUseAnd7E1IsRefused) {
  auto pty = PtyLine::create(temp_link("lsp-in-use"));
  auto first = make_serial_transport(pty->link_path(), 9600, SerialBackend::libserialport);
  const std::string e = error_of_type<LineError>(
      [&] { make_serial_transport(pty->link_path(), 9600, SerialBackend::libserialport); });
  EXPECT_NE(e.find("is in use by another process"), std::string::npos) << e;
  first.reset();
  const std::string e2 = error_of_type<LineError>(
      [&] { make_serial_transport(pty->link_path(), 9600, SerialBackend::libserialport, LineMode::kTrue7E1); });
  EXPECT_NE(e2.find("is a pseudo-terminal, which carries 8 data bits and no parity"), std::string::npos) << e2;
}

TEST_F(LibSerialPortTransport, ALostLineIsTransportLost) {
  auto pty = PtyLine::create("");
  auto t = make_serial_transport(pty->slave_name(), 9600, SerialBackend::libserialport);
  pty.reset();
  std::uint8_t buf[8];
  const std::string e = error_of_type<TransportLost>([&] { t->receive(buf, 2s); });
  EXPECT_NE(e.find("(libserialport)"), std::string::npos) << e;
}

#endif

}  // namespace
}  // namespace sabus::harness
