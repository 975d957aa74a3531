// The step engine (vectors/README.md "Steps"): a send builds its bytes
// (structured or raw, then the modifiers), exchanges them and checks the reply
// path, the NAK rule, the whole reply and the field matchers; a poll repeats
// a send until its `until` matchers hold; a wait lets time pass.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "sabus/harness/motion.hpp"
#include "sabus/harness/profile_records.hpp"
#include "sabus/harness/readings.hpp"
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
  if (e.kind == K::kAnswered) {
    if (replies.size() != 1) return "expected one ACK or NAK reply, got " + (replies.empty() ? std::string("silence") : std::to_string(replies.size()) + " replies");
    const Frame& f = replies[0];
    if (is_offline_reply(f)) return "expected an ACK or NAK reply, got the offline reply";
    if (f.address != address) return "reply from address " + describe_byte(f.address) + ", expected " + describe_byte(address);
    if (f.command != command) return "reply for command " + describe_byte(f.command) + ", expected " + describe_byte(command);
    return std::nullopt;
  }
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

// The names of a reply's header fields (bytes 0-2: start, address,
// command), as describe_frame gives them: all a reply the line garbled after
// its header still shows.
bool names_a_header_field(const std::string& name) {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& f : describe_frame(encode_frame(Frame{FrameKind::kAck, 0x31, 0x31, {}})).fields)
      if (f.last < kFrameDataStart) v.push_back(f.name);
    return v;
  }();
  return std::find(names.begin(), names.end(), name) != names.end();
}

