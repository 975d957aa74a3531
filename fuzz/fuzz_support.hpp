// What the fuzz targets share: the device profiles embedded at build time, the
// structure-aware mutator for byte streams of SAbus frames, the input layout
// of the whole-controller target, and the dictionary tokens derived from the
// command catalog.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sabus/harness/clock.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus::fuzz {

// The profiles of vectors/profiles/*.yaml, read by the product's profile
// loader from copies embedded at build time: fuzz targets also run where the
// source tree is not (a fuzzing service only has the binaries). Sorted by name.
const std::vector<harness::Profile>& profiles();

// How a frame-level target lays out its input: `header` knob bytes, then a
// byte stream of frames.
struct StreamFormat {
  std::size_t header = 0;
  // Whether the stream carries even parity in bit 7 (§1 Data Format), given
  // the header; nullptr: never.
  bool (*wire)(const std::uint8_t* header) = nullptr;
  // The LRC rule the target checks (§1 Check Character), given the header.
  LrcRule (*lrc_rule)(const std::uint8_t* header) = nullptr;
};

// The custom mutator of the frame-level targets (LLVMFuzzerCustomMutator):
// mutates whole frames (insert an encoded request of any catalog command and
// form, delete, duplicate, swap) and fields (command code, address, form
// selector, key code, digits, length), and then repairs the check byte and
// parity of every frame most of the time, so inputs get past the LRC into the
// command handlers. One mutation in ten is libFuzzer's byte-level one.
std::size_t mutate_stream(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed,
                          const StreamFormat& format);

// Dictionary entries, derived from the catalog and the codecs (never a second
// list of codes): delimiters, address bounds, every command code, every form
// selector and sub-command, every key code.
struct Token {
  std::string comment;
  Bytes bytes;
};
std::vector<Token> dictionary_tokens();
// The same single-byte values as the mutator uses for field mutations.
const Bytes& field_bytes();

// The whole-controller target's input: byte 0 picks the profile, byte 1 the
// virtual time between chunks (20 ms units), the rest are wire bytes (even
// parity in bit 7) fed in chunks that each end before a byte whose 7 bits are
// STX, so each chunk completes at most one frame.
struct ControllerInput {
  const harness::Profile* profile = nullptr;
  harness::Duration step{};
  std::vector<ByteView> chunks;
};
inline constexpr std::size_t kControllerHeader = 2;
bool parse_controller_input(const std::uint8_t* data, std::size_t size, ControllerInput& out);
bool controller_stream_is_wire(const std::uint8_t* header);

}  // namespace sabus::fuzz
