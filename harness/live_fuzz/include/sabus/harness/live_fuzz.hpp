// The live fuzzer (`sabus fuzz`): generates and damages command frames from
// the catalog, sends them to a device through a Transport, judges every
// answer against the spec's rules (§1 ignore paths, §3 NAK and offline
// replies, the catalog's reply lengths) and against a reference controller
// kept in step with it (NAK rules, values, effects: issue 24), probes
// liveness, minimizes each finding by delta debugging and writes it as a
// conformance vector.
//
// Small parts, each with its own tests:
//   - is_safe_to_send: the bench-safety gate (READING-NOTES 26, E-26);
//   - Generator: frames from the catalog, damage to them, fields at the
//     rules' edges, write/read-back and motion/stop sequences;
//   - Oracle: which replies a frame may draw, from a reference §1 receiver;
//   - Lockstep: what the reference controller answers the same writes;
//   - ddmin: delta debugging over a sequence;
//   - Session: one device, the exchange loop, findings;
//   - finding_vector_yaml: a finding as a vector `sabus run` replays.
#pragma once

#include <chrono>
#include <deque>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/transport.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness::live_fuzz {

// One write to the line: 7-bit characters, the indexes sent with the wrong
// parity bit (READING-NOTES 1), and what the generator did, for reports.
struct FuzzFrame {
  Bytes chars;
  std::vector<std::size_t> wrong_parity;
  std::string what;
  // Waited before the write goes out (a move given time to run before it
  // is polled or stopped); a replay and the finding's vector wait as long.
  std::chrono::milliseconds pause{0};
  bool operator==(const FuzzFrame&) const = default;
};

// ---- safety -------------------------------------------------------------------

// Whether `chars` can be put on a bench line: no frame in it (any start byte
// followed by an address byte, as the vector lint reads frames) carries a
// command that moves the antenna or changes stored data per the catalog,
// unless allowed. The form selector decides when it is present (36h 'R' is
// safe); otherwise the command's effects in any form. `before`: the last
// bytes of the previous write, so a frame split across writes is seen.
bool is_safe_to_send(ByteView chars, bool allow_motion, bool allow_destructive, ByteView before = {},
                     std::string* why = nullptr);

// The azimuth, elevation or polarization member (axis 0, 1, 2) of a
// controller's state or of a profile.
template <typename T>
auto& by_axis(T& s, std::size_t axis) {
  return axis == 0 ? s.az : axis == 1 ? s.el : s.pol;
}

// Whether every axis of the controller is at rest.
bool all_at_rest(const Controller& c);

// Whether a §3.17 mode moves the antenna by itself, in an order and for a
// time the spec leaves to the controller: STOW, DEPLOY and the spiral search
// (ERRATA E-89, E-90).
bool moves_by_itself(std::uint8_t mode);

// The liveness probe: a device type query (§3.1), which every SAbus slave
// answers (§1 Command Restrictions).
FuzzFrame liveness_probe(std::uint8_t address);

// ---- generator ----------------------------------------------------------------

struct GeneratorOptions {
  std::uint8_t address = '2';
  bool allow_motion = false;
  bool allow_destructive = false;
  bool parity_errors = true;  // the transport can send a wrong parity bit
  // Satellite names the device holds (the profile's STORE list and presets):
  // a name field takes one of them, blanks or a name no list holds.
  std::vector<std::string> names = {};
  // Other controllers on the line (Profile::bus_peers): a frame for one of
  // them draws its reply, so a "foreign" address is none of them.
  std::vector<std::uint8_t> peers = {};
  // The device's profile: arrival sequences draw targets inside its ranges
  // and the forms it has (none: no arrival sequences).
  const Profile* profile = nullptr;
};

// The mutation kinds, one table: id, name (in reports and vector comments).
#define SABUS_LIVE_FUZZ_MUTATIONS(X)                                    \
  X(kValid, "valid")                                                    \
  X(kFieldValue, "boundary or out-of-range field value")                \
  X(kExtraData, "extra data bytes")                                     \
  X(kMissingData, "missing data bytes")                                 \
  X(kTruncated, "truncated")                                            \
  X(kBadLrc, "bad LRC")                                                 \
  X(kParityFlip, "parity flip")                                         \
  X(kForeignAddress, "foreign address")                                 \
  X(kInvalidAddress, "invalid address")                                 \
  X(kControlInBody, "control character in the body")                    \
  X(kUnknownCommand, "unknown command code")                            \
  X(kJunkPrefix, "junk before the frame")                               \
  X(kStxRestart, "STX restart inside a frame")                          \
  X(kBurst, "burst of frames")                                          \
  X(kBoundary, "field at or just past a rule's boundary")               \
  X(kSequence, "sequence")