// What a step expects, as Session::exchange_judged tells the line's faults
// from the device's answer by it.
Session::Due due_of(const Expectation& e) {
  using K = Expectation::Kind;
  auto all_readings = [&](auto pred) {
    return std::all_of(e.readings.begin(), e.readings.end(), [&](const ReadingAlternative& a) { return pred(a.expect.kind); });
  };
  auto refuses = [](K k) { return k == K::kNak || k == K::kOffline || k == K::kSilence; };
  auto acks = [](K k) { return k == K::kAck || k == K::kOffline; };
  Session::Due due;
  due.reply = e.kind != K::kSilence && e.kind != K::kAny;
  due.must_not_act = refuses(e.kind) && all_readings(refuses);
  due.silence = e.kind == K::kSilence && e.readings.empty();
  due.ack = acks(e.kind) && all_readings(acks);
  due.header_judges = (e.kind == K::kAck || e.kind == K::kAnswered || e.kind == K::kAny) && e.readings.empty() &&
                      !e.bytes && e.from_profile.empty() &&
                      std::all_of(e.fields.begin(), e.fields.end(), [](const FieldMatcher& m) { return names_a_header_field(m.field); });
  return due;
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

std::string problem_text(const Expansion& e) {
  return (e.kind == Expansion::Kind::kUnavailable ? "needs " : "") + e.text;
}

// A send's profile expressions expanded: a structured command's field
// values, or a raw template's {expr} placeholders; the first problem instead
// when one does not expand.
std::optional<std::string> expand_fields(Step& s, const ExprContext& cx) {
  if (s.raw) {
    const Expansion e = expand_raw_expressions(s.raw->hex, cx);
    if (!e.ok()) return "raw: " + problem_text(e);
    s.raw->hex = e.text;
  }
  if (!s.command) return std::nullopt;
  for (auto& [name, value] : s.command->fields) {
    if (!has_placeholder(value)) continue;
    const Expansion e = expand_template(value, cx);
    if (!e.ok()) return "field \"" + name + "\": " + problem_text(e);
    value = e.text;
  }
  return std::nullopt;
}

// Whether a reply shows every axis stopped: the movement/alarm status of
// §3.2 bytes 36-38 is 0000 (no movement) or an alarm (1000-1100) on each
// axis it reports. nullopt when the reply has no axis status.
std::optional<bool> every_axis_stopped(const FrameDescription& d) {
  bool seen = false;
  for (const auto& f : d.fields) {
    if (f.name != "az status" && f.name != "el status" && f.name != "pol status") continue;
    const auto byte = matcher_number(f);
    if (!byte) continue;
    seen = true;
    const int code = static_cast<int>(*byte) & 0x0F;
    if (code != 0 && code < 8) return false;
  }
  return seen ? std::optional<bool>(true) : std::nullopt;
}

// The matchers of a poll's `until` on an axis's movement status (§3.2 bytes
// 36-38): a poll with any waits for the mount at rest (kShortRestPoll).
std::vector<FieldMatcher> rest_matchers(const Step& s) {
  std::vector<FieldMatcher> out;
  for (const auto& m : s.until)
    if (m.field == "az status" || m.field == "el status" || m.field == "pol status") out.push_back(m);
  return out;
}

// The slot a `from_profile` names (a number or a profile expression); 0 for
// "navigation", which has one record.
std::optional<std::string> record_index(const std::string& from_profile, std::uint8_t code, const ExprContext& cx,
                                        std::uint32_t& index) {
  index = 0;
  if (from_profile == "navigation") return std::nullopt;
  const Number n = expand_number(from_profile, cx);
  if (n.kind != Expansion::Kind::kValue) return "from_profile: " + n.text;
  const Count slot = count_in(n.value, 1, max_record_index(code));
  if (slot.error) return "from_profile: " + *slot.error;
  index = static_cast<std::uint32_t>(slot.value);
  return std::nullopt;
}

// The bytes of a send of the profile's record (profile_records.hpp).
Expected<Bytes> record_bytes(const StructuredCommand& c, const ExprContext& cx, std::uint8_t address) {
  const CommandInfo* info = find_command(c.command);
  std::uint32_t index = 0;
  if (auto e = record_index(c.from_profile, info->code, cx, index)) return DecodeError{0, "from_profile", *e, ""};
  const RecordRequest r = profile_write(cx.profile, info->code, index);
  if (!r.request) return DecodeError{0, "from_profile", "needs " + r.unavailable, ""};
  return encode_request(*r.request, c.address.value_or(address));
}

// The navigation reply as the profile has it, except that after a 46h write
// a controller reports both sources as remotely entered, 111 (E-73): each
// source is the profile's or 111.
std::optional<std::string> check_navigation_record(const FrameDescription& got, const FrameDescription& want) {
  for (const auto& w : want.fields) {
    if (w.name == "check byte") continue;  // follows from the other bytes; the receiver checked it
    const auto g = std::find_if(got.fields.begin(), got.fields.end(), [&](const FieldDescription& f) { return f.name == w.name; });
    if (g == got.fields.end()) return "field \"" + w.name + "\" is not in the reply";
    const bool source = w.name == "lat/lon source" || w.name == "heading source";
    // The heading's and the magnetic variation's value, zero- or
    // blank-padded, either justification (E-33, E-40: the spec gives none).
    const bool same_value = (w.name == "true heading" || w.name == "magnetic variation") && g->meaning == w.meaning;
    if (g->raw == w.raw || same_value || (source && g->raw == "0x47")) continue;
    return "byte " + std::to_string(w.first) + " " + w.name + ": the profile holds " + w.raw + " (" + w.meaning + "), got " +
           g->raw + " (" + g->meaning + ")" + (source ? "; after a 46h write 0x47 (remotely entered) is accepted too" : "");
  }
  return std::nullopt;
}

// The reply of a read of stored data against the profile's record: the
// whole reply for a filled slot; for an empty one the 7Fh 7Fh index, the rest
// not being described (READING-NOTES 18, E-18); navigation as above.
std::optional<std::string> check_record(const Expectation& e, const Frame& reply, const ExprContext& cx) {
  std::uint32_t index = 0;
  if (auto err = record_index(e.from_profile, reply.command, cx, index)) return err;
  const RecordReply r = profile_read_reply(cx.profile, reply.command, index);
  if (!r.reply) return "from_profile: needs " + r.unavailable;
  auto want = encode_reply(*r.reply, reply.address, reply.command);
  if (!want) return "from_profile: the profile's record does not encode: " + want.error().message();
  const Bytes got = encode_frame(reply);
  if (reply.command == 0x45) return check_navigation_record(describe_frame(got), describe_frame(want.value()));
  const FrameDescription wd = describe_frame(want.value()), gd = describe_frame(got);
  for (const auto& w : wd.fields) {
    if (w.name == "no data" || w.name == "check byte") continue;  // an empty slot's rest is not described
    const auto g = std::find_if(gd.fields.begin(), gd.fields.end(), [&](const FieldDescription& f) { return f.name == w.name; });
    if (g == gd.fields.end()) return "field \"" + w.name + "\" is not in the reply (" + gd.summary + ")";
    if (g->raw != w.raw)
      return "byte " + std::to_string(w.first) + " " + w.name + ": the profile holds " + w.raw + ", got " + g->raw + " (" +
             g->meaning + ")";
  }
  return std::nullopt;
}

// A 32h frame's targets (ERRATA E-45): whether one is spelled so, and the
// frame respelled.
bool spells(const Bytes& frame, TargetSpelling spelling) {
  const auto f = decode_frame(frame);
  return f && f.value().command == AutoMove::kCode && auto_move_spells(f.value().data, spelling);
}
void respell(Bytes& frame, TargetSpelling to) {
  auto f = decode_frame(frame);
  if (f && f.value().command == AutoMove::kCode && respell_auto_move(f.value().data, to)) frame = encode_frame(f.value());
}

}  // namespace

