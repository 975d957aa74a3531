// The live fuzzer's session (one device: writes, answers, liveness) and the
// minimization of a finding by delta debugging over the writes that led to it.
#include <algorithm>
#include <thread>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/timing.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness::live_fuzz {
namespace {

using std::chrono::milliseconds;
using namespace std::chrono_literals;

struct ReplySink : ReceiverSink {
  std::vector<Frame> frames;
  std::vector<std::string> garbage;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard& d) override { garbage.push_back(d.message()); }
};

}  // namespace

FuzzFrame liveness_probe(std::uint8_t address) {
  return {encode_frame({FrameKind::kCommand, address, 0x30, {}}), {}, "liveness probe (device type query, §3.1)"};
}

Session::Session(Transport& transport, const Profile& profile, SessionOptions options)
    : transport_(transport), profile_(profile), options_(options), oracle_(profile) {
  if (options_.lockstep) lockstep_.emplace(profile, transport_.now());
}

Duration Session::timing_uncertainty() const {
  if (transport_.in_process()) return Duration{0};
  return latency_ + std::chrono::milliseconds(5);
}

std::optional<Verdict> Session::lockstep_step(const FuzzFrame& frame, const Observation& seen) {
  if (!lockstep_) return std::nullopt;
  // When the device executed the write: just before its first reply byte
  // came back (a device answers once it has executed, §1 State 5), which
  // varies far less from write to write than the time it was sent; a
  // constant offset (its turnaround, the reply's wire time) changes no
  // difference of times. The time it was sent for a write with no reply.
  const TimePoint executed = first_byte_at_ ? *first_byte_at_ : sent_at_;
  return lockstep_->step(frame, executed, timing_uncertainty(), seen.replies);
}

bool Session::would_be_ignored(const FuzzFrame& frame) const {
  Oracle copy = oracle_;
  return copy.accept(frame).empty();
}

Observation Session::exchange(const FuzzFrame& frame, std::size_t expected_replies, std::size_t reply_bytes) {
  Transport& t = transport_;
  if (frame.pause.count() > 0) t.pause(frame.pause);
  if (options_.pace.count() > 0 && last_write_ != TimePoint{}) {
    const auto since = t.now() - last_write_;
    if (since < options_.pace) t.pause(std::chrono::duration_cast<milliseconds>(options_.pace - since));
  }
  sent_at_ = t.now();
  first_byte_at_.reset();
  t.send(frame.chars, frame.wrong_parity);
  last_write_ = t.now();
  counts_.bytes_sent += frame.chars.size();
  ++counts_.writes;
  const TimePoint sent_at = t.now();
  const TimePoint request_end = sent_at + wire_time(frame.chars.size(), t.baud());
  // The reply window (timing.hpp): every reply the write may draw, at the
  // baud rate, after the turnaround allowance; for a write the device must
  // ignore, the silence window.
  const milliseconds allowance = std::max(options_.turnaround_allowance,
                                          std::chrono::ceil<milliseconds>(std::chrono::duration<double, std::milli>(profile_.turnaround_ms)));
  const milliseconds window =
      t.in_process() ? (expected_replies == 0 ? 500ms : 1000ms)
      : expected_replies == 0
          ? silence_window(std::chrono::duration_cast<std::chrono::microseconds>(allowance), t.baud(), max_reply_length())
          : reply_timeout(t.baud(), frame.chars.size(), reply_bytes, allowance);
  // Once the replies expected are in, listen a few character times more for
  // one too many (§1: one reply a command).
  const milliseconds quiet = std::max<milliseconds>(3ms, std::chrono::ceil<milliseconds>(wire_time(3, t.baud())) + 1ms);
  ReceiverOptions ro = ReceiverOptions::master();
  ro.parity = receiver_parity(t);
  Receiver rx(ro);
  ReplySink sink;
  Observation seen;
  std::uint8_t buf[512];
  while (t.now() - sent_at < window) {
    const auto left = std::chrono::duration_cast<milliseconds>(window - (t.now() - sent_at));
    const bool have_all = expected_replies > 0 && sink.frames.size() >= expected_replies;
    const std::size_t n = t.receive(buf, have_all ? std::min(left, quiet) : std::max(left, 1ms));
    if (n > 0 && !first_byte_at_) first_byte_at_ = t.now();
    if (n > 0 && !seen.first_byte_after)
      seen.first_byte_after = std::max(Duration{0}, std::chrono::duration_cast<Duration>(t.now() - request_end));
    counts_.bytes_received += n;
    rx.feed(ByteView(buf, n), sink);
    if (n == 0 && have_all) break;
  }
  rx.finish(sink);
  // The device executed the write between sent_at_ and its first reply byte
  // (measured, not the request's wire time at the baud rate: a pty has none).
  latency_ = first_byte_at_ ? std::chrono::duration_cast<Duration>(*first_byte_at_ - sent_at_) : Duration{0};
  seen.replies = std::move(sink.frames);
  seen.garbage = std::move(sink.garbage);
  for (const Frame& f : seen.replies) {
    if (f.kind == FrameKind::kNak) ++counts_.nak;
    else if (is_offline_reply(f)) ++counts_.offline;
    else ++counts_.ack;
  }
  if (seen.replies.empty() && seen.garbage.empty()) ++counts_.silence;
  if (!seen.garbage.empty()) ++counts_.garbage;
  return seen;
}

