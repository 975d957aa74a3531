// Controllers on one line (§1: RS-422 multi-drop): every controller has its
// own receiver; only the addressed one answers.
#include <algorithm>

#include "sabus/harness/controller.hpp"

namespace sabus::harness {

ReceiverOptions receiver_options(const Profile& profile, const FaultSet& faults, Parity parity) {
  // The faults that act on frames for other addresses take every address in.
  const bool any_address = faults.has(Fault::kAnswersForeignAddress) || faults.has(Fault::kNaksForeignFrames);
  ReceiverOptions o = any_address ? ReceiverOptions::slave_any_address() : ReceiverOptions::slave(profile.address);
  o.parity = faults.has(Fault::kIgnoresParity) ? Parity::kUnchecked : parity;
  o.stx_restarts_in_data = profile.stx_restarts_in_data;                      // E-7
  o.check_byte_restarts_on_stx = faults.has(Fault::kCheckByteStxRestarts);
  // E-6: the other side reads a control character in the body as data and
  // NAKs the frame (Controller::execute); E-8: it reads a frame to its ETX,
  // however long (up to the receiver's buffer), and NAKs its length.
  const auto other = [&](std::string_view id) { return side_taken(profile.readings, id) == ReadingSide::kOther; };
  o.reject_control_in_body = !other("E-6");
  if (other("E-8")) o.max_frame_length = Receiver::kBufferSize;
  o.skip_control_in_body = faults.has(Fault::kAcceptsControlInBody);
  o.stx_restarts_in_address = !faults.has(Fault::kNoStxStxRestart);
  return o;
}

struct Bus::Unit : ReceiverSink {
  Unit(const Profile& p, const Clock& clock, FaultSet faults, Parity parity)
      : controller(p, clock, faults),
        options(receiver_options(p, faults, parity)),
        receiver(options),
        keeps_recent(faults.has(Fault::kNakBadCheckByte)) {}
  Controller controller;
  ReceiverOptions options;  // the receiver's, from the controller's readings (E-6, E-8)
  Receiver receiver;
  std::vector<Frame> frames;
  std::vector<Discard> discards;
  // The recent bytes of the stream, to read back a discarded frame (fault
  // nak-bad-check-byte answers one); kept only under that fault.
  bool keeps_recent;
  std::size_t replies = 0;  // replies sent, for fault garbles-replies
  TimePoint last_byte{};    // when the receiver last took bytes (E-67)
  Bytes recent;
  std::uint64_t recent_base = 0;

  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard& d) override { discards.push_back(d); }

  Bytes discarded_bytes(const Discard& d) const {
    if (d.offset < recent_base) return {};
    const std::size_t first = d.offset - recent_base;
    const std::size_t n = std::min<std::size_t>(d.length, recent.size() - first);
    Bytes b(recent.begin() + static_cast<std::ptrdiff_t>(first),
            recent.begin() + static_cast<std::ptrdiff_t>(first + n));
    for (auto& c : b) c &= 0x7F;
    return b;
  }
};

Bus::Bus(std::vector<Profile> profiles, const Clock& clock, FaultSet faults, Parity parity) : parity_(parity) {
  for (const auto& p : profiles) units_.push_back(std::make_unique<Unit>(p, clock, faults, parity));
}

Bus::Bus(const Bus& other)
    : LineDevice(other), parity_(other.parity_), transcript_(other.transcript_), log_(other.log_), nak_rules_(other.nak_rules_),
      on_change_(other.on_change_) {
  for (const auto& u : other.units_) units_.push_back(std::make_unique<Unit>(*u));
}

Bus::~Bus() = default;

Controller& Bus::controller(std::size_t i) { return units_[i]->controller; }

// §1 Data Format, E-1: 7E1, even parity in bit 7. A master set to 8N1
// sends about half its bytes with the wrong bit 7, one set to 7O1 all of
// them; both show as parity errors. When more than half the bytes of a
// stretch of the line fail, the transcript says once what to check.
void Bus::watch_parity(ByteView wire) {
  constexpr std::size_t kWindow = 32;  // bytes: a few commands
  if (!transcript_ || parity_ != Parity::kEvenBit7 || parity_hint_given_) return;
  for (std::uint8_t b : wire) {
    ++window_bytes_;
    if (!has_even_parity(b)) ++window_bad_;
    if (window_bytes_ < kWindow) continue;
    if (window_bad_ * 2 > window_bytes_) {
      log_ += "hint: " + std::to_string(window_bad_) + " of the last " + std::to_string(window_bytes_) +
              " bytes failed the parity check (even parity in bit 7, §1 Data Format): is the master set to 7E1?\n";
      parity_hint_given_ = true;
      return;
    }
    window_bytes_ = window_bad_ = 0;
  }
}

