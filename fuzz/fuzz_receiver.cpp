// Fuzz target: the receiver on arbitrary byte streams (§1 state machine).
// Input: byte 0 chooses the options; byte 1 the address (bits 0-1), whether
// the stream is also fed in pieces (bit 7, kReceiverInPieces) and the seed of
// the pieces' sizes; the rest is the stream. A header byte the input lacks
// is 0 and the stream is then empty: every input, the empty one too, reaches
// the receiver, the only instrumented code here. Returning before it left
// libFuzzer with no coverage on its first input ("\n") when started without
// a corpus, and it stopped ("no interesting inputs were found").
// Oracles:
//  - every emitted frame has a correct LRC (under the configured rule), the
//    configured address, a start byte of STX, ETX before the check byte, and
//    is exactly the stream's bytes at its offset (bit 7 stripped); with
//    parity checking every one of those bytes had even parity (§1 Data Format);
//  - no frame is longer than the configured maximum; with the state-diagram
//    reading (E-9) every frame has a catalog command and its length;
//  - frames and discarded runs tile the stream: no byte lost or counted twice;
//  - with bit 7 of byte 1 (every seed, and one execution in eight: the
//    mutator draws it afresh each time), feeding the same bytes again in
//    random chunk sizes (many of 1-4 bytes) gives the same events. Not on
//    every input: a second feed in pieces costs more than the receiver's
//    first (fuzz/README.md, Performance), and would hold the target near
//    half its floor's pace for an oracle that a share of the executions
//    (tens of thousands a second) exercises as well; the chunking property
//    of tests/protocol/receiver_properties.cpp checks it on every CI run.
#include <algorithm>
#include <array>
#include <cstring>
#include <cstdlib>
#include <memory>
#include <vector>

#include "fuzz_support.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/receiver.hpp"

namespace {

// The sizes of the pieces the input is fed in a second time, drawn from the
// input (so a finding replays):
// 1-4 bytes seven times in eight, else 1-64. A few bits a size from a 64-bit
// xorshift: a division a piece (minstd_rand) cost more than feeding it.
class ChunkSizes {
 public:
  explicit ChunkSizes(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ULL | 1) {}
  std::size_t next() { return take(3) == 0 ? 1 + take(6) : 1 + take(2); }

 private:
  std::size_t take(unsigned count) {
    if (left_ < count) {
      state_ ^= state_ >> 12;
      state_ ^= state_ << 25;
      state_ ^= state_ >> 27;
      bits_ = state_ * 0x2545F4914F6CDD1DULL;
      left_ = 64;
    }
    const auto r = static_cast<std::size_t>(bits_ & ((1u << count) - 1));
    bits_ >>= count;
    left_ -= count;
    return r;
  }
  std::uint64_t state_, bits_ = 0;
  unsigned left_ = 0;
};

struct Event {
  bool frame;
  std::uint64_t offset, length;
  sabus::DiscardReason reason;
};

// The input's stream read once, so that each frame is checked against it in
// a few steps, whatever its length: its 7-bit characters (a frame must be
// exactly these at its offset), the XOR of every prefix of them (the LRC of
// any run of bytes) and how many bytes of every prefix break the configured
// parity (§1 Data Format), counted modulo 256: exact for the difference over
// any run shorter than 256 bytes, and a frame is at most 145.
// Eight bytes a step: the prefixes of a word's bytes are a few shifts.
struct Stream {
  sabus::ByteView wire;
  std::vector<std::uint8_t> chars, xor_before, bad_before;

