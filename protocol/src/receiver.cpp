#include "sabus/protocol/receiver.hpp"

#include <algorithm>
#include <charconv>
#include <cstring>

#include "sabus/protocol/catalog.hpp"

namespace sabus {

std::string_view to_string(ReceiverState s) {
  switch (s) {
    case ReceiverState::kSlaveIdle: return "State 1 (Slave Idle)";
    case ReceiverState::kSlaveAddressed: return "State 2 (Slave Addressed)";
    case ReceiverState::kSlaveData: return "State 3 (Slave Data)";
    case ReceiverState::kSlaveDataError: return "State 4 (Slave Data Error)";
    case ReceiverState::kCommandExecute: return "State 5 (Command Execute)";
  }
  return "?";
}

std::string_view to_string(DiscardReason r) {
  switch (r) {
#define SABUS_X(id, name, description) \
  case DiscardReason::id: return name;
    SABUS_DISCARD_REASONS(SABUS_X)
#undef SABUS_X
  }
  return "?";
}

std::string_view description(DiscardReason r) {
  switch (r) {
#define SABUS_X(id, name, description) \
  case DiscardReason::id: return description;
    SABUS_DISCARD_REASONS(SABUS_X)
#undef SABUS_X
  }
  return "?";
}

namespace {

// The message is built by appends into one string: `sabus decode` writes one
// for every discarded run, and random input has one every two bytes.
void append_number(std::string& m, std::uint64_t v) {
  char digits[24];
  const auto r = std::to_chars(digits, digits + sizeof digits, v);
  m.append(digits, r.ptr);
}

}  // namespace

std::string Discard::message() const {
  std::string m;
  m.reserve(96);
  m += "bytes ";
  append_number(m, offset);
  m += '-';
  append_number(m, offset + length - 1);
  m += " (";
  append_number(m, length);
  m += "): ";
  m += to_string(reason);
  const auto byte_at = [&](std::string_view before) {
    m += before;
    m += describe_byte(byte);
    m += " at offset ";
    append_number(m, at);
  };
  switch (reason) {
    case DiscardReason::kBadLrc:
      byte_at(": check byte ");
      m += ", expected ";
      m += describe_byte(expected);
      break;
    case DiscardReason::kOtherAddress:
      byte_at(": address ");
      if (!is_valid_address(byte)) m += " (outside 0x31-0x6f)";
      break;
    case DiscardReason::kControlCharacter:
    case DiscardReason::kParityError:
    case DiscardReason::kNotAscii:
    case DiscardReason::kOverrun:
      byte_at(": ");
      break;
    case DiscardReason::kUnknownCommand:
      m += ": command ";
      m += describe_byte(byte);
      break;
    case DiscardReason::kWrongLength:
      m += ": command ";
      m += describe_byte(byte);
      m += " in a frame of ";
      append_number(m, length);
      m += " bytes";
      break;
    case DiscardReason::kIncomplete:
      if (at == offset + length - 1 && byte == ETX) m += ": ETX where the command byte belongs";
      else if (at == offset + length && byte != 0) byte_at(": new start ");
      else if (at == offset + length) m += ": the input ended";
      break;
    case DiscardReason::kUnknown:
      break;
  }
  return m;
}

ReceiverOptions ReceiverOptions::slave(std::uint8_t address) {
  ReceiverOptions o;
  o.accept_address(address);
  return o;
}

ReceiverOptions ReceiverOptions::slave_any_address() { return ReceiverOptions{}; }

ReceiverOptions ReceiverOptions::master() {
  ReceiverOptions o;
  o.starts = StartBytes::kReply;
  // E-35: status byte 40 can be 10h-1Fh, even 15h (NAK), inside a reply.
  o.reject_control_in_body = false;
  o.stx_restarts_in_data = false;
  return o;
}

ReceiverOptions& ReceiverOptions::accept_address(std::uint8_t address) {
  addresses.set(address & 0x7F);
  return *this;
}

Receiver::Receiver(const ReceiverOptions& options) : options_(options) {
  if (options_.max_frame_length == 0) {
    options_.max_frame_length = options_.starts == StartBytes::kCommand ? max_request_length()
                                : options_.starts == StartBytes::kReply ? max_reply_length()
                                                                        : std::max(max_request_length(), max_reply_length());
  }
  options_.max_frame_length = std::clamp<std::size_t>(options_.max_frame_length, kFrameOverhead, kBufferSize);
  // State 3 accepts a further data byte only while ETX and the check byte still fit.
  data_limit_ = options_.max_frame_length - 2;

  // The word-at-a-time check is exact only when every control character
  // leaves State 3's data run (E-6).
  swar_ = options_.reject_control_in_body;

  const bool any_address = options_.addresses.none();
  for (unsigned a = 0; a < 128; ++a)
    address_ok_[a] = any_address ? is_valid_address(static_cast<std::uint8_t>(a)) : options_.addresses.test(a);

  for (unsigned w = 0; w < 256; ++w) {
    const auto wire = static_cast<std::uint8_t>(w);
    const std::uint8_t c = wire & 0x7F;
    ByteClass k;
    if (options_.parity == Parity::kEvenBit7 && !has_even_parity(wire)) {
      k = kBadParity;
    } else if (options_.parity == Parity::kNone && wire > 0x7F) {
      k = kNotAscii;
    } else if (c == ETX) {
      k = kEtx;
    } else if ((c == STX && options_.starts != StartBytes::kReply) ||
               ((c == ACK || c == NAK) && options_.starts != StartBytes::kCommand)) {
      k = kStart;
    } else if (is_control(c)) {
      k = kControl;
    } else {
      k = kData;
    }
    class_[w] = k;
  }
}

// Whether all eight bytes of `w` are data characters, for the options under
// which swar_ is set: parity right (or bit 7 clear without parity checking)
// and the 7-bit character not a control character (bit 5 or 6 set).
bool Receiver::all_data(std::uint64_t w) const {
  constexpr std::uint64_t kLow = 0x0101010101010101ULL;
  const std::uint64_t c = w & (0x7F * kLow);
  const std::uint64_t t = c & (0x60 * kLow);
  if (((t | (t >> 1)) & (0x20 * kLow)) != 0x20 * kLow) return false;
  if (options_.parity == Parity::kNone) return (w & (0x80 * kLow)) == 0;
  if (options_.parity == Parity::kUnchecked) return true;
  std::uint64_t v = w ^ (w >> 4);  // bit 0 of each byte ends as its parity
  v ^= v >> 2;
  v ^= v >> 1;
  return (v & kLow) == 0;
}

void Receiver::reconfigure(const ReceiverOptions& options) {
  Receiver fresh(options);
  fresh.state_ = state_;
  fresh.buf_ = buf_;
  fresh.len_ = len_;
  fresh.lrc_ = lrc_;
  fresh.pos_ = pos_;
  fresh.frame_start_ = frame_start_;
  fresh.unknown_start_ = unknown_start_;
  fresh.unknown_len_ = unknown_len_;
  fresh.unknown_first_ = unknown_first_;
  fresh.unknown_reason_ = unknown_reason_;
  *this = fresh;
}

void Receiver::reset() {
  state_ = ReceiverState::kSlaveIdle;
  len_ = 0;
  unknown_len_ = 0;
}

void Receiver::begin_frame(std::uint8_t c, std::uint64_t at) {
  frame_start_ = at;
  buf_[0] = c;
  len_ = 1;
  lrc_ = options_.lrc_rule == LrcRule::kFromByte0 ? c : 0;
  state_ = ReceiverState::kSlaveAddressed;
}

void Receiver::discard_frame(DiscardReason reason, std::uint64_t end, std::uint64_t at, std::uint8_t byte,
                             ReceiverSink& sink, std::uint8_t expected) {
  Discard d{reason, frame_start_, end - frame_start_, at, byte, expected};
  state_ = ReceiverState::kSlaveIdle;
  len_ = 0;
  sink.on_discard(d);
}

void Receiver::flush_unknown(ReceiverSink& sink) {
  if (unknown_len_ == 0) return;
  Discard d{unknown_reason_, unknown_start_, unknown_len_, unknown_start_, unknown_first_, 0};
  unknown_len_ = 0;
  sink.on_discard(d);
}

DiscardReason Receiver::idle_reason(std::uint8_t byte_class) {
  return byte_class == kBadParity ? DiscardReason::kParityError
         : byte_class == kNotAscii ? DiscardReason::kNotAscii
                                   : DiscardReason::kUnknown;
}

void Receiver::idle_byte(std::uint8_t wire, std::uint64_t at, ReceiverSink& sink) {
  const DiscardReason r = idle_reason(class_[wire]);
  if (unknown_len_ != 0 && r != unknown_reason_) flush_unknown(sink);
  if (unknown_len_ == 0) {
    unknown_start_ = at;
    unknown_first_ = wire;
    unknown_reason_ = r;
  }
  ++unknown_len_;
}

void Receiver::complete_frame(std::uint64_t at, std::uint8_t wire, ReceiverSink& sink) {
  buf_[len_++] = wire & 0x7F;
  const std::uint8_t command = buf_[2];
  if (options_.validate_command_in_receiver && buf_[0] == STX) {
    // E-9, the state diagram's reading: State 3 -> State 1 on an invalid
    // command or byte count, so no NAK is ever sent for them.
    const CommandInfo* info = find_command(command);
    if (info == nullptr)
      return discard_frame(DiscardReason::kUnknownCommand, at + 1, frame_start_ + 2, command, sink);
    if (info->request_length && *info->request_length != len_)
      return discard_frame(DiscardReason::kWrongLength, at + 1, frame_start_ + 2, command, sink);
  }
  state_ = ReceiverState::kCommandExecute;  // State 5, then always State 1
  const FrameKind kind = buf_[0] == STX ? FrameKind::kCommand : buf_[0] == ACK ? FrameKind::kAck : FrameKind::kNak;
  FrameView f{kind, buf_[1], command, ByteView(buf_.data() + 3, len_ - 5), ByteView(buf_.data(), len_),
              frame_start_};
  state_ = ReceiverState::kSlaveIdle;
  len_ = 0;
  sink.on_frame(f);
}

// One byte in any state: every transition that leaves a frame names its reason.
void Receiver::step_slow(std::uint8_t wire, std::uint64_t at, ReceiverSink& sink) {
  const auto k = static_cast<ByteClass>(class_[wire]);
  const std::uint8_t c = wire & 0x7F;
  switch (state_) {
    case ReceiverState::kSlaveIdle:
    case ReceiverState::kCommandExecute:
      if (k == kStart) {
        flush_unknown(sink);
        begin_frame(c, at);
      } else {
        idle_byte(wire, at, sink);
      }
      return;

    case ReceiverState::kSlaveAddressed:
      if (k == kBadParity) return discard_frame(DiscardReason::kParityError, at + 1, at, wire, sink);
      if (k == kNotAscii) return discard_frame(DiscardReason::kNotAscii, at + 1, at, wire, sink);
      if (k == kStart) {
        if (!options_.stx_restarts_in_address)
          return discard_frame(DiscardReason::kOtherAddress, at + 1, at, wire, sink);
        // State 2 c: "remain in current state if STX byte is received".
        discard_frame(DiscardReason::kIncomplete, at, at, wire, sink);
        return begin_frame(c, at);
      }
      if (k == kEtx || k == kControl) return discard_frame(DiscardReason::kControlCharacter, at + 1, at, wire, sink);
      if (!address_ok_[c]) return discard_frame(DiscardReason::kOtherAddress, at + 1, at, wire, sink);
      buf_[len_++] = c;  // State 2 a: our address
      lrc_ ^= c;
      state_ = ReceiverState::kSlaveData;
      return;

    case ReceiverState::kSlaveData:
      switch (k) {
        case kBadParity: return discard_frame(DiscardReason::kParityError, at + 1, at, wire, sink);
        case kNotAscii: return discard_frame(DiscardReason::kNotAscii, at + 1, at, wire, sink);
        case kEtx:
          if (len_ == 2) return discard_frame(DiscardReason::kIncomplete, at + 1, at, wire, sink);
          buf_[len_++] = c;
          lrc_ ^= c;
          state_ = ReceiverState::kSlaveDataError;  // State 3 a
          return;
        case kStart:
          if (options_.stx_restarts_in_data) {  // E-7
            discard_frame(DiscardReason::kIncomplete, at, at, wire, sink);
            return begin_frame(c, at);
          }
          // E-7's state diagram (State 3 b), whatever E-6 reads: the STX is
          // lost. An ACK or NAK inside a reply is data (master side, E-35).
          if (c == STX) return discard_frame(DiscardReason::kControlCharacter, at + 1, at, wire, sink);
          [[fallthrough]];
        case kControl:
          if (options_.skip_control_in_body && k == kControl) {  // a fault's, no reading
            lrc_ ^= c;
            return;
          }
          if (options_.reject_control_in_body)  // E-6
            return discard_frame(DiscardReason::kControlCharacter, at + 1, at, wire, sink);
          [[fallthrough]];
        case kData:
          if (len_ >= data_limit_) return discard_frame(DiscardReason::kOverrun, at + 1, at, wire, sink);  // E-8
          buf_[len_++] = c;
          lrc_ ^= c;
          return;
      }
      return;

    case ReceiverState::kSlaveDataError:
      if (k == kBadParity) return discard_frame(DiscardReason::kParityError, at + 1, at, wire, sink);
      if (k == kNotAscii) return discard_frame(DiscardReason::kNotAscii, at + 1, at, wire, sink);
      if (k == kStart && options_.check_byte_restarts_on_stx) {
        discard_frame(DiscardReason::kIncomplete, at, at, wire, sink);
        return begin_frame(c, at);
      }
      // E-5: any byte is the check byte, a control character included.
      if (c != lrc_) return discard_frame(DiscardReason::kBadLrc, at + 1, at, wire, sink, lrc_);
      return complete_frame(at, wire, sink);  // State 4 a -> State 5
  }
}

void Receiver::feed(ByteView chunk, ReceiverSink& sink) {
  const std::uint8_t* p = chunk.data();
  const std::size_t n = chunk.size();
  const std::uint64_t base = pos_;
  std::size_t i = 0;
  while (i < n) {
    if (state_ == ReceiverState::kSlaveIdle) {
      // Fast path: skip bytes that cannot start a frame, a run of one kind
      // (idle_byte) at a time.
      while (i < n && class_[p[i]] != kStart) {
        idle_byte(p[i], base + i, sink);
        const DiscardReason kind = unknown_reason_;
        const std::size_t run = ++i;
        while (i < n && class_[p[i]] != kStart && idle_reason(class_[p[i]]) == kind) ++i;
        unknown_len_ += i - run;
      }
      if (i == n) break;
    } else if (state_ == ReceiverState::kSlaveData) {
      // Fast path: a run of ordinary data characters. Locals keep the loop
      // free of member reloads (byte stores may alias any member).
      const std::uint8_t* cls = class_.data();
      std::uint8_t* out = buf_.data() + len_;
      std::uint8_t x = lrc_;
      const std::size_t room = data_limit_ - len_;
      const std::size_t run = std::min(n - i, room);
      std::size_t k = 0;
      if (swar_) {
        // Eight bytes per step while all are data characters.
        for (; k + 8 <= run; k += 8) {
          std::uint64_t w;
          std::memcpy(&w, p + i + k, 8);
          if (!all_data(w)) break;
          const std::uint64_t c = w & 0x7F7F7F7F7F7F7F7FULL;
          std::memcpy(out + k, &c, 8);
          std::uint64_t f = c ^ (c >> 32);
          f ^= f >> 16;
          f ^= f >> 8;
          x ^= static_cast<std::uint8_t>(f);
        }
      }
      for (; k < run; ++k) {
        const std::uint8_t w = p[i + k];
        if (cls[w] != kData) break;
        const std::uint8_t c = w & 0x7F;
        out[k] = c;
        x ^= c;
      }
      len_ += k;
      lrc_ = x;
      i += k;
      if (i == n) break;
    }
    step_slow(p[i], base + i, sink);
    ++i;
  }
  pos_ = base + n;
}

void Receiver::finish(ReceiverSink& sink) {
  if (state_ != ReceiverState::kSlaveIdle && len_ > 0)
    discard_frame(DiscardReason::kIncomplete, pos_, pos_, 0, sink);
  state_ = ReceiverState::kSlaveIdle;
  len_ = 0;
  flush_unknown(sink);
}

}  // namespace sabus
