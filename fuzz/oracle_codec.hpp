// The reply decoding of fuzz_controller's oracle, kept out of the coverage
// that steers libFuzzer (fuzz/CMakeLists.txt, sabus_fuzz_oracle_codec): with
// coverage, oracle_codec.cpp is built with its own uninstrumented copy of the
// protocol library, in another namespace, beside the instrumented copy under
// test. This header names nothing of either copy.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sabus_fuzz_oracle {

// Why a reply does not decode as a frame (the codecs' decode_frame) or its
// fields do not (decode_reply), or nullptr.
const char* why_reply_does_not_decode(const std::uint8_t* reply, std::size_t size);

}  // namespace sabus_fuzz_oracle
