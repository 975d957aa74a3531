// The runner's exchanges on the line: pacing (§4), chunked sends, reading
// replies with the master-side receiver, the reply and silence windows
// (timing.hpp), and the requests the runner makes on its own: liveness
// checks, the 'X' stop after motion, the reads of the stored-data backup.
#include <algorithm>
#include <cmath>
#include <utility>
#include <variant>

#include "session.hpp"

namespace sabus::harness::detail {

using namespace std::chrono_literals;
using std::chrono::milliseconds;

Session::Session(Transport& t, const Profile& p, const RunOptions& o)
    : transport(t), profile(p), options(o), start_(t.now()) {}

double Session::t_ms() const { return std::chrono::duration<double, std::milli>(transport.now() - start_).count(); }

void Session::record(bool sent, const Bytes& bytes, std::string note, std::vector<FieldDescription> fields) {
  if (transcript)
    transcript->push_back({t_ms(), sent, bytes, std::move(note), std::move(fields), sent ? expect : std::string()});
}

// The turnaround the device's profile states (turnaround_ms): a slow
// controller's replies are waited for from the first command on, before the
// runner has measured any. Behind a terminal server the network's round trip
// (measured when the line was opened) comes on top of it; the turnaround the
// runner measures later includes it anyway.
std::chrono::microseconds Session::stated_turnaround() const {
  return std::chrono::microseconds(static_cast<std::int64_t>(std::ceil(profile.turnaround_ms * 1000))) +
         transport.network_round_trip();
}

milliseconds Session::reply_timeout(std::size_t request_bytes) const {
  if (transport.in_process()) return 1000ms;  // virtual time: waiting costs nothing
  const auto expected = std::max(turnaround.max(), stated_turnaround());
  const auto allowance = std::max(options.turnaround_allowance, std::chrono::ceil<milliseconds>(3 * expected));
  return harness::reply_timeout(transport.baud(), request_bytes, max_reply_length(), allowance);
}

// READING-NOTES 9 ignore paths: from the device's turnaround, measured or
// stated, whichever is longer.
milliseconds Session::silence_window() const {
  if (transport.in_process()) return 500ms;
  return harness::silence_window(std::max(turnaround.max(), stated_turnaround()), transport.baud(), max_reply_length());
}

void Session::pace() {
  if (options.pace.count() <= 0 || last_send_ == TimePoint{}) return;
  const auto since = transport.now() - last_send_;
  if (since < options.pace) transport.pause(std::chrono::duration_cast<milliseconds>(options.pace - since));
}

void Session::send_in_chunks(const Bytes& chars, const Modifiers& m) {
  std::vector<std::size_t> sizes = m.chunks;
  std::size_t listed = 0;
  for (auto s : sizes) listed += s;
  if (listed < chars.size()) sizes.push_back(chars.size() - listed);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < sizes.size() && offset < chars.size(); ++i) {
    const std::size_t n = std::min(sizes[i], chars.size() - offset);
    std::vector<std::size_t> wrong;
    for (auto p : m.parity_flip)
      if (p >= offset && p < offset + n) wrong.push_back(p - offset);
    transport.send(ByteView(chars).subspan(offset, n), wrong);
    offset += n;
    if (i + 1 < sizes.size() && m.pause.count() > 0) transport.pause(m.pause);
  }
}

std::vector<Frame> Session::exchange(const Bytes& chars, const Modifiers& m, milliseconds window) {
  Transport& t = transport;
  pace();
  frames_.clear();
  raw_.clear();
  const auto acted_on = frame_acted_on(chars, profile);
  last_command_ = acted_on ? acted_on->command : 0;
  last_address_ = acted_on ? acted_on->address : 0;
  ignored_.clear();
  ReceiverOptions rx_options = ReceiverOptions::master();
  rx_options.parity = receiver_parity(t);
  Receiver rx(rx_options);
  send_in_chunks(chars, m);
  last_send_ = t.now();
  bytes_sent += chars.size();
  ++line.exchanges;
  if (transcript) record(true, chars, describe_frame(chars));  // describing a frame costs more than sending it
  const TimePoint sent_at = t.now();
  // send() does not drain: the request leaves the port over its wire time.
  const TimePoint request_end = sent_at + wire_time(chars.size(), t.baud());
  // Once a reply is complete, listen only a few character times for a
  // second one: a device answers a command with one frame (§1).
  const milliseconds quiet =
      std::max<milliseconds>(3ms, std::chrono::duration_cast<milliseconds>(wire_time(3, t.baud())) + 1ms);
  bool first = true;
  std::uint8_t buf[512];
  while (t.now() - sent_at < window) {
    const auto left = std::chrono::duration_cast<milliseconds>(window - (t.now() - sent_at));
    const std::size_t n = t.receive(buf, frames_.empty() ? std::max(left, 1ms) : std::min(left, quiet));
    if (n > 0 && first) {
      first = false;
      if (!t.in_process()) turnaround.record(request_end, t.now());
    }
    bytes_received += n;
    raw_.insert(raw_.end(), buf, buf + n);
    rx.feed(ByteView(buf, n), *this);
    if (n == 0 && !frames_.empty()) break;  // a complete reply and then quiet
  }
  rx.finish(*this);
  if (transcript) {
    for (const auto& f : frames_) {
      const Bytes b = encode_frame(f);
      record(false, b, describe_frame(b));
    }
    for (const auto& s : ignored_) record(false, {}, "ignored " + s);
  }
  return frames_;
}

