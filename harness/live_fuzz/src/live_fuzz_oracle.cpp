// The live fuzzer's oracle: which answers a write may draw, from the spec's
// rules through the catalog (§1 ignore paths, §3 NAK and offline replies,
// the catalog's reply lengths and layouts).
#include <algorithm>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness::live_fuzz {

std::string_view to_string(FindingKind k) {
  switch (k) {
#define SABUS_X(id, name, paragraph, quote) \
  case FindingKind::id: return name;
    SABUS_LIVE_FUZZ_FINDINGS(SABUS_X)
#undef SABUS_X
  }
  return "?";
}

std::string_view paragraph_of(FindingKind k) {
  switch (k) {
#define SABUS_X(id, name, paragraph, quote) \
  case FindingKind::id: return paragraph;
    SABUS_LIVE_FUZZ_FINDINGS(SABUS_X)
#undef SABUS_X
  }
  return "1";
}

std::string_view quote_of(FindingKind k) {
  switch (k) {
#define SABUS_X(id, name, paragraph, quote) \
  case FindingKind::id: return quote;
    SABUS_LIVE_FUZZ_FINDINGS(SABUS_X)
#undef SABUS_X
  }
  return "";
}

struct Oracle::Sink : ReceiverSink {
  std::vector<Frame> frames;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard&) override {}
};

// The reference receiver: the project's readings for this profile, no faults
// (the same options the reference controller's receiver has).
Oracle::Oracle(const Profile& profile)
    : profile_(profile), receiver_(receiver_options(profile, FaultSet{}, Parity::kEvenBit7)) {
  // The readings that decide which frames a receiver passes on (ERRATA E-6,
  // E-8); those the profile pins keep their side.
  std::vector<std::string> open;
  for (const char* id : {"E-6", "E-8"})
    if (!side_pinned(profile.readings, id)) open.emplace_back(id);
  for (unsigned combination = 1; combination < (1u << open.size()); ++combination) {
    Profile p = profile;
    for (std::size_t i = 0; i < open.size(); ++i)
      p.readings[open[i]] = combination & (1u << i) ? ReadingSide::kOther : ReadingSide::kReference;
    others_.emplace_back(receiver_options(p, FaultSet{}, Parity::kEvenBit7));
  }
}

void Oracle::reset() {
  receiver_.reset();
  for (Receiver& r : others_) r.reset();
  dropped_.reset();
}

std::vector<Frame> Oracle::accept(const FuzzFrame& frame) {
  const Bytes wire = with_software_parity(frame.chars, frame.wrong_parity);
  dropped_.reset();
  dropped_frames_.clear();
  if (receiver_.state() != ReceiverState::kSlaveIdle && side_pinned(profile_.readings, "E-67") != ReadingSide::kReference) {
    dropped_ = receiver_;
    dropped_->reset();
    Sink alternative;
    dropped_->feed(wire, alternative);
    dropped_frames_ = std::move(alternative.frames);
  }
  Sink sink;
  receiver_.feed(wire, sink);
  last_accepted_ = sink.frames;
  others_accepted_.clear();
  for (Receiver& r : others_) {
    Sink other;
    r.feed(wire, other);
    if (other.frames != sink.frames) others_accepted_.push_back(std::move(other.frames));
  }
  return sink.frames;
}

std::optional<Verdict> Oracle::judge_write(const std::vector<Frame>& accepted, const Observation& seen) {
  std::optional<Verdict> v = judge(accepted, seen);
  if (v && dropped_ && !judge(dropped_frames_, seen)) {
    receiver_ = *dropped_;
    v.reset();
  }
  dropped_.reset();
  return v;
}

namespace {

std::string summary(const Frame& f) { return describe_frame(encode_frame(f)).summary; }

// Whether this device answers the command at all with ACK (§3 table '*',
// E-16; §3.20/§3.21 and E-23 for the DVB option).
bool device_implements(const CommandInfo& info, const Profile& p) {
  if (info.needs_dvb_option && !p.dvb_receiver) return false;
  if (info.implemented) return true;
  if (info.code == 0x38) return p.implements_signal_strength;
  return p.implements_iess;  // 3Dh, 3Eh
}

}  // namespace

