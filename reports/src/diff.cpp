// Comparing two runs by vector id.
#include "sabus/reports/diff.hpp"

#include "sabus/reports/writers.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <map>
#include <set>

namespace sabus::reports {

bool TimingThreshold::exceeded(double old_ms, double new_ms) const {
  const double delta = std::abs(new_ms - old_ms);
  if (!percent) return delta > value;
  if (old_ms <= 0) return new_ms > 0 && value < 1e9;  // from nothing to something: any share
  return delta / old_ms * 100.0 > value;
}

std::optional<TimingThreshold> parse_timing_threshold(std::string_view text) {
  TimingThreshold t;
  if (text.ends_with("%")) {
    t.percent = true;
    text.remove_suffix(1);
  } else if (text.ends_with("ms")) {
    text.remove_suffix(2);
  }
  double v = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size() || v < 0 || !std::isfinite(v))
    return std::nullopt;
  t.value = v;
  return t;
}

namespace {

DiffEntry entry(const VectorRecord* o, const VectorRecord* n, std::string detail = "") {
  const VectorRecord* v = n ? n : o;
  return {v->id, v->paragraph, v->level, o ? o->outcome : "", n ? n->outcome : "", std::move(detail)};
}

std::vector<const FrameRecord*> replies(const VectorRecord& v) {
  std::vector<const FrameRecord*> out;
  for (const auto& f : v.transcript)
    if (f.dir == "rx" && !f.hex.empty()) out.push_back(&f);
  return out;
}

// The first reply that differs, and its first differing field.
std::optional<std::string> reply_change(const VectorRecord& o, const VectorRecord& n) {
  const auto a = replies(o), b = replies(n);
  for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
    if (i >= a.size()) return fmt::format("reply {} is new: {}", i + 1, b[i]->note);
    if (i >= b.size()) return fmt::format("reply {} is gone: {}", i + 1, a[i]->note);
    if (a[i]->hex == b[i]->hex) continue;
    for (std::size_t k = 0; k < std::min(a[i]->fields.size(), b[i]->fields.size()); ++k) {
      const Field& x = a[i]->fields[k];
      const Field& y = b[i]->fields[k];
      if (x.raw != y.raw || x.name != y.name)
        return fmt::format("reply {} {} {}: {} -> {} ({})", i + 1, y.first == y.last ? "byte" : "bytes",
                           y.first == y.last ? fmt::format("{}", y.first) : fmt::format("{}-{}", y.first, y.last), y.name,
                           x.raw, y.raw, y.meaning);
    }
    return fmt::format("reply {}: {} -> {}", i + 1, a[i]->hex, b[i]->hex);
  }
  return std::nullopt;
}

bool ran(const VectorRecord& v) { return v.outcome != "skip"; }

// Ran and was judged: neither its purpose unreached (inconclusive) nor left
// unjudged by the line (error). Only a judged vector can be a fix.
bool judged(const VectorRecord& v) { return ran(v) && !v.is_inconclusive() && !v.is_error(); }

std::string list_text(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out.empty() ? "none" : out;
}

}  // namespace