std::string Session::last_fault(const Due& due) const {
  const std::uint8_t command = last_command_;
  if (!ignored_.empty()) {
    std::string s = ignored_.front();
    if (ignored_.size() > 1) s += " (and " + std::to_string(ignored_.size() - 1) + " more)";
    return s;
  }
  if (due.reply && frames_.empty()) return "no reply";
  // Silence was due: a reply means the device took the frame for another
  // one, which a line that drops or adds a byte makes of a frame it must
  // ignore (an overrun one byte shorter is a frame of a wrong length).
  if (due.silence && !frames_.empty()) return "a reply where silence was due";
  // One frame is answered with one reply (§1); a second is a frame the line
  // made of the bytes of the first (an overrun one byte short is a frame).
  if (due.reply && frames_.size() > 1) return std::to_string(frames_.size()) + " replies to one frame";
  // An ACK (or the offline reply) was due and a NAK came: a request the line
  // shortened by two equal bytes (an XOR check byte does not see them go)
  // is NAKed for its length.
  if (due.ack && frames_.size() == 1 && frames_[0].kind == FrameKind::kNak) return "a NAK where an ACK was due";
  // A reply for another command is a late or stray frame (a request the
  // line cut in two can be answered after the next one went out).
  if (frames_.size() == 1 && command != 0 && frames_[0].command != command && !is_offline_reply(frames_[0]))
    return "a reply for command " + describe_byte(frames_[0].command) + " to " + describe_byte(command);
  // Bytes lost or added in pairs can leave a frame whose check byte still
  // holds (an XOR does not see two equal bytes go): an ACK of another length
  // than the catalog's (§3) was cut short or stretched.
  const CommandInfo* info = find_command(command);
  if (frames_.size() == 1 && frames_[0].kind == FrameKind::kAck && !is_offline_reply(frames_[0]) && info &&
      frames_[0].command == command && info->reply_length &&
      frames_[0].data.size() + kFrameOverhead != *info->reply_length)
    return "a reply of " + std::to_string(frames_[0].data.size() + kFrameOverhead) + " bytes where §" +
           std::string(info->paragraph) + " gives " + std::to_string(*info->reply_length);
  return "";
}

// The device is not known to have taken the frame when a byte of the
// header is not a well-formed character (its parity bit wrong where the
// line carries one, or an 8-bit byte on a 7-bit line) or is not what the
// device sends for this frame: the line may have made it of a NAK's.
std::optional<Frame> Session::accepted_header() const {
  if (raw_.size() < kFrameDataStart || last_command_ == 0) return std::nullopt;
  const Parity parity = receiver_parity(transport);
  std::uint8_t header[kFrameDataStart];
  for (std::size_t i = 0; i < kFrameDataStart; ++i) {
    const std::uint8_t wire = raw_[i];
    if (parity == Parity::kEvenBit7 && !has_even_parity(wire)) return std::nullopt;
    if (parity == Parity::kNone && wire > 0x7F) return std::nullopt;
    header[i] = wire & 0x7F;
  }
  if (header[0] != ACK || header[1] != last_address_ || header[2] != last_command_) return std::nullopt;
  return Frame{FrameKind::kAck, header[1], header[2], {}};
}

bool Session::read_back() {
  const Bytes poll = encode_request(StatusPoll{}, profile.address);
  for (int i = 0; i <= options.retries; ++i) {
    if (i > 0) transport.pause(silence_window());
    const auto replies = exchange(poll, {}, reply_timeout(poll.size()));
    if (last_fault(Due{}).empty() && replies.size() == 1 && replies[0].command == 0x31) return true;
  }
  return false;
}

