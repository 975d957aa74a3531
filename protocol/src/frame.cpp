#include "sabus/protocol/frame.hpp"

namespace sabus {

std::string_view to_string(FrameKind kind) {
  switch (kind) {
    case FrameKind::kCommand: return "command";
    case FrameKind::kAck: return "ACK";
    case FrameKind::kNak: return "NAK";
  }
  return "?";
}

std::uint8_t start_byte(FrameKind kind) {
  switch (kind) {
    case FrameKind::kCommand: return STX;
    case FrameKind::kAck: return ACK;
    case FrameKind::kNak: return NAK;
  }
  return STX;
}

Bytes encode_frame(const Frame& f, LrcRule rule) {
  Bytes out;
  out.reserve(f.data.size() + 5);
  out.push_back(start_byte(f.kind));
  out.push_back(f.address);
  out.push_back(f.command);
  out.insert(out.end(), f.data.begin(), f.data.end());
  out.push_back(ETX);
  out.push_back(lrc(out, rule));
  return out;
}

Expected<Frame> decode_frame(ByteView b, const FrameCheck& check) {
  // The shortest frame is NAK A CC ETX LRC (§3 NAK Reply).
  if (b.size() < 5)
    return DecodeError{b.size(), "frame", "at least 5 bytes (start, address, command, ETX, check byte)",
                       std::to_string(b.size()) + " bytes"};
  Frame f;
  switch (b[0]) {
    case STX: f.kind = FrameKind::kCommand; break;
    case ACK: f.kind = FrameKind::kAck; break;
    case NAK: f.kind = FrameKind::kNak; break;
    default: return DecodeError{0, "start", "STX, ACK or NAK", describe_byte(b[0])};
  }
  if (!is_valid_address(b[1]))
    return DecodeError{1, "address", "an address 0x31-0x6f (§1 Address Character)", describe_byte(b[1])};
  f.address = b[1];
  if (!is_printable(b[2])) return DecodeError{2, "command", "a printable command code", describe_byte(b[2])};
  f.command = b[2];
  const std::size_t etx = b.size() - 2;
  for (std::size_t i = 3; i < etx; ++i) {
    std::uint8_t c = b[i];
    if (c > 0x7F) return DecodeError{i, "data", "a 7-bit character", describe_byte(c)};
    bool control_ok = f.kind != FrameKind::kCommand && check.allow_control_in_reply_body && c != ETX;
    if (is_control(c) && !control_ok) {
      if (c == ETX)
        return DecodeError{i, "data", "data up to byte " + std::to_string(etx) + ", then ETX",
                           "ETX at byte " + std::to_string(i)};
      return DecodeError{i, "data", "a printable character 0x20-0x7f (READING-NOTES 6)", describe_byte(c)};
    }
  }
  if (b[etx] != ETX) return DecodeError{etx, "ETX", "ETX before the check byte", describe_byte(b[etx])};
  const std::uint8_t want = lrc(b.first(b.size() - 1), check.lrc);
  if (b.back() != want)
    return DecodeError{b.size() - 1, "check byte", describe_byte(want) + " (XOR of byte 0 through ETX)",
                       describe_byte(b.back())};
  f.data.assign(b.begin() + 3, b.begin() + static_cast<std::ptrdiff_t>(etx));
  return f;
}

Frame nak_reply(std::uint8_t address, std::uint8_t command) { return {FrameKind::kNak, address, command, {}}; }

Frame offline_reply(std::uint8_t address, std::uint8_t command) {
  return {FrameKind::kAck, address, command, {kOfflineMarker}};
}

bool is_offline_reply(const Frame& f) {
  // ERRATA E-44: a one-byte 'F' ACK is the offline reply for every command code.
  return f.kind == FrameKind::kAck && f.data.size() == 1 && f.data[0] == kOfflineMarker;
}

std::optional<std::size_t> last_frame_start(ByteView b) {
  for (std::size_t i = b.size(); i-- > 0;)
    if ((b[i] == STX || b[i] == ACK || b[i] == NAK) && i + 1 < b.size() && is_valid_address(b[i + 1])) return i;
  return std::nullopt;
}

}  // namespace sabus

namespace sabus {
Expected<std::uint8_t> parse_address(std::string_view text) {
  auto bad = [&] {
    std::string got(1, '"');
    got.append(text).push_back('"');
    return DecodeError{0, "address", "49-111 (decimal), an address character '1'-'o', or 0x31-0x6f", got};
  };
  if (text.empty()) return bad();
  unsigned v = 0;
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    for (char c : text.substr(2)) {
      int d = (c >= '0' && c <= '9') ? c - '0' : (c >= 'a' && c <= 'f') ? c - 'a' + 10 : (c >= 'A' && c <= 'F') ? c - 'A' + 10 : -1;
      if (d < 0 || v > 0xFF) return bad();
      v = v * 16 + static_cast<unsigned>(d);
    }
  } else if (text.size() == 1) {
    v = static_cast<unsigned char>(text[0]);
  } else {
    for (char c : text) {
      if (c < '0' || c > '9' || v > 1000) return bad();
      v = v * 10 + static_cast<unsigned>(c - '0');
    }
  }
  if (v > 0xFF || !is_valid_address(static_cast<std::uint8_t>(v))) return bad();
  return static_cast<std::uint8_t>(v);
}
}  // namespace sabus