// ERRATA E-67's other side: a frame whose next byte comes later than the
// controller's inter-character timeout after the one before is dropped
// (reported as incomplete) and the receiver is back in State 1 for the next
// STX. The bytes of one receive() come at one instant.
void Bus::time_out_frame(Unit& u, ByteView wire) {
  if (wire.empty()) return;
  const TimePoint now = u.controller.now();
  const auto limit = u.controller.inter_character_timeout();
  if (limit && u.receiver.state() != ReceiverState::kSlaveIdle && now - u.last_byte > *limit) {
    if (transcript_) log_ += "inter-character timeout (ERRATA E-67): the frame begun is dropped\n";
    u.receiver.finish(u);
  }
  u.last_byte = now;
}

void Bus::receive(ByteView wire, Bytes& out) {
  constexpr std::size_t kRecent = 512;
  for (auto& u : units_) {
    time_out_frame(*u, wire);
    if (u->keeps_recent) u->recent.insert(u->recent.end(), wire.begin(), wire.end());
    // A reading taken late (Controller::set_reading, the live fuzzer's
    // lockstep) from the next byte on.
    if (ReceiverOptions now = receiver_options(u->controller.profile(), u->controller.faults(), parity_); !(now == u->options)) {
      u->receiver.reconfigure(now);
      u->options = now;
    }
    u->receiver.feed(wire, *u);
    for (const Discard& d : u->discards) {
      if (transcript_) log_ += "ignored " + d.message() + "\n";
      if (d.reason == DiscardReason::kBadLrc && u->controller.faults().has(Fault::kNakBadCheckByte)) {
        const Bytes b = u->discarded_bytes(d);
        if (b.size() >= 3 && b[1] == u->controller.profile().address) {
          Bytes nak = encode_frame(nak_reply(b[1], b[2]));
          append_to_line(out, nak);
          if (transcript_) log_ += "reply " + to_hex(nak) + " (NAK for a bad check byte)\n";
        }
      }
    }
    u->discards.clear();
    for (const Frame& f : u->frames) {
      const bool foreign = f.address != u->controller.profile().address;
      if (foreign && !u->controller.faults().has(Fault::kAnswersForeignAddress)) {
        // Fault naks-foreign-frames: §1 "A remote station only sends a
        // response following a command containing its unique address", but
        // this one NAKs a frame for another address that it would NAK for its
        // own (unknown code, wrong length, bad data), executing nothing: the
        // NAK is decided on a copy.
        Controller probe = u->controller;
        Frame own = f;
        own.address = probe.profile().address;
        if (probe.execute(own).nak) {
          Bytes nak = encode_frame(nak_reply(f.address, f.command));
          append_to_line(out, nak);
          if (transcript_) log_ += "reply " + to_hex(nak) + " (NAK for a frame to another address)\n";
        }
        continue;
      }
      if (transcript_) {
        const Bytes in = encode_frame(f);
        log_ += "command " + to_hex(in) + "  " + describe_frame(in).summary + "\n";
      }
      Outcome o = u->controller.execute(f);
      if (o.nak && nak_rules_.size() < 64) nak_rules_.push_back(*o.nak);
      if (o.reply) {
        // Fault garbles-replies: every third reply leaves with a wrong check
        // byte, every byte's parity right: the controller's own garbling, which
        // a line survey (§4 "a garbled status reply") tells from the line's.
        if (u->controller.faults().has(Fault::kGarblesReplies) && ++u->replies % 3 == 0 && !o.reply->empty())
          o.reply->back() ^= 0x01;
        append_to_line(out, *o.reply);
        if (transcript_) log_ += "reply " + to_hex(*o.reply) + "  " + o.note + "\n";
      } else {
        if (transcript_) log_ += "no reply: " + o.note + "\n";
      }
      if (o.stored_data_changed && on_change_) on_change_(u->controller);
    }
    u->frames.clear();
    trim_log();
    if (u->recent.size() > 2 * kRecent) {
      const std::size_t drop = u->recent.size() - kRecent;
      u->recent.erase(u->recent.begin(), u->recent.begin() + static_cast<std::ptrdiff_t>(drop));
      u->recent_base += drop;
    }
  }
  watch_parity(wire);  // after the runs it ignored: the hint follows them in the transcript
}

void Bus::trim_log() {
  // Nobody may ever take the log (an in-process run keeps its own
  // transcript): keep the newest part only.
  constexpr std::size_t kMaxLog = 1 << 16;
  if (log_.size() > kMaxLog) log_.erase(0, log_.find('\n', log_.size() - kMaxLog / 2) + 1);
}

void Bus::tick() {
  for (auto& u : units_) u->controller.update();
}

std::vector<std::string> Bus::take_nak_rules() {
  std::vector<std::string> r;
  r.reserve(nak_rules_.size());
  for (NakRule rule : nak_rules_) r.emplace_back(name(rule));
  nak_rules_.clear();
  return r;
}

void Bus::append_to_line(Bytes& out, ByteView reply) const {
  if (parity_ == Parity::kNone) {
    out.insert(out.end(), reply.begin(), reply.end());
    return;
  }
  for (std::uint8_t c : reply) out.push_back(with_even_parity(c));  // §1 Data Format: 7E1
}

std::string Bus::take_log() {
  std::string s;
  s.swap(log_);
  return s;
}

}  // namespace sabus::harness
