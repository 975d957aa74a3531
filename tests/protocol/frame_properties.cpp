// Properties of whole frames: the LRC closes every frame.
#include "generators.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus {
namespace {

Frame random_frame() {
  Frame f;
  f.kind = *rc::gen::element(FrameKind::kCommand, FrameKind::kAck, FrameKind::kNak);
  f.address = static_cast<std::uint8_t>(*rc::gen::inRange(0x31, 0x70));
  f.command = static_cast<std::uint8_t>(*rc::gen::inRange(0x20, 0x80));
  const int n = *rc::gen::inRange(0, 165);
  for (int i = 0; i < n; ++i) f.data.push_back(static_cast<std::uint8_t>(*rc::gen::inRange(0x20, 0x80)));
  return f;
}

RC_GTEST_PROP(FrameProperties, XorOfAWholeFrameIsZero, ()) {
  const Bytes b = encode_frame(random_frame());
  std::uint8_t x = 0;
  for (auto c : b) x ^= c;
  RC_ASSERT(x == 0);
}

RC_GTEST_PROP(FrameProperties, DecodeInvertsEncode, ()) {
  const Frame f = random_frame();
  const auto d = decode_frame(encode_frame(f));
  RC_ASSERT(d.ok());
  RC_ASSERT(d.value() == f);
}

RC_GTEST_PROP(FrameProperties, AnySingleByteChangeIsDetected, ()) {
  // Changing one byte of a frame breaks its LRC (or its structure).
  const Bytes good = encode_frame(random_frame());
  Bytes bad = good;
  const auto i = static_cast<std::size_t>(*rc::gen::inRange<int>(0, static_cast<int>(bad.size())));
  bad[i] = static_cast<std::uint8_t>(bad[i] ^ *rc::gen::inRange(1, 256));
  RC_ASSERT(!decode_frame(bad).ok());
}

RC_GTEST_PROP(FrameProperties, ParityIsEvenOnEveryWireByte, ()) {
  for (auto w : add_even_parity(encode_frame(random_frame()))) RC_ASSERT(has_even_parity(w));
}

}  // namespace
}  // namespace sabus
