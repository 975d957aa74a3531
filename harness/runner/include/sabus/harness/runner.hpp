// The conformance runner: runs vectors against a device through a Transport
// and gives a verdict per vector, per spec paragraph and per level.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/expressions.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/harness/transport.hpp"
#include "sabus/harness/vector.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness {

// ---- matching replies (pure; used by the engine and its tests) --------------

// matcher_text (the text a matcher compares) is vector.hpp's.
// The number a range matcher compares, when the field has one: positions in
// degrees, counts, digits, a binary byte's data bits.
std::optional<double> matcher_number(const FieldDescription& field);

using Captures = std::map<std::string, std::string>;

// Checks one matcher against a described reply; on failure returns a message
// that names the byte range, the field, what was expected and what came, e.g.
//   byte 36 az status: expected 0x57, got 0x44 (slow, ccw automatic movement in progress)
std::optional<std::string> check_field(const FrameDescription& reply, const FieldMatcher& m, Captures& captures);

// A matcher with its profile expressions resolved against the device's
// profile and the vector's captures: eq and one_of values expanded; range
// bounds, `near` and `jogged` turned into a range with words of their own for
// the failure message. When `kind` is not kValue, `problem` says why: the
// capability the profile lacks, or the vector's error.
struct ResolvedMatcher {
  Expansion::Kind kind = Expansion::Kind::kValue;
  FieldMatcher matcher;
  std::string problem;
};
ResolvedMatcher resolve_matcher(const FieldMatcher& m, const ExprContext& cx);

// Applies a step's modifiers to an encoded frame of 7-bit characters.
Bytes apply_modifiers(Bytes frame, const Modifiers& m);

// ---- running --------------------------------------------------------------------

// kInconclusive: TTCN-3's `inconc` (ETSI ES 201 873-1; ISO/IEC 9646): a
// precondition step's expectation did not hold (Step::precondition), so the
// device never reached the state the vector's test purpose needs and the
// vector says nothing of its conformance. Neither a pass nor a failure: it
// never fails the run and is never a known failure or an unexpected pass.
// kError: TTCN-3's `error` (ETSI ES 201 873-1): the test system, not
// the device, went wrong: the line garbled an exchange and its retries
// (RunOptions::retries) did not get a clean one, or the command could not be
// sent again safely. The vector says nothing of the device; it never fails
// the run, but a run with errors and no failure has an exit code of its own
// (kLineErrorExitCode).
enum class Verdict : std::uint8_t { kPass, kFail, kSkip, kKnownFailure, kUnexpectedPass, kInconclusive, kError };
// "pass", "fail", "skip", "known failure", "unexpected pass", "inconclusive", "error".
std::string_view to_string(Verdict v);

// Why the gate passed a selected vector over (Verdict::kSkip): its level is
// above the one asked, the profile lacks what it requires, it moves the
// antenna or changes stored data and that was not allowed, or it sends
// parity errors a true 7E1 port cannot send.
enum class SkipCause : std::uint8_t { kNone, kLevel, kProfile, kMotion, kDestructive, kParity, kFresh };
// "", "level", "profile", "motion", "destructive", "parity", "fresh" (the run JSON's skip_cause).
std::string_view to_string(SkipCause c);

struct TranscriptEntry {
  double t_ms = 0;         // since the start of the run
  bool sent = false;       // true: to the device; false: from it
  Bytes bytes;             // 7-bit characters (sent: before parity; received: as decoded)
  std::string note;        // decoded summary, or what was ignored
  // describe_frame's fields of `bytes`, as the runner described the frame
  // when it sent or received it (the reports show them; describing every
  // frame again cost a run with reports a tenth of its time). Empty when
  // there are no bytes.
  std::vector<FieldDescription> fields;
  // Sent frames of a vector's send or poll step: the reply path the step
  // expects ("ack", "nak", "offline", "silence", "any"); "" for frames the
  // runner sends on its own (liveness, stop, backup).
  std::string expect;
};