// One exchange, and after a line fault the same frame again while
// RunOptions::retries and the frame's resend rule allow: after the silence
// window, so the device's receiver has dropped what the fault left of the
// last frame (§1: a bad frame is ignored); after a status poll for a frame
// that changes state. A silence on every try where a reply was due is the
// device's answer, not the line's: it is judged as one (except for a frame
// that is never sent again: its silence may be a request the line lost).
Session::Judged Session::exchange_judged(const Bytes& chars, const Modifiers& m, std::chrono::milliseconds window,
                                         const Due& due) {
  Judged j;
  j.replies = exchange(chars, m, window);
  j.fault = last_fault(due);
  if (j.fault.empty()) return j;
  // A frame the device must refuse or ignore (the step expects a NAK, the
  // offline reply or silence) does nothing on a conforming device, however
  // often it comes: it is sent again like a read. On a device that acts on
  // it the vector fails anyway.
  // A NAK says the command was not executed (§3): sending it again cannot
  // make it act twice.
  const bool naked = j.fault == "a NAK where an ACK was due";
  const Resend rule = due.must_not_act || naked ? Resend::kAtOnce : resend_rule(chars);
  const std::string first_fault = j.fault;
  bool garbled = j.fault != "no reply";  // bytes came back that were not a clean reply
  int tries = 1;
  auto note = [&](const std::string& what) {
    if (transcript) transcript->push_back({t_ms(), false, {}, what, {}, ""});
  };
  const int retries = measuring ? 0 : options.retries;
  // A frame that is never sent again, answered with an ACK the line garbled
  // after its header: a device answers only a frame it took whole (§1: a
  // bad frame is ignored), so the header shows the command was accepted and
  // acted on once. A step that checks no more than the header is judged by
  // it; one that checks the data is left unjudged below.
  if (rule == Resend::kNever && due.header_judges && retries > 0 && garbled) {
    if (auto header = accepted_header()) {
      ++line.faults;
      ++line.recovered;
      note("recovered: the reply's header shows the device took the frame (" + first_fault +
           "); the step checks no more than the header");
      j.replies = {*header};
      j.header_only = true;
      return j;
    }
  }
  for (; tries <= retries && rule != Resend::kNever; ++tries) {
    note("line fault: " + j.fault + "; sending it again (" + std::string(to_string(rule)) + ")");
    transport.pause(silence_window());
    if (rule == Resend::kAfterReadBack && !read_back()) {
      ++line.faults;
      j.error = true;
      j.fault = first_fault + "; the status poll before sending it again got no clean reply either";
      return j;
    }
    ++line.repeats;
    const Bytes before = raw_;
    j.replies = exchange(chars, m, window);
    j.fault = last_fault(due);
    if (j.fault.empty()) {
      ++line.faults;
      ++line.recovered;
      note("recovered: the repeat got a clean reply");
      return j;
    }
    // The same bytes again: a line does not garble twice alike, so the
    // device sent them; its reply is judged as it is.
    if (!raw_.empty() && raw_ == before) {
      ++unsure_repeats;  // a line can drop any one of ten blanks alike: the vector may run again
      note("the repeat got the same bytes: the device's reply, not the line's");
      j.fault += " (the same bytes on a repeat: the device's, not the line's)";
      return j;
    }
    garbled = garbled || j.fault != "no reply";
  }
  // Silence on every try is the device's own answer, unless the frame was
  // not sent again: a request lost on the line leaves the same silence.
  if (!garbled && (rule != Resend::kNever || retries == 0)) {
    if (tries > 1) ++unsure_repeats;  // the vector may run again (runner.cpp): a lost request looks the same
    j.fault.clear();
    return j;
  }
  // A survey counts what it measures apart (LineFaultCounts::surveyed).
  ++(measuring ? line.surveyed : line.faults);
  if (retries == 0) return j;  // judged as it came; the failure names the fault
  j.error = true;
  const bool took_it = rule == Resend::kNever && accepted_header().has_value();
  j.fault = rule == Resend::kNever && tries == 1
                ? first_fault + (took_it ? "; its header shows the device took it, and the step checks the data the line garbled" : "") +
                      "; not sent again: " + std::string(to_string(rule))
                : "no clean reply in " + std::to_string(tries) + " tries: " + j.fault + " (first: " + first_fault + ")";
  return j;
}

// The runner's own requests (liveness, the stop, the backup) belong to no
// vector that could run again: up to kSettleRounds rounds of
// exchange_judged's repeats.
Session::Judged Session::exchange_settled(const Bytes& chars) {
  constexpr std::size_t kSettleRounds = 3;
  Judged j;
  for (std::size_t round = 0; round < kSettleRounds; ++round) {
    j = exchange_judged(chars, {}, reply_timeout(chars.size()), Due{});
    if (!j.error) {
      line.recovered += round;  // the rounds before, each an unrecovered fault
      break;
    }
  }
  return j;
}

