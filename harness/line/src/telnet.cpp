// The Telnet layer of a terminal server's connection (telnet.hpp): escaping,
// the incremental decoder, option states, and RFC 2217's COM-PORT-OPTION
// payloads.
#include "sabus/harness/telnet.hpp"

#include <fmt/format.h>

namespace sabus::harness::telnet {

void append_escaped(ByteView data, Bytes& out) {
  out.reserve(out.size() + data.size());
  for (const std::uint8_t b : data) {
    out.push_back(b);
    if (b == kIAC) out.push_back(kIAC);  // RFC 854: a data byte 255 is sent as IAC IAC
  }
}

Bytes escaped(ByteView data) {
  Bytes out;
  append_escaped(data, out);
  return out;
}

Bytes negotiation(std::uint8_t verb, std::uint8_t option) { return {kIAC, verb, option}; }

Bytes subnegotiation(std::uint8_t option, ByteView payload) {
  Bytes out{kIAC, kSB, option};
  append_escaped(payload, out);
  out.push_back(kIAC);
  out.push_back(kSE);
  return out;
}

std::string option_name(std::uint8_t option) {
  switch (option) {
    case kBinary: return "BINARY";
    case kEcho: return "ECHO";
    case kSuppressGoAhead: return "SUPPRESS-GO-AHEAD";
    case kComPortOption: return "COM-PORT-OPTION";
    default: return fmt::format("option {}", option);
  }
}

namespace {
std::string verb_name(std::uint8_t verb) {
  switch (verb) {
    case kWILL: return "WILL";
    case kWONT: return "WONT";
    case kDO: return "DO";
    case kDONT: return "DONT";
    case kNOP: return "NOP";
    default: return fmt::format("command {}", verb);
  }
}
}  // namespace

std::string describe(const Event& e) {
  switch (e.kind) {
    case Event::Kind::negotiation: return verb_name(e.verb) + " " + option_name(e.option);
    case Event::Kind::subnegotiation: {
      std::string text = "SB " + option_name(e.option);
      if (e.option == kComPortOption && !e.payload.empty()) {
        text += " " + com_port::command_name(e.payload[0]);
        if (e.payload.size() > 1) text += " " + to_hex(ByteView(e.payload).subspan(1));
      } else if (!e.payload.empty()) {
        text += " " + to_hex(e.payload);
      }
      return text;
    }
    case Event::Kind::command: return verb_name(e.verb);
    case Event::Kind::error: return "error: " + e.reason;
  }
  return "?";
}

void Decoder::after_iac(std::uint8_t b, Bytes& data, std::vector<Event>& events) {
  state_ = State::data;
  switch (b) {
    case kIAC: data.push_back(kIAC); return;
    case kWILL: case kWONT: case kDO: case kDONT: verb_ = b; state_ = State::after_verb; return;
    case kSB: state_ = State::sb_option; return;
    case kSE: events.push_back({Event::Kind::error, 0, 0, {}, "IAC SE outside a subnegotiation: ignored"}); return;
    default: events.push_back({Event::Kind::command, b, 0, {}, {}}); return;
  }
}

void Decoder::feed(ByteView in, Bytes& data, std::vector<Event>& events) {
  for (const std::uint8_t b : in) {
    switch (state_) {
      case State::data:
        if (b == kIAC) state_ = State::after_iac;
        else data.push_back(b);
        break;
      case State::after_iac: after_iac(b, data, events); break;
      case State::after_verb:
        events.push_back({Event::Kind::negotiation, verb_, b, {}, {}});
        state_ = State::data;
        break;
      case State::sb_option:
        sb_option_ = b;
        sb_.clear();
        state_ = State::sb_payload;
        break;
      case State::sb_payload:
      case State::sb_after_iac: {
        const bool escaped_iac = state_ == State::sb_after_iac && b == kIAC;
        if (state_ == State::sb_payload && b == kIAC) {
          state_ = State::sb_after_iac;
          break;
        }
        if (state_ == State::sb_after_iac && b == kSE) {
          if (sb_.empty())
            events.push_back({Event::Kind::error, 0, sb_option_, {}, "empty subnegotiation of " + option_name(sb_option_)});
          else
            events.push_back({Event::Kind::subnegotiation, 0, sb_option_, sb_, {}});
          sb_.clear();
          state_ = State::data;
          break;
        }
        if (state_ == State::sb_after_iac && !escaped_iac) {
          // RFC 855 ends a subnegotiation only with IAC SE; a peer that sends
          // another command inside one has lost its place. The payload so far
          // is dropped and the command is taken as it comes.
          events.push_back({Event::Kind::error, 0, sb_option_, {},
                            fmt::format("subnegotiation of {} cut short by IAC {} (no IAC SE): dropped",
                                        option_name(sb_option_), b)});
          sb_.clear();
          after_iac(b, data, events);
          break;
        }
        if (sb_.size() >= kMaxSubnegotiation) {
          events.push_back({Event::Kind::error, 0, sb_option_, {},
                            fmt::format("subnegotiation of {} longer than {} bytes: dropped",
                                        option_name(sb_option_), kMaxSubnegotiation)});
          sb_.clear();
          state_ = State::sb_discard;
          break;
        }
        sb_.push_back(b);
        state_ = State::sb_payload;
        break;
      }
      case State::sb_discard:
        if (b == kIAC) state_ = State::sb_discard_after_iac;
        break;
      case State::sb_discard_after_iac:
        if (b == kSE) state_ = State::data;
        else if (b == kIAC) state_ = State::sb_discard;
        else after_iac(b, data, events);
        break;
    }
  }
}

Options::Options(std::vector<std::uint8_t> local_allowed, std::vector<std::uint8_t> remote_allowed)
    : local_allowed_(std::move(local_allowed)), remote_allowed_(std::move(remote_allowed)) {}

bool Options::has(const std::vector<std::uint8_t>& list, std::uint8_t option) {
  for (const auto o : list)
    if (o == option) return true;
  return false;
}

Bytes Options::request_local(std::uint8_t option) {
  if (local_[option] != State::off) return {};
  local_[option] = State::requested;
  return negotiation(kWILL, option);
}

Bytes Options::request_remote(std::uint8_t option) {
  if (remote_[option] != State::off) return {};
  remote_[option] = State::requested;
  return negotiation(kDO, option);
}

Bytes Options::receive(std::uint8_t verb, std::uint8_t option) {
  // WILL/WONT speak of the peer's side, DO/DONT of ours.
  const bool about_remote = verb == kWILL || verb == kWONT;
  const bool yes = verb == kWILL || verb == kDO;
  State& state = about_remote ? remote_[option] : local_[option];
  const bool allowed = has(about_remote ? remote_allowed_ : local_allowed_, option);
  const std::uint8_t agree = about_remote ? kDO : kWILL;
  const std::uint8_t refuse = about_remote ? kDONT : kWONT;
  if (yes) {
    if (state == State::on) return {};  // already on: never answer an acknowledgement
    if (state == State::requested) {  // the answer to our request
      state = State::on;
      return {};
    }
    if (!allowed) return negotiation(refuse, option);
    state = State::on;
    return negotiation(agree, option);
  }
  const State before = state;
  state = State::off;
  // Turning off must be acknowledged when it was on; a refusal of our request needs no answer.
  return before == State::on ? negotiation(refuse, option) : Bytes{};
}

namespace com_port {

Bytes set_baudrate(std::uint8_t code, std::uint32_t baud) {
  return {code, static_cast<std::uint8_t>(baud >> 24), static_cast<std::uint8_t>(baud >> 16),
          static_cast<std::uint8_t>(baud >> 8), static_cast<std::uint8_t>(baud)};
}

std::optional<std::uint32_t> baudrate_of(ByteView payload) {
  if (payload.size() < 5) return std::nullopt;
  return (std::uint32_t{payload[1]} << 24) | (std::uint32_t{payload[2]} << 16) | (std::uint32_t{payload[3]} << 8) |
         std::uint32_t{payload[4]};
}

namespace {
std::string bits_text(std::uint8_t state, const char* const names[8]) {
  std::string out;
  for (int bit = 7; bit >= 0; --bit)
    if ((state & (1u << bit)) != 0) out += (out.empty() ? "" : ", ") + std::string(names[bit]);
  return out.empty() ? "none" : out;
}
}  // namespace

std::string linestate_text(std::uint8_t state) {
  // RFC 2217 NOTIFY-LINESTATE bits, 0 (data ready) to 7 (timeout error).
  static const char* const names[8] = {"data ready",      "overrun error",          "parity error",
                                       "framing error",   "break",                  "holding register empty",
                                       "shift register empty", "timeout error"};
  return bits_text(state, names);
}

std::string modemstate_text(std::uint8_t state) {
  static const char* const names[8] = {"CTS changed", "DSR changed", "RI trailing edge", "CD changed",
                                       "CTS",         "DSR",         "RI",               "CD"};
  return bits_text(state, names);
}

std::string command_name(std::uint8_t code) {
  static const char* const names[13] = {"SIGNATURE",          "SET-BAUDRATE",      "SET-DATASIZE",
                                        "SET-PARITY",         "SET-STOPSIZE",      "SET-CONTROL",
                                        "NOTIFY-LINESTATE",   "NOTIFY-MODEMSTATE", "FLOWCONTROL-SUSPEND",
                                        "FLOWCONTROL-RESUME", "SET-LINESTATE-MASK", "SET-MODEMSTATE-MASK",
                                        "PURGE-DATA"};
  if (code < 13) return names[code];
  if (code >= kServerOffset && code < kServerOffset + 13) return std::string("SERVER ") + names[code - kServerOffset];
  return fmt::format("command {}", code);
}

}  // namespace com_port

}  // namespace sabus::harness::telnet
