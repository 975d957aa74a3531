// One writer per report format, each working from the run document.
#pragma once

#include <chrono>
#include <cstddef>
#include <fstream>
#include <map>
#include <vector>
#include <optional>
#include <string>
#include <utility>

#include "sabus/harness/transport.hpp"
#include "sabus/reports/document.hpp"

namespace sabus::reports {

// ---- device identity -------------------------------------------------------------

// Asks the device type (30h, §3.1) once through the transport; on failure
// says why (no answer, NAK, offline, a reply that does not decode, lost port).
Identity query_identity(harness::Transport& transport, std::uint8_t address);

// ---- console ---------------------------------------------------------------------

struct Progress {
  std::size_t done = 0, total = 0, passed = 0, failed = 0, skipped = 0;
  std::chrono::milliseconds elapsed{0};
  std::string current;  // the id of the last vector
};
// "[ 12/310] 10 pass 1 fail 1 skip  0:04 elapsed  ~1:40 left  3.3-form2A-basic"
// (remaining time: elapsed per vector so far times the vectors left).
std::string progress_line(const Progress& p, std::size_t width = 100);
// "FAIL 3.2-status-length §3.2 must: expected 52 bytes, got 51"
std::string failure_line(const VectorRecord& v);
// "PASS", "FAIL" (a failure or an unexpected pass), "SKIP", "KNOWN" (a known
// failure), "INCONCLUSIVE" (its test purpose was not reached) or "ERROR"
// (the line left it unjudged).
std::string_view verdict_word(const VectorRecord& v);
// One line a vector as it finishes: "PASS 3.1-x §3.1 must", the failure line
// for a failure, "SKIP 3.4-x §3.4 must: <skip reason>", "KNOWN 3.2-x §3.2
// must: <difference> (known issue: <reason>)", "INCONCLUSIVE 3.7-x §3.7
// must: precondition not met (...): ...", "ERROR 3.4-x §3.4 must: step 2
// (41h): no clean reply in 2 tries: ...". With `colour`, the first word in
// ANSI colour.
std::string verdict_line(const VectorRecord& v, bool colour = false);
// The skipped vectors by cause: "98 need another profile, 113 need
// --allow-motion, 68 need --allow-destructive"; "" when none is recorded.
std::string skip_causes_text(const Summary& s);
// "N passed, N failed, N skipped (the skips by cause)" (and ", N known
// failures", ", N inconclusive", ", N errors" when there are any).
std::string summary_line(const Summary& s);
// The run's line figures: "line: 3 faults in 1,412 exchanges, all recovered
// (fault rate 0.21%)" (harness::describe); "" when no exchange was counted
// (a document of versions 1 to 4, a transport that counts none).
std::string line_text(const Summary& s);
// Why the line's fault rate is a warning, when it is above a healthy line's
// (harness::kHealthyLineFaultRate); "" when it is not.
std::string line_warning(const Summary& s);
// What the vectors in error mean for the run (exit code 6): "2 vectors
// ended in error: the line, not the firmware, left them unjudged", or when
// every vector that ran did, "nothing was judged: all 3 vectors that ran
// ended in error (...)"; "" when none did.
std::string line_error_text(const Summary& s);
// Why a run checked nothing (exit code 5): "all 34 vectors selected were
// skipped (34 need --allow-motion)", "no vector was selected", "the one
// vector that ran ended inconclusive (its test purpose was not reached)".
std::string nothing_ran_reason(const Summary& s);
// "m:ss" or "h:mm:ss".
std::string clock_text(std::chrono::milliseconds d);

// ---- files -----------------------------------------------------------------------

// JUnit XML as Jenkins and GitLab read it (reports/junit.xsd): one testsuite
// per spec paragraph, one testcase per vector; times from the wall clock,
// the run's firmware, profile, seed and suite version as properties. A run
// that did not reach its end (RunDocument::unfinished_reason) adds the
// testsuite kJunitRunSuite, whose one testcase holds an <error> naming why;
// the vector during which the device was lost is an <error>, not a failure.
std::string junit_xml(const RunDocument& doc);
inline constexpr std::string_view kJunitRunSuite = "run";
inline constexpr std::string_view kJunitRunTestcase = "the run reached its end";
inline constexpr std::string_view kJunitRunClassname = "sabus.run";
// One self-contained HTML page: nothing from the network, one inline script
// (the filter; the page's Content-Security-Policy allows it by its hash and
// nothing else); every string from the device or the vectors is escaped.
std::string html_report(const RunDocument& doc);
// A short Markdown summary for a merge request or a release note.
std::string markdown_summary(const RunDocument& doc);

// What every report shows of a string from the device, the vectors or the
// command line: UTF-8 (a byte that is not becomes U+FFFD), with the
// characters that XML 1.0 cannot carry even as references (C0 controls but
// tab, LF and CR; U+FFFE, U+FFFF) and those HTML5 reads as parse errors (DEL,
// C1 controls, noncharacters) written out as text ("\x01", "\u{fffe}").
std::string shown_text(std::string_view s);
// shown_text for XML and HTML (text and attribute values): & < > " ' as
// references.
std::string xml_escape(std::string_view s);
// Markdown (GitHub Flavored) text for a table cell or a list item: shown_text
// on one line (line ends and tabs as spaces), every character that starts
// markup in the middle of a line (\ ` * _ [ ] < > & | ~ !) escaped with a
// backslash. Not for the start of a line, where # - + . would count too.
std::string markdown_text(std::string_view s);
// The text of a code span: shown_text on one line, a backtick (which would
// end the span) as '. Backslashes are not escapes in a code span.
std::string markdown_code(std::string_view s);
// Whether `s` is UTF-8 (RFC 3629), and `s` with each byte that does not
// begin or continue a UTF-8 sequence replaced by U+FFFD. A device may send
// any byte; every report format is read as UTF-8.
bool is_valid_utf8(std::string_view s);
std::string valid_utf8(std::string_view s);
// A JSON value as the reports show it (an option's value, a seed): its JSON
// text on one line, a string that is not UTF-8 repaired rather than thrown
// at (nlohmann's dump() throws by default; options come from a command line).
std::string json_value_text(const nlohmann::json& value);

// A report path that means standard output.
inline constexpr const char* kStandardOutput = "-";
// Why a report cannot be written at `path`, or "" when it can: a regular
// file, a symbolic link to one (written through: the link stays), or a new
// name in an existing folder. Directories, devices, FIFOs, sockets, links to
// them or to nothing, and this process's own standard output or error
// (`/dev/stdout` redirected to a file) are refused with the reason; a report
// for standard output is "-". Callers check every report path before a run.
std::string output_path_problem(const std::string& path);
// The reports of one command, each checked before anything is written: at
// most one on standard output, no two on one file, and each path's
// output_path_problem. Pairs of (option, path); empty paths are not asked
// for. The first problem, naming the option ("--md /tmp is a directory: ..."),
// or "".
std::string report_paths_problem(const std::vector<std::pair<std::string, std::string>>& reports);
// Writes text to a file, or to standard output for "-"; false with `error`
// set when it cannot (output_path_problem's refusals included).
bool write_file(const std::string& path, const std::string& text, std::string& error);

}  // namespace sabus::reports