  void read(sabus::ByteView w, sabus::Parity parity) {
    constexpr std::uint64_t kLow = 0x0101010101010101ULL, kHigh = 0x80 * kLow;
    const std::size_t n = w.size();
    wire = w;
    chars.resize(n);
    xor_before.resize(n + 1);
    bad_before.resize(n + 1);
    std::uint8_t x = 0, bad = 0;
    xor_before[0] = 0;
    bad_before[0] = 0;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      std::uint64_t v, c, p, q, badness;
      std::memcpy(&v, w.data() + i, 8);
      c = v & ~kHigh;
      std::memcpy(chars.data() + i, &c, 8);
      p = c ^ (c << 8);  // byte k: XOR of bytes 0..k
      p ^= p << 16;
      p ^= p << 32;
      p ^= x * kLow;
      std::memcpy(xor_before.data() + i + 1, &p, 8);
      x = static_cast<std::uint8_t>(p >> 56);
      if (parity == sabus::Parity::kEvenBit7) {
        badness = v ^ (v >> 4);  // bit 0 of each byte: its parity
        badness ^= badness >> 2;
        badness ^= badness >> 1;
        badness &= kLow;
      } else {
        badness = parity == sabus::Parity::kNone ? (v >> 7) & kLow : 0;
      }
      // Byte k: the bytes 0..k that break it (at most 8, no carry), plus
      // `bad`, each byte on its own modulo 256.
      const std::uint64_t counts = badness * kLow, before = bad * kLow;
      q = ((counts & ~kHigh) + (before & ~kHigh)) ^ ((counts ^ before) & kHigh);
      std::memcpy(bad_before.data() + i + 1, &q, 8);
      bad = static_cast<std::uint8_t>(q >> 56);
    }
    for (; i < n; ++i) {
      const std::uint8_t c = w[i] & 0x7F;
      chars[i] = c;
      x ^= c;
      xor_before[i + 1] = x;
      bad = static_cast<std::uint8_t>(bad + (parity == sabus::Parity::kEvenBit7 ? !sabus::has_even_parity(w[i])
                                             : parity == sabus::Parity::kNone   ? w[i] > 0x7F
                                                                                : 0));
      bad_before[i + 1] = bad;
    }
  }
};

// Checks every event of one feed. The first feed (whole) checks that its
// events tile the stream, and records them when a second feed will come; the
// second (pieces) must give the same events, compared as they come.
struct Check : sabus::ReceiverSink {
  std::vector<Event> events;       // whole: what it saw, when `record`
  bool record = false;
  const std::vector<Event>* expected = nullptr;  // pieces: the whole feed's events
  std::size_t seen = 0;            // events so far
  std::uint64_t next = 0;          // whole: where the next event must begin
  std::uint64_t base = 0;          // the receiver's stream offset when this input began
  const Stream* stream = nullptr;
  const sabus::ReceiverOptions* o = nullptr;
  std::uint8_t address = 0;

  void begin(std::uint64_t receiver_offset, const std::vector<Event>* compare_with, bool record_events) {
    events.clear();
    record = record_events;
    expected = compare_with;
    seen = 0;
    next = 0;
    base = receiver_offset;
  }
  // Inlined: it runs for every event of both feeds.
  [[gnu::always_inline]] void event(bool frame, std::uint64_t offset, std::uint64_t length,
                                    sabus::DiscardReason reason) {
    if (expected) {
      // Chunking changed the events.
      if (seen >= expected->size()) std::abort();
      const Event& e = (*expected)[seen];
      if (e.frame != frame || e.offset != offset || e.length != length || e.reason != reason) std::abort();
    } else {
      if (offset != next) std::abort();  // a byte lost or counted twice
      next += length;
      if (record) events.push_back({frame, offset, length, reason});
    }
    ++seen;
  }
  // After finish(): every event of the whole feed seen, every byte in one.
  void end() const {
    if (expected ? seen != expected->size() : next != stream->wire.size()) std::abort();
  }

  void on_frame(const sabus::FrameView& f) override {
    const std::uint64_t at = f.offset - base;
    const std::size_t n = f.bytes.size();
    if (n < 5 || n > kLongest) std::abort();  // shorter than a frame, longer than the overrun limit
    if (at > stream->wire.size() || n > stream->wire.size() - at) std::abort();  // not inside the stream
    // Exactly the stream's bytes at its offset, bit 7 stripped ...
    if (!sabus::fuzz::same_bytes(f.bytes.data(), stream->chars.data() + at, n)) std::abort();
    // ... so the LRC of byte 0 (or 1) through ETX is the stream's XOR there.
    const std::size_t first = o->lrc_rule == sabus::LrcRule::kFromAddress ? 1 : 0;
    if ((stream->xor_before[at + n - 1] ^ stream->xor_before[at + first]) != f.bytes[n - 1]) std::abort();  // wrong LRC
    if (stream->bad_before[at + n] != stream->bad_before[at]) std::abort();  // a byte that breaks the parity
    if (f.address != address || f.bytes[1] != address) std::abort();  // a frame for another address
    if (f.kind != sabus::FrameKind::kCommand || f.bytes[0] != sabus::STX) std::abort();
    if (f.bytes[n - 2] != sabus::ETX) std::abort();
    if (f.command != f.bytes[2] || f.data.size() + sabus::kFrameOverhead != n) std::abort();
    if (o->validate_command_in_receiver) {
      const auto* info = sabus::find_command(f.command);
      if (!info) std::abort();
      if (info->request_length && *info->request_length != n) std::abort();
    }
    event(true, at, n, sabus::DiscardReason::kUnknown);
  }
  void on_discard(const sabus::Discard& d) override {
    if (d.length == 0) std::abort();
    event(false, d.offset - base, d.length, d.reason);
  }

