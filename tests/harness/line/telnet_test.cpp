// The Telnet/RFC 2217 layer (harness/line telnet.hpp, rfc2217.hpp): escaping,
// the decoder fed in any chunking, garbled subnegotiations, option
// negotiation that cannot loop, and the client and server lines against
// each other and against servers that do not negotiate.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "sabus/harness/rfc2217.hpp"
#include "sabus/harness/telnet.hpp"

namespace sabus::harness {
namespace {

using namespace telnet;
using namespace std::chrono_literals;

struct Decoded {
  Bytes data;
  std::vector<std::string> events;  // describe() of each event, in order
  bool operator==(const Decoded&) const = default;
};

// Feeds `stream` in chunks of the given sizes (the rest in one last chunk).
Decoded decode_in(ByteView stream, const std::vector<std::size_t>& sizes) {
  Decoder d;
  Decoded out;
  std::vector<Event> events;
  std::size_t at = 0;
  for (std::size_t s : sizes) {
    s = std::min(s, stream.size() - at);
    d.feed(stream.subspan(at, s), out.data, events);
    at += s;
  }
  d.feed(stream.subspan(at), out.data, events);
  for (const auto& e : events) out.events.push_back(describe(e));
  return out;
}

Decoded decode(ByteView stream) { return decode_in(stream, {}); }

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

TEST(Telnet, AnFFInDataIsDoubledAndComesBackAtEveryPosition) {
  for (std::size_t at = 0; at < 6; ++at) {
    Bytes data = {0x02, 0x32, 0x31, 0x7F, 0x03, 0x30};
    data[at] = 0xFF;
    const Bytes wire = escaped(data);
    ASSERT_EQ(wire.size(), data.size() + 1) << "position " << at;
    EXPECT_EQ(wire[at], 0xFF);
    EXPECT_EQ(wire[at + 1], 0xFF);
    const Decoded back = decode(wire);
    EXPECT_EQ(back.data, data) << "position " << at;
    EXPECT_TRUE(back.events.empty());
  }
  const Bytes all(7, 0xFF);
  EXPECT_EQ(escaped(all).size(), 14u);
  EXPECT_EQ(decode(escaped(all)).data, all);
}

// A stream with everything a server sends: data with FFs, negotiation, a
// subnegotiation holding an escaped FF, a NOP.
Bytes busy_stream() {
  return cat({escaped(Bytes{0x02, 0xFF, 0x31}), negotiation(kDO, kBinary),
              subnegotiation(kComPortOption, Bytes{101, 0x00, 0x00, 0x25, 0xFF}), Bytes{0xB1, kIAC, kNOP},
              escaped(Bytes{0xFF, 0xFF, 0x03}), negotiation(kWILL, kComPortOption)});
}

TEST(Telnet, SplitAtEveryByteBoundaryDecodesAsWhole) {
  const Bytes stream = busy_stream();
  const Decoded whole = decode(stream);
  EXPECT_EQ(whole.data, (Bytes{0x02, 0xFF, 0x31, 0xB1, 0xFF, 0xFF, 0x03}));
  ASSERT_EQ(whole.events.size(), 4u);
  EXPECT_EQ(whole.events[0], "DO BINARY");
  EXPECT_EQ(whole.events[1], "SB COM-PORT-OPTION SERVER SET-BAUDRATE 00 00 25 ff");
  EXPECT_EQ(whole.events[2], "NOP");
  EXPECT_EQ(whole.events[3], "WILL COM-PORT-OPTION");
  for (std::size_t i = 0; i <= stream.size(); ++i)
    EXPECT_EQ(decode_in(stream, {i}), whole) << "split at " << i;
  for (std::size_t i = 0; i <= stream.size(); ++i)
    for (std::size_t j = 0; i + j <= stream.size(); ++j)
      ASSERT_EQ(decode_in(stream, {i, j}), whole) << "split at " << i << " and " << i + j;
  EXPECT_EQ(decode_in(stream, std::vector<std::size_t>(stream.size(), 1)), whole) << "one byte at a time";
}

TEST(Telnet, SubnegotiationsInterleavedWithDataKeepTheirOrder) {
  const Bytes stream = cat({Bytes{'a'}, subnegotiation(kComPortOption, Bytes{106, 0x04}), Bytes{'b'},
                            negotiation(kWILL, kSuppressGoAhead), Bytes{'c'},
                            subnegotiation(kComPortOption, Bytes{107, 0xB0}), Bytes{'d'}});
  const Decoded d = decode(stream);
  EXPECT_EQ(d.data, (Bytes{'a', 'b', 'c', 'd'}));
  EXPECT_EQ(d.events, (std::vector<std::string>{"SB COM-PORT-OPTION SERVER NOTIFY-LINESTATE 04",
                                                "WILL SUPPRESS-GO-AHEAD",
                                                "SB COM-PORT-OPTION SERVER NOTIFY-MODEMSTATE b0"}));
}

TEST(Telnet, APeerThatSendsOnlyNegotiationGivesNoData) {
  const Bytes stream = cat({negotiation(kDO, kBinary), negotiation(kWILL, kBinary), negotiation(kDONT, kEcho),
                            subnegotiation(kComPortOption, Bytes{107, 0x00})});
  const Decoded d = decode(stream);
  EXPECT_TRUE(d.data.empty());
  EXPECT_EQ(d.events.size(), 4u);
}

TEST(Telnet, ASubnegotiationCutShortIsAnErrorAndTheCommandAfterItCounts) {
  // IAC SB COM-PORT 1 2 then IAC WILL ECHO without IAC SE.
  const Bytes stream = {kIAC, kSB, kComPortOption, 1, 2, kIAC, kWILL, kEcho, 'x'};
  const Decoded d = decode(stream);
  EXPECT_EQ(d.data, Bytes{'x'});
  ASSERT_EQ(d.events.size(), 2u);
  EXPECT_EQ(d.events[0], "error: subnegotiation of COM-PORT-OPTION cut short by IAC 251 (no IAC SE): dropped");
  EXPECT_EQ(d.events[1], "WILL ECHO");
  for (std::size_t i = 0; i <= stream.size(); ++i) EXPECT_EQ(decode_in(stream, {i}), d) << "split at " << i;
}

TEST(Telnet, AnOverlongOrEmptySubnegotiationIsDroppedAndDecodingGoesOn) {
  Bytes stream = {kIAC, kSB, kComPortOption};
  stream.insert(stream.end(), kMaxSubnegotiation + 100, 'z');
  stream.insert(stream.end(), {kIAC, kSE, 'o', 'k', kIAC, kSB, kBinary, kIAC, kSE, kIAC, kSE, '!'});
  const Decoded d = decode(stream);
  EXPECT_EQ(d.data, (Bytes{'o', 'k', '!'}));
  ASSERT_EQ(d.events.size(), 3u);
  EXPECT_EQ(d.events[0], "error: subnegotiation of COM-PORT-OPTION longer than 512 bytes: dropped");
  EXPECT_EQ(d.events[1], "error: empty subnegotiation of BINARY");
  EXPECT_EQ(d.events[2], "error: IAC SE outside a subnegotiation: ignored");
}

TEST(Telnet, AStreamThatStopsInsideASequenceSaysSo) {
  for (const Bytes& cut : {Bytes{kIAC}, Bytes{kIAC, kDO}, Bytes{kIAC, kSB}, Bytes{kIAC, kSB, 44, 1, kIAC}}) {
    Decoder d;
    Bytes data;
    std::vector<Event> events;
    d.feed(cut, data, events);
    EXPECT_TRUE(d.mid_sequence()) << to_hex(cut);
    EXPECT_TRUE(data.empty());
    EXPECT_TRUE(events.empty());
  }
}

TEST(Telnet, TwoPeersNegotiateOnceAndStop) {
  // Each side requests what it wants; the replies are fed back and forth
  // until none is left: both sides end with the options on, and the
  // exchange ends (no acknowledgement of an acknowledgement).
  Options a({kBinary, kComPortOption}, {kBinary}), b({kBinary}, {kBinary, kComPortOption});
  Bytes to_b = cat({a.request_local(kBinary), a.request_remote(kBinary), a.request_local(kComPortOption),
                    a.request_local(kEcho)});
  Bytes to_a = cat({b.request_local(kBinary), b.request_remote(kBinary)});
  int rounds = 0;
  while ((!to_a.empty() || !to_b.empty()) && ++rounds < 10) {
    Bytes next_a, next_b;
    for (auto [in, peer, out] : {std::tuple{&to_b, &b, &next_a}, std::tuple{&to_a, &a, &next_b}}) {
      Decoder d;
      Bytes data;
      std::vector<Event> events;
      d.feed(*in, data, events);
      for (const auto& e : events) {
        const Bytes r = peer->receive(e.verb, e.option);
        out->insert(out->end(), r.begin(), r.end());
      }
    }
    to_a = next_a;
    to_b = next_b;
  }
  EXPECT_LT(rounds, 10);
  EXPECT_TRUE(a.local_on(kBinary) && a.remote_on(kBinary) && b.local_on(kBinary) && b.remote_on(kBinary));
  EXPECT_TRUE(a.local_on(kComPortOption) && b.remote_on(kComPortOption));
  EXPECT_FALSE(a.local_on(kEcho));  // b refused it (DONT)
  EXPECT_FALSE(a.local_pending(kEcho));
}

TEST(Telnet, ComPortPayloads) {
  EXPECT_EQ(com_port::set_baudrate(1, 9600), (Bytes{1, 0x00, 0x00, 0x25, 0x80}));
  EXPECT_EQ(com_port::baudrate_of(Bytes{101, 0x00, 0x01, 0xC2, 0x00}), 115200u);
  EXPECT_FALSE(com_port::baudrate_of(Bytes{101, 0x00}).has_value());
  EXPECT_EQ(com_port::linestate_text(0x04), "parity error");
  EXPECT_EQ(com_port::command_name(105), "SERVER SET-CONTROL");
}

TEST(Rfc2217Url, PyserialsFormAndItsErrors) {
  std::string error;
  auto u = parse_rfc2217_url("rfc2217://127.0.0.1:7000", error);
  ASSERT_TRUE(u) << error;
  EXPECT_EQ(u->host, "127.0.0.1");
  EXPECT_EQ(u->port, 7000);
  u = parse_rfc2217_url("rfc2217://[::1]:7001?ign_set_control", error);
  ASSERT_TRUE(u) << error;
  EXPECT_EQ(u->host, "::1");
  for (const char* bad : {"rfc2217://host", "rfc2217://host:0", "rfc2217://host:70000", "rfc2217://:7000",
                          "rfc2217://host:70x", "rfc2217://host:7000?bogus", "/dev/ttyUSB0"}) {
    error.clear();
    EXPECT_FALSE(parse_rfc2217_url(bad, error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
  EXPECT_TRUE(is_rfc2217_url("rfc2217://x:1"));
  EXPECT_FALSE(is_rfc2217_url("/dev/ttyS0"));
}

// ---- the lines over loopback TCP ---------------------------------------------

TEST(Rfc2217Line, ClientAndServerSetTheBaudRateAndCarryFFBothWays) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  std::atomic<int> server_baud{0};
  std::thread server([&] {
    auto tcp = listener->accept(5s);
    ASSERT_TRUE(tcp);
    Rfc2217ServerLine line(std::move(tcp), 9600);
    std::uint8_t buf[64];
    Bytes got;
    const auto end = std::chrono::steady_clock::now() + 5s;
    while (got.size() < 4 && std::chrono::steady_clock::now() < end) {
      const std::size_t n = line.read(buf, 50ms);
      got.insert(got.end(), buf, buf + n);
      if (auto b = line.take_baud_change()) server_baud = *b;
    }
    line.write(got);  // echo
    try {
      while (std::chrono::steady_clock::now() < end) line.read(buf, 50ms);  // until the client hangs up
    } catch (const LineError&) {
    }
  });
  std::vector<std::string> notes;
  auto client = Rfc2217Line::connect("127.0.0.1", listener->port(), 4800, CharFormat::k8N1, 3s,
                                     [&](const std::string& t, bool) { notes.push_back(t); });
  const Bytes data = {0xFF, 0x02, 0xFF, 0xFF};
  client->write(data);
  Bytes back;
  std::uint8_t buf[64];
  const auto end = std::chrono::steady_clock::now() + 3s;
  while (back.size() < data.size() && std::chrono::steady_clock::now() < end) {
    const std::size_t n = client->read(buf, 100ms);
    back.insert(back.end(), buf, buf + n);
  }
  EXPECT_EQ(back, data);
  EXPECT_EQ(server_baud.load(), 4800);
  EXPECT_NE(client->describe().find("rfc2217 127.0.0.1:"), std::string::npos) << client->describe();
  for (const auto& n : notes) EXPECT_EQ(n.find("SET-CONTROL"), std::string::npos) << n;  // acknowledged
  client.reset();
  server.join();
}

TEST(Rfc2217Line, ASilentServerIsAClearErrorAfterTheTimeout) {
  auto listener = TcpListener::listen("127.0.0.1", 0);
  std::atomic<bool> done{false};
  std::thread server([&] {
    auto tcp = listener->accept(5s);  // accepts, then says nothing: a raw TCP port
    while (!done) std::this_thread::sleep_for(10ms);
  });
  try {
    Rfc2217Line::connect("127.0.0.1", listener->port(), 9600, CharFormat::k8N1, 300ms);
    ADD_FAILURE() << "connected to a server that never negotiated";
  } catch (const LineError& e) {
    EXPECT_NE(std::string(e.what()).find("no Telnet negotiation from the server within 300 ms"), std::string::npos)
        << e.what();
  }
  done = true;
  server.join();
}

TEST(Rfc2217Line, AServerThatNeverAnswersSetControlIsNotedNotWaitedFor) {
  // Negotiates and answers SET-BAUDRATE..SET-STOPSIZE with what was asked,
  // ignores SET-CONTROL, as ser2net on a pty does.
  auto listener = TcpListener::listen("127.0.0.1", 0);
  std::atomic<bool> done{false};
  std::thread server([&] {
    auto tcp = listener->accept(5s);
    ASSERT_TRUE(tcp);
    Options options({kBinary, kSuppressGoAhead, kComPortOption}, {kBinary, kSuppressGoAhead, kComPortOption});
    Decoder d;
    Bytes data;
    std::uint8_t buf[256];
    try {
      while (!done) {
        const std::size_t n = tcp->read(buf, 20ms);
        std::vector<Event> events;
        d.feed(ByteView(buf, n), data, events);
        for (const auto& e : events) {
          if (e.kind == Event::Kind::negotiation) {
            const Bytes r = options.receive(e.verb, e.option);
            if (!r.empty()) tcp->write(r);
          } else if (e.kind == Event::Kind::subnegotiation && e.payload[0] != com_port::kSetControl) {
            Bytes answer = e.payload;
            answer[0] = static_cast<std::uint8_t>(answer[0] + com_port::kServerOffset);
            tcp->write(subnegotiation(kComPortOption, answer));
          }
        }
      }
    } catch (const LineError&) {
    }
  });
  std::vector<std::string> important;
  auto client = Rfc2217Line::connect("127.0.0.1", listener->port(), 9600, CharFormat::k8N1, 2s,
                                     [&](const std::string& t, bool i) {
                                       if (i) important.push_back(t);
                                     });
  ASSERT_EQ(important.size(), 1u);
  EXPECT_NE(important[0].find("did not acknowledge SET-CONTROL"), std::string::npos) << important[0];
  done = true;
  client.reset();
  server.join();
}

}  // namespace
}  // namespace sabus::harness