std::optional<Verdict> Oracle::judge(const Frame& request, const Frame& reply) const {
  const std::string about = " to " + summary(request);
  if (reply.address != profile_.address)
    return Verdict{FindingKind::kWrongAddress,
                   "reply from address " + describe_byte(reply.address) + " instead of " + describe_byte(profile_.address) + about};
  if (reply.command != request.command)
    return Verdict{FindingKind::kWrongReply, "reply for command " + describe_byte(reply.command) + about};
  if (reply.kind == FrameKind::kNak) {
    if (!reply.data.empty())  // §3: NAK A CC ETX LRC
      return Verdict{FindingKind::kMalformedReply, "NAK with " + std::to_string(reply.data.size()) + " data bytes" + about};
    return std::nullopt;
  }
  if (is_offline_reply(reply)) {
    if (profile_.remote_enabled)
      return Verdict{FindingKind::kWrongReply, "the offline reply although remote control is enabled" + about};
    return std::nullopt;
  }
  // An ACK with data: the command's normal reply.
  if (!profile_.remote_enabled)
    return Verdict{FindingKind::kWrongReply, "executed with remote control disabled (§3 Online/Offline Reply)" + about};
  const CommandInfo* info = find_command(request.command);
  if (!info) return Verdict{FindingKind::kWrongReply, "ACK to an unknown command code; §3 asks for a NAK" + about};
  const std::size_t length = request.data.size() + kFrameOverhead;
  if (info->request_length && length != *info->request_length)
    return Verdict{FindingKind::kWrongReply, "ACK to a frame of " + std::to_string(length) + " bytes; the catalog says " +
                                                 std::to_string(*info->request_length) + " for " + std::string(info->key) +
                                                 " (§" + std::string(info->paragraph) + "), so §3 asks for a NAK" + about};
  if (!device_implements(*info, profile_))
    return Verdict{FindingKind::kWrongReply,
                   "ACK to a command this device does not implement (§" + std::string(info->paragraph) + ")" + about};
  const Bytes bytes = encode_frame(reply);
  if (info->reply_length && bytes.size() != *info->reply_length)
    return Verdict{FindingKind::kMalformedReply, "reply of " + std::to_string(bytes.size()) + " bytes; the catalog says " +
                                                     std::to_string(*info->reply_length) + " (§" + std::string(info->paragraph) +
                                                     ")" + about};
  const FrameDescription d = describe_frame(bytes);
  if (d.error) return Verdict{FindingKind::kMalformedReply, "reply does not decode: " + d.error->message() + about};
  return std::nullopt;
}

std::optional<Verdict> Oracle::judge(const std::vector<Frame>& accepted, const Observation& seen) const {
  auto verdict = judge_frames(accepted, seen);
  if (!verdict || accepted != last_accepted_) return verdict;  // not the last write's frames
  for (const std::vector<Frame>& other : others_accepted_)
    if (!judge_frames(other, seen)) return std::nullopt;
  return verdict;
}

std::optional<Verdict> Oracle::judge_frames(const std::vector<Frame>& accepted, const Observation& seen) const {
  if (!seen.garbage.empty()) return Verdict{FindingKind::kMalformedReply, "bytes that are no reply frame: " + seen.garbage.front()};
  if (accepted.empty() && !seen.replies.empty())
    return Verdict{FindingKind::kReplyToIgnored, "a frame the device must ignore drew " + summary(seen.replies.front())};
  // More replies than accepted frames: the device answered a frame it must
  // ignore (its reply comes first: one reply at a time on the line).
  if (seen.replies.size() > accepted.size())
    return Verdict{FindingKind::kReplyToIgnored, std::to_string(seen.replies.size()) + " replies to " +
                                                     std::to_string(accepted.size()) + " frame(s) the device must accept; the first: " +
                                                     summary(seen.replies.front())};
  // ERRATA E-16's other side: a code the device does not implement (§3
  // table '*'), of the catalog's length, may draw no reply online; E-23's:
  // nor may 43h/44h without the DVB receiver option. Such a frame is passed
  // over when the next reply is not its own.
  auto side_may_be = [&](std::string_view id, ReadingSide side) {
    const auto pinned = side_pinned(profile_.readings, id);
    return !pinned || *pinned == side;
  };
  auto may_be_silent = [&](const Frame& f) {
    const CommandInfo* info = find_command(f.command);
    if (!info || !profile_.remote_enabled ||
        (info->request_length && f.data.size() + kFrameOverhead != *info->request_length))
      return false;
    if (info->needs_dvb_option) return !profile_.dvb_receiver && side_may_be("E-23", ReadingSide::kOther);
    return !info->implemented && side_may_be("E-16", ReadingSide::kOther) && !device_implements(*info, profile_);
  };
  std::size_t j = 0;  // the next reply
  for (std::size_t i = 0; i < accepted.size(); ++i) {
    const bool silent_ok = may_be_silent(accepted[i]);
    if (j >= seen.replies.size()) {
      if (silent_ok) continue;
      return Verdict{FindingKind::kNoReply, "no reply to " + summary(accepted[i])};
    }
    if (silent_ok && seen.replies[j].command != accepted[i].command) continue;
    if (auto v = judge(accepted[i], seen.replies[j])) return v;
    ++j;
  }
  if (j < seen.replies.size())
    return Verdict{FindingKind::kReplyToIgnored, "a reply that answers none of the frames the device must accept: " +
                                                     summary(seen.replies[j])};
  return std::nullopt;
}

std::size_t expected_reply_bytes(const std::vector<Frame>& accepted) {
  std::size_t n = 0;
  for (const Frame& f : accepted) {
    const CommandInfo* info = find_command(f.command);
    n += info && info->reply_length ? std::max<std::size_t>(*info->reply_length, kOfflineReplyLength) : max_reply_length();
  }
  return n;
}

}  // namespace sabus::harness::live_fuzz
