// The run document: one in-memory model of a conformance run that every
// report is written from. `sabus run` builds it as vectors finish (each one
// appended to the run's journal, journal.hpp) and writes the run JSON once at
// the end; `sabus report` and `sabus diff` read the JSON (or a journal) back
// into it. The JSON is the source of truth; its schema is reports/SCHEMA.md
// ("sabus-run", version 5).
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/runner.hpp"

namespace sabus::reports {

inline constexpr int kSchemaVersion = 7;
inline constexpr const char* kSchemaName = "sabus-run";

// One named field of a frame with its byte range (protocol describe_frame).
struct Field {
  std::size_t first = 0, last = 0;  // byte offsets in the frame, inclusive
  std::string name, raw, meaning;
  bool ok = true;
  bool operator==(const Field&) const = default;
};

// One frame sent or received (or a discard note) in a vector's transcript.
struct FrameRecord {
  double t_ms = 0;       // since the start of the run
  std::string dir;       // "tx" (to the device) or "rx" (from it)
  std::string hex;       // 7-bit characters; "" for an "ignored ..." note
  std::string note;      // decoded summary
  std::string command;   // catalog key of the frame's command byte ("status"); "" if none
  std::string form;      // tx: catalog form id chosen by the selector byte; "" if none
  std::string expect;    // tx: the step's expected path (ack, nak, offline, silence, any)
  std::string path;      // tx: the path taken for the coverage matrix: ack, nak, offline, ignore
  std::vector<Field> fields;
};

struct VectorRecord {
  std::string id, paragraph, file, level, outcome;  // outcome: harness to_string(Verdict)
  std::vector<std::string> failures;
  // Why the test purpose was not reached (v4; harness
  // VectorResult::inconclusive_reason): "precondition not met (...): ...".
  // "" when it was, and in documents of versions 1 to 3.
  std::string inconclusive_reason;
  // Why the line left the vector unjudged (v5; harness
  // VectorResult::error_reason): "step 2 (41h): no clean reply in 2 tries:
  // ...". "" when it did not, and in documents of versions 1 to 4.
  std::string error_reason;
  // The vector's exchanges and the line faults among them (v5; harness
  // VectorResult::line). All zero when none was counted: a skipped vector,
  // a document of versions 1 to 4.
  harness::LineFaultCounts line;
  std::string skip_reason, known_issue, quote, comment;
  std::string skip_cause;                // harness to_string(SkipCause): "motion", "profile", ...; "" when not skipped
  double duration_ms = 0;                // transport clock: virtual in-process, real on a line
  std::optional<double> wall_ms;         // wall clock (v3); absent in documents of versions 1 and 2
  int repeats = 0, repeat_failures = 0;
  std::vector<FrameRecord> transcript;

  bool is_failure() const { return outcome == "fail" || outcome == "unexpected pass"; }
  bool is_skip() const { return outcome == "skip" || outcome == "known failure"; }
  // Ran, but its test purpose was not reached (TTCN-3 `inconc`): neither a
  // pass nor a failure.
  bool is_inconclusive() const { return outcome == "inconclusive"; }
  // Ran, but the line left it unjudged (TTCN-3 `error`): neither a pass nor
  // a failure, and nothing of the device.
  bool is_error() const { return outcome == "error"; }
  // A failure that is the bench's: the device was lost while the vector ran
  // (harness::kDeviceLostFailure). JUnit shows it as an error.
  bool lost_device() const;
  // A step failed (fail, known failure): the reports show its frames field by field.
  bool has_failed_steps() const { return outcome == "fail" || outcome == "known failure"; }
  // The decoded difference in one line: the first failure, why an
  // unexpected pass fails the run, for an inconclusive vector
  // "inconclusive: " and why its purpose was not reached, for a vector in
  // error "error: " and what the line did.
  std::string difference() const;
};

// The controller's answer to a device type query (30h, §3.1), asked once at
// the start of the run.
struct Identity {
  bool ok = false;
  std::string controller_type, firmware_version, reply_hex;
  std::string error;  // why there is no identity
};

struct Liveness {
  std::string when;
  bool alive = true;
  std::string detail;
};

struct Summary {
  std::size_t passed = 0, failed = 0, skipped = 0, known = 0, unexpected = 0;
  int exit_code = 0;
  // Skipped vectors by cause ("level", "profile", "motion", "destructive",
  // "parity"; "" for a vector of a document that did not record it).
  std::map<std::string, std::size_t> skipped_by_cause = {};
  // Vectors that ended inconclusive (v4; 0 in documents of versions 1 to 3).
  // Last, so that the counts above keep their places.
  std::size_t inconclusive = 0;
  // Vectors that ended in error (v5; 0 in documents of versions 1 to 4).
  std::size_t errors = 0;
  // The whole run's exchanges and line faults, liveness and backup included
  // (v5; harness RunResult::line); all zero when none was counted.
  harness::LineFaultCounts line = {};
};

// Why line counts cannot be what a run counted, or "": a fault is an
// exchange, a recovered fault a fault, a repeat an exchange
// (harness::LineFaultCounts). The readers and the checker ask it.
std::string line_counts_problem(const harness::LineFaultCounts& c);
// The share of exchanges that showed a line fault; 0 for none counted.
double line_fault_rate(const harness::LineFaultCounts& c);

// One stop of a run that `sabus run --resume` continued (tools/sabus/resume.cpp).
struct Resumption {
  std::string stopped_at;    // UTC, ISO 8601: the stopped run's finished_at (a killed run: its journal's last write)
  std::string stopped_by;    // "SIGINT", "SIGTERM", "lost device", or "killed" (the journal had no end record)
  std::string abort_reason;  // the stopped run's, "" for a killed run
  std::string resumed_at;    // UTC, ISO 8601
  std::size_t kept = 0;      // vectors finished before the stop, kept as they were
  std::vector<std::string> restore;  // what the stopped run restored of the stored data when it stopped
};

// Where the device was reached and which reports were asked for, as given on
// the command line: what `sabus run --resume` needs besides `options` (which
// say what is checked, and which `sabus diff` compares). Absent in documents
// written before it was added.
struct Invocation {
  std::string profile;  // --profile as given, "" for the default
  std::string port, tcp, line, serial_backend, reading;
  int baud = 0;         // --baud, 0: the profile's
  std::string json, junit, html, md, report_dir;  // the report options as given, "" when not
  bool operator==(const Invocation&) const = default;
};

struct RunDocument {
  int schema_version = kSchemaVersion;
  std::string generator = "sabus";
  std::string started_at, finished_at;   // UTC, ISO 8601
  std::string status = "running";        // running, complete, aborted
  std::string abort_reason;
  // Why the bench stopped the run (harness RunResult::stopped_by): "SIGINT",
  // "SIGTERM", "lost device"; "" when it was not.
  std::string stopped_by;
  std::string journal;                   // while running: the journal file beside the JSON (v3)
  std::string device;                    // the transport ("in-process reference controller", a port)
  Identity identity;
  std::string profile;
  int address = 0;
  std::vector<std::string> faults;
  nlohmann::json options = nlohmann::json::object();
  std::optional<Invocation> invocation;
  std::size_t planned = 0;               // vectors selected for the run
  std::vector<Resumption> resumptions;   // each stop `sabus run --resume` continued after, in order
  std::vector<VectorRecord> vectors;
  std::optional<Summary> summary;        // set when the run ends
  std::vector<Liveness> liveness;
  std::vector<std::string> restore;
  // The stored-data backup file the runner wrote before the first
  // destructive vector (harness StoredDataBackup::file); "" when none was taken.
  std::string backup;
  nlohmann::json traffic = nlohmann::json::object();

