// Which vectors a run takes, in one place: --filter and --exclude globs over
// vector ids, --paragraph for one spec paragraph exactly (the glob '3.2*'
// also takes §3.20-§3.25), --shard K/N (a stable slice by vector id), the
// vectors an earlier run failed (--last-failed: only them; --failed-first:
// them first), and the known-issues file. `sabus run` and `sabus vectors
// list` (a preview) call it; the runner runs every vector it is given. The
// gates that leave a selected vector skipped (level, profile, motion,
// destructive, parity) are the runner's: they are verdicts a report counts.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/harness/vector.hpp"

namespace sabus::harness {

// --shard K/N: the K-th (1-based) of N slices. A vector is in slice
// 1 + (FNV-1a 64 of its id) mod N, whatever else is selected, so the N
// slices of one selection hold each of its vectors exactly once, and a
// vector stays in its slice as others are added or removed.
struct Shard {
  std::uint32_t index = 1, count = 1;
};
// "K/N" with 1 <= K <= N <= 10000; nullopt with `error` ("--shard 3/2: K
// must be between 1 and N") otherwise. `option` names the option in errors.
std::optional<Shard> parse_shard(std::string_view text, std::string& error, std::string_view option = "--shard");
bool in_shard(const Shard& shard, std::string_view key);

// Whether a vector id matches a glob (fnmatch(3), as --filter takes it).
bool glob_matches(const std::string& glob, const std::string& id);

struct SelectionOptions {
  std::vector<std::string> filters, excludes, paragraphs;
  std::optional<Shard> shard;
  // --last-failed: only these ids (an earlier run's failures); nullopt: no restriction.
  std::optional<std::set<std::string>> only;
  std::string only_from;  // the file they came from, for notes and errors
  // --failed-first: these ids run first, then the rest.
  std::set<std::string> first;
};

struct Selection {
  // The vectors the run takes, in the order it takes them: suite order, the
  // --failed-first ones moved to the front (each group in suite order).
  std::vector<Vector> vectors;
  // For the user, one line each: a glob or paragraph that selects nothing, a
  // glob whose vectors span several paragraphs, failures of the earlier run
  // that are not in the suite any more.
  std::vector<std::string> notes;
};

Selection select_vectors(const std::vector<Vector>& all, const SelectionOptions& o);

// Why nothing is selected, for the line that ends the command: "no vector
// matches --filter '3.2-stauts*'".
std::string empty_selection_reason(const SelectionOptions& o);

// Known issues: one vector id per line, then its reason ("id: reason" or
// "id  reason"); '#' starts a comment. Every id must name a vector of the
// suite: a mistyped id would leave its failure failing the run and the list
// silently wrong. `errors` has one line each ("FILE:LINE: no vector has the
// id ..."; "FILE: cannot read"); the issues are usable when it is empty.
struct KnownIssues {
  std::map<std::string, std::string> reasons;  // id -> reason
  std::vector<std::string> errors;
};
KnownIssues read_known_issues(const std::string& path, const std::set<std::string>& ids);

}  // namespace sabus::harness
