// The runner's exchanges on the line: pacing (§4), chunked sends, reading
// replies with the master-side receiver, the reply and silence windows
// (timing.hpp), and the requests the runner makes on its own: liveness
// checks, the 'X' stop after motion, the reads of the stored-data backup.
#include <algorithm>
#include <cmath>
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
  ignored_.clear();
  ReceiverOptions rx_options = ReceiverOptions::master();
  rx_options.parity = receiver_parity(t);
  Receiver rx(rx_options);
  send_in_chunks(chars, m);
  last_send_ = t.now();
  bytes_sent += chars.size();
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

std::optional<Bytes> Session::ask(const Request& request) {
  const Bytes cmd = encode_request(request, profile.address);
  const auto replies = exchange(cmd, {}, reply_timeout(cmd.size()));
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
      const auto replies = exchange(cmd, {}, reply_timeout(cmd.size()));
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
  try {
    exchange(x, {}, reply_timeout(x.size()));
  } catch (const TransportLost&) {
  }
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