std::optional<std::string> Session::check_matchers(const FrameDescription& d, const std::vector<FieldMatcher>& matchers) {
  for (const auto& m : matchers) {
    const ResolvedMatcher r = resolve_matcher(m, expr_context());
    if (r.kind != Expansion::Kind::kValue)
      return r.problem + (r.kind == Expansion::Kind::kUnavailable ? " (a capability the profile lacks)" : "");
    if (auto e = check_field(d, r.matcher, captures)) return e;
  }
  return std::nullopt;
}

std::optional<std::string> Session::run_send(const Step& step) {
  Step s = step;
  if (auto e = expand_fields(s, expr_context())) return "cannot build the command: " + *e;
  if (!s.modifiers.address_text.empty()) {
    const Number a = expand_number(s.modifiers.address_text, expr_context());
    if (a.kind != Expansion::Kind::kValue) return "modify.address: " + a.text;
    const Count byte = count_in(a.value, 0, 0x7F);  // any 7-bit byte, control characters too: on purpose
    if (byte.error) return "modify.address: " + *byte.error;
    s.modifiers.address = static_cast<std::uint8_t>(byte.value);
  }
  auto bytes = s.command && !s.command->from_profile.empty() ? record_bytes(*s.command, expr_context(), profile.address)
                                                             : step_bytes(s, profile.address, captures);
  if (!bytes) return "cannot build the command: " + bytes.error().message();
  // ERRATA E-45: a negative 32h target built from fields is spelled as the
  // device reads it, once the profile or the run has shown how (run_sides).
  Bytes frame = bytes.value();
  const bool spelled = s.command && spells(frame, TargetSpelling::kSignFirst);
  const auto e45 = spelled ? side_known("E-45") : std::nullopt;
  if (e45 == ReadingSide::kOther) respell(frame, TargetSpelling::kZerosFirst);
  std::vector<Frame> replies;
  auto failure = send_and_judge(s, apply_modifiers(frame, s.modifiers), replies);
  // Neither side known yet: the codec's spelling ('-' first) went first. A
  // NAK that fails the step may be the other side's "malformed": the command
  // goes again with the zeros left of the sign (a NAKed command has no
  // effect), and judged by that reply. The spelling the device ACKs is its
  // side for the rest of the run.
  if (!spelled || e45 || line_error) return failure;
  auto answered = [&](FrameKind kind) { return replies.size() == 1 && replies[0].kind == kind; };
  if (!failure || !answered(FrameKind::kNak)) {
    if (answered(FrameKind::kAck)) run_sides["E-45"] = ReadingSide::kReference;
    return failure;
  }
  respell(frame, TargetSpelling::kZerosFirst);
  if (transcript)
    transcript->push_back({t_ms(), false, {}, "E-45: NAKed with the target '-' first; sent again with the zeros left of the sign", {}, ""});
  auto again = send_and_judge(s, apply_modifiers(frame, s.modifiers), replies);
  if (!line_error && answered(FrameKind::kAck)) run_sides["E-45"] = ReadingSide::kOther;
  if (!again || line_error) return again;
  return *failure + "; sent again with the zeros left of the sign (ERRATA E-45): " + *again;
}

