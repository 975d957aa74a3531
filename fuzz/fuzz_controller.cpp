// Fuzz target: the whole reference controller, bytes in -> bytes out, as
// `sabus sim` runs it (harness::Bus: receiver, controller, parity).
// Input (fuzz_support.hpp ControllerInput): byte 0 picks the device profile,
// byte 1 the virtual time between chunks; the rest are wire bytes, fed in
// chunks that each complete at most one frame.
// Oracles, after every chunk:
//  - at most one reply (§1: one response per command);
//  - a reply answers a command frame of this chunk that a correct device
//    must answer: it starts with STX, carries the controller's address, has
//    even parity on every byte and a correct LRC (§1 Data Format, Check
//    Character, State 2 b) -- no reply to a bad LRC, a foreign address or a
//    parity error -- and the reply names that frame's command;
//  - the reply is a well-formed frame: even parity, ACK or NAK, the
//    controller's address, a correct LRC, and the catalog's length for its
//    command (or the NAK / offline reply length, §3);
//  - the model's invariants hold (Controller::check_invariants: positions
//    within limits, STORE <= 50, ...), and held at power-on.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <functional>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "oracle_codec.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/protocol/catalog.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_controller oracle: %s\n", what);
  std::abort();
}

// What the oracle reads in a wire byte, a table: even parity in bit 7 (§1
// Data Format), the byte with parity (for the replies), and whether its 7
// bits are STX or ETX or it lacks even parity (for the commands).
enum : std::uint8_t { kStx = 1, kEtx = 2, kOdd = 4 };
struct WireByte {
  bool even;
  std::uint8_t with_parity;  // of the byte's 7 bits
  std::uint8_t marks;        // kStx | kEtx | kOdd
};
constexpr auto kWireBytes = [] {
  std::array<WireByte, 256> t{};
  for (unsigned w = 0; w < 256; ++w) {
    const auto b = static_cast<std::uint8_t>(w);
    const std::uint8_t c = b & 0x7F;
    t[w].even = sabus::has_even_parity(b);
    t[w].with_parity = sabus::with_even_parity(c);
    t[w].marks = static_cast<std::uint8_t>((c == sabus::STX ? kStx : 0) | (c == sabus::ETX ? kEtx : 0) |
                                           (t[w].even ? 0 : kOdd));
  }
  return t;
}();

// The input's wire bytes read once, so that whether a good frame ends in a
// chunk is a few look-ups a candidate start instead of a pass over its bytes:
// the STX bytes, and for each the first ETX after it and the first byte
// without even parity from it on, and the XOR of the 7-bit characters before
// each byte.
struct Wire {
  struct Start {
    std::uint32_t at, etx, odd;  // etx, odd: the wire's size when there is none
  };
  sabus::ByteView bytes;
  std::vector<Start> starts;
  std::vector<std::uint32_t> etx, odd;
  std::vector<std::uint8_t> xor_before;

  void read(sabus::ByteView w) {
    const auto n = static_cast<std::uint32_t>(w.size());
    bytes = w;
    starts.clear();
    etx.clear();
    odd.clear();
    xor_before.resize(n + 1);
    // Raw pointers: a byte store may alias any member, so the loop would
    // reload them after every byte.
    const std::uint8_t* in = w.data();
    std::uint8_t* prefix = xor_before.data();
    std::uint8_t x = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      prefix[i] = x;
      x ^= in[i] & 0x7F;
    }
    prefix[n] = x;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (const std::uint8_t marks = kWireBytes[in[i]].marks) {
        if (marks & kStx) starts.push_back({i, n, n});
        if (marks & kEtx) etx.push_back(i);
        if (marks & kOdd) odd.push_back(i);
      }
    }
    std::size_t e = 0, o = 0;
    for (Start& s : starts) {
      while (e < etx.size() && etx[e] <= s.at) ++e;
      while (o < odd.size() && odd[o] < s.at) ++o;
      if (e < etx.size()) s.etx = etx[e];
      if (o < odd.size()) s.odd = odd[o];
    }
  }

  // Whether the stream holds a frame that a correct device answers with a
  // reply to `command`, ending in the chunk [chunk_begin, chunk_end): an STX
  // at s (at most the longest request before the chunk), the first ETX after
  // it at e, the check byte at e + 1 inside the chunk, the device's address,
  // even parity on every byte and a correct LRC (the XOR of s through e + 1
  // is zero).
  bool good_frame_for(std::size_t chunk_begin, std::size_t chunk_end, std::uint8_t address,
                      std::uint8_t command) const {
    const std::size_t first = chunk_begin > kLongest ? chunk_begin - kLongest : 0;
    auto it = std::lower_bound(starts.begin(), starts.end(), first,
                               [](const Start& s, std::size_t at) { return s.at < at; });
    for (; it != starts.end() && it->at < chunk_end; ++it) {
      const std::size_t s = it->at, e = it->etx;
      if (e + 1 >= chunk_end || e + 1 < chunk_begin || e < s + 3 || it->odd <= e + 1) continue;
      if ((bytes[s + 1] & 0x7F) == address && (bytes[s + 2] & 0x7F) == command &&
          (xor_before[e + 2] ^ xor_before[s]) == 0)
        return true;
    }
    return false;
  }

  static inline const std::size_t kLongest = sabus::max_request_length();
};

