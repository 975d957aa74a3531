// What fuzz_record and its seeds share (fuzz_record.cpp): the vectors it
// runs, the device it runs them on, and how an input scripts the device's
// replies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/profile.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/vector.hpp"
#include "sabus/protocol/bytes.hpp"

namespace sabus::fuzz::record {

// A short selection of the suite: a reply of each layout family, a read of a
// filled and of an empty slot, a NAK, a frame the device must ignore, and
// vectors the run skips (motion, a profile it lacks) so every outcome a
// record holds can come up. An id the suite no longer has stops the target
// and the seed generator at once.
inline constexpr const char* kVectorIds[] = {
    "3.1-device-type-fields",         "3.2-status-frame-fields",      "3.11-read-satellite-first",
    "3.11-read-satellite-empty-slot", "3.13-read-tle-first",          "3.17-extended-status-status-block",
    "3.6-query-name-first-entry",     "3.16-pulse-count-five-digits", "nak-reply-fields",
    "framing-bad-lrc-silence",        "3.3-form2A-move-and-arrive",   "offline-31h-status"};
// Listed in the run's known issues, so that a failure is a known failure and
// a pass an unexpected pass.
inline constexpr const char* kKnownIssueId = "3.2-status-frame-fields";

// The run's options: no motion, nothing stored changed, each failure run
// once more, kKnownIssueId a known issue.
harness::RunOptions run_options();

// The vectors above, loaded from the suite embedded at build time
// (embedded_vectors.cpp), in that order. Throws std::runtime_error naming an
// id that is missing or a file that does not load.
const std::vector<harness::Vector>& vectors();
// The device: the default profile (vectors/profiles/rc3000-1.59.yaml).
const harness::Profile& profile();

// The input: byte 0 knobs, then one reply script per command the runner
// sends, in order; when the input runs out the device is silent.
//   byte 0, bit 0: a true 7E1 port (the transport's parity_in_bit7() false:
//                  received bytes are 7-bit characters, a byte with bit 7
//                  set one the UART flagged) rather than software parity
//   each reply: [flags] [length] [length bytes]
//     flags bit 0: put even parity in bit 7 of each byte (the bytes are
//                  characters); otherwise the bytes are as on the wire
//     flags bit 1: the device is lost at this command (the port closes:
//                  TransportLost), the reply is not sent
inline constexpr std::uint8_t kTrue7E1 = 0x01;
inline constexpr std::uint8_t kWithParity = 0x01;
inline constexpr std::uint8_t kLost = 0x02;

struct Script {
  bool true_7e1 = false;
  std::vector<Bytes> replies;  // wire bytes for each command, in order
  std::optional<std::size_t> lost_at;  // the command at which the device is lost
};
Script parse_script(const std::uint8_t* data, std::size_t size);
// The input of a script (its replies as wire bytes, up to 255 each).
Bytes script_input(const Script& s);

}  // namespace sabus::fuzz::record
