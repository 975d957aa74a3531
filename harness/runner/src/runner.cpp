// The conformance runner's step engine: sends commands (structured or raw,
// with modifiers), reads replies with the master-side receiver, checks them
// with field matchers, and keeps the bench safe (motion and destructive
// gating, an 'X' stop after motion, liveness checks).
#include "sabus/harness/runner.hpp"

#include <algorithm>
#include <cmath>
#include <fnmatch.h>
#include <fstream>
#include <regex>
#include <sstream>

#include "sabus/harness/vector_loader.hpp"
#include "sabus/harness/timing.hpp"
#include "sabus/protocol/receiver.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::harness {
namespace {

using namespace std::chrono_literals;
using std::chrono::milliseconds;

std::string trim_right(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

bool glob_match(const std::string& pattern, const std::string& id) {
  return fnmatch(pattern.c_str(), id.c_str(), 0) == 0;
}

std::string range_text(const FieldDescription& f) {
  return f.first == f.last ? "byte " + std::to_string(f.first)
                           : "bytes " + std::to_string(f.first) + "-" + std::to_string(f.last);
}

std::string fmt_slot(std::uint8_t read_code, std::uint8_t index) {
  const char* what = read_code == 0x3A ? "preset satellite" : read_code == 0x3C ? "TLE" : "signpost";
  return std::string(what) + " " + std::to_string(index);
}

}  // namespace

// ---- matching --------------------------------------------------------------------

std::string matcher_text(const FieldDescription& f) {
  if (f.raw.size() >= 2 && f.raw.front() == '"' && f.raw.back() == '"') return trim_right(f.raw.substr(1, f.raw.size() - 2));
  return f.raw;
}

std::optional<double> matcher_number(const FieldDescription& f) {
  // One-byte fields: the byte's value; text fields: a leading number in the
  // meaning ("-152.5 deg", "11050", "index 12").
  if (f.first == f.last && f.raw.rfind("0x", 0) == 0) return static_cast<double>(std::stoi(f.raw.substr(2), nullptr, 16));
  std::istringstream in(f.meaning.rfind("index ", 0) == 0 ? f.meaning.substr(6)
                        : f.meaning.rfind("heading ", 0) == 0 ? f.meaning.substr(8)
                                                              : f.meaning);
  double v = 0;
  if (in >> v) return v;
  return std::nullopt;
}

static std::optional<std::string> check_one_field(const FieldDescription& f, const FieldMatcher& m, Captures& captures);

static bool values_equal(const std::string& want, const std::string& got) {
  if (want == got) return true;
  // Numbers may be written as 0x47 or 71 in a vector.
  try {
    std::size_t a = 0, b = 0;
    const long x = std::stol(want, &a, 0), y = std::stol(got, &b, 0);
    return a == want.size() && b == got.size() && x == y;
  } catch (...) {
    return false;
  }
}

std::optional<std::string> check_field(const FrameDescription& reply, const FieldMatcher& m, Captures& captures) {
  // A matcher holds for every field of its name (the status reply has two
  // "reserved" fields: byte 13 and bytes 45-49).
  bool found = false;
  for (const auto& f : reply.fields) {
    if (f.name != m.field) continue;
    found = true;
    if (auto e = check_one_field(f, m, captures)) return e;
  }
  if (!found) return "field \"" + m.field + "\" is not in the reply (" + reply.summary + ")";
  return std::nullopt;
}

static std::optional<std::string> check_one_field(const FieldDescription& f, const FieldMatcher& m, Captures& captures) {
  const FieldDescription* field = &f;
  const std::string got = matcher_text(*field);
  auto fail = [&](const std::string& expected) {
    return range_text(*field) + " " + field->name + ": expected " + expected + ", got " + got + " (" + field->meaning + ")";
  };
  if (!m.capture.empty()) captures[m.capture] = got;
  switch (m.kind) {
    case FieldMatcher::Kind::kAny: return std::nullopt;
    case FieldMatcher::Kind::kEq:
      if (!m.values.empty() && !values_equal(m.values[0], got)) return fail(m.values[0]);
      return std::nullopt;
    case FieldMatcher::Kind::kOneOf:
      for (const auto& v : m.values)
        if (values_equal(v, got)) return std::nullopt;
      {
        std::string list;
        for (const auto& v : m.values) list += (list.empty() ? "" : ", ") + v;
        return fail("one of " + list);
      }
    case FieldMatcher::Kind::kRegex:
      try {
        if (!m.values.empty() && !std::regex_search(got, std::regex(m.values[0]))) return fail("/" + m.values[0] + "/");
      } catch (const std::regex_error&) {
        return "matcher for \"" + m.field + "\": bad regex /" + m.values[0] + "/";
      }
      return std::nullopt;
    case FieldMatcher::Kind::kRange: {
      const auto n = matcher_number(*field);
      std::ostringstream want;
      want << m.low << " to " << m.high;
      if (!n || *n < m.low - 1e-9 || *n > m.high + 1e-9) return fail(want.str());
      return std::nullopt;
    }
  }
  return std::nullopt;
}

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

std::string StoredDataBackup::to_json() const {
  auto slots = [](const std::map<std::uint8_t, Bytes>& m) {
    std::string out = "{";
    for (const auto& [i, d] : m) out += (out.size() > 1 ? ", " : "") + std::string("\"") + std::to_string(i) + "\": \"" + to_hex(d) + "\"";
    return out + "}";
  };
  std::string names = "[";
  for (const auto& n : store_names) {
    names += (names.size() > 1 ? ", \"" : "\"");
    for (char c : n) names += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    names += "\"";
  }
  names += "]";
  return "{\n  \"store_names\": " + names + ",\n  \"presets\": " + slots(presets) + ",\n  \"tles\": " + slots(tles) +
         ",\n  \"signposts\": " + slots(signposts) + ",\n  \"navigation\": \"" +
         (navigation ? to_hex(*navigation) : std::string()) + "\"\n}\n";
}

std::string_view to_string(Verdict v) {
  switch (v) {
    case Verdict::kPass: return "pass";
    case Verdict::kFail: return "fail";
    case Verdict::kSkip: return "skip";
    case Verdict::kKnownFailure: return "known failure";
    case Verdict::kUnexpectedPass: return "unexpected pass";
  }
  return "?";
}

bool VectorResult::counts_as_failure(bool strict) const {
  return (verdict == Verdict::kFail && (level == Level::kMust || (strict && level == Level::kShould))) ||
         verdict == Verdict::kUnexpectedPass;
}

int RunResult::exit_code() const {
  if (!liveness.empty() && !liveness.front().alive) return liveness.front().heard ? 1 : 3;
  if (aborted) return 1;
  for (const auto& v : vectors)
    if (v.counts_as_failure(strict)) return 1;
  return 0;
}

// ---- the engine -----------------------------------------------------------------

struct Runner::Context : ReceiverSink {
  Runner& runner;
  Captures captures;
  std::vector<TranscriptEntry>* transcript = nullptr;
  std::string expect;  // the expected path of the step being sent (TranscriptEntry::expect)
  TimePoint start;
  TimePoint last_send{};
  TurnaroundMeter turnaround;  // request end on the wire -> first reply byte
  std::vector<Frame> frames;
  std::vector<std::string> ignored;
  std::size_t bytes_sent = 0, bytes_received = 0;
  std::chrono::microseconds silence_listened{0};
  std::size_t silence_windows = 0;