enum class Mutation : std::uint8_t {
#define SABUS_X(id, name) id,
  SABUS_LIVE_FUZZ_MUTATIONS(SABUS_X)
#undef SABUS_X
  kCount
};
std::string_view to_string(Mutation m);

// Frames from the catalog (every command the options allow, each form), as
// the structured builder makes them with its default fields.
std::vector<Bytes> base_frames(const GeneratorOptions& options);

class Generator {
 public:
  Generator(GeneratorOptions options, std::uint64_t seed);
  // The next write. Always passes is_safe_to_send for the options.
  FuzzFrame next();
  // One mutation of a random base frame (for tests). kSequence queues the
  // writes after the first for the next calls of next().
  FuzzFrame make(Mutation m);
  // The NAK rules the device has fired so far (LockstepCoverage): boundary
  // values go more often to the commands of the rules not yet fired.
  void set_rules_fired(const std::set<std::string>* fired) { fired_ = fired; }
  // The model the lockstep oracle keeps (Lockstep::model): an arrival
  // sequence aims within reach of where it stands and lasts while it moves.
  struct ModelView {
    const Controller* controller;
    TimePoint now;  // the model's clock
    // The device leads an episode (a STOW, DEPLOY, search or LOCATE,
    // Lockstep::device_led): an arrival lasts until the device's extended
    // status shows it at rest too.
    bool device_led = false;
  };
  void set_model(std::function<ModelView()> model) { model_ = std::move(model); }

 private:
  // A move to a target the model can reach in a few seconds (at a range
  // edge now and then, negative now and then), by one of the forms the
  // profile has; then, while the model moves, writes that cannot move
  // anything with a status poll every tenth, and once it rests its status,
  // extended status and, at a limit, a jog further into it (§3.4). nullopt
  // when no model or profile is set.
  std::optional<FuzzFrame> arrival();
  // A sequence (Mutation::kSequence): an arrival, a stored write and the
  // read that shows it, a read of a stored list at any of its indexes, or a
  // motion, its stop and the status after it.
  FuzzFrame sequence();
  FuzzFrame stored_sequence();
  FuzzFrame stored_read();
  FuzzFrame motion_sequence();
  std::vector<const Bytes*> bases_where(const std::function<bool(const Bytes&)>& keep) const;
  Bytes command(std::uint8_t code, std::string_view data = {}) const;  // a well-formed command frame to the device
  std::size_t uniform(std::size_t lo, std::size_t hi);                 // drawn from rng_
  // What a legal move aims at: a form ('L' a LOCATE; 0 any the profile
  // has), an axis sent to a limit, negative targets; otherwise drawn. Where
  // the limit or the negatives are out of reach, a step toward them
  // (aim_met_ false).
  struct Aim {
    char form = 0;
    int limit_axis = -1;
    bool negative = false;
    bool auto_move_only = false;  // a 32h form, no LOCATE
  };
  // The move an arrival sequence starts with (and a motion sequence's
  // legal move or LOCATE): `limits` says which axes it aims at a limit
  // (+1, -1) or not.
  std::optional<Bytes> legal_move(std::array<int, 3>* limits, Aim aim);
  // What each arrival aimed at and each motion sequence ran and stopped
  // with, so far: the next one goes to the least covered, as boundary
  // values go to the rules not yet fired. A motion counts in full where the
  // model was moving when its stop went out, a third otherwise (a STOW at
  // the stow position stops nothing).
  static constexpr std::size_t kArrivalGoals = 6, kMotionKinds = 7, kStopKinds = 3;
  std::array<double, kArrivalGoals> arrivals_aimed_{};
  bool aim_met_ = true;  // the last legal_move reached what its Aim asked
  std::array<std::array<double, kStopKinds>, kMotionKinds> motions_stopped_{};
  std::optional<std::pair<std::size_t, std::size_t>> stop_pending_;  // the motion and stop of the queued stop
  // The least covered of `scores`' entries `available` allows (three times
  // in four; any available one otherwise), ties drawn at random.
  template <typename Scores, typename Available>
  std::size_t least_covered(const Scores& scores, Available available);
  // The next write while an arrival sequence waits for the model to rest.
  std::optional<FuzzFrame> while_arriving();
  std::function<ModelView()> model_;
  bool arriving_ = false;
  std::size_t motions_since_arrival_ = SIZE_MAX;  // motion sequences since the last arrival (none yet: one first)
  TimePoint arrival_start_{};
  std::optional<TimePoint> at_rest_since_;  // the model's axes all at rest since then
  std::size_t writes_since_poll_ = 0;
  std::optional<TimePoint> session_start_;  // the model's clock at the first write
  std::deque<FuzzFrame> after_arrival_;
  Bytes pick_base();
  // A well-framed base frame with one data field set to a value at or just
  // past the edge of what its rules take (§3: index 0, 1, 20, 21; a choice
  // set and one outside it; signs, blanks, hundredths).
  Bytes boundary(Bytes frame);
  Bytes pick_boundary_base();
  std::deque<FuzzFrame> queued_;
  Bytes tail_;  // the last bytes of the last write returned
  const std::set<std::string>* fired_ = nullptr;
  std::uint8_t pick(std::initializer_list<std::uint8_t> bytes);
  GeneratorOptions options_;
  std::vector<Bytes> bases_;
  std::mt19937_64 rng_;
};