std::optional<Verdict> Session::step(const FuzzFrame& frame) {
  std::string why;
  if (!is_safe_to_send(frame.chars, options_.allow_motion, options_.allow_destructive, tail_, &why)) {
    ++counts_.refused;  // the safety gate: never on the line without the flag
    return std::nullopt;
  }
  const std::vector<Frame> accepted = oracle_.accept(frame);
  const Observation seen = exchange(frame, accepted.size(), expected_reply_bytes(accepted));
  tail_.assign(frame.chars.end() - static_cast<std::ptrdiff_t>(std::min<std::size_t>(4, frame.chars.size())), frame.chars.end());
  const std::optional<Verdict> model = lockstep_step(frame, seen);
  if (auto v = oracle_.judge_write(accepted, seen)) return v;
  // Late: the first reply byte after the profile's turnaround, the allowance
  // and what the host adds (timing.hpp kHostLatency).
  if (seen.first_byte_after && !transport_.in_process()) {
    const auto limit = std::chrono::duration_cast<Duration>(std::chrono::duration<double, std::milli>(profile_.turnaround_ms)) +
                       options_.turnaround_allowance + kHostLatency;
    if (*seen.first_byte_after > limit)
      return Verdict{FindingKind::kLateReply, "first reply byte " + std::to_string(seen.first_byte_after->count() / 1000) +
                                                  " ms after the request; the profile's turnaround is " +
                                                  std::to_string(profile_.turnaround_ms) + " ms"};
  }
  return model;
}

std::optional<Verdict> Session::probe() {
  ++counts_.probes;
  const FuzzFrame q = liveness_probe(profile_.address);
  const std::vector<Frame> accepted = oracle_.accept(q);
  const Observation seen = exchange(q, accepted.size(), expected_reply_bytes(accepted));
  tail_.clear();
  const std::optional<Verdict> model = lockstep_step(q, seen);
  // No byte at all: dead. Bytes that are no reply frame are judged below.
  if (seen.replies.empty() && seen.garbage.empty())
    return Verdict{FindingKind::kDead, "no answer to the liveness probe (device type query, §3.1)"};
  if (auto v = oracle_.judge_write(accepted, seen)) return v;
  const Frame& reply = seen.replies.front();
  if (reply.kind == FrameKind::kAck && !is_offline_reply(reply)) {
    if (!first_device_type_) first_device_type_ = reply;
    else if (reply != *first_device_type_)
      return Verdict{FindingKind::kReset, "the device type changed from " + to_hex(encode_frame(*first_device_type_)) + " to " +
                                              to_hex(encode_frame(reply)) + " (a reset?)"};
  }
  return model;
}

std::optional<Verdict> Session::synchronize(std::vector<FuzzFrame>* sent, std::string* taken) {
  if (!lockstep_) return std::nullopt;
  // 40h alone: its status block has the positions, and a 31h first could
  // change the mode it is asked for (a device that takes a status poll for
  // a remote command).
  for (const std::uint8_t code : {std::uint8_t{0x40}}) {
    const FuzzFrame q{encode_frame({FrameKind::kCommand, profile_.address, code, {}}), {},
                      "synchronize the model (extended status, §3.17)"};
    if (sent) sent->push_back(q);
    const std::vector<Frame> accepted = oracle_.accept(q);
    const Observation seen = exchange(q, accepted.size(), expected_reply_bytes(accepted));
    tail_.clear();
    const std::string t = lockstep_->adopt(q, first_byte_at_ ? *first_byte_at_ : sent_at_, seen.replies);
    if (taken && !t.empty()) *taken += (taken->empty() ? "" : "; ") + t;
    if (auto v = oracle_.judge_write(accepted, seen)) return v;
  }
  return std::nullopt;
}

// The lockstep oracle's kinds: a replay must start with the device as the
// model starts, from its profile.
static bool from_the_model(FindingKind kind) {
  return kind == FindingKind::kNakRule || kind == FindingKind::kValue || kind == FindingKind::kEffect;
}

bool Session::shows(const std::vector<FuzzFrame>& frames, FindingKind kind) {
  // On the same device the state a lockstep finding rests on (positions,
  // stored data) is not restored: such a replay would prove nothing.
  if (from_the_model(kind) && (!transport_.in_process() || counts_.writes > 0)) return false;
  if (lockstep_) lockstep_->rebuild(transport_.now());
  if (!transport_.in_process() || counts_.writes > 0) {
    // The same device: back to §1 State 1 with a liveness probe first.
    oracle_.reset();
    if (probe()) return false;
  }
  oracle_.reset();
  for (const FuzzFrame& f : frames)
    if (auto v = step(f); v && v->kind == kind) return true;
  if (kind == FindingKind::kDead || kind == FindingKind::kReset)
    if (auto v = probe(); v && v->kind == kind) return true;
  return false;
}

void minimize(Finding& finding, const Profile& profile, const SessionOptions& options, const DeviceFactory& fresh,
              Session* same_device, std::size_t window) {
  auto fails = [&](const std::vector<FuzzFrame>& frames) {
    if (fresh) {
      std::unique_ptr<Transport> t = fresh();
      SessionOptions o = options;
      o.pace = 0ms;
      Session s(*t, profile, o);
      return s.shows(frames, finding.kind);
    }
    return same_device && same_device->shows(frames, finding.kind);
  };
  const std::vector<FuzzFrame>& h = finding.history;
  std::vector<FuzzFrame> start(h.end() - static_cast<std::ptrdiff_t>(std::min(window, h.size())), h.end());
  bool reproduces = fails(start);
  if (!reproduces && start.size() < h.size() && fresh) {
    start = h;
    reproduces = fails(start);
  }
  finding.reproduced = reproduces;
  if (!reproduces) {
    finding.reproducer = start;
    return;
  }
  // On a real line every trial costs wire time: fewer tests.
  finding.reproducer = ddmin<FuzzFrame>(start, fails, fresh ? 2000 : 200);
}

}  // namespace sabus::harness::live_fuzz