// One exchange of a send step and its judgement: the failure, if any, and
// the replies judged.
std::optional<std::string> Session::send_and_judge(const Step& s, const Bytes& wire, std::vector<Frame>& replies_judged) {
  const bool silence = s.expect.kind == Expectation::Kind::kSilence;
  const auto window = silence ? silence_window() : reply_timeout(wire.size());
  const TimePoint listen_start = transport.now();
  (void)transport.take_nak_rules();  // only this exchange's rules count
  expect = std::string(to_string(s.expect.kind));
  const std::size_t faults_before = line.faults;
  const Judged judged = exchange_judged(wire, s.modifiers, window, due_of(s.expect));
  const auto& replies = judged.replies;
  replies_judged = replies;
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
  if (judged.error) {
    line_error = true;
    return "the line left " + describe_byte(sent.command) + " unjudged: " + judged.fault;
  }
  if (options.strict_line && line.faults > faults_before)
    return "a line fault (--strict-line): " + (judged.fault.empty() ? std::string("recovered by a repeat") : judged.fault);
  const Reply got{replies, nak_rules, want_address, sent.command, judged.header_only};
  auto failure = s.expect.readings.empty() ? check_reply(s.expect, got) : check_sides(s.expect, got);
  // With no repeat allowed (--retries 0) a line fault is judged as the reply
  // it left; the failure says what the line did, for whoever reads it.
  // (Without a line the failure's own words say what the reply was.)
  if (failure && !judged.fault.empty() && transport.is_a_line())
    *failure += " (the reply showed a line fault: " + judged.fault + ")";
  return failure;
}

std::optional<ReadingSide> Session::side_known(const std::string& errata) const {
  if (auto side = side_pinned(profile.readings, errata)) return side;
  return side_pinned(run_sides, errata);
}

std::optional<std::string> Session::check_reply(const Expectation& e, const Reply& got) {
  if (auto err = check_kind(e, got.replies, got.address, got.command)) return err;
  if (auto err = check_nak_rule(e, got.nak_rules)) return err;
  if (got.replies.empty()) return std::nullopt;
  const Bytes reply = encode_frame(got.replies[0]);
  if (e.bytes) {
    const Expansion template_ = expand_raw_expressions(e.bytes->hex, expr_context());
    if (!template_.ok()) return "expected bytes: " + problem_text(template_);
    auto want = expand_raw_bytes(template_.text, profile.address, captures);
    if (!want) return "bad expected bytes: " + want.error().message();
    if (want.value() != reply) return "expected bytes " + to_hex(want.value()) + ", got " + to_hex(reply);
  }
  const FrameDescription d = describe_frame(reply);
  // A header alone (Judged::header_only) has no data to decode.
  if (e.kind == Expectation::Kind::kAck && d.error && !got.header_only) return "reply does not decode: " + d.error->message();
  if (!e.from_profile.empty())
    if (auto err = check_record(e, got.replies[0], expr_context())) return err;
  return check_matchers(d, e.fields);
}