// ---- oracle -------------------------------------------------------------------

// What the device answered one write with, as the master-side receiver read it.
struct Observation {
  std::vector<Frame> replies;
  std::vector<std::string> garbage;  // discarded runs: bytes that are no reply frame
  std::optional<std::chrono::microseconds> first_byte_after;  // request end -> first reply byte
};

// The finding kinds, one table: id, name, the spec paragraph of the rule it
// breaks and a verbatim quote of it (for the vector a finding is written as).
#define SABUS_LIVE_FUZZ_FINDINGS(X)                                                                                  \
  X(kReplyToIgnored, "reply-to-ignored-frame", "1",                                                                  \
    "A remote device ignores all commands that contain parity or checksum errors, protocol errors, a wrong address, " \
    "or message overrun errors.")                                                                                    \
  X(kNoReply, "no-reply", "1",                                                                                       \
    "A slave will send an appropriate response message to a master-controller after receiving the last character "  \
    "of the message.")                                                                                               \
  X(kWrongReply, "wrong-reply", "3",                                                                                 \
    "If an unrecognized command arrives (one whose command code is either unknown or whose length is not compatible " \
    "with the given command code, but which has the correct address and checksum), a NAK reply is sent to the host.") \
  X(kWrongAddress, "reply-from-wrong-address", "1",                                                                  \
    "carries out the requested commands, and then replies with a response message containing its own address")      \
  X(kMalformedReply, "malformed-reply", "1",                                                                         \
    "Response messages are identical to command messages in format (but not content)")                              \
  X(kLateReply, "late-reply", "1",                                                                                   \
    "A slave will send an appropriate response message to a master-controller after receiving the last character "  \
    "of the message.")                                                                                               \
  X(kDead, "device-dead", "1",                                                                                       \
    "A slave will send an appropriate response message to a master-controller after receiving the last character "  \
    "of the message.")                                                                                               \
  X(kReset, "device-reset", "3.1",                                                                                   \
    "The SA Bus specification requires that command character 30h must trigger the return of the six character "    \
    "device type string.")                                                                                          \
  X(kNakRule, "nak-rule", "1",                                                                                       \
    "A remote device replies with a not-acknowledged (NAK) character, 15 hex, if it receives an invalid command or " \
    "data.")                                                                                                         \
  X(kValue, "value", "1",                                                                                            \
    "replies with a response message containing its own address and status information relating to its present "   \
    "condition")                                                                                                     \
  X(kEffect, "effect", "1",                                                                                          \
    "The user should query the controller later to see if the command was actually carried out, or is still in "    \
    "progress.")

enum class FindingKind : std::uint8_t {
#define SABUS_X(id, name, paragraph, quote) id,
  SABUS_LIVE_FUZZ_FINDINGS(SABUS_X)
#undef SABUS_X
};
std::string_view to_string(FindingKind k);
std::string_view paragraph_of(FindingKind k);
std::string_view quote_of(FindingKind k);

struct Verdict {
  FindingKind kind;
  std::string message;
  std::string field = {};  // the reply field that differs (value, effect), as describe_frame names it
};

