// The device identity of a run: one device type query (30h, §3.1) at the start.
#include <variant>

#include "sabus/harness/timing.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/receiver.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

struct Collect : ReceiverSink {
  std::vector<Frame> frames;
  std::vector<std::string> discards;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard& d) override { discards.push_back(d.message()); }
};

}  // namespace

Identity query_identity(harness::Transport& t, std::uint8_t address) {
  using namespace std::chrono_literals;
  constexpr std::uint8_t kDeviceType = 0x30;
  Identity id;
  const Bytes cmd = encode_frame({FrameKind::kCommand, address, kDeviceType, {}});
  ReceiverOptions options = ReceiverOptions::master();
  options.parity = harness::receiver_parity(t);
  Receiver rx(options);
  Collect sink;
  try {
    t.send(cmd);
    const auto window = t.in_process() ? 1000ms : harness::reply_timeout(t.baud(), cmd.size(), max_reply_length(), 200ms);
    const auto start = t.now();
    std::uint8_t buf[256];
    while (sink.frames.empty() && t.now() - start < window) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(window - (t.now() - start));
      const std::size_t n = t.receive(buf, std::max(left, 1ms));
      rx.feed(ByteView(buf, n), sink);
    }
    rx.finish(sink);
  } catch (const harness::TransportLost& e) {
    id.error = std::string("device lost: ") + e.what();
    return id;
  }
  if (sink.frames.empty()) {
    id.error = "no answer to the device type query (30h)" +
               (sink.discards.empty() ? std::string() : "; ignored " + sink.discards.front());
    return id;
  }
  const Frame& f = sink.frames.front();
  id.reply_hex = to_hex(encode_frame(f));
  if (f.kind == FrameKind::kNak) {
    id.error = "the device type query (30h) was NAKed";
    return id;
  }
  if (is_offline_reply(f)) {
    id.error = "the device answered the device type query (30h) with the offline reply";
    return id;
  }
  const auto reply = decode_reply(f);
  if (!reply) {
    id.error = "the device type reply does not decode: " + reply.error().message();
    return id;
  }
  const auto* type = std::get_if<DeviceTypeReply>(&reply.value());
  if (!type) {
    id.error = "the reply to 30h is not a device type reply";
    return id;
  }
  id.ok = true;
  id.controller_type = type->controller;
  id.firmware_version = type->version;
  return id;
}

}  // namespace sabus::reports