// An expectation with `readings:` (ERRATA class reading): the reply passes
// when it meets the side of some point the profile has not pinned away —
// the reference side (`e` itself) unless a listed point is pinned to a side
// the step lists (one it does not list answers as the reference), or a
// listed side unless the point is pinned to another. The captures are
// those of the side that passed. A step that lists one point and meets only
// one of its sides shows the device's side: the rest of the vector is held
// to it (sides_shown), so that two steps each allowing both sides cannot
// pass a device that takes neither (ERRATA E-45's two spellings).
std::optional<std::string> Session::check_sides(const Expectation& e, const Reply& got) {
  auto pinned = [&](const std::string& id) {
    if (auto side = side_known(id)) return side;
    return side_pinned(sides_shown, id);
  };
  // A side is left unless its point is pinned (or shown) to another.
  auto allowed = [&](const std::string& id, ReadingSide side) {
    const auto p = pinned(id);
    return !p || *p == side;
  };
  auto named = [](const ReadingAlternative& alt) { return alt.errata + " " + std::string(to_string(alt.side)); };
  // A side of a listed point that the step does not list answers as the
  // reference side does (E-23's other-2 NAKs without the option, as the
  // reference does).
  auto listed = [&](const std::string& id, ReadingSide side) {
    return std::any_of(e.readings.begin(), e.readings.end(),
                       [&](const ReadingAlternative& alt) { return alt.errata == id && alt.side == side; });
  };
  std::string ids, failures, shown;
  bool reference_allowed = true;
  for (const auto& alt : e.readings) {
    if (ids.find(alt.errata) == std::string::npos) ids += (ids.empty() ? "" : ", ") + alt.errata;
    if (const auto p = pinned(alt.errata); p && *p != ReadingSide::kReference && listed(alt.errata, *p))
      reference_allowed = false;
    // A side the device showed (not one the profile pins) is named.
    const auto by_device = side_pinned(profile.readings, alt.errata) ? std::nullopt : pinned(alt.errata);
    if (by_device && shown.find(alt.errata) == std::string::npos)
      shown += (shown.empty() ? "" : ", ") + alt.errata + " " + std::string(to_string(*by_device));
  }
  const Captures before = captures;
  // Each side's failure, to say once what every side met alike (a reply
  // that does not decode, silence: nothing the reading decides).
  std::vector<std::string> reasons;
  auto attempt = [&](const Expectation& side, const std::string& name) {
    captures = before;
    auto failure = check_reply(side, got);
    if (failure) {
      failures += (failures.empty() ? "" : "; ") + name + ": " + *failure;
      reasons.push_back(*failure);
    }
    return !failure;
  };
  // One open point: the side that held alone is the device's from here on.
  const std::string& first = e.readings.front().errata;
  const bool one_open = std::all_of(e.readings.begin(), e.readings.end(), [&](const auto& alt) { return alt.errata == first; }) &&
                        !pinned(first);
  auto show = [&](ReadingSide side) {
    sides_shown[first] = side;
    if (transcript)
      transcript->push_back({t_ms(), false, {}, first + " " + std::string(to_string(side)) +
                                                    " shown: the rest of the vector is held to it", {}, ""});
  };
  // Whether an alternative after `from` holds too (captures and failures kept).
  auto another_holds = [&](std::size_t from) {
    const Captures passed = captures;
    const std::string kept = failures;
    bool holds = false;
    for (std::size_t k = from; k < e.readings.size() && !holds; ++k) holds = attempt(e.readings[k].expect, named(e.readings[k]));
    captures = passed;
    failures = kept;
    return holds;
  };
  if (reference_allowed && attempt(e, ids + " reference")) {
    // Shown only where no unlisted side answers alike.
    const auto sides = sides_of(*find_reading_point(first));
    const bool all_listed = std::all_of(sides.begin() + 1, sides.end(), [&](ReadingSide side) { return listed(first, side); });
    if (one_open && all_listed && !another_holds(0)) show(ReadingSide::kReference);
    return std::nullopt;
  }
  for (std::size_t k = 0; k < e.readings.size(); ++k) {
    const ReadingAlternative& alt = e.readings[k];
    if (!allowed(alt.errata, alt.side) || !attempt(alt.expect, named(alt))) continue;
    if (one_open && !another_holds(k + 1)) show(alt.side);
    if (alt.expect.ends) {
      steps_ended = true;
      if (transcript)
        transcript->push_back({t_ms(), false, {}, named(alt) + " holds: the vector's steps end here (ends)", {}, ""});
    }
    return std::nullopt;
  }
  captures = before;
  if (failures.empty()) return "no side of " + ids + " is left by the profile's readings: pins";
  if (reasons.size() > 1 &&
      std::all_of(reasons.begin(), reasons.end(), [&](const std::string& r) { return r == reasons.front(); }))
    return reasons.front();
  return "no legal reading holds (ERRATA " + ids + (shown.empty() ? "" : "; the device showed " + shown + " earlier") + "): " + failures;
}