// What the line did to a vector's or a run's exchanges (§4: "a garbled
// status reply" is a symptom of unreliable communications). A line fault is
// an exchange whose reply showed one: a bad check byte, a parity error, a
// reply cut short or stretched, bytes between frames, or silence where a
// reply was due that a repeat then got.
struct LineFaultCounts {
  std::size_t exchanges = 0;  // frames sent and their replies read, repeats included
  std::size_t faults = 0;     // exchanges that showed a line fault
  std::size_t recovered = 0;  // faults a repeat or a read-back settled
  std::size_t repeats = 0;    // exchanges sent again after a fault
  // Garbled replies a line survey counted (§4; a survey sends each frame
  // once: what it counts is its measure, not a fault to recover); not in
  // `faults`.
  std::size_t surveyed = 0;
  LineFaultCounts& operator+=(const LineFaultCounts& o) {
    exchanges += o.exchanges;
    faults += o.faults;
    recovered += o.recovered;
    repeats += o.repeats;
    surveyed += o.surveyed;
    return *this;
  }
};
// "line: 3 faults in 1,412 exchanges, all recovered" (every report's words),
// and "; 2 garbled replies counted by the line survey" when one counted any.
std::string describe(const LineFaultCounts& c);

struct VectorResult {
  std::string id, paragraph, file;
  std::string quote, comment;  // the spec quote the vector checks, and what and why (reports)
  Level level = Level::kMust;
  Verdict verdict = Verdict::kPass;
  std::vector<std::string> failures;   // one line each
  // Why the test purpose was not reached: "precondition not met (<the
  // step's precondition>): <what its expectation found>". Set when a
  // precondition step's expectation did not hold; the verdict is then
  // inconclusive, unless a failure was recorded too (a verdict only gets
  // worse: a teardown that fails after it makes the vector a failure).
  std::string inconclusive_reason;
  // Why the vector ended in error (Verdict::kError): the exchange the line
  // left unjudged and what it showed, e.g. "step 2 (41h): no clean reply in
  // 2 tries: bad check byte ...; not sent again: a second LOCATE acts again".
  std::string error_reason;
  LineFaultCounts line;  // this vector's exchanges and the line faults among them
  std::string skip_reason;
  SkipCause skip_cause = SkipCause::kNone;
  std::string known_issue_reason;
  std::vector<TranscriptEntry> transcript;
  double duration_ms = 0;
  int repeats = 0, repeat_failures = 0;  // --repeat on a failure
  bool counts_as_failure(bool strict = false) const;  // a must failure (and with strict a should one) fails the run
};

struct LivenessResult {
  std::string when;   // "before the first vector", "after 3.2-..."
  bool alive = true;
  bool heard = false;   // some bytes came back: reachable, if not alive
  std::string detail;
};

struct StoredDataBackup;