std::vector<std::string> comparability_warnings(const RunDocument& o, const RunDocument& n) {
  std::vector<std::string> w;
  // Every option, also those only one run recorded (older schema versions
  // have fewer): a run with other options is another experiment.
  std::set<std::string> keys;
  for (const auto& [k, v] : o.options.items()) keys.insert(k);
  for (const auto& [k, v] : n.options.items()) keys.insert(k);
  for (const auto& k : keys) {
    const auto a = o.options.find(k), b = n.options.find(k);
    const std::string av = a == o.options.end() ? "(not recorded)" : json_value_text(*a);
    const std::string bv = b == n.options.end() ? "(not recorded)" : json_value_text(*b);
    if (av != bv) w.push_back(fmt::format("option {}: {} -> {}", k, av, bv));
  }
  if (o.profile != n.profile) w.push_back("profile: " + o.profile + " -> " + n.profile);
  if (o.address != n.address) w.push_back(fmt::format("address: {} -> {}", o.address, n.address));
  std::set<std::string> ran_old, ran_new;
  for (const auto& v : o.vectors)
    if (ran(v)) ran_old.insert(v.id);
  for (const auto& v : n.vectors)
    if (ran(v)) ran_new.insert(v.id);
  std::size_t only_old = 0, only_new = 0;
  for (const auto& id : ran_old) only_old += !ran_new.count(id);
  for (const auto& id : ran_new) only_new += !ran_old.count(id);
  if (only_old || only_new)
    w.push_back(fmt::format("selection: OLD ran {} vectors, NEW ran {}; {} ran only in OLD, {} only in NEW", ran_old.size(),
                            ran_new.size(), only_old, only_new));
  if (!w.empty())
    w.push_back("the runs put the controller through other states: a reply or a timing that changed may come from that, "
                "not from the device");
  return w;
}

RunDiff diff_runs(const RunDocument& o, const RunDocument& n, const TimingThreshold& threshold) {
  RunDiff d;
  auto identity = [](const RunDocument& r) {
    return r.identity.ok ? r.identity.controller_type + " " + r.identity.firmware_version : "unknown";
  };
  if (identity(o) != identity(n)) d.run_changes.push_back("device: " + identity(o) + " -> " + identity(n));
  d.warnings = comparability_warnings(o, n);
  if (o.faults != n.faults) d.run_changes.push_back("faults: " + list_text(o.faults) + " -> " + list_text(n.faults));
  if (o.status != n.status) d.run_changes.push_back("status: " + o.status + " -> " + n.status);
  if (n.status != "complete") {
    d.new_run_incomplete = true;
    d.run_changes.push_back("the new run is " + n.status + (n.abort_reason.empty() ? "" : ": " + n.abort_reason));
  }
  std::map<std::string, const VectorRecord*> old_by_id;
  for (const auto& v : o.vectors) old_by_id.emplace(v.id, &v);
  std::map<std::string, bool> seen;
  for (const auto& nv : n.vectors) {
    if (seen[nv.id]) continue;  // --repeat does not repeat ids; be safe with duplicates
    seen[nv.id] = true;
    const auto it = old_by_id.find(nv.id);
    const VectorRecord* ov = it == old_by_id.end() ? nullptr : it->second;
    if (!ov) {
      d.added.push_back(entry(nullptr, &nv, nv.difference()));
      if (nv.is_failure()) d.new_failures.push_back(entry(nullptr, &nv, nv.difference()));
      continue;
    }
    if (nv.is_failure() && !ov->is_failure()) {
      d.new_failures.push_back(entry(ov, &nv, nv.difference()));
    } else if (ov->is_failure() && !nv.is_failure() && judged(nv)) {
      // (A failure that is now inconclusive is not fixed: the purpose was
      // not reached. Nor one now in error: the line left it unjudged. Each
      // is an other change, as pass -> inconclusive and pass -> error are;
      // inconclusive -> fail and error -> fail are new failures above: the
      // device was judged and failed.)
      d.fixes.push_back(entry(ov, &nv));
    } else if (ov->outcome == "pass" && nv.outcome == "skip" && nv.level == "must") {
      d.must_now_skipped.push_back(entry(ov, &nv, nv.skip_reason));
    } else if (ov->outcome != nv.outcome) {
      d.other_changes.push_back(entry(ov, &nv, nv.outcome == "skip" ? nv.skip_reason : nv.difference()));
    }
    if (ov->outcome == "pass" && nv.outcome == "pass")
      if (auto change = reply_change(*ov, nv)) d.replies_changed.push_back(entry(ov, &nv, *change));
    if (ran(*ov) && ran(nv) && threshold.exceeded(ov->duration_ms, nv.duration_ms))
      d.timing_shifts.push_back(entry(ov, &nv, fmt::format("{:.1f} ms -> {:.1f} ms ({:+.1f} ms)", ov->duration_ms,
                                                           nv.duration_ms, nv.duration_ms - ov->duration_ms)));
  }
  for (const auto& ov : o.vectors) {
    if (seen.count(ov.id)) continue;
    seen[ov.id] = true;
    if (ov.outcome == "pass") d.now_missing.push_back(entry(&ov, nullptr, "passed before; not in the new run"));
    else d.other_changes.push_back(entry(&ov, nullptr, "not in the new run"));
  }
  return d;
}