// A poll without a timeout of its own waits as long as the longest moves it
// can be waiting for take (motion::longest_move: slow speed, both ramps): the
// distance from the first reply's position to each position the poll waits
// for, or every axis's whole range when it waits for none, one axis after the
// other (a controller may run a LOCATE's, STOW's or DEPLOY's legs in turn:
// ERRATA E-89, E-94); then half as long again and 10 s more. At most an hour.
std::chrono::milliseconds Session::poll_timeout(const Step& s, const FrameDescription& first_reply) {
  using std::chrono::milliseconds;
  std::array<milliseconds, 3> per_axis{};  // the longest move of each axis named
  bool named = false;
  for (const auto& m : s.until) {
    const auto axis = motion::axis_of_field(m.field);
    if (!axis) continue;
    const ResolvedMatcher r = resolve_matcher(m, expr_context());
    const auto field = std::find_if(first_reply.fields.begin(), first_reply.fields.end(),
                                    [&](const FieldDescription& f) { return f.name == m.field; });
    if (r.kind != Expansion::Kind::kValue || field == first_reply.fields.end()) continue;
    const auto now_at = matcher_number(*field);
    if (!now_at || r.matcher.kind == FieldMatcher::Kind::kRegex || r.matcher.kind == FieldMatcher::Kind::kAny) continue;
    const double target = (r.matcher.low + r.matcher.high) / 2;
    const AxisProfile& a = motion::profile_of(profile, *axis);
    // A fluxgate azimuth reads a heading, modulo 360 (§3.2 NOTE): two
    // readings do not tell how far apart the positions are on a mount whose
    // range passes 360, so the poll allows the whole range.
    const bool heading = *axis == motion::Axis::kAz && profile.az_sensor == AzSensor::kFluxgate;
    milliseconds& slot = per_axis[static_cast<std::size_t>(*axis)];
    slot = std::max(slot, motion::longest_move(a, heading ? a.max_deg - a.min_deg : target - *now_at));
    named = true;
  }
  if (!named)
    for (auto axis : {motion::Axis::kAz, motion::Axis::kEl, motion::Axis::kPol}) {
      const AxisProfile& a = motion::profile_of(profile, axis);
      per_axis[static_cast<std::size_t>(axis)] = motion::longest_move(a, a.max_deg - a.min_deg);
    }
  const milliseconds longest = per_axis[0] + per_axis[1] + per_axis[2];
  return std::min<milliseconds>(longest * 3 / 2 + milliseconds(10000), milliseconds(3600000));
}

