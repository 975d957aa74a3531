// oracle_codec.hpp. With coverage, compiled with `sabus` defined as
// `sabus_oracle` (fuzz/CMakeLists.txt): the codecs called here are then the
// uninstrumented copy's.
#include "oracle_codec.hpp"

#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/frame.hpp"

namespace sabus_fuzz_oracle {

const char* why_reply_does_not_decode(const std::uint8_t* reply, std::size_t size) {
  auto frame = sabus::decode_frame(sabus::ByteView(reply, size));
  if (!frame) return "a reply that does not decode as a frame";
  if (!sabus::decode_reply(frame.value())) return "a reply whose fields do not decode";
  return nullptr;
}

}  // namespace sabus_fuzz_oracle
