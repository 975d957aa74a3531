// Helpers shared by the tests: byte literals and a receiver event log.
#pragma once

#include <string>
#include <vector>

#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::test {

// "02 32 31 03 02" -> bytes; aborts the test on bad hex.
inline Bytes hex(std::string_view text) {
  auto b = parse_hex(text);
  if (!b) throw std::runtime_error("bad hex in test: " + b.error().message());
  return b.value();
}

// A frame of 7-bit characters from a text body: frame(STX, '2', '1', "") etc.
inline Bytes frame_bytes(FrameKind kind, char address, char command, std::string_view data) {
  return encode_frame(Frame{kind, static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(command),
                            Bytes(data.begin(), data.end())});
}
inline Bytes command(char address, char code, std::string_view data = "") {
  return frame_bytes(FrameKind::kCommand, address, code, data);
}
inline Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// Records every receiver event in order, comparable between runs.
struct EventLog : ReceiverSink {
  struct Entry {
    bool frame;
    Bytes bytes;          // frame bytes
    std::uint64_t offset;
    Discard discard;
    bool operator==(const Entry& o) const {
      return frame == o.frame && bytes == o.bytes && offset == o.offset && (frame || discard == o.discard);
    }
  };
  std::vector<Entry> entries;
  void on_frame(const FrameView& f) override {
    entries.push_back({true, Bytes(f.bytes.begin(), f.bytes.end()), f.offset, {}});
  }
  void on_discard(const Discard& d) override { entries.push_back({false, {}, d.offset, d}); }
  std::vector<Bytes> frames() const {
    std::vector<Bytes> out;
    for (const auto& e : entries)
      if (e.frame) out.push_back(e.bytes);
    return out;
  }
  std::vector<Discard> discards() const {
    std::vector<Discard> out;
    for (const auto& e : entries)
      if (!e.frame) out.push_back(e.discard);
    return out;
  }
};

inline EventLog receive(const ReceiverOptions& options, ByteView bytes) {
  Receiver r(options);
  EventLog log;
  r.feed(bytes, log);
  r.finish(log);
  return log;
}

// 7-bit receiver (no parity bit), as after a true 7E1 UART: most tests speak
// in characters; parity tests use the even_bit7 default explicitly.
inline ReceiverOptions chars(ReceiverOptions o) {
  o.parity = Parity::kNone;
  return o;
}

}  // namespace sabus::test
