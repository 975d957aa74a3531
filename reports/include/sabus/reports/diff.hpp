// `sabus diff OLD.json NEW.json`: what changed between two runs (two firmware
// releases, or a run before and after a change).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/reports/document.hpp"

namespace sabus::reports {

// A duration change counts as a timing shift when it exceeds this: an
// absolute number of milliseconds ("50ms", "50") or a share of the old
// duration ("20%").
struct TimingThreshold {
  double value = 100;
  bool percent = false;
  bool exceeded(double old_ms, double new_ms) const;
};
std::optional<TimingThreshold> parse_timing_threshold(std::string_view text);

struct DiffEntry {
  std::string id, paragraph, level, old_outcome, new_outcome;
  std::string detail;  // the new failure's difference, the changed reply field, the durations
};

struct RunDiff {
  // The runs differ in options, profile or the vectors that ran: the
  // controller went through other states, so a changed reply or timing may
  // come from that and not from the device. One line each.
  std::vector<std::string> warnings;
  std::vector<std::string> run_changes;    // identity, faults, status: one line each
  bool new_run_incomplete = false;         // NEW is aborted or still running: a regression
  std::vector<DiffEntry> new_failures;     // not failing before, failing now (regression)
  std::vector<DiffEntry> now_missing;      // passed before, absent now (regression)
  std::vector<DiffEntry> must_now_skipped; // a must vector passed before and is skipped now (regression)
  std::vector<DiffEntry> fixes;            // failing before, passing now (not inconclusive, not in error)
  std::vector<DiffEntry> added;            // not in OLD
  // Any other change of outcome: pass -> inconclusive, fail -> inconclusive
  // and back (an inconclusive vector neither passes nor fails); pass ->
  // error, fail -> error and back (the line left it unjudged: nothing was
  // learnt of the device); skips. (inconclusive -> fail and error -> fail
  // are new failures.)
  std::vector<DiffEntry> other_changes;
  std::vector<DiffEntry> replies_changed;  // passes in both, but a reply differs
  std::vector<DiffEntry> timing_shifts;    // ran in both, duration moved beyond the threshold
  bool regressed() const {
    return new_run_incomplete || !new_failures.empty() || !now_missing.empty() || !must_now_skipped.empty();
  }
};

RunDiff diff_runs(const RunDocument& old_run, const RunDocument& new_run, const TimingThreshold& threshold);
// The warnings of diff_runs alone.
std::vector<std::string> comparability_warnings(const RunDocument& old_run, const RunDocument& new_run);

std::string diff_text(const RunDiff& diff);
std::string diff_markdown(const RunDiff& diff);

}  // namespace sabus::reports