  explicit Context(Runner& r) : runner(r), start(r.transport_.now()) {}
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard& d) override { ignored.push_back(d.message()); }

  double t_ms() const {
    return std::chrono::duration<double, std::milli>(runner.transport_.now() - start).count();
  }
  void record(bool sent, const Bytes& bytes, std::string note) {
    if (transcript) transcript->push_back({t_ms(), sent, bytes, std::move(note), sent ? expect : std::string()});
  }
  Parity parity() const { return receiver_parity(runner.transport_); }

  // How long to wait for a reply to a command of `request_bytes` bytes
  // (timing.hpp: wire times at the baud rate plus the turnaround allowance).
  milliseconds reply_timeout(std::size_t request_bytes) const {
    Transport& t = runner.transport_;
    if (t.in_process()) return 1000ms;  // virtual time: waiting costs nothing
    const auto allowance = std::max(runner.options_.turnaround_allowance,
                                    std::chrono::duration_cast<milliseconds>(3 * turnaround.max()));
    return harness::reply_timeout(t.baud(), request_bytes, max_reply_length(), allowance);
  }
  // How long silence must last to count as "no reply" (READING-NOTES 9 ignore
  // paths), from the device's measured turnaround (timing.hpp).
  milliseconds silence_window(std::size_t) const {
    Transport& t = runner.transport_;
    if (t.in_process()) return 500ms;
    return harness::silence_window(turnaround.max(), t.baud(), max_reply_length());
  }

