// Fuzz target: the receiver on arbitrary byte streams (§1 state machine).
// Input: byte 0 chooses the options, byte 1 the address and the seed of the
// chunk sizes; the rest is the stream.
// Oracles:
//  - every emitted frame has a correct LRC (under the configured rule), the
//    configured address, a start byte of STX, ETX before the check byte, and
//    is exactly the stream's bytes at its offset (bit 7 stripped); with
//    parity checking every one of those bytes had even parity (§1 Data Format);
//  - no frame is longer than the configured maximum; with the state-diagram
//    reading (E-9) every frame has a catalog command and its length;
//  - frames and discarded runs tile the stream: no byte lost or counted twice;
//  - feeding the same bytes in random chunk sizes (many of 1-4 bytes) gives
//    the same events.
#include <array>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "fuzz_support.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/receiver.hpp"

namespace {

constexpr std::uint8_t kAddresses[] = {'2', 0x31, 0x6F, 'P'};

struct Event {
  bool frame;
  std::uint64_t offset, length;
  sabus::DiscardReason reason;
  bool operator==(const Event&) const = default;
};

struct Check : sabus::ReceiverSink {
  std::vector<Event> events;
  std::uint64_t base = 0;  // the receiver's stream offset when this input began
  sabus::ByteView stream;
  const sabus::ReceiverOptions* o = nullptr;
  std::uint8_t address = 0;

  void on_frame(const sabus::FrameView& fv) override {
    sabus::FrameView f = fv;
    f.offset -= base;
    if (sabus::lrc(f.bytes.first(f.bytes.size() - 1), o->lrc_rule) != f.bytes.back()) std::abort();  // wrong LRC
    if (f.address != address || f.bytes[1] != address) std::abort();  // a frame for another address
    if (f.kind != sabus::FrameKind::kCommand || f.bytes[0] != sabus::STX) std::abort();
    if (f.bytes.size() < 5 || f.bytes[f.bytes.size() - 2] != sabus::ETX) std::abort();
    if (f.bytes.size() > sabus::max_request_length()) std::abort();  // longer than the overrun limit
    if (f.offset + f.bytes.size() > stream.size()) std::abort();
    for (std::size_t i = 0; i < f.bytes.size(); ++i) {
      const std::uint8_t wire = stream[f.offset + i];
      if ((wire & 0x7F) != f.bytes[i]) std::abort();  // not the bytes of the stream
      if (o->parity == sabus::Parity::kEvenBit7 && !sabus::has_even_parity(wire)) std::abort();
      if (o->parity == sabus::Parity::kNone && wire > 0x7F) std::abort();
    }
    if (f.command != f.bytes[2] || f.data.size() + sabus::kFrameOverhead != f.bytes.size()) std::abort();
    if (o->validate_command_in_receiver) {
      const auto* info = sabus::find_command(f.command);
      if (!info) std::abort();
      if (info->request_length && *info->request_length != f.bytes.size()) std::abort();
    }
    events.push_back({true, f.offset, f.bytes.size(), sabus::DiscardReason::kUnknown});
  }
  void on_discard(const sabus::Discard& d) override {
    if (d.length == 0) std::abort();
    events.push_back({false, d.offset - base, d.length, d.reason});
  }
};

std::uint8_t knobs_of(const std::uint8_t* h) { return h[0]; }
bool wire(const std::uint8_t* h) { return (knobs_of(h) & 1) || (knobs_of(h) & 64); }
sabus::LrcRule rule(const std::uint8_t* h) {
  return (knobs_of(h) & 32) ? sabus::LrcRule::kFromAddress : sabus::LrcRule::kFromByte0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t knobs = data[0];
  sabus::ReceiverOptions o = sabus::ReceiverOptions::slave(kAddresses[data[1] & 3]);
  o.parity = (knobs & 1) ? sabus::Parity::kEvenBit7 : (knobs & 64) ? sabus::Parity::kUnchecked : sabus::Parity::kNone;
  o.stx_restarts_in_address = !(knobs & 128);
  o.stx_restarts_in_data = knobs & 2;
  o.reject_control_in_body = knobs & 4;
  o.check_byte_restarts_on_stx = knobs & 8;
  o.validate_command_in_receiver = knobs & 16;
  o.lrc_rule = rule(data);
  const sabus::ByteView stream(data + 2, size - 2);

  static Check whole, pieces;  // reused: no allocation per input once the vectors have grown
  whole.events.clear();
  pieces.events.clear();
  for (Check* c : {&whole, &pieces}) {
    c->stream = stream;
    c->o = &o;
    c->address = kAddresses[data[1] & 3];
  }
  // One receiver pair per option set, made once: building the byte-class
  // table costs more than feeding a short input. reset() keeps the stream
  // offset running, so offsets are taken relative to where each run starts.
  static std::array<std::unique_ptr<std::array<sabus::Receiver, 2>>, 1024> cache;
  auto& pair = cache[knobs * 4u + (data[1] & 3u)];
  if (!pair) pair = std::make_unique<std::array<sabus::Receiver, 2>>(std::array<sabus::Receiver, 2>{sabus::Receiver(o), sabus::Receiver(o)});
  sabus::Receiver& a = (*pair)[0];
  sabus::Receiver& b = (*pair)[1];
  a.reset();
  b.reset();
  whole.base = a.offset();
  pieces.base = b.offset();
  a.feed(stream, whole);
  a.finish(whole);
  std::minstd_rand rng(data[1] * 131u + static_cast<unsigned>(size));
  for (std::size_t i = 0; i < stream.size();) {
    const unsigned r = static_cast<unsigned>(rng());
    const std::size_t n = std::min<std::size_t>(1 + ((r & 7) == 0 ? (r >> 3) % 64 : (r >> 3) % 4), stream.size() - i);
    b.feed(stream.subspan(i, n), pieces);
    i += n;
  }
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

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  static const sabus::fuzz::StreamFormat format{2, &wire, &rule};
  return sabus::fuzz::mutate_stream(data, size, max_size, seed, format);
}