// The spec's answer rules for one device profile. It keeps a reference §1
// receiver (the project's readings, no faults) fed with everything sent, so a
// frame cut short in one write and completed in the next is read as the
// device must read it.
class Oracle {
 public:
  explicit Oracle(const Profile& profile);
  // The frames the device must accept from this write (§1 State 5), in order.
  std::vector<Frame> accept(const FuzzFrame& frame);
  // Why `reply` is not an acceptable answer to `request` (an accepted
  // frame), or nullopt: the catalog's reply (ACK, its length, every field
  // decoding), a NAK (§3), or the offline reply with remote control disabled.
  std::optional<Verdict> judge(const Frame& request, const Frame& reply) const;
  // Judges a whole write: one acceptable reply per accepted frame, in order;
  // silence for a write with none; no garbage. The receiver-level readings
  // the profile leaves open (ERRATA E-6, E-8) accept more frames on their
  // other side: where `accepted` is what accept() returned for the last
  // write, replies to the frames a combination of sides accepted from it
  // pass as well.
  std::optional<Verdict> judge(const std::vector<Frame>& accepted, const Observation& seen) const;
  // judge() of the write accept() last took. Where that write went on with a
  // frame an earlier write began, a device with an inter-character timeout
  // (ERRATA E-67's other side; the pause between two writes is longer) has
  // dropped that frame: unless the profile pins E-67's reference side, the
  // replies of a receiver that dropped it are acceptable too, and the
  // oracle's receiver then goes on as the device's.
  std::optional<Verdict> judge_write(const std::vector<Frame>& accepted, const Observation& seen);
  void reset();

 private:
  struct Sink;
  std::optional<Verdict> judge_frames(const std::vector<Frame>& accepted, const Observation& seen) const;
  Profile profile_;
  Receiver receiver_;
  // One receiver per other combination of the open receiver-level readings;
  // what the reference receiver accepted from the last write, and what each
  // other one accepted where that differs.
  std::vector<Receiver> others_;
  std::vector<Frame> last_accepted_;
  std::vector<std::vector<Frame>> others_accepted_;
  // The write's frames for a receiver that dropped the frame begun before
  // it (E-67), and that receiver; nullopt when none was begun.
  std::optional<Receiver> dropped_;
  std::vector<Frame> dropped_frames_;
};

// The longest reply `accepted` can draw (catalog lengths; the longest reply of
// the catalog when a length is unknown), for reply windows.
std::size_t expected_reply_bytes(const std::vector<Frame>& accepted);

// ---- lockstep -----------------------------------------------------------------

// What the lockstep oracle has seen in a session, for the summary.
struct LockstepCoverage {
  std::set<std::string> rules_fired;      // NAK rules the device NAKed by (as the model names them)
  std::set<std::string> fields_compared;  // "31h azimuth": reply fields compared with the model
  std::size_t resyncs = 0;                // positions taken from the device within the drift window
};

// How many reply fields the lockstep oracle can compare: every field of the
// field classes' table but the device's (field_classes.hpp), counted once
// for each command whose reply has it.
std::size_t comparable_reply_fields();

// The lockstep oracle: a reference controller (the project's Bus, this
// profile, no faults) on its own virtual clock, fed every write the session
// sends (the same characters and wrong-parity marks, through the controller's
// own §1 receiver) at the time it was sent, its replies compared with the
// device's (issue 24):
//   - ACK vs NAK: the model's NAK names its rule (nak-rule);
//   - each reply field by its class (field_classes.hpp): fixed, echo,
//     profile, stored and state fields exactly; motion fields within a window
//     while an axis moves or has drifted; device fields never (value or effect,
//     see classify()).
// Time on a line is known only to within the exchange's latency: the model
// is also run `uncertainty` earlier and later (copies of the bus), and a
// device reply is accepted when it is one the model gives somewhere in that
// span; the copy that matched is kept, so the model stays in step.
struct ReplyField;  // a reply field's name and text, as describe_frame shows it