  static inline const std::size_t kLongest = sabus::max_request_length();
};

std::uint8_t knobs_of(const std::uint8_t* h) { return h[0]; }
bool wire(const std::uint8_t* h) { return (knobs_of(h) & 1) || (knobs_of(h) & 64); }
void draw(std::uint8_t* h, std::uint32_t random) {
  const bool in_pieces = random % sabus::fuzz::kReceiverInPiecesOneIn == 0;
  h[1] = static_cast<std::uint8_t>((h[1] & ~sabus::fuzz::kReceiverInPieces) | (in_pieces ? sabus::fuzz::kReceiverInPieces : 0));
}
sabus::LrcRule rule(const std::uint8_t* h) {
  return (knobs_of(h) & 32) ? sabus::LrcRule::kFromAddress : sabus::LrcRule::kFromByte0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::uint8_t header[2] = {0, 0};
  const std::size_t header_size = std::min<std::size_t>(size, 2);
  if (header_size) std::memcpy(header, data, header_size);
  const std::uint8_t knobs = header[0];
  sabus::ReceiverOptions o = sabus::ReceiverOptions::slave(sabus::fuzz::kReceiverAddresses[header[1] & 3]);
  o.parity = (knobs & 1) ? sabus::Parity::kEvenBit7 : (knobs & 64) ? sabus::Parity::kUnchecked : sabus::Parity::kNone;
  o.stx_restarts_in_address = !(knobs & 128);
  o.stx_restarts_in_data = knobs & 2;
  o.reject_control_in_body = knobs & 4;
  o.check_byte_restarts_on_stx = knobs & 8;
  o.validate_command_in_receiver = knobs & 16;
  o.lrc_rule = rule(header);

  // Reused: no allocation per input once the buffers have grown.
  static Stream stream;
  static Check whole, pieces;
  stream.read(sabus::ByteView(data + header_size, size - header_size), o.parity);
  for (Check* c : {&whole, &pieces}) {
    c->stream = &stream;
    c->o = &o;
    c->address = sabus::fuzz::kReceiverAddresses[header[1] & 3];
  }
  // One receiver pair per option set, made once: building the byte-class
  // table costs more than feeding a short input. reset() keeps the stream
  // offset running, so offsets are taken relative to where each run starts.
  static std::array<std::unique_ptr<std::array<sabus::Receiver, 2>>, 1024> cache;
  auto& pair = cache[knobs * 4u + (header[1] & 3u)];
  if (!pair) pair = std::make_unique<std::array<sabus::Receiver, 2>>(std::array<sabus::Receiver, 2>{sabus::Receiver(o), sabus::Receiver(o)});
  sabus::Receiver& a = (*pair)[0];
  sabus::Receiver& b = (*pair)[1];
  const bool in_pieces = header[1] & sabus::fuzz::kReceiverInPieces;
  a.reset();
  whole.begin(a.offset(), nullptr, in_pieces);
  a.feed(stream.wire, whole);
  a.finish(whole);
  whole.end();
  if (!in_pieces) return 0;
  b.reset();
  pieces.begin(b.offset(), &whole.events, false);
  ChunkSizes sizes(header[1] * 131u + size);
  for (std::size_t i = 0; i < stream.wire.size();) {
    const std::size_t n = std::min(sizes.next(), stream.wire.size() - i);
    b.feed(stream.wire.subspan(i, n), pieces);
    i += n;
  }
  b.finish(pieces);
  pieces.end();
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  static const sabus::fuzz::StreamFormat format{2, &wire, &rule, &draw};
  return sabus::fuzz::mutate_stream(data, size, max_size, seed, format);
}
