// The step engine (vectors/README.md "Steps"): a send builds its bytes
// (structured or raw, then the modifiers), exchanges them and checks the reply
// path, the NAK rule, the whole reply and the field matchers; a poll repeats
// a send until its `until` matchers hold; a wait lets time pass.
#include <algorithm>

#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/lrc.hpp"
#include "session.hpp"

namespace sabus::harness {

Bytes apply_modifiers(Bytes f, const Modifiers& m) {
  if (f.size() < 5) return f;
  bool relrc = false;
  if (m.address) {
    f[1] = *m.address;
    relrc = true;
  }
  if (m.extra_data_bytes > 0) {
    f.insert(f.end() - 2, m.extra_data_bytes, static_cast<std::uint8_t>('0'));
    relrc = true;
  }
  if (relrc) f.back() = lrc(ByteView(f).first(f.size() - 1));
  if (m.lrc_xor) f.back() ^= *m.lrc_xor;
  for (const auto& [index, byte] : m.replace)
    if (index < f.size()) f[index] = byte;
  if (m.truncate > 0) f.resize(f.size() > m.truncate ? f.size() - m.truncate : 0);
  return f;
}

namespace detail {
namespace {

// The reply path: one frame of the expected kind, from the address and for
// the command of the frame sent.
std::optional<std::string> check_kind(const Expectation& e, const std::vector<Frame>& replies, std::uint8_t address,
                                      std::uint8_t command) {
  using K = Expectation::Kind;
  auto describe = [&](const Frame& f) { return describe_frame(encode_frame(f)).summary; };
  if (e.kind == K::kAny) return std::nullopt;
  if (e.kind == K::kSilence) {
    if (replies.empty()) return std::nullopt;
    return "expected silence, got " + describe(replies[0]);
  }
  const char* want = e.kind == K::kAck ? "an ACK reply" : e.kind == K::kNak ? "a NAK reply" : "the offline reply";
  if (replies.empty()) return std::string("expected ") + want + ", got silence";
  if (replies.size() > 1) return "expected one reply, got " + std::to_string(replies.size());
  const Frame& f = replies[0];
  const bool offline = is_offline_reply(f);
  const bool ok = (e.kind == K::kAck && f.kind == FrameKind::kAck && !offline) ||
                  (e.kind == K::kNak && f.kind == FrameKind::kNak) || (e.kind == K::kOffline && offline);
  if (!ok) return std::string("expected ") + want + ", got " + describe(f);
  if (f.address != address) return "reply from address " + describe_byte(f.address) + ", expected " + describe_byte(address);
  if (f.command != command) return "reply for command " + describe_byte(f.command) + ", expected " + describe_byte(command);
  return std::nullopt;
}

// Against the reference controller: the NAK came from the rule the vector
// names, not from another (a wrong length, an unknown code).
std::optional<std::string> check_nak_rule(const Expectation& e, const std::optional<std::vector<std::string>>& fired) {
  if (e.nak_rule.empty() || !fired || std::find(fired->begin(), fired->end(), e.nak_rule) != fired->end())
    return std::nullopt;
  std::string names;
  for (const auto& r : *fired) names += (names.empty() ? "" : ", ") + r;
  return "expected a NAK by rule " + e.nak_rule + ", the reference controller applied " +
         (names.empty() ? std::string("none") : names);
}

std::string expect_name(Expectation::Kind k) {
  switch (k) {
    case Expectation::Kind::kAck: return "ack";
    case Expectation::Kind::kNak: return "nak";
    case Expectation::Kind::kOffline: return "offline";
    case Expectation::Kind::kSilence: return "silence";
    case Expectation::Kind::kAny: return "any";
  }
  return "any";
}

}  // namespace

std::optional<std::string> Session::run_send(const Step& s) {
  auto bytes = step_bytes(s, profile.address, captures);
  if (!bytes) return "cannot build the command: " + bytes.error().message();
  const Bytes wire = apply_modifiers(bytes.value(), s.modifiers);
  const bool silence = s.expect.kind == Expectation::Kind::kSilence;
  const auto window = silence ? silence_window() : reply_timeout(wire.size());
  const TimePoint listen_start = transport.now();
  (void)transport.take_nak_rules();  // only this exchange's rules count
  expect = expect_name(s.expect.kind);
  const auto replies = exchange(wire, s.modifiers, window);
  expect.clear();
  const auto nak_rules = transport.take_nak_rules();
  if (silence) {
    silence_listened += std::chrono::duration_cast<std::chrono::microseconds>(transport.now() - listen_start) -
                        std::chrono::duration_cast<std::chrono::microseconds>(wire_time(wire.size(), transport.baud()));
    ++silence_windows;
  }
  // The reply is checked against the frame the device acts on; with none
  // complete in the bytes, against the first frame's header bytes.
  const auto acted_on = frame_acted_on(wire, profile);
  const SentFrame sent = acted_on ? *acted_on
                                  : SentFrame{wire.size() > 1 ? wire[1] : profile.address,
                                              static_cast<std::uint8_t>(wire.size() > 2 ? wire[2] : 0)};
  const std::uint8_t want_address = s.command && s.command->address ? *s.command->address : sent.address;
  if (auto e = check_kind(s.expect, replies, want_address, sent.command)) return e;
  if (auto e = check_nak_rule(s.expect, nak_rules)) return e;
  if (replies.empty()) return std::nullopt;
  const Bytes reply = encode_frame(replies[0]);
  if (s.expect.bytes) {
    auto want = expand_raw_bytes(s.expect.bytes->hex, profile.address, captures);
    if (!want) return "bad expected bytes: " + want.error().message();
    if (want.value() != reply) return "expected bytes " + to_hex(want.value()) + ", got " + to_hex(reply);
  }
  const FrameDescription d = describe_frame(reply);
  if (s.expect.kind == Expectation::Kind::kAck && d.error) return "reply does not decode: " + d.error->message();
  for (const auto& m : s.expect.fields)
    if (auto e = check_field(d, m, captures)) return e;
  return std::nullopt;
}

std::optional<std::string> Session::run_poll(const Step& s) {
  const TimePoint end = transport.now() + s.timeout;
  Step probe = s;
  probe.kind = Step::Kind::kSend;
  while (true) {
    if (auto e = run_send(probe)) return "poll: " + *e;
    // The reply of the last exchange, checked against `until`.
    const Bytes reply = last_replies().empty() ? Bytes{} : encode_frame(last_replies()[0]);
    const FrameDescription d = describe_frame(reply);
    std::optional<std::string> unmet;
    for (const auto& m : s.until)
      if (!unmet) unmet = check_field(d, m, captures);
    if (!unmet) return std::nullopt;
    if (transport.now() >= end) return "poll timed out after " + std::to_string(s.timeout.count()) + " ms: " + *unmet;
    if (options.stop && options.stop()) return "stopped";
    transport.pause(s.interval);
  }
}

std::optional<std::string> Session::run_step(const Step& s) {
  switch (s.kind) {
    case Step::Kind::kWait:
      transport.pause(s.timeout);
      return std::nullopt;
    case Step::Kind::kSend: return run_send(s);
    case Step::Kind::kPoll: return run_poll(s);
  }
  return std::nullopt;
}

}  // namespace detail
}  // namespace sabus::harness