// Repeats the send until `until` holds. In a vector that moves the antenna,
// a poll ends as soon as every axis has shown stopped for kStoppedPolls
// polls in a row with `until` still unmet: a mount that stops in the wrong
// place fails in seconds, not at the timeout.
std::optional<std::string> Session::run_poll(const Step& s) {
  constexpr int kStoppedPolls = 3;
  const TimePoint start = transport.now();
  std::chrono::milliseconds timeout = s.timeout;
  if (!s.timeout_text.empty()) {
    const Number n = expand_number(s.timeout_text, expr_context());
    if (n.kind != Expansion::Kind::kValue) return "poll: timeout_ms: " + n.text;
    const Count ms = count_in(n.value, 1, kMaxMs);  // as a literal time (vector_steps.cpp)
    if (ms.error) return "poll: timeout_ms: " + *ms.error;
    timeout = std::chrono::milliseconds(ms.value);
  }
  Step probe = s;
  probe.kind = Step::Kind::kSend;
  int stopped_polls = 0, requests = 0;
  // A poll for the rest of an axis whose poll for rest timed out is short
  // (kShortRestPoll requests), until that axis shows rest.
  const std::vector<FieldMatcher> rest = rest_matchers(s);
  auto waits_for_unshown_rest = [&] {
    return std::any_of(rest.begin(), rest.end(), [&](const FieldMatcher& m) { return rest_not_shown.count(m.field) > 0; });
  };
  bool short_poll = waits_for_unshown_rest();
  rest_unseen = false;
  // Polls the line left unjudged in a row: a poll asks again anyway, so a
  // garbled reply only costs one interval, until kUnjudgedPolls in a row.
  constexpr int kUnjudgedPolls = 5;
  int unjudged = 0;
  while (true) {
    if (auto e = run_send(probe)) {
      if (!line_error || ++unjudged >= kUnjudgedPolls) return "poll: " + *e;
      line_error = false;
      if (transport.now() - start >= (timeout.count() > 0 ? timeout : std::chrono::milliseconds(kMaxMs))) return "poll: " + *e;
      transport.pause(s.interval);
      continue;
    }
    line.recovered += static_cast<std::size_t>(unjudged);  // the poll asked again and got a clean reply
    unjudged = 0;
    ++requests;
    // The reply of the last exchange, checked against `until`.
    const Bytes reply = last_replies().empty() ? Bytes{} : encode_frame(last_replies()[0]);
    const FrameDescription d = describe_frame(reply);
    const std::optional<std::string> unmet = check_matchers(d, s.until);
    // The axes that show rest now; when every one a poll timed out on has,
    // the run is back to normal.
    std::vector<std::string> moving;
    for (const auto& m : rest) {
      if (!check_matchers(d, {m})) rest_not_shown.erase(m.field);
      else moving.push_back(m.field);
    }
    short_poll = short_poll && waits_for_unshown_rest();
    if (rest_not_shown.empty()) rest_timed_out_in.clear();
    if (!unmet) return std::nullopt;
    if (timeout.count() == 0) timeout = poll_timeout(s, d);
    if (vector_moves && every_axis_stopped(d).value_or(false)) {
      if (++stopped_polls >= kStoppedPolls)
        return "poll: the mount stopped (every axis idle for " + std::to_string(kStoppedPolls) +
               " polls) before the poll's condition held: " + *unmet;
    } else {
      stopped_polls = 0;
    }
    if (short_poll && requests >= kShortRestPoll) {
      rest_unseen = true;
      return "the mount did not show rest in a short poll of " + std::to_string(kShortRestPoll) +
             (kShortRestPoll == 1 ? " request" : " requests") + " (" + *unmet + "): the poll for rest of " + rest_timed_out_in +
             " timed out, and later polls for rest are short";
    }
    if (transport.now() - start >= timeout) {
      if (!moving.empty() && rest_not_shown.empty()) rest_timed_out_in = vector_id;
      rest_not_shown.insert(moving.begin(), moving.end());
      return "poll timed out after " + std::to_string(timeout.count()) + " ms: " + *unmet;
    }
    if (options.stop && !options.stop().empty()) return "stopped";
    transport.pause(s.interval);
  }
}

// The first poll of the vector's setup and steps that waits for the rest of
// an axis that has not shown rest, its `until` cut to those axes' status:
// the poll it would run short. nullopt when there is none.
std::optional<Step> Session::unshown_rest_poll(const Vector& v) const {
  if (rest_not_shown.empty()) return std::nullopt;
  for (const auto* list : {&v.setup, &v.steps})
    for (const Step& s : *list) {
      if (s.kind != Step::Kind::kPoll) continue;
      std::vector<FieldMatcher> unshown;
      for (const auto& m : rest_matchers(s))
        if (rest_not_shown.count(m.field) > 0) unshown.push_back(m);
      if (unshown.empty()) continue;
      Step probe = s;
      probe.until = std::move(unshown);
      return probe;
    }
  return std::nullopt;
}

