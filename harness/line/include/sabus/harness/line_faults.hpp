// A noisy line, made on purpose: `sabus sim --line-faults` and `sabus run
// --sim --line-faults` put it between the runner and the reference
// controller, so the runner's handling of line faults (RunOptions::retries,
// Verdict::kError) is tested against the faults a real RS-422 run, a USB
// adapter or a terminal server makes (§4 lists "a garbled status reply"
// among the symptoms of unreliable communications). Pure: a seeded generator
// and the bytes; no clock, no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <string_view>

#include "sabus/protocol/bytes.hpp"

namespace sabus::harness {

// What the line does to a byte it hits.
enum class LineFaultKind : std::uint8_t {
  kFlip = 1,    // one of its 8 wire bits inverted (the parity bit too): a parity error
  kDrop = 2,    // lost
  kInsert = 4,  // a byte of noise after it
  kOutage = 8,  // the line drops for a short spell: it and up to kOutageBytes - 1 bytes after it are lost
};
inline constexpr unsigned kAllLineFaultKinds = 15;
inline constexpr std::size_t kOutageBytes = 16;

struct LineFaultSpec {
  double rate = 0;  // the share of bytes hit, each way (a byte error rate: 1e-3)
  unsigned kinds = kAllLineFaultKinds;
  std::uint64_t seed = 1;
};

// "RATE[,KIND...]": "1e-3", "0.01,flip,drop" (kinds: flip, drop, insert,
// outage; all four when none is named). The rate is in [0, 0.5]. nullopt
// with `error` saying what is wrong.
std::optional<LineFaultSpec> parse_line_faults(std::string_view text, std::string& error);
// "byte error rate 0.001 (flip, drop, insert, outage), seed 7".
std::string describe(const LineFaultSpec& spec);

// What the line did, by kind: the faults injected.
struct LineFaultTally {
  std::size_t bytes = 0;  // bytes offered to the line
  std::size_t flips = 0, drops = 0, inserts = 0, outages = 0;
  std::size_t total() const { return flips + drops + inserts + outages; }
};
// "3 faults in 14,120 bytes (1 flipped, 1 dropped, 0 inserted, 1 outage)".
std::string describe(const LineFaultTally& tally);

class LineFaultInjector {
 public:
  explicit LineFaultInjector(LineFaultSpec spec);
  // `wire` as the far end receives it: bytes on the wire, parity bit included.
  Bytes pass(ByteView wire);
  const LineFaultTally& tally() const { return tally_; }
  const LineFaultSpec& spec() const { return spec_; }

 private:
  LineFaultKind pick_kind();
  LineFaultSpec spec_;
  std::mt19937_64 rng_;
  LineFaultTally tally_;
};

}  // namespace sabus::harness