struct RunOptions {
  bool allow_motion = false;
  bool allow_destructive = false;
  // The device stands as its profile powers on (just powered on in that
  // state, or sabus sim): the `power-on` vectors, which compare the status
  // with the profile's power-on state (positions, alarms, the name shown),
  // run. A controller on a bench is wherever the last run left it.
  bool fresh_device = false;
  Level max_level = Level::kInformative;      // run vectors up to this level
  // Which vectors run is decided before the run (selection.hpp): the runner
  // runs every vector it is given.
  std::map<std::string, std::string> known_issues;  // id -> reason (selection.hpp read_known_issues)
  int repeat = 0;                             // re-run each failing vector N times
  bool strict = false;                        // should-level failures fail the run (h2spec's --strict)
  // -x/--exitfirst (pytest's): the run stops after the first vector that
  // fails it (VectorResult::counts_as_failure); RunResult::not_run names
  // those that did not run, and the abort reason says so.
  bool exit_first = false;
  std::uint64_t seed = 0;
  std::chrono::milliseconds pace{0};          // at least this long between commands (§4); 0: none
  std::chrono::milliseconds turnaround_allowance{50};
  // The signal that asks the run to stop after the current step ("SIGINT",
  // "SIGTERM"); "" to go on.
  std::function<std::string_view()> stop;
  std::function<void(const VectorResult&)> on_result;  // progress and incremental reports
  // false: RunResult::vectors keep no transcripts (on_result has had them), so
  // a run of thousands of vectors does not hold every frame it exchanged.
  bool keep_transcripts = true;
  // false: no transcript is recorded at all, not even for on_result: a sweep
  // of thousands of profiles reads only the verdicts, and describing every
  // frame it exchanges was a fifth of its time.
  bool record_transcripts = true;
  // Where the stored-data backup is written ("": not written); never over a
  // file that is there (write_new_file: backup-2.json, ...).
  std::string backup_path;
  // false: no backup and no restore, for a device that does not outlive the
  // run (the in-process reference controller).
  bool backup_stored_data = true;
  // Called once the stored-data backup is taken and written
  // (StoredDataBackup::file, "" when backup_path is), before the destructive
  // vector it was taken for runs: a run killed after that leaves no end
  // record to name the file, so the caller's journal records it here for
  // `sabus run --resume` to restore from.
  std::function<void(const StoredDataBackup&)> on_backup;
  // Line faults (LineFaultCounts): how many times an exchange whose reply
  // showed one is repeated (pymodbus's `retries`). A read or status poll is
  // sent again after the silence window; a command that changes state only
  // when the catalog says a second one leaves the device as one does, and
  // after a status poll has read the device back; never a command that acts
  // again (a jog, a LOCATE, a key). 0: a line fault is judged as the
  // device's answer, as a clean line's would be, and the failure says it was
  // a line fault. The CLI's default is 1 on a line, 0 in-process.
  int retries = 0;
  // --strict-line: every line fault fails the vector it happened in, even
  // one a repeat recovered.
  bool strict_line = false;
  // --max-line-fault-rate: the share of garbled replies a line survey
  // (Step::Kind::kSurvey) accepts before it fails the device.
  double max_line_fault_rate = 0.1;
  // `sabus run --resume`: the vectors a stopped run finished, counted first
  // as this run's own (they are not run again), and the stored-data backup
  // it took, which the restore at the end writes back instead of a new one
  // (the device may hold what the stopped run's vectors wrote).
  std::vector<VectorResult> kept;
  std::shared_ptr<const StoredDataBackup> backup;
};

// The controller's stored data as read back through the protocol before the
// first destructive vector: the STORE list's names (35h), the preset
// satellites (3Ah), TLEs (3Ch), signposts (44h, with the DVB option) and the
// navigation data (45h). Slots hold the reply's data bytes.
struct StoredDataBackup {
  bool taken = false;
  std::vector<std::string> store_names;
  std::map<std::uint8_t, Bytes> presets, tles, signposts;
  std::optional<Bytes> navigation;
  std::string file;  // the file it was written to ("": none asked for)
  // The backup file: {"store_names": [names], "presets" / "tles" /
  // "signposts": {"slot": "hex of the reply's data"} (empty slots left out),
  // "navigation": "hex" or null (no reply)}.
  std::string to_json() const;
  // The backup file read back (to_json's form); nullopt with `error` saying
  // what is wrong. `file` and `taken` are left for the caller.
  static std::optional<StoredDataBackup> from_json(const std::string& text, std::string& error);
};

// A poll for rest is a poll whose `until` names an axis's movement status
// (§3.2 bytes 36-38: "az status", "el status", "pol status"). Once one has
// timed out with an axis still showing movement, each later poll for that
// axis's rest sends this many status requests: when the axis shows rest, the
// run goes back to normal for it; when not, the poll's vector ends
// inconclusive, naming the vector whose poll timed out. A vector whose setup
// or steps poll for that rest sends that short poll before its setup, and
// when it does not see rest, nothing else: no setup move, no teardown, no
// stop. A controller that never shows rest is judged by its first timeout,
// not after a full poll, or a setup and a teardown, of every later vector
// that needs the mount at rest. One: after a poll of minutes that never saw
// rest, a second request a second later tells nothing more, and costs a
// second of the §4 pace.
inline constexpr int kShortRestPoll = 1;

