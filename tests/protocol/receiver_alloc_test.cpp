// The receiver allocates nothing per byte or per frame: global operator new is
// replaced here to count allocations while a long stream is fed.
#include <gtest/gtest.h>

#include "sabus/protocol/receiver.hpp"
#include "alloc_counter.hpp"
#include "test_support.hpp"

namespace sabus {
namespace {

struct CountingSink : ReceiverSink {
  std::size_t frames = 0, discards = 0;
  void on_frame(const FrameView&) override { ++frames; }
  void on_discard(const Discard&) override { ++discards; }
};

TEST(ReceiverAllocations, NoneWhileFeeding) {
  Bytes stream;
  for (int i = 0; i < 1000; ++i) {
    Bytes f = add_even_parity(test::command('2', 0x31));
    stream.insert(stream.end(), f.begin(), f.end());
    Bytes junk = {0x41, 0x02, 0x32, 0x31, 0x03, 0x00};
    stream.insert(stream.end(), junk.begin(), junk.end());
  }
  Receiver receiver(ReceiverOptions::slave('2'));
  CountingSink sink;
  const std::size_t before = test::g_allocations.load();
  for (std::size_t i = 0; i < stream.size(); i += 7)
    receiver.feed(ByteView(stream).subspan(i, std::min<std::size_t>(7, stream.size() - i)), sink);
  receiver.finish(sink);
  const std::size_t after = test::g_allocations.load();
  EXPECT_EQ(sink.frames, 1000u);
  EXPECT_GE(sink.discards, 1000u);
  EXPECT_EQ(after - before, 0u) << "heap allocations while feeding " << stream.size() << " bytes";
}

}  // namespace
}  // namespace sabus