class Lockstep {
 public:
  Lockstep(const Profile& profile, TimePoint start);
  Lockstep(const Lockstep&) = delete;
  ~Lockstep();
  Lockstep& operator=(const Lockstep&) = delete;
  // One write sent at `sent_at` (the device's clock), and the replies the
  // device gave to it, in order. `uncertainty`: how far the device's
  // execution time can be from `sent_at` (0 in-process).
  std::optional<Verdict> step(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                              const std::vector<Frame>& device);
  // Back to the profile's state (after the device was restored, or before a replay).
  void rebuild(TimePoint now);
  // One write the model executes without judging the replies, then takes
  // from them what a controller's state may hold that the profile does not
  // say: the position of each axis at rest (a status block, to its tenths)
  // and the §3.17 mode bytes (a 40h reply). At the session's start and after
  // a finding (Session::synchronize). Returns what it took ("" for nothing:
  // the device was where the model was).
  std::string adopt(const FuzzFrame& frame, TimePoint sent_at, const std::vector<Frame>& device);
  const LockstepCoverage& coverage() const { return coverage_; }
  // A difference from the model that the other side of an open point of
  // the spec explains (readings.hpp, ERRATA entries of class reading): a
  // legal controller's, so a note, never a finding. The model takes that
  // side for the rest of the session (the device has shown which it
  // takes); a point the profile pins is never taken over.
  struct ReadingNote {
    std::string errata;   // "E-91", or "E-95+E-96" when only both together explain it
    ReadingSide side;     // the side the device showed
    std::size_t count = 0;
    std::string example;  // what the model would have reported, the first time
  };
  const std::vector<ReadingNote>& notes() const { return notes_; }
  // The model (for tests, and for the generator's arrival sequences).
  Controller& model();
  const Controller& model() const;
  // The model's clock: when it executed the last write.
  TimePoint now() const { return last_; }
  // Whether the device leads the motion now (an episode not over yet).
  bool device_led() const { return device_led_; }

  // The spread a position may have on this axis for `uncertainty` of timing
  // (fast speed both ways), the axis's arrival tolerance and the display's
  // 0.1 deg: within it a device at rest is resynchronized, not reported.
  static double drift_window(const AxisProfile& axis, Duration uncertainty);

