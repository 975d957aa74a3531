// Receiver throughput against a plain byte-by-byte XOR loop over the same
// buffer, in one binary and one run; prints the ratio and the heap
// allocations made while the receiver ran. Run: build/tools/bench_receiver
#include <benchmark/benchmark.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <new>
#include <string>

#include "sabus/protocol/codec.hpp"
#include "alloc_counter.hpp"
#include "sabus/protocol/receiver.hpp"

namespace {

using namespace sabus;

// ~1 MiB on the wire (even parity in bit 7): status polls, auto moves, TLE
// writes and status replies' worth of data, with a garbage run every 16 frames.
const Bytes& stream() {
  static const Bytes s = [] {
    Bytes out;
    WriteTle tle;
    tle.line1 = std::string(69, '1');
    tle.line2 = std::string(69, '2');
    const Bytes frames[] = {
        encode_request(StatusPoll{}, '2'),
        encode_request(AutoMove{AutoMoveAzEl{-1525, 456}}, '2'),
        encode_request(tle, '2'),
        encode_request(WriteSatellite{}, '2'),
        encode_request(Jog{}, '3'),  // another address
    };
    std::uint32_t rng = 12345;
    std::size_t n = 0;
    while (out.size() < (1u << 20)) {
      const Bytes wire = add_even_parity(frames[n % 5]);
      out.insert(out.end(), wire.begin(), wire.end());
      if (++n % 16 == 0)
        for (int i = 0; i < 24; ++i) {
          rng = rng * 1103515245 + 12345;
          out.push_back(static_cast<std::uint8_t>(rng >> 16));
        }
    }
    return out;
  }();
  return s;
}

struct CountingSink : ReceiverSink {
  std::size_t frames = 0, discards = 0;
  void on_frame(const FrameView&) override { ++frames; }
  void on_discard(const Discard&) override { ++discards; }
};

std::size_t g_receiver_allocations = 0;
std::size_t g_frames = 0;

void BM_Receiver(benchmark::State& state) {
  const Bytes& s = stream();
  Receiver receiver(ReceiverOptions::slave('2'));
  CountingSink sink;
  const std::size_t before = test::g_allocations.load();
  for (auto _ : state) {
    receiver.feed(s, sink);
    benchmark::DoNotOptimize(sink.frames);
  }
  g_receiver_allocations = test::g_allocations.load() - before;
  g_frames = sink.frames / state.iterations();
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s.size()));
}
BENCHMARK(BM_Receiver);

// One byte per iteration, as the LRC is defined; auto-vectorisation is
// switched off so the baseline stays a byte-by-byte loop.
#if defined(__clang__)
__attribute__((noinline)) std::uint8_t xor_bytes(const std::uint8_t* p, std::size_t n) {
  std::uint8_t x = 0;
#pragma clang loop vectorize(disable) interleave(disable)
  for (std::size_t i = 0; i < n; ++i) x ^= p[i];
  return x;
}
#else
__attribute__((noinline, optimize("no-tree-vectorize", "no-unroll-loops"))) std::uint8_t xor_bytes(
    const std::uint8_t* p, std::size_t n) {
  std::uint8_t x = 0;
  for (std::size_t i = 0; i < n; ++i) x ^= p[i];
  return x;
}
#endif

void BM_XorLoop(benchmark::State& state) {
  const Bytes& s = stream();
  for (auto _ : state) benchmark::DoNotOptimize(xor_bytes(s.data(), s.size()));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s.size()));
}
BENCHMARK(BM_XorLoop);

// Keeps each benchmark's bytes per second for the closing ratio.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  std::map<std::string, double> bytes_per_second;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs) {
      // With --benchmark_repetitions, the mean stands for the run.
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "mean") continue;
      auto it = r.counters.find("bytes_per_second");
      if (it != r.counters.end()) bytes_per_second[r.run_name.function_name] = it->second;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  const double rx = reporter.bytes_per_second["BM_Receiver"];
  const double xr = reporter.bytes_per_second["BM_XorLoop"];
  std::printf("\nstream: %zu bytes, %zu frames accepted per pass\n", stream().size(), g_frames);
  std::printf("receiver: %.1f MB/s   byte-by-byte XOR loop: %.1f MB/s   ratio: %.3f (target >= 0.25)\n", rx / 1e6,
              xr / 1e6, xr > 0 ? rx / xr : 0.0);
  std::printf("heap allocations while the receiver ran: %zu\n", g_receiver_allocations);
  benchmark::Shutdown();
  return 0;
}