namespace sabus::reports {

// ---- tables shared by the HTML and Markdown reports ------------------------------

struct Tally {
  std::size_t passed = 0, failed = 0, skipped = 0, known = 0;  // failed counts unexpected passes
  std::size_t inconclusive = 0;
  std::size_t errors = 0;  // the line left them unjudged
  void add(const VectorRecord& v);
  std::size_t total() const { return passed + failed + skipped + known + inconclusive + errors; }
};

// Per spec paragraph (in paragraph order: "3.2" before "3.10"), per level.
std::map<std::string, std::map<std::string, Tally>, bool (*)(const std::string&, const std::string&)> paragraph_levels(
    const RunDocument& doc);
bool paragraph_less(const std::string& a, const std::string& b);

// The coverage matrix: command × form × path (ack, nak, offline, ignore),
// each cell counting the vectors that sent such a frame, by outcome. Rows
// are every catalog command and each of its forms ("" for a command without
// forms, or a frame whose selector picks none).
struct CoverageRow {
  std::string command, name, paragraph, form;
  std::map<std::string, Tally> paths;  // "ack", "nak", "offline", "ignore"
};
inline constexpr const char* kPaths[] = {"ack", "nak", "offline", "ignore"};
std::vector<CoverageRow> coverage(const RunDocument& doc);

// Failing vectors grouped by their difference (VectorRecord::difference), the
// largest group first, then in run order.
struct FailureGroup {
  std::string reason;
  std::vector<const VectorRecord*> vectors;
};
std::vector<FailureGroup> failure_groups(const RunDocument& doc);

// Reply turnaround per command: from a command frame sent to the first reply
// frame after it, on the transport clock (virtual in-process, real on a
// line). One row per catalog command that got a reply, in catalog order.
struct Turnaround {
  std::string command, name, paragraph;
  std::size_t count = 0;
  double min_ms = 0, median_ms = 0, max_ms = 0;
};
std::vector<Turnaround> turnaround_by_command(const RunDocument& doc);

}  // namespace sabus::reports