// Why a reply does not decode as a frame or its fields do not, or nullptr
// (oracle_codec.hpp: decoding is the oracle's work, outside the coverage).
// Both are functions of the bytes alone, so bytes that decoded once need not
// be decoded again: most replies repeat (the same status, the same
// acknowledgement). The replies that decoded are kept in a table of 4096
// slots, one reply a slot, found by a hash of its bytes and compared whole; a
// newer reply takes an older one's slot.
const char* why_not_decoded(const sabus::Bytes& reply) {
  static std::array<sabus::Bytes, 4096> decoded;
  const std::size_t hash = std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(reply.data()), reply.size()));
  sabus::Bytes& slot = decoded[hash % decoded.size()];
  if (slot.size() == reply.size() && sabus::fuzz::same_bytes(slot.data(), reply.data(), reply.size())) return nullptr;
  if (const char* why = sabus_fuzz_oracle::why_reply_does_not_decode(reply.data(), reply.size())) return why;
  slot = reply;
  return nullptr;
}

// Checks one chunk's output; returns the command it answers.
std::uint8_t check_reply(const sabus::Bytes& wire, std::uint8_t address) {
  static sabus::Bytes f;  // reused: no allocation per reply
  f.resize(wire.size());
  const std::uint8_t* in = wire.data();
  std::uint8_t* chars = f.data();
  bool even = true;
  for (std::size_t i = 0, n = wire.size(); i < n; ++i) {
    even &= kWireBytes[in[i]].even;
    chars[i] = in[i] & 0x7F;
  }
  if (!even) fail("a reply byte without even parity");
  if (f.size() < sabus::kNakReplyLength) fail("a reply shorter than 5 bytes");
  if (f[0] != sabus::ACK && f[0] != sabus::NAK) fail("a reply that starts with neither ACK nor NAK");
  if (f[1] != address) fail("a reply with another address");
  if (f[f.size() - 2] != sabus::ETX) fail("a reply without ETX before the check byte");
  if (sabus::lrc(sabus::ByteView(f).first(f.size() - 1)) != f.back()) fail("a reply with a wrong LRC");
  for (std::size_t i = 3; i + 2 < f.size(); ++i)
    if (f[i] == sabus::ETX) fail("ETX inside a reply");
  if (f[0] == sabus::NAK) {
    if (f.size() != sabus::kNakReplyLength) fail("a NAK reply of the wrong length");
    return f[2];
  }
  if (f.size() == sabus::kOfflineReplyLength && f[3] == sabus::kOfflineMarker) return f[2];
  const auto* info = sabus::find_command(f[2]);
  if (!info) fail("an ACK reply to an unknown command");
  if (info->reply_length && f.size() != *info->reply_length) fail("a reply length that is not the catalog's");
  if (const char* why = why_not_decoded(f)) fail(why);
  return f[2];
}