std::optional<Bytes> Session::ask(const Request& request) {
  const Bytes cmd = encode_request(request, profile.address);
  const auto replies = exchange_settled(cmd).replies;
  if (replies.size() != 1 || replies[0].kind != FrameKind::kAck || is_offline_reply(replies[0])) return std::nullopt;
  return replies[0].data;
}

LivenessResult Session::liveness(std::string when) {
  LivenessResult l{std::move(when), true, false, ""};
  std::vector<TranscriptEntry> scratch;
  std::vector<TranscriptEntry>* saved = transcript;
  transcript = &scratch;
  const std::size_t received_before = bytes_received;
  for (std::uint8_t code : {std::uint8_t{0x30}, std::uint8_t{0x31}}) {
    const Bytes cmd = encode_frame({FrameKind::kCommand, profile.address, code, {}});
    try {
      const auto replies = exchange_settled(cmd).replies;
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
  transcript = saved;
  l.heard = bytes_received > received_before;
  if (!l.alive && l.heard) l.detail += " (the device sends bytes, but not the reply the spec asks for)";
  return l;
}

// Whether TRACK mode governs the antenna now: §3.2 byte 40 SSSS is not 0000.
// Asked only of a controller that powers up in TRACK (the profile's
// track.active).
bool Session::track_governs() {
  if (!profile.track.active) return false;
  const auto data = ask(StatusPoll{});
  if (!data) return false;
  const auto reply = decode_reply(Frame{FrameKind::kAck, profile.address, 0x31, *data});
  if (!reply || !std::holds_alternative<StatusReply>(reply.value())) return false;
  return (std::get<StatusReply>(reply.value()).status.track & 0x0F) != 0;
}

// The stop after a moving vector (33h 'X'), except while TRACK governs the
// antenna: there the stop would hand control to REMOTE (§3.4) and end the
// TRACK mode the profile says the controller is in, which later TRACK
// vectors rest on; TRACK's own motion is not the vector's to stop.
void Session::stop_motion() {
  try {
    if (track_governs()) return;
  } catch (const TransportLost&) {
    return;
  }
  const Bytes x = encode_request(Jog{{'X', 'S', 0}}, profile.address);
  // The antenna may be moving: a stop the line garbles is sent again (a
  // second 'X' stops what one does) until it is settled.
  try {
    exchange_settled(x);
  } catch (const TransportLost&) {
  }
}

Resend resend_rule(ByteView frame) {
  const CommandInfo* info = frame.size() > 2 ? find_command(frame[2]) : nullptr;
  if (!info) return Resend::kAtOnce;  // no command the device may act on: it NAKs or ignores it
  const FormInfo* form =
      info->form_selector_offset && frame.size() > *info->form_selector_offset ? info->form_for_selector(frame[*info->form_selector_offset]) : nullptr;
  const Effects e = form ? form->effects : info->effects();  // an unknown form: what any form may do
  if (e.acts_again) return Resend::kNever;
  // §3.19 pol selection 'C' (byte 29) needs "a LOCATE function ...
  // immediately prior to the Remote Store" (the scan is garbled there): a
  // second one, after the status poll, no longer follows it.
  constexpr std::size_t kStorePolSelection = 29;
  if (info->code == 0x42 && (frame.size() <= kStorePolSelection || frame[kStorePolSelection] == 'C')) return Resend::kNever;
  if (e.moves_antenna || e.changes_stored_data) return Resend::kAfterReadBack;
  return Resend::kAtOnce;
}

std::string_view to_string(Resend r) {
  switch (r) {
    case Resend::kAtOnce: return "it changes nothing";
    case Resend::kAfterReadBack: return "a second one leaves the device as one does; after a status poll";
    case Resend::kNever: return "a second one would act again";
  }
  return "?";
}

std::optional<SentFrame> frame_acted_on(ByteView chars, const Profile& profile) {
  struct LastFrame : ReceiverSink {
    std::optional<SentFrame> frame;
    void on_frame(const FrameView& f) override { frame = SentFrame{f.address, f.command}; }
    void on_discard(const Discard&) override {}
  } sink;
  // The frames a controller on the line acts on: to the device's address or
  // a bus peer's (§1 State 2: another address sends a slave back to State 1).
  ReceiverOptions options = ReceiverOptions::slave(profile.address);
  for (std::uint8_t peer : profile.bus_peers) options.accept_address(peer);
  options.parity = Parity::kNone;  // 7-bit characters: the line adds the parity bit
  options.stx_restarts_in_data = profile.stx_restarts_in_data;  // E-7
  Receiver rx(options);
  rx.feed(chars, sink);
  rx.finish(sink);
  return sink.frame;
}

}  // namespace sabus::harness::detail
