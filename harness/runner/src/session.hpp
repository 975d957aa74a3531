// The runner's engine for one run (private to harness/runner): the
// transport, the profile and the options; the values the current vector
// captured and its transcript; the device's measured turnaround and the run's
// traffic figures. Runner::run (runner.cpp) drives it phase by phase; the
// step engine is steps.cpp, the line exchange session.cpp, the stored-data
// backup backup.cpp.
#pragma once

#include <chrono>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sabus/harness/runner.hpp"
#include "sabus/harness/timing.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness::detail {

class Session : public ReceiverSink {
 public:
  Session(Transport& transport, const Profile& profile, const RunOptions& options);

  Transport& transport;
  const Profile& profile;
  const RunOptions& options;
  Captures captures;                                // this vector's captured values
  std::vector<TranscriptEntry>* transcript = nullptr;  // where exchanges are recorded; null: nowhere
  std::string expect;  // the expected path of the step being sent (TranscriptEntry::expect)
  bool vector_moves = false;  // the current vector can move the antenna: its polls watch for motion ending
  // A mount that never shows rest (runner.hpp kShortRestPoll): the vector
  // running now; the status fields ("az status") a poll for rest timed out
  // on, in the vector named, until each has shown rest; whether the last
  // poll was a short one that did not see rest (its failure is then an
  // inconclusive's reason).
  std::string vector_id;
  std::set<std::string> rest_not_shown;
  std::string rest_timed_out_in;
  bool rest_unseen = false;
  // The last send's exchange left unjudged by the line (RunOptions::retries):
  // its failure is then an error's reason (Verdict::kError), not the device's.
  bool line_error = false;
  // The last send met a `readings:` alternative with `ends` (the reference
  // side did not hold): the vector's steps end there, passed (runner.cpp).
  bool steps_ended = false;
  // The side of a reading a step of this vector showed (one alternative
  // listed, and only one side held): the rest of the vector is held to it,
  // as a device takes one side of a point (check_sides).
  ReadingPins sides_shown;
  // The side of a reading the device's answers showed for the whole run
  // (ERRATA E-45: the spelling of a negative target it ACKed), and the side
  // known from the profile's pins or from the run.
  ReadingPins run_sides;
  std::optional<ReadingSide> side_known(const std::string& errata) const;
  std::optional<std::string> send_and_judge(const Step& s, const Bytes& wire, std::vector<Frame>& replies_judged);
  bool measuring = false;  // a survey runs: no exchange is repeated, the faults are what it counts
  // Exchanges judged as the device's answer after a repeat (every try
  // silent, or the same bytes twice) that a line could still have made:
  // the vector may run again (runner.cpp).
  std::size_t unsure_repeats = 0;
  LineFaultCounts line;  // the run's exchanges and line faults so far
  TurnaroundMeter turnaround;  // request end on the wire -> first reply byte
  std::size_t bytes_sent = 0, bytes_received = 0;
  std::chrono::microseconds silence_listened{0};
  std::size_t silence_windows = 0;

  // ---- the line (session.cpp) ---------------------------------------------------
  // Sends one frame (in chunks if the modifiers ask) and collects the frames
  // that come back within `window`, stopping early once a frame arrived and
  // the line went quiet. Paces commands (RunOptions::pace). Throws TransportLost.
  std::vector<Frame> exchange(const Bytes& chars, const Modifiers& m, std::chrono::milliseconds window);
  // What a step expects of the device, as far as telling the line's faults
  // from the device's answer goes (due_of in steps.cpp derives it from the
  // step's Expectation).
  struct Due {
    bool reply = true;           // a reply is due: a silence may be a request the line lost
    bool must_not_act = false;   // the device must refuse or ignore the frame (a NAK, the offline reply, silence)
    bool silence = false;        // silence is due: a reply is a fault to try again
    bool ack = false;            // an ACK or the offline reply is due: a NAK is a fault (a NAKed command did nothing)
    bool header_judges = false;  // an ACK is due and the step checks no more than its header (start, address, command)
  };
  // exchange(), repeated after a line fault as RunOptions::retries and the
  // frame's resend rule allow (resend_rule).
  struct Judged {
    std::vector<Frame> replies;
    // The line fault the replies still show ("" when clean): with retries
    // left unused, it is added to a failure's words; with `error` set, the
    // exchange could not be judged.
    std::string fault;
    bool error = false;
    // The reply the line garbled after its header, which showed the device
    // took the frame (accepted_header): `replies` holds that header alone.
    bool header_only = false;
  };
  Judged exchange_judged(const Bytes& chars, const Modifiers& m, std::chrono::milliseconds window, const Due& due);
  bool track_governs();
  // The frames of the last exchange.
  const std::vector<Frame>& last_replies() const { return frames_; }
  // How long to wait for a reply to a command of `request_bytes` bytes, and
  // how long silence must last to count as no reply (timing.hpp).
  std::chrono::milliseconds reply_timeout(std::size_t request_bytes) const;
  std::chrono::milliseconds silence_window() const;
  std::chrono::microseconds stated_turnaround() const;
  // exchange_judged, in rounds until one is not an error (at most three):
  // for the runner's own requests, which no vector runs again.
  Judged exchange_settled(const Bytes& chars);
  // One request outside any vector (liveness, backup): the data of its single
  // ACK reply, or nullopt (NAK, offline reply, silence).
  std::optional<Bytes> ask(const Request& request);
  // A device type query and a status poll (tlsfuzzer's sanity runs).
  LivenessResult liveness(std::string when);
  // An 'X' stop of every axis (§3.4), sent after every vector that can move the antenna.
  void stop_motion();

