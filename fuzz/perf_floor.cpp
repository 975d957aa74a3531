// Reference points for tools/fuzz-perf.sh, not fuzz targets: how fast
// libFuzzer itself runs on a machine when the target does as little as
// possible, so that the fuzz targets' speeds can be read against them.
//   SABUS_FLOOR 0  nothing: libFuzzer's own loop (mutation, timing, features);
//   SABUS_FLOOR 1  the receiver, fed the input once, no oracle (fuzz_receiver
//                  checks every event, and feeds one input in eight again in
//                  pieces);
//   SABUS_FLOOR 2  the controller, executing every frame of the input, no
//                  oracle (fuzz_controller also checks every reply and the
//                  model's invariants).
// Each has the same coverage instrumentation as its fuzz target and uses
// libFuzzer's own mutator.
#include <cstddef>
#include <cstdint>

#if SABUS_FLOOR == 1
#include "sabus/protocol/receiver.hpp"
#elif SABUS_FLOOR == 2
#include "fuzz_support.hpp"
#include "sabus/harness/controller.hpp"
#endif

namespace {

#if SABUS_FLOOR == 1
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
#error "SABUS_FLOOR is 0, 1 or 2"
#endif
  return 0;
}