// The line side of one controller without the Bus's transcript, which costs
// more than the rest (describe_frame of every frame): the same receiver
// options, Controller::execute and parity as Bus::receive.
struct Direct : sabus::ReceiverSink {
  Direct(const sabus::harness::Profile& p, const sabus::harness::Clock& clock)
      : controller(p, clock), receiver(sabus::harness::receiver_options(p, {}, sabus::Parity::kEvenBit7)) {}
  sabus::harness::Controller controller;
  sabus::Receiver receiver;
  sabus::Bytes* out = nullptr;
  void on_frame(const sabus::FrameView& f) override {
    const auto o = controller.execute(f.to_frame());
    if (o.reply)
      for (std::uint8_t c : *o.reply) out->push_back(kWireBytes[c].with_parity);
  }
  void on_discard(const sabus::Discard&) override {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static sabus::fuzz::ControllerInput in;  // reused: no allocation per input
  sabus::fuzz::parse_controller_input(data, size, in);
  // One controller and one Bus per profile, built once at power-on; every
  // input starts from a copy of one, with the clock back at zero. Building
  // one (its enum lookups by name, the receiver's byte tables) cost more
  // than a short input.
  static sabus::harness::VirtualClock clock;
  static const std::vector<Direct> powered_on = [] {
    std::vector<Direct> v;
    v.reserve(sabus::fuzz::profiles().size());
    for (const auto& p : sabus::fuzz::profiles()) v.emplace_back(p, clock);
    return v;
  }();
  static const std::vector<sabus::harness::Bus> powered_on_bus = [] {
    std::vector<sabus::harness::Bus> v;
    v.reserve(sabus::fuzz::profiles().size());
    for (const auto& p : sabus::fuzz::profiles()) {
      v.emplace_back(std::vector<sabus::harness::Profile>{p}, clock);
      // Nothing reads the transcript here; building it (describe_frame and
      // hex text of every frame) cost more than the rest of the Bus.
      v.back().set_transcript(false);
    }
    return v;
  }();
  clock.set({});
  // Byte 0 bits 7 and 6 both set (one input in four): through the Bus,
  // exactly as `sabus sim` runs it; otherwise the same parts without its
  // transcript (fuzz_handler_report checks on a whole corpus that the two
  // give the same bytes). The Bus's own code is a small part of what the
  // target reaches, and an input through it costs more (a Bus copied for
  // each input): with half the inputs through it, 8-13 % of the target's time.
  const auto profile = static_cast<std::size_t>(in.profile - sabus::fuzz::profiles().data());
  std::optional<sabus::harness::Bus> bus;
  std::optional<Direct> direct;
  if (size > 0 && (data[0] & 0xC0) == 0xC0) bus.emplace(powered_on_bus[profile]);
  else direct.emplace(powered_on[profile]);
  auto& controller = bus ? bus->controller(0) : direct->controller;
  auto invariants_hold = [&] {
    const std::string broken = controller.check_invariants();
    if (!broken.empty()) fail(broken.c_str());
  };
  invariants_hold();  // at power-on, before any byte
  static Wire stream;
  const std::size_t header = std::min(size, sabus::fuzz::kControllerHeader);
  stream.read(sabus::ByteView(data + header, size - header));
  const std::uint8_t address = in.profile->address;
  std::size_t at = 0;
  static sabus::Bytes out;
  for (const auto chunk : in.chunks) {
    out.clear();
    if (bus) {
      bus->receive(chunk, out);
    } else {
      direct->out = &out;
      direct->receiver.feed(chunk, *direct);
    }
    const std::size_t end = at + chunk.size();
    if (!out.empty()) {
      // One well-formed reply (its length is exact, so there is no second one) ...
      const std::uint8_t command = check_reply(out, address);
      // ... to a good frame of this command for this address.
      if (!stream.good_frame_for(at, end, address, command)) fail("a reply without a good command frame for it");
    }
    at = end;
    clock.advance(in.step);
    if (bus) bus->tick();
    else controller.update();
    invariants_hold();
  }
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  static const sabus::fuzz::StreamFormat format{sabus::fuzz::kControllerHeader, &sabus::fuzz::controller_stream_is_wire,
                                                nullptr};
  return sabus::fuzz::mutate_stream(data, size, max_size, seed, format);
}
