// Fuzz target: the receiver on arbitrary byte streams (§1 state machine).
// Oracles: every emitted frame has a correct LRC and an accepted address;
// frames and discarded runs tile the stream; feeding the same bytes in other
// chunk sizes gives the same events.
#include <cstdlib>
#include <vector>

#include "sabus/protocol/receiver.hpp"

namespace {

struct Event {
  bool frame;
  std::uint64_t offset, length;
  sabus::DiscardReason reason;
  bool operator==(const Event&) const = default;
};

struct Log : sabus::ReceiverSink {
  std::vector<Event> events;
  std::uint8_t address = 0;
  sabus::LrcRule rule = sabus::LrcRule::kFromByte0;
  void on_frame(const sabus::FrameView& f) override {
    std::uint8_t x = 0;
    for (std::size_t i = rule == sabus::LrcRule::kFromByte0 ? 0 : 1; i < f.bytes.size(); ++i) x ^= f.bytes[i];
    if (x != 0) std::abort();                          // a frame with a wrong LRC
    if (f.address != address) std::abort();           // a frame for another address
    if (f.bytes.size() < 5 || f.bytes[f.bytes.size() - 2] != sabus::ETX) std::abort();
    events.push_back({true, f.offset, f.bytes.size(), sabus::DiscardReason::kUnknown});
  }
  void on_discard(const sabus::Discard& d) override {
    if (d.length == 0) std::abort();
    events.push_back({false, d.offset, d.length, d.reason});
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  // Byte 0 chooses the options, byte 1 the chunk size of the second pass.
  const std::uint8_t knobs = data[0];
  const std::size_t chunk = 1 + data[1] % 16;
  sabus::ReceiverOptions o = sabus::ReceiverOptions::slave('2');
  o.parity = (knobs & 1) ? sabus::Parity::kEvenBit7 : (knobs & 64) ? sabus::Parity::kUnchecked : sabus::Parity::kNone;
  o.stx_restarts_in_address = !(knobs & 128);
  o.stx_restarts_in_data = knobs & 2;
  o.reject_control_in_body = knobs & 4;
  o.check_byte_restarts_on_stx = knobs & 8;
  o.validate_command_in_receiver = knobs & 16;
  o.lrc_rule = (knobs & 32) ? sabus::LrcRule::kFromAddress : sabus::LrcRule::kFromByte0;
  const sabus::ByteView stream(data + 2, size - 2);

  Log whole, pieces;
  whole.address = pieces.address = '2';
  whole.rule = pieces.rule = o.lrc_rule;
  sabus::Receiver a(o), b(o);
  a.feed(stream, whole);
  a.finish(whole);
  for (std::size_t i = 0; i < stream.size(); i += chunk)
    b.feed(stream.subspan(i, std::min(chunk, stream.size() - i)), pieces);
  b.finish(pieces);
  if (whole.events != pieces.events) std::abort();  // chunking changed the events

  std::uint64_t next = 0;
  for (const auto& e : whole.events) {
    if (e.offset != next) std::abort();  // a byte lost or counted twice
    next += e.length;
  }
  if (next != stream.size()) std::abort();
  return 0;
}