  // Sends one frame (in chunks if asked) and collects what comes back within
  // `window`, stopping early once a frame arrived and the line went quiet.
  std::vector<Frame> exchange(const Bytes& chars, const Modifiers& m, milliseconds window) {
    Transport& t = runner.transport_;
    if (runner.options_.pace.count() > 0 && last_send != TimePoint{}) {
      const auto since = t.now() - last_send;
      if (since < runner.options_.pace) t.pause(std::chrono::duration_cast<milliseconds>(runner.options_.pace - since));
    }
    frames.clear();
    ignored.clear();
    ReceiverOptions options = ReceiverOptions::master();
    options.parity = parity();
    Receiver rx(options);
    std::size_t offset = 0;
    std::vector<std::size_t> sizes = m.chunks;
    std::size_t listed = 0;
    for (auto s : sizes) listed += s;
    if (listed < chars.size()) sizes.push_back(chars.size() - listed);
    for (std::size_t i = 0; i < sizes.size() && offset < chars.size(); ++i) {
      const std::size_t n = std::min(sizes[i], chars.size() - offset);
      std::vector<std::size_t> wrong;
      for (auto p : m.parity_flip)
        if (p >= offset && p < offset + n) wrong.push_back(p - offset);
      t.send(ByteView(chars).subspan(offset, n), wrong);
      offset += n;
      if (i + 1 < sizes.size() && m.pause.count() > 0) t.pause(m.pause);
    }
    last_send = t.now();
    bytes_sent += chars.size();
    record(true, chars, describe_frame(chars).summary);
    const TimePoint sent_at = t.now();
    // send() does not drain: the request leaves the port over its wire time.
    const TimePoint request_end = sent_at + wire_time(chars.size(), t.baud());
    bool first = true;
    std::uint8_t buf[512];
    while (t.now() - sent_at < window) {
      const auto left = std::chrono::duration_cast<milliseconds>(window - (t.now() - sent_at));
      // Once a reply is complete, listen only a few character times for a
      // second one: a device answers a command with one frame (§1).
      const milliseconds quiet = std::max<milliseconds>(
          3ms, std::chrono::duration_cast<milliseconds>(wire_time(3, t.baud())) + 1ms);
      const std::size_t n = t.receive(buf, frames.empty() ? std::max(left, 1ms) : std::min(left, quiet));
      if (n > 0 && first) {
        first = false;
        if (!t.in_process()) turnaround.record(request_end, t.now());
      }
      bytes_received += n;
      rx.feed(ByteView(buf, n), *this);
      if (n == 0 && !frames.empty()) break;  // a complete reply and then quiet
    }
    rx.finish(*this);
    for (const auto& f : frames) {
      const Bytes b = encode_frame(f);
      record(false, b, describe_frame(b).summary);
    }
    for (const auto& s : ignored) record(false, {}, "ignored " + s);
    return frames;
  }
};

