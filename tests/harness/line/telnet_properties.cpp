// Properties of the Telnet codec (telnet.hpp), the oracle a fuzz target
// would check: escaped data decodes back to itself with no events, and any
// byte stream decodes the same whole or split at any points (llhttp's rule
// for its parser, STYLE.md).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "sabus/harness/telnet.hpp"

namespace sabus::harness::telnet {
namespace {

struct Decoded {
  Bytes data;
  std::vector<std::string> events;
  bool mid = false;
  bool operator==(const Decoded&) const = default;
};

Decoded decode_at(const Bytes& stream, std::vector<std::size_t> cuts) {
  std::sort(cuts.begin(), cuts.end());
  Decoder d;
  Decoded out;
  std::vector<Event> events;
  std::size_t at = 0;
  for (std::size_t c : cuts) {
    c = std::min(c, stream.size());
    d.feed(ByteView(stream).subspan(at, c - at), out.data, events);
    at = c;
  }
  d.feed(ByteView(stream).subspan(at), out.data, events);
  for (const auto& e : events) out.events.push_back(describe(e));
  out.mid = d.mid_sequence();
  return out;
}

// Bytes rich in telnet's own: IAC, SB, SE and the verbs come often.
rc::Gen<Bytes> telnet_heavy_bytes() {
  return rc::gen::container<Bytes>(rc::gen::oneOf(
      rc::gen::arbitrary<std::uint8_t>(),
      rc::gen::elementOf(std::vector<std::uint8_t>{kIAC, kIAC, kSB, kSE, kWILL, kDO, kComPortOption, kBinary})));
}

RC_GTEST_PROP(TelnetProperties, EscapedDataDecodesToItselfInAnyChunking, ()) {
  const Bytes data = *telnet_heavy_bytes();
  const Bytes wire = escaped(data);
  const auto cuts = *rc::gen::container<std::vector<std::size_t>>(rc::gen::inRange<std::size_t>(0, wire.size() + 1));
  const Decoded d = decode_at(wire, cuts);
  RC_ASSERT(d.data == data);
  RC_ASSERT(d.events.empty());
  RC_ASSERT(!d.mid);
}

RC_GTEST_PROP(TelnetProperties, AnyStreamDecodesTheSameWholeOrSplit, ()) {
  const Bytes stream = *telnet_heavy_bytes();
  const auto cuts =
      *rc::gen::container<std::vector<std::size_t>>(rc::gen::inRange<std::size_t>(0, stream.size() + 1));
  RC_ASSERT(decode_at(stream, cuts) == decode_at(stream, {}));
}

RC_GTEST_PROP(TelnetProperties, ASubnegotiationComesBackWithItsPayload, ()) {
  const auto option = *rc::gen::arbitrary<std::uint8_t>();
  const Bytes payload = *rc::gen::resize(kMaxSubnegotiation, rc::gen::nonEmpty(telnet_heavy_bytes()));
  Decoder d;
  Bytes data;
  std::vector<Event> events;
  d.feed(subnegotiation(option, payload), data, events);
  RC_ASSERT(data.empty());
  RC_ASSERT(events.size() == 1u);
  RC_ASSERT(events[0].kind == Event::Kind::subnegotiation);
  RC_ASSERT(events[0].option == option);
  RC_ASSERT(events[0].payload == payload);
}

}  // namespace
}  // namespace sabus::harness::telnet