// The vector's own poll for rest would be short and, on a mount still
// showing movement, end it inconclusive after its setup had moved the
// mount, with its teardown and the runner's stop to follow. That short poll
// comes first instead: when the axis still does not show rest, the vector
// ends before its setup, having sent nothing else, and a controller that
// never shows rest costs one request a vector. Anything else runs the vector
// as before, which judges it: rest seen (the run is back to normal for that
// axis, as in run_poll), a reply the poll's expectation fails, a line that
// left the request unjudged. So this only ever ends a vector inconclusive,
// never fails or passes one. What its setup and steps would have checked
// before its poll is left unchecked, as in any inconclusive vector, and a
// vector that waits before its poll for rest does not get that wait.
std::optional<std::string> Session::rest_still_unseen(const Vector& v) {
  const std::optional<Step> probe = unshown_rest_poll(v);
  if (!probe) return std::nullopt;
  std::optional<std::string> e = run_poll(*probe);
  line_error = false;
  if (!std::exchange(rest_unseen, false)) return std::nullopt;
  return e;
}

namespace {
// The lower bound of the Wilson score interval for `hits` of `n` at 99%
// confidence (z = 2.576): the share is at least this, but for a 1-in-100
// chance. A survey fails the device only when even this is above the
// threshold, so a line that garbles a reply now and then does not fail a
// legal controller by bad luck.
double share_at_least(std::size_t hits, std::size_t n) {
  if (n == 0) return 0;
  constexpr double z = 2.576;
  const double p = static_cast<double>(hits) / static_cast<double>(n), nn = static_cast<double>(n);
  const double centre = p + z * z / (2 * nn);
  const double spread = z * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn));
  return std::max(0.0, (centre - spread) / (1 + z * z / nn));
}
}  // namespace

// §4: "a garbled status reply" is a symptom of unreliable communications. A
// survey sends its frame `survey_count` times at its interval, each once (a
// repeat would hide what it counts), and counts the replies that came
// garbled: a controller that garbles its own replies fails here, where the
// rest of the run repeats and recovers them. A silence is not counted (a
// request the line lost looks the same); a clean reply that is not an ACK
// fails as a send's would.
std::optional<std::string> Session::run_survey(const Step& s) {
  Step probe = s;
  probe.kind = Step::Kind::kSend;
  std::size_t garbled = 0, answered = 0;
  std::string first;
  measuring = true;
  for (std::size_t i = 0; i < s.survey_count; ++i) {
    if (i > 0) transport.pause(s.interval);
    const auto failure = run_send(probe);
    line_error = false;
    const std::string fault = last_fault(due_of(s.expect));
    if (fault == "no reply") continue;
    ++answered;
    if (!fault.empty()) {
      if (first.empty()) first = fault;
      ++garbled;
    } else if (failure) {
      measuring = false;
      return "survey: " + *failure;
    }
    if (options.stop && !options.stop().empty()) break;
  }
  measuring = false;
  const double limit = options.max_line_fault_rate;
  const std::string measured = std::to_string(garbled) + " of " + std::to_string(answered) + " replies garbled";
  if (transcript) transcript->push_back({t_ms(), false, {}, "survey: " + measured, {}, ""});
  if (answered == 0) return "survey: no reply to any of " + std::to_string(s.survey_count) + " sends";
  if (share_at_least(garbled, answered) > limit)
    return "survey: " + measured + " (first: " + first + "), more than " + std::to_string(static_cast<int>(limit * 100 + 0.5)) +
           "% (--max-line-fault-rate) even at the low end of its 99% confidence interval: the controller garbles its replies";
  return std::nullopt;
}

std::optional<std::string> Session::run_step(const Step& s) {
  switch (s.kind) {
    case Step::Kind::kWait: {
      std::chrono::milliseconds wait = s.timeout;
      if (!s.timeout_text.empty()) {
        const Number n = expand_number(s.timeout_text, expr_context());
        if (n.kind != Expansion::Kind::kValue) return "wait: " + n.text;
        const Count ms = count_in(n.value, 1, kMaxMs);
        if (ms.error) return "wait: " + *ms.error;
        wait = std::chrono::milliseconds(ms.value);
      }
      transport.pause(wait);
      return std::nullopt;
    }
    case Step::Kind::kSend: return run_send(s);
    case Step::Kind::kPoll: return run_poll(s);
    case Step::Kind::kSurvey: return run_survey(s);
  }
  return std::nullopt;
}

}  // namespace detail
}  // namespace sabus::harness
