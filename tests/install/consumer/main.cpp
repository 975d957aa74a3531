// Encodes a Device Status Poll with the installed protocol library and reads
// it back; prints the frame and exits 0 when both directions agree with the
// manual's own example (02 32 31 03 02, docs/bench-regression.md, "Decoding captures").
#include <cstdio>
#include <string>

#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/frame.hpp"

int main() {
  const sabus::CommandInfo* poll = sabus::find_command("status");
  if (poll == nullptr) {
    std::puts("the catalog has no status command");
    return 1;
  }
  const sabus::Bytes bytes = sabus::encode_frame({sabus::FrameKind::kCommand, 0x32, poll->code, {}});
  const std::string hex = sabus::to_hex(bytes);
  const auto back = sabus::decode_frame(bytes);
  std::printf("%s: %s\n", std::string(poll->name).c_str(), hex.c_str());
  if (hex != "02 32 31 03 02") return 1;
  if (!back || back->command != poll->code || back->address != 0x32) return 1;
  return 0;
}