namespace {

struct Section {
  const char* title;
  const std::vector<DiffEntry>* entries;
  bool regression;
};

std::vector<Section> sections(const RunDiff& d) {
  return {{"New failures", &d.new_failures, true},
          {"Passed before, missing now", &d.now_missing, true},
          {"Must vectors now skipped", &d.must_now_skipped, true},
          {"Fixed", &d.fixes, false},
          {"New vectors", &d.added, false},
          {"Other outcome changes", &d.other_changes, false},
          {"Replies changed (both pass)", &d.replies_changed, false},
          {"Timing shifts", &d.timing_shifts, false}};
}

std::string outcome_change(const DiffEntry& e) {
  return (e.old_outcome.empty() ? "(none)" : e.old_outcome) + " → " + (e.new_outcome.empty() ? "(none)" : e.new_outcome);
}

std::string verdict_line(const RunDiff& d) {
  return d.regressed() ? fmt::format("REGRESSED: {} new failure(s), {} missing, {} must now skipped{}", d.new_failures.size(),
                                     d.now_missing.size(), d.must_now_skipped.size(),
                                     d.new_run_incomplete ? ", the new run is incomplete" : "")
                       : fmt::format("no regression: {} fixed, {} replies changed, {} timing shift(s)", d.fixes.size(),
                                     d.replies_changed.size(), d.timing_shifts.size());
}

std::string md(std::string_view s) { return markdown_text(s); }

}  // namespace

std::string diff_text(const RunDiff& d) {
  std::string out;
  for (const auto& w : d.warnings) out += "WARNING " + w + "\n";
  for (const auto& c : d.run_changes) out += c + "\n";
  for (const auto& s : sections(d)) {
    if (s.entries->empty()) continue;
    out += fmt::format("{}{} ({}):\n", s.regression ? "REGRESSION " : "", s.title, s.entries->size());
    for (const auto& e : *s.entries)
      out += fmt::format("  {} §{} {}: {}{}{}\n", e.id, e.paragraph, e.level, outcome_change(e), e.detail.empty() ? "" : "  ",
                         e.detail);
  }
  return out + verdict_line(d) + "\n";
}

std::string diff_markdown(const RunDiff& d) {
  std::string out = fmt::format("### SAbus run diff: **{}**\n\n", d.regressed() ? "regressed" : "no regression");
  for (const auto& w : d.warnings) out += "> **Warning:** " + md(w) + "\n>\n";
  if (!d.warnings.empty()) out += "\n";
  for (const auto& c : d.run_changes) out += "- " + md(c) + "\n";
  if (!d.run_changes.empty()) out += "\n";
  for (const auto& s : sections(d)) {
    if (s.entries->empty()) continue;
    out += fmt::format("**{}{}** ({})\n\n| Vector | § | Level | Outcome | Detail |\n|---|---|---|---|---|\n",
                       s.regression ? "Regression: " : "", s.title, s.entries->size());
    for (const auto& e : *s.entries)
      out += fmt::format("| `{}` | {} | {} | {} | {} |\n", markdown_code(e.id), md(e.paragraph), md(e.level), md(outcome_change(e)),
                         md(e.detail));
    out += "\n";
  }
  return out + md(verdict_line(d)) + "\n";
}

}  // namespace sabus::reports