 private:
  struct Run;
  // The model's replies to `frame` at `at`: on the model itself (in_place)
  // or on a copy of `from`.
  Run run(const Bus& from, TimePoint at, const FuzzFrame& frame, bool in_place = false);
  // Whether a controller fresh from the profile answers `field` of the
  // `reply`-th reply to `frame` otherwise than the model, and as the device.
  bool kept_as_before(const FuzzFrame& frame, std::size_t reply, std::string_view field, std::size_t occurrence,
                      const std::string& model_value, const std::string& device_value);
  // Where the frames of a write end within it (a reference §1 receiver fed
  // every write): the model executes them one after the other.
  std::vector<std::size_t> frame_cuts(const FuzzFrame& frame);
  // A §3.16 count field's text as degrees (count_offset and counts_per_degree
  // of the profile); nullopt when it is no count.
  std::optional<double> count_degrees(std::string_view raw) const;
  // One write's judgement against the model as it is (step tries it again
  // with a reading flipped when it ends in a finding).
  std::optional<Verdict> judge_write(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                                     const std::vector<Frame>& device);
  // The axes (0 az, 1 el, 2 pol) a jog of this write moves whose position
  // the model has lost, each with the limit in the jog's direction: where
  // the device NAKed a jog, that limit may be why (§3.4; step).
  std::vector<std::pair<std::size_t, double>> jogs_on_lost_axes(const Receiver& splitter, const FuzzFrame& frame,
                                                                const std::vector<Frame>& device) const;
  // What judge_write changes, kept to judge a write again.
  struct Memory;
  // step's judgement of a write: one that ends in a finding is tried again
  // with readings flipped, an axis at a limit, a point decided late.
  std::optional<Verdict> judge_step(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                                    const std::vector<Frame>& device, const Receiver& split_before, const Memory& before);
  // Points whose side the model took where the device did not show it: the
  // mode bytes, seen only in a 40h, after a LOCATE that completed (E-93),
  // after any command the device took (E-52, which commands enter REMOTE),
  // after a Stop key sent remotely (E-88: whether it leaves REMOTE) and
  // after a LOCATE, STOW or DEPLOY was left before it ended (E-82, E-89:
  // which exit status).
  // The model before the first such write since the last 40h that showed
  // them, and the writes since with the sides each was judged on; a later
  // write that ends in a finding is judged again from there with each point
  // on each of its other sides (with one more open point flipped in that
  // write), a note where one explains it.
  struct Undecided;
  std::unique_ptr<Undecided> undecided_;
  void keep_undecided(Memory before, const Receiver& split_before, const FuzzFrame& frame, TimePoint sent_at,
                      Duration uncertainty, const std::vector<Frame>& device);
  bool undecided_explains(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                          const std::vector<Frame>& device, const Receiver& split_before, const Verdict& finding);
  Memory remember() const;
  void recall(const Memory& m);
  // The reading points the model may still take the other side of: those
  // the profile leaves open.
  std::vector<std::string> open_readings() const;
  // The open points the device has not shown a side of yet (the model, on
  // `taken`, still on the profile's), each on its first other side, those
  // `keep` keeps: flipped together where a reply shows many at once.
  std::vector<std::pair<std::string, ReadingSide>> unshown_flips(
      const ReadingPins& taken, const std::function<bool(const std::string&, ReadingSide)>& keep) const;
  void note_reading(std::vector<std::string> ids, const Verdict& explained);
  std::vector<ReadingNote> notes_;
  // One write's judgement, rule by rule (step).
  struct Judging;
  struct AckJudging;
  // The model's runs of a write: the nominal one on the model itself, and on
  // a line copies run earlier, later and with axes nudged (kNudgesDeg).
  std::vector<Run> runs_of(const FuzzFrame& frame, TimePoint at, Duration uncertainty);
  // A move ending within the drift window (the mode bytes settle), an
  // azimuth move to the half turn.
  void note_settling(const Controller& nominal, const Judging& j);
  // A STOW, DEPLOY, search or LOCATE in the model or the device (E-89,
  // E-90, E-94), `before` the model's mode before the write: whether the
  // model has stopped out of one.
  bool follow_device_led(const Controller& nominal, const ModeState& before, bool modes_entered,
                         const std::vector<Frame>& device);
  // Whether the device leads the model's current episode (`ms` a STOW,
  // DEPLOY or search, a LOCATE that runs while E-94 is open, or a TRACK
  // that peaks or searches while E-100 is not pinned to the reference side),
  // or would lead one in `mode`.
  bool locate_led() const;
  bool track_led(const ModeState& ms) const;
  // The enumeration lists the profile reads (E-28), for exit names.
  enums::EnumReading profile_reading() const;
  // Whether a last mode and its exit are a LOCATE that completed.
  bool left_completed_locate(std::uint8_t last_mode, std::uint8_t exit_status) const;
  bool device_leads(const ModeState& ms) const;
  bool device_leads_mode(std::uint8_t mode) const;
  bool locate_ended_alike(const AckJudging& r) const;
  std::optional<std::string> judge_locate_end(const AckJudging& r, const ReplyField& f) const;
  bool mode_outside_locate(const AckJudging& r, const ReplyField& f) const;
  bool y_outside_track(const AckJudging& r, const ReplyField& f, const std::vector<const std::string*>& values) const;
  bool track_submode_shown(const AckJudging& r, const ReplyField& f, const std::vector<const std::string*>& values) const;
  bool no_hundredths(const ReplyField& f, const std::vector<const std::string*>& values) const;
  bool lower_case_while_moving(const AckJudging& r, const ReplyField& f,
                               const std::vector<const std::string*>& values) const;
  // The i-th reply, and an ACK's fields: false once judging stops (a finding).
  bool judge_reply(Judging& j, std::size_t i);
  bool judge_field(Judging& j, AckJudging& r, const ReplyField& f, std::size_t occurrence);
  // nullopt: the rule does not apply; "": it holds; otherwise the finding.
  std::optional<std::string> judge_arrival_hundredths(const AckJudging& r, const ReplyField& f) const;
  bool held_by_a_command(const AckJudging& r, const ReplyField& f) const;
  void note_limits_shown(Judging& j, const std::vector<Frame>& device) const;
  std::optional<std::string> judge_stop_exit(const Judging& j, const AckJudging& r, const ReplyField& f) const;
  bool position_in_window(const Judging& j, const AckJudging& r, const ReplyField& f, std::size_t axis) const;
  // Motion or limit bits the timing of a line leaves open.
  bool motion_bits_unjudged(const Judging& j, const AckJudging& r, const ReplyField& f, std::size_t axis) const;
  // After a write without finding: positions and mode bytes taken from the
  // device where the spec allows it to differ.
  void keep_in_step(const std::vector<Frame>& device, Duration uncertainty);
  const AxisProfile& axis_profile(std::size_t axis) const;
  // The device's reading of each axis both show at rest, where `take(axis,
  // distance)` agrees: the model's axis moved to it (drifted).
  void take_positions(const std::vector<Frame>& device, const std::function<bool(std::size_t, double)>& take);
  Profile profile_;
  std::unique_ptr<Receiver> splitter_;
  std::vector<std::size_t> cuts_;  // of the write being judged
  Duration spacing_{0};            // between its frames
  std::unique_ptr<VirtualClock> clock_;
  std::unique_ptr<Bus> bus_;
  // A controller fresh from the profile that no write reaches: what a field
  // reads when no command of the session has changed it (classify an effect).
  VirtualClock pristine_clock_;
  std::unique_ptr<Bus> pristine_;
  TimePoint last_{};
  std::array<bool, 3> drifted_{};     // az, el, pol resynchronized: hundredths and counts not compared
  std::array<bool, 3> moved_on_line_{};  // moved with a timing uncertainty: likewise
  // At a limit by the device's own word (its status at rest asserts it,
  // §3.2 bytes 32-34, or it NAKed a jog into it, §3.4), until the next status
  // block or a command the device takes that moves the antenna: in a write
  // of one frame every run has the axis exactly there (not nudged), so its
  // limit bits and a jog into it are judged on a line too.
  std::array<bool, 3> at_limit_agreed_{};
  // The widest timing uncertainty of the writes since the model and the
  // device were last both at rest: a motion's position carries the error of
  // the write that started it as well as the one that reads it.
  Duration uncertainty_since_rest_{0};
  // Whether the model's axis runs a §3.3 auto move, and the target of the
  // one it has arrived at and rests on: its hundredths are then judged on a
  // line too (ERRATA E-86: within the arrival window of the target).
  std::array<bool, 3> auto_moving_{};
  std::array<std::optional<double>, 3> arrived_at_{};
  std::array<double, 3> arrived_position_{};  // the model's position then: judged only while it stands there
  void note_arrivals();
  TimePoint settle_until_{};             // mode bytes taken from the device until then
  ModeState settle_mode_{};              // the model's while that move still ran
  // A STOW, DEPLOY, search or (E-94 open) moving LOCATE in the model or the
  // device: motion and mode bytes are the device's until both are at rest
  // out of it (E-89, E-90, E-94).
  bool device_led_ = false;
  bool stopped_out_ = false;          // the model stopped out of it, at rest
  bool handed_over_ = false;          // left for another command's move, not stopped
  bool model_was_led_ = false;        // the model in such a mode after the last write
  bool moving_when_stopped_ = false;  // a status just before that stop, in its write, showed the device moving
  TimePoint stopped_at_{};            // when the model stopped out of it
  bool locate_completed_ = false;     // the model's LOCATE has completed, the device's maybe not
  bool ramping_down(std::size_t axis, std::uint8_t status, Duration uncertainty) const;
  bool half_turn_ = false;               // an azimuth move to +-180 on a line: azimuth not compared
  // Out of a STOW, DEPLOY or search where the axis's reading is '*' (an
  // A/D error, E-42): where the device left it shows first in a pulse count
  // (§3.16), which is taken, not judged.
  std::array<bool, 3> position_unknown_{};
  LockstepCoverage coverage_;
};