  // ---- the step engine (steps.cpp) --------------------------------------------
  // Each returns the failure, if any.
  std::optional<std::string> run_step(const Step& s);
  std::optional<std::string> run_send(const Step& s);
  std::optional<std::string> run_poll(const Step& s);
  std::optional<std::string> run_survey(const Step& s);
  // Before a vector's setup, while an axis has not shown rest since its poll
  // for rest timed out (kShortRestPoll): the short poll's failure when the
  // vector needs that axis at rest and it still does not show it; nullopt
  // when the vector is to run.
  std::optional<std::string> rest_still_unseen(const Vector& v);
  // What came back to a send, as its expectation is checked against it.
  struct Reply {
    const std::vector<Frame>& replies;
    const std::optional<std::vector<std::string>>& nak_rules;  // the reference controller's, when it says
    std::uint8_t address = 0, command = 0;                    // the frame the device acted on
    bool header_only = false;                                 // the line garbled the reply after its header (Judged)
  };
  std::optional<std::string> check_reply(const Expectation& e, const Reply& got);
  // check_reply against each side of the open points `e.readings` names.
  std::optional<std::string> check_sides(const Expectation& e, const Reply& got);

  double t_ms() const;
  // Profile expressions of the current vector: the profile, its captures, the pace.
  ExprContext expr_context() const { return {profile, &captures, options.pace}; }

 private:
  void on_frame(const FrameView& f) override { frames_.push_back(f.to_frame()); }
  void on_discard(const Discard& d) override { ignored_.push_back(d.message()); }
  void record(bool sent, const Bytes& bytes, std::string note, std::vector<FieldDescription> fields = {});
  void record(bool sent, const Bytes& bytes, FrameDescription d) {
    record(sent, bytes, std::move(d.summary), std::move(d.fields));
  }
  void pace();
  void send_in_chunks(const Bytes& chars, const Modifiers& m);
  std::optional<std::string> check_matchers(const FrameDescription& d, const std::vector<FieldMatcher>& matchers);
  std::optional<Step> unshown_rest_poll(const Vector& v) const;
  std::chrono::milliseconds poll_timeout(const Step& s, const FrameDescription& first_reply);
  // The line fault the last exchange showed, for a step that expects `due`:
  // what the master's receiver discarded, or no reply where one was due; ""
  // when clean.
  std::string last_fault(const Due& due) const;
  // The ACK header the garbled reply of the last exchange starts with, when
  // it is the device's answer to the frame sent (its address and command),
  // each byte a well-formed character: the device took the frame. nullopt
  // otherwise.
  std::optional<Frame> accepted_header() const;
  // A status poll after a line fault, before a command that changes state is
  // sent again: the device answers cleanly again. False when it does not.
  bool read_back();

  TimePoint start_;
  TimePoint last_send_{};
  std::vector<Frame> frames_;
  std::vector<std::string> ignored_;
  Bytes raw_;  // the bytes of the last exchange's replies, as received
  std::uint8_t last_command_ = 0;  // the code of the frame the device acts on in the last exchange (0: none)
  std::uint8_t last_address_ = 0;  // and its address
};

// The frame of a send that the device acts on, as a device's receiver reads
// the bytes (§1 states 1-5; an STX in the data restarts reception under E-7):
// its address and command, for checking the reply. nullopt when no complete
// frame is in the bytes (a bad LRC, a truncated frame).
// Whether a frame may be sent again after a line fault (catalog Effects): a
// frame that changes nothing (a read, a poll, an unknown code the device
// must NAK) at once; one that moves the antenna or writes stored data and
// leaves the device as one does when sent twice (an absolute move, a stop, a
// write of the same record) after a status poll has read the device back;
// one that acts again (a jog, a LOCATE, a key) never.
enum class Resend : std::uint8_t { kAtOnce, kAfterReadBack, kNever };
Resend resend_rule(ByteView frame);
std::string_view to_string(Resend r);  // why, for the error's words

struct SentFrame {
  std::uint8_t address = 0;
  std::uint8_t command = 0;
};
std::optional<SentFrame> frame_acted_on(ByteView chars, const Profile& profile);

}  // namespace sabus::harness::detail