// RunResult::exit_code when no vector ran.
inline constexpr int kNothingRanExitCode = 5;
// RunResult::exit_code when the run was stopped before its end by the bench,
// not by the firmware: a signal or a lost device. 4 is the first code free
// here (1 failed, 2 usage, 3 unreachable); pytest's 2 for an interrupted
// session is this project's usage error, and 128+signal (130, 143) would be
// read as "killed" and has no number for a lost device.
inline constexpr int kStoppedExitCode = 4;
// RunResult::exit_code when no vector failed but some ended in error
// (Verdict::kError): the line, not the firmware, left them unjudged; the
// firmware is neither accepted nor rejected. The next code after 5.
inline constexpr int kLineErrorExitCode = 6;
// A line whose share of faulty exchanges is above this is not a healthy
// line: the summary warns (a healthy RS-422 run sees none in thousands).
inline constexpr double kHealthyLineFaultRate = 0.01;
// How the failure of the vector that was running when the device was lost
// begins: the reports show that vector as an error of the bench, not a
// failure of the firmware.
inline constexpr std::string_view kDeviceLostFailure = "device lost: ";

struct RunResult {
  std::vector<VectorResult> vectors;
  std::vector<LivenessResult> liveness;
  bool aborted = false;
  std::string abort_reason;
  // Why the bench stopped the run ("SIGINT", "SIGTERM", "lost device"); ""
  // when it ran to its end or the device's answers ended it.
  std::string stopped_by;
  // With RunOptions::exit_first, the vectors given that did not run after
  // the first failure, in run order ("" ids never).
  std::vector<std::string> not_run;
  std::chrono::microseconds measured_turnaround{0};
  // Traffic of the whole run, liveness checks included: for line-efficiency figures.
  std::size_t bytes_sent = 0, bytes_received = 0;
  std::chrono::microseconds silence_listened{0};  // time spent in silence windows
  std::size_t silence_windows = 0;
  StoredDataBackup backup;
  std::vector<std::string> restore_notes;  // what was restored, and what could not be
  std::size_t passed = 0, failed = 0, skipped = 0, known = 0, unexpected = 0;
  std::size_t inconclusive = 0;  // Verdict::kInconclusive: ran, checked nothing
  std::size_t errors = 0;        // Verdict::kError: ran, the line left it unjudged
  // The whole run's exchanges, liveness and backup included; all zero
  // without a line (Transport::is_a_line: the in-process controller).
  LineFaultCounts line;
  std::map<SkipCause, std::size_t> skipped_by_cause;
  // 0: every must-level vector that ran passed; 1: otherwise (a liveness
  // check failed on a device that sends bytes, too); 3: the device could not
  // be reached (nothing came back to the first liveness check); 4: stopped
  // by a signal or a lost device (stopped_by), whatever ran before; 5: no vector
  // ran (every one was skipped, or none was given), or every one that ran
  // ended inconclusive: a run that checked nothing is not a success (pytest's
  // "no tests ran" is 5 too). An inconclusive vector never makes it 1.
  // 6 (kLineErrorExitCode): no failure, but some vector ended in error.
  bool strict = false;  // RunOptions::strict: should-level failures fail the run too
  int exit_code() const;
  // The vectors that ran and checked something: inconclusive ones ran but
  // checked nothing (their test purpose was not reached), so they are not counted.
  std::size_t ran() const { return passed + failed + known + unexpected; }
};

class Runner {
 public:
  Runner(Transport& transport, const Profile& profile, RunOptions options);
  RunResult run(const std::vector<Vector>& vectors);

 private:
  Transport& transport_;
  Profile profile_;
  RunOptions options_;
};

}  // namespace sabus::harness
