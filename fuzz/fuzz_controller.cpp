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
//    within limits, STORE <= 50, ...).
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <vector>

#include "fuzz_support.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/protocol/catalog.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_controller oracle: %s\n", what);
  std::abort();
}

// Whether `stream` holds a frame that a correct device answers with a reply
// to `command`, ending in the chunk [chunk_begin, chunk_end): an STX at s, the
// first ETX after it at e, the check byte at e + 1 inside the chunk, the
// device's address, even parity on every byte and a correct LRC.
bool good_frame_for(sabus::ByteView stream, std::size_t chunk_begin, std::size_t chunk_end, std::uint8_t address,
                    std::uint8_t command) {
  const std::size_t longest = sabus::max_request_length();
  const std::size_t first = chunk_begin > longest ? chunk_begin - longest : 0;
  for (std::size_t s = first; s < chunk_end; ++s) {
    if ((stream[s] & 0x7F) != sabus::STX) continue;
    std::size_t e = s + 1;
    while (e < chunk_end && (stream[e] & 0x7F) != sabus::ETX) ++e;
    if (e + 1 >= chunk_end || e + 1 < chunk_begin || e < s + 3) continue;
    bool ok = (stream[s + 1] & 0x7F) == address && (stream[s + 2] & 0x7F) == command;
    std::uint8_t x = 0;
    for (std::size_t i = s; i <= e + 1; ++i) {
      ok = ok && sabus::has_even_parity(stream[i]);
      x ^= stream[i] & 0x7F;
    }
    if (ok && x == 0) return true;
  }
  return false;
}

// Checks one chunk's output; returns the command it answers.
std::uint8_t check_reply(const sabus::Bytes& wire, std::uint8_t address) {
  sabus::Bytes f;
  for (std::uint8_t b : wire) {
    if (!sabus::has_even_parity(b)) fail("a reply byte without even parity");
    f.push_back(b & 0x7F);
  }
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
  auto frame = sabus::decode_frame(f);
  if (!frame) fail("a reply that does not decode as a frame");
  if (!sabus::decode_reply(frame.value())) fail("a reply whose fields do not decode");
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
      for (std::uint8_t c : *o.reply) out->push_back(sabus::with_even_parity(c));
  }
  void on_discard(const sabus::Discard&) override {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sabus::fuzz::ControllerInput in;
  if (!sabus::fuzz::parse_controller_input(data, size, in)) return 0;
  // One controller per profile, built once at power-on; every input starts
  // from a copy of it, with the clock back at zero. Building one (its enum
  // lookups by name, the receiver's byte tables) cost more than a short input.
  static sabus::harness::VirtualClock clock;
  static const std::vector<Direct> powered_on = [] {
    std::vector<Direct> v;
    v.reserve(sabus::fuzz::profiles().size());
    for (const auto& p : sabus::fuzz::profiles()) v.emplace_back(p, clock);
    return v;
  }();
  clock.set({});
  // Byte 0 bit 7: through the Bus, exactly as `sabus sim` runs it; otherwise
  // the same parts without its transcript (fuzz_handler_report checks on a
  // whole corpus that the two give the same bytes).
  const bool through_bus = data[0] & 0x80;
  std::optional<sabus::harness::Bus> bus;
  std::optional<Direct> direct;
  if (through_bus) {
    bus.emplace(std::vector<sabus::harness::Profile>{*in.profile}, clock);
    // Nothing reads the transcript here; building it (describe_frame and
    // hex text of every frame) cost more than the rest of the Bus.
    bus->set_transcript(false);
  }
  else direct.emplace(powered_on[static_cast<std::size_t>(in.profile - sabus::fuzz::profiles().data())]);
  const sabus::ByteView stream(data + sabus::fuzz::kControllerHeader, size - sabus::fuzz::kControllerHeader);
  const std::uint8_t address = in.profile->address;
  std::size_t at = 0;
  sabus::Bytes out;
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
      if (!good_frame_for(stream, at, end, address, command)) fail("a reply without a good command frame for it");
    }
    at = end;
    clock.advance(in.step);
    auto& controller = bus ? bus->controller(0) : direct->controller;
    if (bus) bus->tick();
    else controller.update();
    const std::string broken = controller.check_invariants();
    if (!broken.empty()) fail(broken.c_str());
  }
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  static const sabus::fuzz::StreamFormat format{sabus::fuzz::kControllerHeader, &sabus::fuzz::controller_stream_is_wire,
                                                nullptr};
  return sabus::fuzz::mutate_stream(data, size, max_size, seed, format);
}