// ---- minimizer ----------------------------------------------------------------

// Zeller's ddmin: a 1-minimal subsequence of `items` for which `fails` holds
// (fails(items) must hold). `max_tests` bounds the work.
template <class T>
std::vector<T> ddmin(std::vector<T> items, const std::function<bool(const std::vector<T>&)>& fails,
                     std::size_t max_tests = 2000) {
  std::size_t n = 2, tests = 0;
  while (items.size() >= 2 && tests < max_tests) {
    const std::size_t chunk = (items.size() + n - 1) / n;
    bool reduced = false;
    // Try each subset, then each complement.
    for (std::size_t start = 0; start < items.size() && !reduced && tests < max_tests; start += chunk) {
      std::vector<T> subset(items.begin() + static_cast<std::ptrdiff_t>(start),
                            items.begin() + static_cast<std::ptrdiff_t>(std::min(items.size(), start + chunk)));
      ++tests;
      if (fails(subset)) {
        items = std::move(subset);
        n = 2;
        reduced = true;
      }
    }
    for (std::size_t start = 0; start < items.size() && !reduced && n > 2 && tests < max_tests; start += chunk) {
      std::vector<T> complement(items.begin(), items.begin() + static_cast<std::ptrdiff_t>(start));
      complement.insert(complement.end(), items.begin() + static_cast<std::ptrdiff_t>(std::min(items.size(), start + chunk)),
                        items.end());
      ++tests;
      if (fails(complement)) {
        items = std::move(complement);
        n = std::max<std::size_t>(n - 1, 2);
        reduced = true;
      }
    }
    if (!reduced) {
      if (n >= items.size()) break;
      n = std::min(items.size(), 2 * n);
    }
  }
  return items;
}

// ---- the session ----------------------------------------------------------------