  // Counts from the vectors (the summary may be absent in an aborted run);
  // the line counts the summary's, or without one the vectors' summed (a
  // run killed before its end).
  Summary counts() const;
  // Stopped by the bench before its end: SIGINT, SIGTERM or a lost device
  // (exit code 4, harness::kStoppedExitCode).
  bool stopped() const;
  // Why the run did not reach its end, as the reports say it: the abort
  // reason, or that a run with no end record was killed; "" for a complete run.
  std::string unfinished_reason() const;
  // "PASS", "FAIL", "NOTHING RAN" (exit code 5: every vector skipped or
  // inconclusive, or none selected), "ERROR" (exit code 6: no failure, but
  // the line left some vector unjudged), or "STOPPED" (exit code 4) /
  // "ABORTED" / "INCOMPLETE".
  std::string verdict() const;
};

// ---- building from the runner ----------------------------------------------------

FrameRecord frame_record(const harness::TranscriptEntry& entry);
VectorRecord vector_record(const harness::VectorResult& result);
// Sets the paths of the tx frames: the expected path, or for "any" the
// reply that came (ack, nak, offline; ignore when nothing came).
void assign_paths(std::vector<FrameRecord>& transcript);
// Fills status, summary, liveness, restore notes and traffic at the end.
void finish(RunDocument& doc, const harness::RunResult& run, std::string finished_at);
// Drops the per-field decoding of the frames of a vector that did not fail
// (pass, skip, unexpected pass): the reports show it only for failures, and
// the journal and the JSON keep it. A long run keeps its document small so.
void compact_for_reports(VectorRecord& v);

// ---- JSON ------------------------------------------------------------------------

// Members in the order of reports/SCHEMA.md; a vector's JSON is vector_json
// (journal.hpp).
nlohmann::ordered_json header_json(const RunDocument& doc);  // everything except "vectors"
// A "line" member, the vector's and the summary's: {exchanges, faults,
// recovered, repeats}.
nlohmann::ordered_json line_json(const harness::LineFaultCounts& c);
// A string of the document as its JSON holds it: UTF-8, each byte that is not
// replaced by U+FFFD (valid_utf8, writers.hpp), the same replacement every
// report makes, so that the reports `sabus report` makes from the JSON are
// the run's own. And a value of the document's own JSON (options, traffic)
// with its keys and strings so.
nlohmann::ordered_json json_string(std::string_view s);
nlohmann::ordered_json json_value(const nlohmann::json& j);

// Reads a run document; on a bad document sets `error` (what and where) and
// returns nullopt. Accepts schema versions 1 to 5 (each lacks the fields the
// next one added); line counts that line_counts_problem refuses are an error.
std::optional<RunDocument> from_json(const nlohmann::json& j, std::string& error);
// Reads one member of "vectors" (or of a journal's vector record); throws
// nlohmann::json::exception on a missing id or outcome, a field of the wrong
// type, or line counts that line_counts_problem refuses.
VectorRecord vector_from_json(const nlohmann::json& v);
std::optional<RunDocument> read_run_file(const std::string& path, std::string& error);

// The time now, UTC, as "2024-05-01T12:00:00Z".
std::string utc_now();

}  // namespace sabus::reports