namespace {

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

bool is_selected(const RunOptions& options, const std::string& id) {
  bool selected = options.filters.empty();
  for (const auto& f : options.filters) selected |= glob_match(f, id);
  for (const auto& x : options.excludes)
    if (glob_match(x, id)) selected = false;
  return selected;
}

Runner::Runner(Transport& transport, const Profile& profile, RunOptions options)
    : transport_(transport), profile_(profile), options_(std::move(options)) {}

RunResult Runner::run(const std::vector<Vector>& vectors) {
  RunResult result;
  result.strict = options_.strict;
  Context ctx(*this);
  const std::uint8_t address = profile_.address;

  // Builds the bytes of a send step.
  auto frame_of = [&](const Step& s) { return step_bytes(s, address, ctx.captures); };

  // Runs one send step; returns the failure, if any.
  auto run_send = [&](const Step& s) -> std::optional<std::string> {
    auto bytes = frame_of(s);
    if (!bytes) return "cannot build the command: " + bytes.error().message();
    const Bytes wire = apply_modifiers(bytes.value(), s.modifiers);
    const bool silence = s.expect.kind == Expectation::Kind::kSilence;
    const auto window = silence ? ctx.silence_window(wire.size()) : ctx.reply_timeout(wire.size());
    const TimePoint listen_start = transport_.now();
    (void)transport_.take_nak_rules();  // only this exchange's rules count
    ctx.expect = expect_name(s.expect.kind);
    const auto replies = ctx.exchange(wire, s.modifiers, window);
    ctx.expect.clear();
    const auto nak_rules = transport_.take_nak_rules();
    if (silence) {
      ctx.silence_listened += std::chrono::duration_cast<std::chrono::microseconds>(transport_.now() - listen_start) -
                              std::chrono::duration_cast<std::chrono::microseconds>(wire_time(wire.size(), transport_.baud()));
      ++ctx.silence_windows;
    }
    // The frame the device answers is the one the last STX begins; the final
    // byte is a check byte, which may itself be 02h (READING-NOTES 7).
    std::size_t start = wire.empty() ? 0 : wire.size() - 1;
    while (start > 0 && wire[start - 1] != STX) --start;
    const std::uint8_t sent_address = start < wire.size() ? wire[start] : address;
    const std::uint8_t sent_command = start + 1 < wire.size() ? wire[start + 1] : 0;
    const std::uint8_t want_address = s.command && s.command->address ? *s.command->address : sent_address;
    if (auto e = check_kind(s.expect, replies, want_address, sent_command)) return e;
    if (!s.expect.nak_rule.empty() && nak_rules &&
        std::find(nak_rules->begin(), nak_rules->end(), s.expect.nak_rule) == nak_rules->end()) {
      std::string fired;
      for (const auto& r : *nak_rules) fired += (fired.empty() ? "" : ", ") + r;
      return "expected a NAK by rule " + s.expect.nak_rule + ", the reference controller applied " +
             (fired.empty() ? std::string("none") : fired);
    }
    if (replies.empty()) return std::nullopt;
    const Bytes reply = encode_frame(replies[0]);
    if (s.expect.bytes) {
      auto want = expand_raw_bytes(s.expect.bytes->hex, address, ctx.captures);
      if (!want) return "bad expected bytes: " + want.error().message();
      if (want.value() != reply) return "expected bytes " + to_hex(want.value()) + ", got " + to_hex(reply);
    }
    const FrameDescription d = describe_frame(reply);
    if (s.expect.kind == Expectation::Kind::kAck && d.error) return "reply does not decode: " + d.error->message();
    for (const auto& m : s.expect.fields)
      if (auto e = check_field(d, m, ctx.captures)) return e;
    return std::nullopt;
  };

  auto run_step = [&](const Step& s) -> std::optional<std::string> {
    switch (s.kind) {
      case Step::Kind::kWait:
        transport_.pause(s.timeout);
        return std::nullopt;
      case Step::Kind::kSend: return run_send(s);
      case Step::Kind::kPoll: {
        const TimePoint end = transport_.now() + s.timeout;
        Step probe = s;
        probe.kind = Step::Kind::kSend;
        std::string last = "no reply";
        while (true) {
          probe.expect.fields = s.expect.fields;
          if (auto e = run_send(probe)) return "poll: " + *e;
          // The reply of the last exchange, checked against `until`.
          const Bytes reply = ctx.frames.empty() ? Bytes{} : encode_frame(ctx.frames[0]);
          const FrameDescription d = describe_frame(reply);
          std::optional<std::string> unmet;
          for (const auto& m : s.until)
            if (!unmet) unmet = check_field(d, m, ctx.captures);
          if (!unmet) return std::nullopt;
          last = *unmet;
          if (transport_.now() >= end) return "poll timed out after " + std::to_string(s.timeout.count()) + " ms: " + last;
          if (options_.stop && options_.stop()) return "stopped";
          transport_.pause(s.interval);
        }
      }
    }
    return std::nullopt;
  };

  // Liveness: a device type query and a status poll (tlsfuzzer's sanity runs).
  auto liveness = [&](const std::string& when) {
    LivenessResult l{when, true, false, ""};
    std::vector<TranscriptEntry> scratch;
    ctx.transcript = &scratch;
    const std::size_t received_before = ctx.bytes_received;
    for (std::uint8_t code : {std::uint8_t{0x30}, std::uint8_t{0x31}}) {
      const Bytes cmd = encode_frame({FrameKind::kCommand, address, code, {}});
      try {
        const auto replies = ctx.exchange(cmd, {}, ctx.reply_timeout(cmd.size()));
        const bool answered = replies.size() == 1 && replies[0].command == code;
        if (!answered) {
          l.alive = false;
          l.detail = replies.empty() ? "no answer to " + describe_frame(cmd).summary : "unexpected reply";
          break;
        }
      } catch (const TransportLost& e) {
        l.alive = false;
        l.detail = e.what();
        break;
      }
    }
    ctx.transcript = nullptr;
    l.heard = ctx.bytes_received > received_before;
    if (!l.alive && l.heard) l.detail += " (the device sends bytes, but not the reply the spec asks for)";
    result.liveness.push_back(l);
    return l.alive;
  };

  // ---- backup and restore of stored data (bench safety) -------------------------
  // One request and its single ACK reply's data, or nullopt (NAK, silence).
  auto ask = [&](const Request& request) -> std::optional<Bytes> {
    const Bytes cmd = encode_request(request, address);
    const auto replies = ctx.exchange(cmd, {}, ctx.reply_timeout(cmd.size()));
    if (replies.size() != 1 || replies[0].kind != FrameKind::kAck || is_offline_reply(replies[0])) return std::nullopt;
    return replies[0].data;
  };
  auto slot_data = [&](const Request& request) -> std::optional<Bytes> {
    auto data = ask(request);
    if (!data || data->size() < 2 || (*data)[0] == fields::kEmptySlot) return std::nullopt;  // empty slot
    return data;
  };
  // The STORE list's names, read with 35h from index 1 until the NAK (§3.6).
  auto read_store_names = [&]() {
    std::vector<std::string> names;
    for (std::uint32_t i = 1; i <= 50; ++i) {
      auto d = ask(QueryName{{i}});
      if (!d) break;
      if (auto r = decode_reply(Frame{FrameKind::kAck, address, 0x35, *d}); r && std::holds_alternative<QueryNameReply>(r.value()))
        names.push_back(std::get<QueryNameReply>(r.value()).name);
    }
    return names;
  };
  auto take_backup = [&]() {
    StoredDataBackup& b = result.backup;
    std::vector<TranscriptEntry> scratch;
    ctx.transcript = &scratch;
    b.store_names = read_store_names();
    for (std::uint8_t i = 1; i <= 20; ++i)
      if (auto d = slot_data(ReadSatellite{{i}})) b.presets[i] = *d;
    for (std::uint8_t i = 1; i <= 10; ++i)
      if (auto d = slot_data(ReadTle{{i}})) b.tles[i] = *d;
    for (std::uint8_t i = 1; i <= 20; ++i) {
      auto d = ask(ReadSignpost{{i}});
      if (!d) break;  // no DVB option: 44h is NAKed (E-23)
      if (d->size() >= 2 && (*d)[0] != fields::kEmptySlot) b.signposts[i] = *d;
    }
    b.navigation = ask(NavigationQuery{});
    b.taken = true;
    ctx.transcript = nullptr;
    if (!options_.backup_path.empty()) {
      std::ofstream out(options_.backup_path);
      out << b.to_json();
    }
  };
  // Writes back what differs from the backup; says what cannot be restored.
  auto restore_backup = [&]() {
    const StoredDataBackup& b = result.backup;
    std::vector<TranscriptEntry> scratch;
    ctx.transcript = &scratch;
    auto note = [&](std::string s) { result.restore_notes.push_back(std::move(s)); };
    auto restore_slots = [&]<class Read, class Reply>(std::uint8_t code, std::uint8_t max, const auto& saved,
                                                       std::type_identity<Read>, std::type_identity<Reply>, auto write) {
      for (std::uint8_t i = 1; i <= max; ++i) {
        const auto now = slot_data(Read{{i}});
        const auto it = saved.find(i);
        if (it == saved.end()) {
          if (now) note(fmt_slot(code, i) + " was empty and now holds data; the protocol cannot clear a slot");
          continue;
        }
        if (now && *now == it->second) continue;
        const auto decoded = decode_reply(Frame{FrameKind::kAck, address, code, it->second});
        if (!decoded || !std::holds_alternative<Reply>(decoded.value())) continue;
        const bool ok = ask(write(i, std::get<Reply>(decoded.value()))).has_value();
        note(fmt_slot(code, i) + (ok ? " restored" : " could not be restored (NAK or no reply)"));
      }
    };
    restore_slots(0x3A, 20, b.presets, std::type_identity<ReadSatellite>{}, std::type_identity<SatelliteDataReply>{},
                  [](std::uint8_t i, const SatelliteDataReply& r) { return Request{WriteSatellite{i, r.sat}}; });
    restore_slots(0x3C, 10, b.tles, std::type_identity<ReadTle>{}, std::type_identity<TleDataReply>{},
                  [](std::uint8_t i, const TleDataReply& r) { return Request{WriteTle{i, r.line1, r.line2}}; });
    if (!b.signposts.empty())
      restore_slots(0x44, 20, b.signposts, std::type_identity<ReadSignpost>{}, std::type_identity<SignpostDataReply>{},
                    [](std::uint8_t i, const SignpostDataReply& r) { return Request{WriteSignpost{i, r.signpost}}; });
    const auto nav = ask(NavigationQuery{});
    if (b.navigation && nav && *nav != *b.navigation) {
      const auto d = decode_reply(Frame{FrameKind::kAck, address, 0x45, *b.navigation});
      const auto* n = d ? std::get_if<NavigationDataReply>(&d.value()) : nullptr;
      if (n && n->latitude && n->longitude) {
        // §3.23 takes sddmm / sdddmm; writing it deletes the STORE list.
        auto ddmm = [](std::int32_t minutes) { return (minutes < 0 ? -1 : 1) * (std::abs(minutes) / 60 * 100 + std::abs(minutes) % 60); };
        const bool ok = ask(WriteNavigation{ddmm(*n->latitude), ddmm(*n->longitude), n->heading.value_or(0), ""}).has_value();
        note(std::string("navigation data ") + (ok ? "restored (this deletes the STORE list, §3.23)" : "could not be restored"));
      } else {
        note("navigation data changed and the backup holds no position to write back");
      }
    }
    const std::vector<std::string> names = read_store_names();
    for (const auto& n : b.store_names)
      if (std::find(names.begin(), names.end(), n) == names.end())
        note("STORE entry \"" + n + "\" is gone; it can only be stored again at its satellite (42h stores the current position)");
    ctx.transcript = nullptr;
  };

  // An 'X' stop after every vector that can move the antenna (§3.4).
  auto stop_motion = [&]() {
    const Bytes x = encode_request(Jog{{'X', 'S', 0}}, address);
    try {
      ctx.exchange(x, {}, ctx.reply_timeout(x.size()));
    } catch (const TransportLost&) {
    }
  };

  try {
    // A device that sends bytes is reachable, however wrong they are: its
    // vectors run and say what is wrong. Only silence ends the run here.
    if (!liveness("before the first vector") && !result.liveness.back().heard) {
      result.aborted = true;
      result.abort_reason = "the device did not answer: " + result.liveness.back().detail;
      return result;
    }
  } catch (const TransportLost& e) {
    result.aborted = true;
    result.abort_reason = e.what();
    return result;
  }
  result.measured_turnaround = ctx.turnaround.max();

  int dead_probes = 0;
  for (const Vector& v : vectors) {
    if (options_.stop && options_.stop()) {
      result.aborted = true;
      result.abort_reason = "stopped by SIGINT";
      break;
    }
    VectorResult r;
    r.id = v.id;
    r.paragraph = v.paragraph;
    r.file = v.where.file;
    r.quote = v.quote;
    r.comment = v.comment;
    r.level = v.level;
    auto skip = [&](std::string why) {
      r.verdict = Verdict::kSkip;
      r.skip_reason = std::move(why);
    };
    if (!is_selected(options_, v.id)) continue;  // not part of this run at all
    if (static_cast<int>(v.level) > static_cast<int>(options_.max_level)) skip("level " + std::string(to_string(v.level)));
    for (const auto& req : v.requires_)
      if (r.verdict != Verdict::kSkip)
        if (auto why = unmet_requirement(profile_, req)) skip("requires: " + *why);
    if (r.verdict != Verdict::kSkip && v.has_tag("motion") && !options_.allow_motion)
      skip("moves the antenna: needs --allow-motion");
    if (r.verdict != Verdict::kSkip && v.has_tag("destructive") && !options_.allow_destructive)
      skip("changes stored data: needs --allow-destructive");
    if (r.verdict != Verdict::kSkip && v.has_tag("parity") && !transport_.can_send_parity_errors())
      skip("sends parity errors: the port is a true 7E1 port (--line 7E1)");

    if (r.verdict != Verdict::kSkip && v.has_tag("destructive") && !result.backup.taken) {
      try {
        take_backup();
      } catch (const TransportLost& e) {
        result.aborted = true;
        result.abort_reason = std::string("device lost while backing up stored data: ") + e.what();
        break;
      }
    }
    if (r.verdict != Verdict::kSkip) {
      const auto attempt = [&](std::vector<TranscriptEntry>& transcript) {
        std::vector<std::string> failures;
        ctx.transcript = &transcript;
        ctx.captures.clear();
        for (const auto* phase : {&v.setup, &v.steps}) {
          for (const Step& s : *phase)
            if (auto e = run_step(s)) {
              failures.push_back((phase == &v.setup ? "setup: " : "") + *e);
              break;
            }
          if (!failures.empty()) break;
        }
        for (const Step& s : v.teardown)
          if (auto e = run_step(s)) failures.push_back("teardown: " + *e);
        if (v.has_tag("motion")) stop_motion();
        ctx.transcript = nullptr;
        return failures;
      };
      const TimePoint t0 = transport_.now();
      try {
        r.failures = attempt(r.transcript);
        if (!r.failures.empty() && options_.repeat > 0) {
          for (int i = 0; i < options_.repeat; ++i) {
            std::vector<TranscriptEntry> again;
            ++r.repeats;
            if (!attempt(again).empty()) ++r.repeat_failures;
          }
          r.failures.push_back(r.repeat_failures == r.repeats ? "reproducible: failed " + std::to_string(r.repeats + 1) +
                                                                    " of " + std::to_string(r.repeats + 1) + " runs"
                                                              : "intermittent: failed " +
                                                                    std::to_string(r.repeat_failures + 1) + " of " +
                                                                    std::to_string(r.repeats + 1) + " runs");
        }
      } catch (const TransportLost& e) {
        r.failures.push_back(std::string("device lost: ") + e.what());
        result.aborted = true;
        result.abort_reason = std::string("device lost during ") + v.id + ": " + e.what();
      }
      r.duration_ms = std::chrono::duration<double, std::milli>(transport_.now() - t0).count();
      r.verdict = r.failures.empty() ? Verdict::kPass : Verdict::kFail;
      if (auto it = options_.known_issues.find(v.id); it != options_.known_issues.end()) {
        r.known_issue_reason = it->second;
        r.verdict = r.verdict == Verdict::kFail ? Verdict::kKnownFailure : Verdict::kUnexpectedPass;
      }
    }
    switch (r.verdict) {
      case Verdict::kPass: ++result.passed; break;
      case Verdict::kFail: ++result.failed; break;
      case Verdict::kSkip: ++result.skipped; break;
      case Verdict::kKnownFailure: ++result.known; break;
      case Verdict::kUnexpectedPass: ++result.unexpected; break;
    }
    const bool expected_silence = std::any_of(v.steps.begin(), v.steps.end(), [](const Step& s) {
      return s.expect.kind == Expectation::Kind::kSilence;
    });
    result.vectors.push_back(r);
    if (options_.on_result) options_.on_result(result.vectors.back());
    if (!options_.keep_transcripts) result.vectors.back().transcript = {};
    if (result.aborted) break;
    // After an ignore path, make sure the device did not silently die.
    if (expected_silence && r.verdict != Verdict::kSkip) {
      if (liveness("after " + v.id)) {
        dead_probes = 0;
      } else if (++dead_probes >= 3) {
        result.aborted = true;
        result.abort_reason = "no answer to three liveness probes";
        break;
      }
    }
  }
  if (result.backup.taken) {
    try {
      restore_backup();
    } catch (const TransportLost& e) {
      result.restore_notes.push_back(std::string("stored data not restored, the device is lost: ") + e.what());
    }
  }
  if (!result.aborted || result.abort_reason == "stopped by SIGINT") {
    try {
      liveness("after the last vector");
    } catch (const TransportLost&) {
    }
  }
  result.measured_turnaround = ctx.turnaround.max();
  result.bytes_sent = ctx.bytes_sent;
  result.bytes_received = ctx.bytes_received;
  result.silence_listened = ctx.silence_listened;
  result.silence_windows = ctx.silence_windows;
  return result;
}

}  // namespace sabus::harness