struct SessionOptions {
  bool allow_motion = false;       // the safety gate (is_safe_to_send)
  bool allow_destructive = false;
  std::chrono::milliseconds pace{0};                   // §4: at least this long between writes
  std::chrono::milliseconds turnaround_allowance{50};  // beyond the profile's turnaround: late
  std::size_t liveness_every = 50;                     // a device type query every N writes
  bool lockstep = true;  // judge every reply against the reference controller too (Lockstep)
};

struct Counts {
  std::size_t writes = 0, bytes_sent = 0, bytes_received = 0;
  std::size_t ack = 0, nak = 0, offline = 0, silence = 0, garbage = 0, probes = 0, refused = 0;
};

struct Finding {
  FindingKind kind;
  std::string message;
  std::vector<FuzzFrame> history;    // every write up to the one that showed it
  std::vector<FuzzFrame> reproducer; // minimized (empty until minimized)
  bool reproduced = false;           // the reproducer shows the finding again
  std::string field = {};            // Verdict::field
};

// One device: sends writes, judges answers, probes liveness.
class Session {
 public:
  Session(Transport& transport, const Profile& profile, SessionOptions options);
  // Sends one write and judges the answer; a finding, or nullopt.
  std::optional<Verdict> step(const FuzzFrame& frame);
  // A device type query (§3.1); a finding when it is not answered, or
  // answered differently from the first one (the device reset or changed).
  std::optional<Verdict> probe();
  // The device's extended status (40h), judged by the
  // framing oracle, and the lockstep model given its positions and mode
  // (Lockstep::adopt): a device on a bench is no fresh controller. The writes
  // are appended to `sent` (a replay needs them), what the model took to
  // `taken`. A framing finding, or nullopt.
  std::optional<Verdict> synchronize(std::vector<FuzzFrame>* sent = nullptr, std::string* taken = nullptr);
  // Whether the writes show a finding of `kind` (fresh oracle; the device as it is).
  bool shows(const std::vector<FuzzFrame>& frames, FindingKind kind);
  // Whether the reference receiver would accept no frame of this write (the
  // oracle's state is not changed): the caller may append a probe frame, so
  // that the ignore path is checked without waiting out a silence window.
  bool would_be_ignored(const FuzzFrame& frame) const;
  const Counts& counts() const { return counts_; }
  Transport& transport() { return transport_; }
  // The lockstep oracle, or nullptr when SessionOptions::lockstep is off.
  const Lockstep* lockstep() const { return lockstep_ ? &*lockstep_ : nullptr; }
  // How far the device's time of execution of the last write can be from
  // the time the model takes: 0 in-process, else that write's reply
  // latency and 5 ms (the lockstep oracle adds up those of a motion).
  Duration timing_uncertainty() const;

 private:
  Observation exchange(const FuzzFrame& frame, std::size_t expected_replies, std::size_t reply_bytes);
  // Feeds the lockstep oracle the write just exchanged; its verdict.
  std::optional<Verdict> lockstep_step(const FuzzFrame& frame, const Observation& seen);
  Transport& transport_;
  Profile profile_;
  SessionOptions options_;
  Oracle oracle_;
  std::optional<Lockstep> lockstep_;
  TimePoint sent_at_{};
  std::optional<TimePoint> first_byte_at_;  // of the last exchange's replies
  Duration latency_{0};  // of the last exchange: sent to its first reply byte
  Counts counts_;
  TimePoint last_write_{};
  std::optional<Frame> first_device_type_;
  Bytes tail_;
};

// A fresh device for each minimization trial (the in-process controller), or
// nullptr: replay on the same device after a liveness probe.
using DeviceFactory = std::function<std::unique_ptr<Transport>()>;

// Minimizes `finding.history` to `finding.reproducer` (the last `window`
// writes first, the whole history if they do not reproduce).
void minimize(Finding& finding, const Profile& profile, const SessionOptions& options, const DeviceFactory& fresh,
              Session* same_device, std::size_t window = 64);

// ---- findings as vectors -----------------------------------------------------------

struct FindingContext {
  std::uint64_t seed = 0;
  std::string command_line;
  std::size_t number = 1;  // of the run's findings
};

// The reproducer as a vector file (vectors/README.md) in paragraph `framing`:
// one raw send per accepted frame, expectations from the reference
// controller with the same profile, the spec paragraph and quote of the rule
// the finding broke, and a comment with the seed and the command line.
// Written by yaml-cpp's Emitter; the message, the command line and the
// writes' descriptions, which hold what a device said and a person typed,
// made printable first (yaml_writer::printable_text).
std::string finding_vector_yaml(const Finding& finding, const Profile& profile, const FindingContext& context);

}  // namespace sabus::harness::live_fuzz
