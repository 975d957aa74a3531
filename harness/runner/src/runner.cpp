// The conformance runner: runs vectors through a Transport in named phases —
// gate (level, requirements, motion/destructive/parity
// safety), backup (before the first destructive vector), setup, steps,
// teardown (and an 'X' stop after motion), verdict (known issues, repeats),
// journal (counts and the on_result callback), and a liveness check after
// every ignore path. The step engine is steps.cpp; the line session.cpp.
#include "sabus/harness/runner.hpp"

#include <algorithm>
#include <functional>
#include <utility>

#include "backup.hpp"
#include "sabus/harness/expressions.hpp"
#include "sabus/harness/profile_records.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "session.hpp"

namespace sabus::harness {

std::string_view to_string(Verdict v) {
  switch (v) {
    case Verdict::kPass: return "pass";
    case Verdict::kFail: return "fail";
    case Verdict::kSkip: return "skip";
    case Verdict::kKnownFailure: return "known failure";
    case Verdict::kUnexpectedPass: return "unexpected pass";
    case Verdict::kInconclusive: return "inconclusive";
    case Verdict::kError: return "error";
  }
  return "?";
}

std::string_view to_string(SkipCause c) {
  switch (c) {
    case SkipCause::kNone: return "";
    case SkipCause::kLevel: return "level";
    case SkipCause::kProfile: return "profile";
    case SkipCause::kMotion: return "motion";
    case SkipCause::kDestructive: return "destructive";
    case SkipCause::kParity: return "parity";
    case SkipCause::kFresh: return "fresh";
  }
  return "?";
}

bool VectorResult::counts_as_failure(bool strict) const {
  return (verdict == Verdict::kFail && (level == Level::kMust || (strict && level == Level::kShould))) ||
         verdict == Verdict::kUnexpectedPass;
}

int RunResult::exit_code() const {
  if (!liveness.empty() && !liveness.front().alive) return liveness.front().heard ? 1 : 3;
  if (!stopped_by.empty()) return kStoppedExitCode;
  if (aborted) return 1;
  for (const auto& v : vectors)
    if (v.counts_as_failure(strict)) return 1;
  if (errors > 0) return kLineErrorExitCode;
  return ran() == 0 ? kNothingRanExitCode : 0;
}

namespace {
// 1412 -> "1,412": the figures a bench engineer reads at a glance.
std::string grouped(std::size_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}
}  // namespace

std::string describe(const LineFaultCounts& c) {
  std::string s = "line: " + grouped(c.faults) + (c.faults == 1 ? " fault" : " faults") + " in " + grouped(c.exchanges) +
                  (c.exchanges == 1 ? " exchange" : " exchanges");
  if (c.faults > 0)
    s += c.recovered == c.faults ? (c.faults == 1 ? ", recovered" : ", all recovered") : ", " + grouped(c.recovered) + " recovered";
  if (c.surveyed > 0)
    s += "; " + grouped(c.surveyed) + (c.surveyed == 1 ? " garbled reply" : " garbled replies") + " counted by the line survey";
  return s;
}

Runner::Runner(Transport& transport, const Profile& profile, RunOptions options)
    : transport_(transport), profile_(profile), options_(std::move(options)) {}

namespace {

using detail::Session;

VectorResult result_of(const Vector& v) {
  VectorResult r;
  r.id = v.id;
  r.paragraph = v.paragraph;
  r.file = v.where.file;
  r.quote = v.quote;
  r.comment = v.comment;
  r.level = v.level;
  return r;
}

// A send of the profile's record the profile does not hold (navigation data
// on a profile without any).
std::optional<std::string> missing_record(const StructuredCommand& c, const ExprContext& cx) {
  const CommandInfo* info = find_command(c.command);
  if (!info || (has_placeholder(c.from_profile) && !template_captures(c.from_profile).empty())) return std::nullopt;
  std::uint32_t index = 0;
  if (c.from_profile != "navigation") {
    const Number n = expand_number(c.from_profile, cx);
    const Count slot = count_in(n.value, 1, max_record_index(info->code));
    if (n.kind != Expansion::Kind::kValue || slot.error) return std::nullopt;  // the step reports it
    index = static_cast<std::uint32_t>(slot.value);
  }
  const RecordRequest r = profile_write(cx.profile, info->code, index);
  return r.request ? std::nullopt : std::optional<std::string>(r.unavailable);
}

// The first capability a vector's profile expressions find missing
// ("{first_empty(presets)}" on a profile with every slot filled). Only
// expressions that read no capture are known before the run; an error is
// left for the step to report.
std::optional<std::string> missing_capability(const Vector& v, const ExprContext& cx) {
  std::optional<std::string> missing;
  auto check = [&](const std::string& text) {
    if (missing || !has_placeholder(text) || !template_captures(text).empty()) return;
    const Expansion e = expand_template(text, cx);
    if (e.kind == Expansion::Kind::kUnavailable) missing = e.text;
  };
  auto check_matchers = [&](const std::vector<FieldMatcher>& matchers) {
    for (const auto& m : matchers)
      if (m.kind != FieldMatcher::Kind::kRegex)
        for (const auto& value : m.values) check(value);
  };
  for (const auto& need : v.needs) check(need);
  for (const auto* list : {&v.setup, &v.steps, &v.teardown})
    for (const Step& s : *list) {
      if (s.command) {
        for (const auto& [name, value] : s.command->fields) check(value);
        check(s.command->from_profile);
        if (!missing && !s.command->from_profile.empty()) missing = missing_record(*s.command, cx);
      }
      check(s.expect.from_profile);
      if (s.raw) {
        const Expansion e = expand_raw_expressions(s.raw->hex, ExprContext{cx.profile, nullptr, cx.pace});
        if (e.kind == Expansion::Kind::kUnavailable && !missing) missing = e.text;
      }
      check_matchers(s.expect.fields);
      check_matchers(s.until);
      check(s.timeout_text);
      check(s.modifiers.address_text);
    }
  return missing;
}
// A teardown step that stops the antenna: 33h or 47h 'X' (§3.4, §3.24).
bool is_stop(const Step& step) {
  if (!step.command || step.command->form != "X") return false;
  const CommandInfo* info = find_command(step.command->command);
  return info && (info->code == 0x33 || info->code == 0x47);
}

struct Skip {
  SkipCause cause;
  std::string reason;
};

// Gate: why a selected vector does not run here, or nullopt when it runs.
std::optional<Skip> skip_reason(const Vector& v, const RunOptions& o, const Profile& profile, const Transport& transport) {
  if (static_cast<int>(v.level) > static_cast<int>(o.max_level))
    return Skip{SkipCause::kLevel, "level " + std::string(to_string(v.level))};
  for (const auto& req : v.requires_)
    if (auto why = unmet_requirement(profile, req)) return Skip{SkipCause::kProfile, "requires: " + *why};
  if (auto why = missing_capability(v, ExprContext{profile, nullptr, o.pace}))
    return Skip{SkipCause::kProfile, "needs " + *why};
  if (!v.each_slot.empty() && filled_slots(profile, v.each_slot).value_or(std::vector<int>{}).empty())
    return Skip{SkipCause::kProfile, "needs a stored " + std::string(slot_what(v.each_slot).value_or(v.each_slot)) +
                                         " in the profile: it stores none"};
  if (v.has_tag("motion") && !o.allow_motion) return Skip{SkipCause::kMotion, "moves the antenna: needs --allow-motion"};
  if (v.has_tag("destructive") && !o.allow_destructive)
    return Skip{SkipCause::kDestructive, "changes stored data: needs --allow-destructive"};
  if (v.has_tag("power-on") && !o.fresh_device && !transport.in_process())
    return Skip{SkipCause::kFresh, "compares the status with the profile's power-on state: needs --fresh-device"};
  if (v.has_tag("parity") && !transport.can_send_parity_errors())
    return Skip{SkipCause::kParity, "sends parity errors: the port is a true 7E1 port (--line 7E1)"};
  return std::nullopt;
}

// What one attempt of a vector found: its failures, one line each, and why
// its test purpose was not reached ("" when it was).
struct Attempt {
  std::vector<std::string> failures;
  std::string inconclusive;
  std::string error;  // why the line left it unjudged (Verdict::kError)
  // Whether it ended inconclusive on a short poll for rest (kShortRestPoll).
  bool rest_unseen = false;
  // Whether the setup and the steps are over: a step failed, a
  // precondition did not hold or the line left a step unjudged (the
  // teardown still runs).
  bool ended() const { return !failures.empty() || !inconclusive.empty() || !error.empty(); }
};

// A step's failure, recorded as what it is: a precondition step's
// (Step::precondition) ends the vector inconclusive, TTCN-3's `inconc`: the
// device never got into the state the test purpose needs; any other step's
// is a failure. `where` says which phase or slot ("setup: ", "preset
// satellite 2: ").
// A short poll for rest that did not see rest (kShortRestPoll) ends it
// inconclusive too: the mount was never shown at rest, which an earlier
// vector's failure has reported already.
// A step the line left unjudged (Session::line_error) ends it in error.
void record(Attempt& a, Session& s, const Step& step, const std::string& where, const std::string& error) {
  if (std::exchange(s.line_error, false)) {
    a.error = where + error;
  } else if (std::exchange(s.rest_unseen, false)) {
    a.inconclusive = where + error;
    a.rest_unseen = true;
  } else if (step.precondition.empty()) {
    a.failures.push_back(where + error);
  } else if (!step.precondition_reading.empty() &&
             side_pinned(s.profile.readings, step.precondition_reading) == ReadingSide::kReference) {
    // The profile pins the reading whose other side alone lets it fail.
    a.failures.push_back(where + "precondition (" + step.precondition + ") held strictly, " +
                         step.precondition_reading + " pinned to its reference side: " + error);
  } else {
    a.inconclusive = where + "precondition not met (" + step.precondition + "): " + error;
  }
}

// The steps, once, or once for each slot of the list `each_slot` names that
// the profile fills, its index captured as $slot: a failing step ends its
// slot's pass and the next slot is read, so one run names every slot that
// differs. A precondition not met ends every slot's pass: the purpose is
// not reached.
void run_steps(Session& s, const Vector& v, Attempt& a) {
  const auto slots = v.each_slot.empty() ? std::optional<std::vector<int>>(std::vector<int>{0})
                                         : filled_slots(s.profile, v.each_slot);
  for (const int slot : slots.value_or(std::vector<int>{})) {
    if (!v.each_slot.empty()) s.captures["$slot"] = std::to_string(slot);
    // Where the failure was: "preset satellite 2: ...", "STORE entry 2: ...".
    const std::string where =
        v.each_slot.empty() ? "" : std::string(slot_what(v.each_slot).value_or(v.each_slot)) + " " + std::to_string(slot) + ": ";
    for (const Step& step : v.steps) {
      if (auto e = s.run_step(step)) {
        record(a, s, step, where, *e);
        break;
      }
      // A `readings:` alternative with `ends` held: the rest of the steps
      // needs the reference side (vectors/README.md).
      if (std::exchange(s.steps_ended, false)) break;
    }
    if (!a.inconclusive.empty() || !a.error.empty()) return;
  }
}

// Setup, steps and teardown of one attempt. A failing setup or step ends
// its phase, and a precondition not met ends the setup and the steps; the
// teardown always runs, and an 'X' stop follows every vector that can move
// the antenna, unless its teardown has just ended with one the device ACKed.
// A vector ended before its setup (the mount still not at rest) has moved
// nothing and has neither.
Attempt attempt(Session& s, const Vector& v, std::vector<TranscriptEntry>& transcript) {
  Attempt a;
  s.transcript = s.options.record_transcripts ? &transcript : nullptr;
  s.vector_moves = v.has_tag("motion");
  s.vector_id = v.id;
  // A vector that needs an axis at rest that has not shown rest since its
  // poll for rest timed out: one status request, and no setup, teardown or
  // stop when it still does not (Session::rest_still_unseen).
  if (auto e = s.rest_still_unseen(v)) {
    a.inconclusive = "before the setup: " + *e;
    a.rest_unseen = true;
    s.transcript = nullptr;
    return a;
  }
  s.captures.clear();
  s.steps_ended = false;
  s.sides_shown.clear();
  for (const Step& step : v.setup)
    if (auto e = s.run_step(step)) {
      record(a, s, step, "setup: ", *e);
      break;
    }
  if (!a.ended()) run_steps(s, v, a);
  // Whether the teardown's last step stopped the mount (an 'X' stop the
  // device ACKed): the runner's own stop after it would repeat it.
  bool stopped = false;
  for (const Step& step : v.teardown) {
    stopped = false;
    if (is_stop(step) && s.track_governs()) continue;  // as the runner's own stop (Session::stop_motion)
    auto e = s.run_step(step);
    const auto& replies = s.last_replies();
    stopped = !e && is_stop(step) && replies.size() == 1 && replies[0].kind == FrameKind::kAck && !is_offline_reply(replies[0]) &&
              replies[0].command == find_command(step.command->command)->code;
    if (e) {
      // A short poll for rest that did not see rest: the mount's state after
      // the vector is unknown, not wrong (an earlier failure said so); a step
      // the line left unjudged is an error.
      if (std::exchange(s.line_error, false)) {
        if (a.error.empty()) a.error = "teardown: " + *e;
      } else if (std::exchange(s.rest_unseen, false)) {
        if (a.inconclusive.empty()) a.inconclusive = "teardown: " + *e;
      } else {
        a.failures.push_back("teardown: " + *e);
      }
    }
  }
  if (v.has_tag("motion") && !stopped) s.stop_motion();  // not while TRACK governs (Session::stop_motion)
  s.transcript = nullptr;
  return a;
}

// --repeat: re-runs a failing vector and says whether it fails every time
// (an attempt that ends inconclusive does not fail).
void repeat_failing(Session& s, const Vector& v, int times, VectorResult& r) {
  for (int i = 0; i < times; ++i) {
    std::vector<TranscriptEntry> again;
    ++r.repeats;
    if (!attempt(s, v, again).failures.empty()) ++r.repeat_failures;
  }
  const std::string runs = std::to_string(r.repeats + 1);
  r.failures.push_back(r.repeat_failures == r.repeats
                           ? "reproducible: failed " + runs + " of " + runs + " runs"
                           : "intermittent: failed " + std::to_string(r.repeat_failures + 1) + " of " + runs + " runs");
}

// Verdict: fail, error, inconclusive or pass, in that order (a verdict only
// gets worse: a failure recorded stays one, TTCN-3's rule). TTCN-3 puts
// error above fail; here a failure was judged on a clean exchange, so a line
// fault later in the vector (its teardown) does not take it back. A pass or a failure
// turned into an unexpected pass or a known failure for a vector listed as
// a known issue. An inconclusive vector checked nothing: the known issue
// says nothing of it, so it stays inconclusive.
void set_verdict(VectorResult& r, const RunOptions& o) {
  r.verdict = !r.failures.empty()              ? Verdict::kFail
              : !r.error_reason.empty()        ? Verdict::kError
              : !r.inconclusive_reason.empty() ? Verdict::kInconclusive
                                               : Verdict::kPass;
  if (r.verdict == Verdict::kInconclusive || r.verdict == Verdict::kError) return;
  if (auto it = o.known_issues.find(r.id); it != o.known_issues.end()) {
    r.known_issue_reason = it->second;
    r.verdict = r.verdict == Verdict::kFail ? Verdict::kKnownFailure : Verdict::kUnexpectedPass;
  }
}

// Runs one vector that passed the gate: its attempts, timing and verdict. A
// lost device fails the vector and aborts the run.
void execute(Session& s, const Vector& v, VectorResult& r, RunResult& result) {
  const TimePoint t0 = s.transport.now();
  const LineFaultCounts before = s.line;
  try {
    std::size_t faults_before = s.line.faults, recovered_before = s.line.recovered, silent_before = s.unsure_repeats;
    Attempt a = attempt(s, v, r.transcript);
    // The line: an attempt the line left unjudged (an error), or one that
    // failed after a line fault (a repeat also shifts the timing a vector
    // may rest on), says nothing sure of the device. The vector runs again
    // from its setup, up to RunOptions::retries + 1 times, and the first attempt
    // the line left alone decides; its commands are not sent twice blindly,
    // the setup puts the device back where the vector starts. (Under
    // --strict-line a line fault is the failure: nothing runs again.)
    // One run more than the exchange's repeats: a vector of fifty STOREs
    // meets the line fifty times.
    const int reruns = s.options.retries > 0 ? s.options.retries + 1 : 0;
    for (int again = 1; again <= reruns && !s.options.strict_line; ++again) {
      const bool touched =
          !a.error.empty() || (!a.failures.empty() && (s.line.faults > faults_before || s.unsure_repeats > silent_before));
      if (!touched) break;
      if (s.options.record_transcripts)
        r.transcript.push_back({s.t_ms(), false, {}, "the line touched this attempt (" +
                                    (a.error.empty() ? a.failures.front() : a.error) + "): the vector runs again from its setup",
                                {}, ""});
      faults_before = s.line.faults;
      recovered_before = s.line.recovered;
      silent_before = s.unsure_repeats;
      Attempt next = attempt(s, v, r.transcript);
      // A run again that a short poll ended, because this vector's own poll
      // for rest timed out and the axis still does not show rest, reached
      // nothing: the failure before it stands (that poll judged the clean
      // replies it got until its timeout), or a mount that never shows rest
      // would pass on a line with a fault in that poll's minutes.
      if (next.rest_unseen && s.rest_timed_out_in == v.id) {
        if (s.options.record_transcripts)
          r.transcript.push_back({s.t_ms(), false, {}, "the mount still does not show rest (" + next.inconclusive +
                                      "): the failure of the attempt before stands", {}, ""});
        break;
      }
      a = std::move(next);
    }
    // An attempt that ended with every fault of its own recovered settled
    // those of the attempts before it.
    if (a.error.empty() && s.line.faults - faults_before == s.line.recovered - recovered_before)
      s.line.recovered = before.recovered + (s.line.faults - before.faults);
    r.failures = std::move(a.failures);
    r.inconclusive_reason = std::move(a.inconclusive);
    r.error_reason = std::move(a.error);
    // --repeat re-runs failures only: an inconclusive vector is not one.
    if (!r.failures.empty() && s.options.repeat > 0) repeat_failing(s, v, s.options.repeat, r);
  } catch (const TransportLost& e) {
    r.failures.push_back(std::string(kDeviceLostFailure) + e.what());
    result.aborted = true;
    result.abort_reason = std::string("device lost during ") + v.id + ": " + e.what();
    result.stopped_by = "lost device";
  }
  r.duration_ms = std::chrono::duration<double, std::milli>(s.transport.now() - t0).count();
  r.line = {s.line.exchanges - before.exchanges, s.line.faults - before.faults, s.line.recovered - before.recovered,
            s.line.repeats - before.repeats, s.line.surveyed - before.surveyed};
  if (!s.transport.is_a_line()) r.line = {};  // no line, no line figures: every fault was the device's
  set_verdict(r, s.options);
}

// Journal: the run's counts, and the result handed to the caller at once.
void journal(RunResult& result, VectorResult r, const RunOptions& o) {
  switch (r.verdict) {
    case Verdict::kPass: ++result.passed; break;
    case Verdict::kFail: ++result.failed; break;
    case Verdict::kSkip:
      ++result.skipped;
      ++result.skipped_by_cause[r.skip_cause];
      break;
    case Verdict::kKnownFailure: ++result.known; break;
    case Verdict::kUnexpectedPass: ++result.unexpected; break;
    case Verdict::kInconclusive: ++result.inconclusive; break;
    case Verdict::kError: ++result.errors; break;
  }
  result.vectors.push_back(std::move(r));
  if (o.on_result) o.on_result(result.vectors.back());
  if (!o.keep_transcripts) result.vectors.back().transcript = {};
}

bool expects_silence(const Vector& v) {
  return std::any_of(v.steps.begin(), v.steps.end(),
                     [](const Step& s) { return s.expect.kind == Expectation::Kind::kSilence; });
}

void abort_run(RunResult& result, std::string why) {
  result.aborted = true;
  result.abort_reason = std::move(why);
}

// -x/--exitfirst: the run ends after `failed`, the first vector that fails
// it, when vectors are left; the reason names it and the vectors that did not run (the first ten,
// and how many more; RunResult::not_run has them all).
void stop_at_first_failure(RunResult& result, const std::string& failed,
                           const std::vector<std::reference_wrapper<const Vector>>& order, std::size_t next) {
  for (std::size_t i = next; i < order.size(); ++i) result.not_run.push_back(order[i].get().id);
  std::string why = "stopped at the first failure (--exitfirst): " + failed + " failed; " +
                    std::to_string(result.not_run.size()) + " vector(s) did not run: ";
  constexpr std::size_t kNamed = 10;
  for (std::size_t i = 0; i < result.not_run.size() && i < kNamed; ++i) why += (i ? ", " : "") + result.not_run[i];
  if (result.not_run.size() > kNamed) why += " and " + std::to_string(result.not_run.size() - kNamed) + " more";
  abort_run(result, std::move(why));
}

// The order the vectors run in: as given, except that `as-found` vectors
// come first. They read stored data as the profile describes it, which a
// destructive vector may change for good (46h deletes the STORE list, which
// the protocol cannot write back: §3.23).
std::vector<std::reference_wrapper<const Vector>> run_order(const std::vector<Vector>& vectors) {
  std::vector<std::reference_wrapper<const Vector>> order(vectors.begin(), vectors.end());
  std::stable_partition(order.begin(), order.end(), [](const Vector& v) { return v.has_tag("as-found"); });
  return order;
}

}  // namespace

RunResult Runner::run(const std::vector<Vector>& vectors) {
  RunResult result;
  result.strict = options_.strict;
  for (const VectorResult& r : options_.kept) journal(result, r, RunOptions{});  // counted, not handed on
  if (options_.backup) result.backup = *options_.backup;
  Session s(transport_, profile_, options_);

  // A device that sends bytes is reachable, however wrong they are: its
  // vectors run and say what is wrong. Only silence ends the run here.
  result.liveness.push_back(s.liveness("before the first vector"));
  if (!result.liveness.back().alive && !result.liveness.back().heard) {
    abort_run(result, "the device did not answer: " + result.liveness.back().detail);
    return result;
  }
  result.measured_turnaround = s.turnaround.max();

  int dead_probes = 0;
  const auto order = run_order(vectors);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Vector& v = order[i];
    if (const std::string_view signal = options_.stop ? options_.stop() : ""; !signal.empty()) {
      abort_run(result, "stopped by " + std::string(signal));
      result.stopped_by = signal;
      break;
    }
    VectorResult r = result_of(v);
    if (auto why = skip_reason(v, options_, profile_, transport_)) {
      r.verdict = Verdict::kSkip;
      r.skip_cause = why->cause;
      r.skip_reason = std::move(why->reason);
    } else {
      if (v.has_tag("destructive") && options_.backup_stored_data && !result.backup.taken) {
        std::string error;
        try {
          result.backup = detail::take_backup(s, error);
        } catch (const TransportLost& e) {
          abort_run(result, std::string("device lost while backing up stored data: ") + e.what());
          result.stopped_by = "lost device";
          break;
        }
        // The file is what is left when the run (or the machine) dies before
        // the restore: no destructive vector runs without it.
        if (!error.empty()) {
          abort_run(result, error + "; no destructive vector runs without it");
          break;
        }
        if (options_.on_backup) options_.on_backup(result.backup);
      }
      execute(s, v, r, result);
    }
    const bool probe = r.verdict != Verdict::kSkip && expects_silence(v);
    const bool fails_run = r.counts_as_failure(options_.strict);
    journal(result, std::move(r), options_);
    if (result.aborted) break;
    if (options_.exit_first && fails_run && i + 1 < order.size()) {  // the last one cuts nothing short
      stop_at_first_failure(result, v.id, order, i + 1);
      break;
    }
    // After an ignore path, make sure the device did not silently die.
    if (!probe) continue;
    result.liveness.push_back(s.liveness("after " + v.id));
    if (result.liveness.back().alive) {
      dead_probes = 0;
    } else if (++dead_probes >= 3) {
      abort_run(result, "no answer to three liveness probes");
      break;
    }
  }
  if (result.backup.taken) {
    try {
      detail::restore_backup(s, result.backup, result.restore_notes);
    } catch (const TransportLost& e) {
      result.restore_notes.push_back(std::string("stored data not restored, the device is lost: ") + e.what());
    }
  }
  if (!result.aborted || (!result.stopped_by.empty() && result.stopped_by != "lost device")) result.liveness.push_back(s.liveness("after the last vector"));
  result.measured_turnaround = s.turnaround.max();
  result.bytes_sent = s.bytes_sent;
  result.bytes_received = s.bytes_received;
  result.silence_listened = s.silence_listened;
  result.silence_windows = s.silence_windows;
  result.line = s.line;
  if (!transport_.is_a_line()) result.line = {};  // no line, no line figures: every fault was the device's
  return result;
}

}  // namespace sabus::harness
