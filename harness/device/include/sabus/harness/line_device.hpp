// What a line server serves: bytes in from the line, bytes out to it.
#pragma once

#include <string>

#include "sabus/protocol/bytes.hpp"

namespace sabus::harness {

class LineDevice {
 public:
  virtual ~LineDevice() = default;
  // Bytes received from the line, as they came (parity bit included). Reply
  // bytes to put on the line are appended to `out`.
  virtual void receive(ByteView wire, Bytes& out) = 0;
  // Lets time pass (motion, jog timers); called often by the server loop.
  virtual void tick() = 0;
  // Human-readable lines about what happened since the last call, for
  // `--log` transcripts (decoded frames, ignore reasons); may be empty.
  virtual std::string take_log() { return {}; }
};

}  // namespace sabus::harness
