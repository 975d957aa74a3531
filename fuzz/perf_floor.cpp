// Reference points for tools/fuzz-perf.sh, not fuzz targets: how fast
// libFuzzer itself runs on a machine when the target does as little as
// possible, so that the fuzz targets' speeds can be read against them.
//   SABUS_FLOOR 0  nothing: libFuzzer's own loop (mutation, timing, features);
//   SABUS_FLOOR 1  the receiver, fed the input once, no oracle (fuzz_receiver
//                  feeds it twice and checks every event);
//   SABUS_FLOOR 2  the controller, executing every frame of the input, no
//                  oracle (fuzz_controller also checks every reply and the
//                  model's invariants);
//   SABUS_FLOOR 3  the receiver fed the input twice, whole and in the
//                  pieces fuzz_receiver uses, no oracle: what the receiver
//                  target's two feeds cost before their comparison and the
//                  stream oracles.
// Each has the same coverage instrumentation as its fuzz target and uses
// libFuzzer's own mutator.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>

#if SABUS_FLOOR == 1 || SABUS_FLOOR == 3
#include "fuzz_support.hpp"
#include "sabus/protocol/receiver.hpp"
#elif SABUS_FLOOR == 2
#include "fuzz_support.hpp"
#include "sabus/harness/controller.hpp"
#endif

namespace {

#if SABUS_FLOOR == 1 || SABUS_FLOOR == 3
struct Ignore : sabus::ReceiverSink {
  void on_frame(const sabus::FrameView&) override {}
  void on_discard(const sabus::Discard&) override {}
};
#elif SABUS_FLOOR == 2
struct Execute : sabus::ReceiverSink {
  sabus::harness::Controller* controller = nullptr;
  void on_frame(const sabus::FrameView& f) override { (void)controller->execute(f.to_frame()); }
  void on_discard(const sabus::Discard&) override {}
};
#endif

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#if SABUS_FLOOR == 1
  static sabus::Receiver receiver(sabus::ReceiverOptions::slave('2'));
  static Ignore sink;
  receiver.reset();
  receiver.feed(sabus::ByteView(data, size), sink);
  receiver.finish(sink);
#elif SABUS_FLOOR == 3
  static sabus::Receiver whole(sabus::ReceiverOptions::slave('2')), pieces(sabus::ReceiverOptions::slave('2'));
  static Ignore sink;
  whole.reset();
  whole.feed(sabus::ByteView(data, size), sink);
  whole.finish(sink);
  pieces.reset();
  sabus::fuzz::ChunkSizes sizes((size > 1 ? data[1] : 0) * 131u + size);
  for (std::size_t i = 0; i < size;) {
    const std::size_t n = std::min(sizes.next(), size - i);
    pieces.feed(sabus::ByteView(data + i, n), sink);
    i += n;
  }
  pieces.finish(sink);
#elif SABUS_FLOOR == 2
  static sabus::harness::VirtualClock clock;
  static const auto& profile = sabus::fuzz::profiles().front();
  static const sabus::harness::Controller powered_on(profile, clock);
  static sabus::Receiver receiver(sabus::harness::receiver_options(profile, {}, sabus::Parity::kUnchecked));
  clock.set({});
  sabus::harness::Controller controller(powered_on);
  Execute sink;
  sink.controller = &controller;
  receiver.reset();
  receiver.feed(sabus::ByteView(data, size), sink);
#elif SABUS_FLOOR == 0
  (void)data;
  (void)size;
#else
#error "SABUS_FLOOR is 0, 1, 2 or 3"
#endif
  return 0;
}
