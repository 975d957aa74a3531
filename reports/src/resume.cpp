// A stopped run read back for `sabus run --resume`, and the resumed run made
// one run with it (resume.hpp).
#include "sabus/reports/resume.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <ctime>
#include <filesystem>

#include "sabus/reports/journal.hpp"

namespace sabus::reports {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kJournalSuffix = ".journal.jsonl";

// The time a file was last written, UTC, as utc_now() writes it; "" when it
// cannot be read.
std::string modified_at(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "";
  std::tm tm{};
  gmtime_r(&st.st_mtime, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// The enumerator whose name (the harness's to_string) is `name`: every one
// the harness names, so that an outcome added there reads back here.
template <class E>
E named(std::string_view name, E fallback) {
  for (unsigned i = 0; i <= 0xFF; ++i)
    if (const auto e = static_cast<E>(i); harness::to_string(e) == name) return e;
  return fallback;
}

}  // namespace

std::optional<StoppedRun> read_stopped_run(const std::string& path, std::string& error) {
  StoppedRun s;
  std::error_code ec;
  const std::string file = fs::is_directory(path, ec) ? (fs::path(path) / "run.json").string() : path;
  auto fail = [&](const std::string& why) -> std::optional<StoppedRun> {
    error = file + ": " + why;
    return std::nullopt;
  };
  if (!fs::exists(file, ec)) return fail("no such file (give the run.json of a stopped `sabus run`, or its journal)");
  std::optional<RunDocument> doc;
  std::string journal;
  JournalNotes notes;
  if (is_journal(file)) {
    if (!file.ends_with(kJournalSuffix)) return fail("a run journal is named RUN.journal.jsonl, beside its RUN.json");
    s.json = file.substr(0, file.size() - kJournalSuffix.size()) + ".json";
    // The resumed run writes the stopped run's JSON and no other file: one
    // that is not there was not the stopped run's.
    if (!fs::exists(s.json, ec)) return fail("the run JSON of this journal, " + s.json + ", is not there");
    journal = file;
    doc = read_journal(file, notes, error);
  } else {
    s.json = file;
    journal = journal_path_for(file);
    doc = read_run_file(file, error);
    if (doc && doc->status == "running") {
      // Killed (or still going): the JSON was written at the start, the
      // vectors are in the journal.
      if (!fs::exists(journal, ec)) return fail("the run did not end (status \"running\") and its journal, " + journal + ", is not there");
      doc = read_journal(journal, notes, error);
    }
  }
  if (!doc) return std::nullopt;
  const int code = doc->summary ? doc->summary->exit_code : 0;
  if (doc->status == "complete")
    return fail(fmt::format("the run ran to its end (exit {}): there is nothing to resume (`sabus run --last-failed {}` runs "
                            "its failures again)",
                            code, file));
  if (doc->status == "aborted" && !doc->stopped())
    return fail(fmt::format("the run was ended by what it found, not stopped by the bench ({}; exit {}): only a run stopped by "
                            "SIGINT, SIGTERM or a lost device (exit {}), or killed, is resumed",
                            doc->abort_reason, code, harness::kStoppedExitCode));
  if (doc->status != "aborted" && doc->status != "running") return fail("status \"" + doc->status + "\" is not a run's");
  if (!doc->invocation)
    return fail("the run does not record how it was run (`invocation`, written by sabus since --resume): run it again");

  const bool killed = doc->status == "running";
  s.stop.stopped_by = killed ? "killed" : doc->stopped_by;
  // A killed run has no end: its journal's last write is the last vector's.
  s.stop.stopped_at = killed ? modified_at(journal) : doc->finished_at;
  s.stop.abort_reason = doc->abort_reason;
  s.stop.restore = doc->restore;
  std::vector<VectorRecord> kept;
  for (auto& v : doc->vectors) {
    if (v.lost_device()) s.rerun.push_back(v.id);
    else kept.push_back(std::move(v));
  }
  s.stop.kept = kept.size();
  doc->vectors = std::move(kept);
  s.doc = std::move(*doc);
  return s;
}

harness::VectorResult kept_result(const VectorRecord& v) {
  harness::VectorResult r;
  r.id = v.id;
  r.paragraph = v.paragraph;
  r.file = v.file;
  r.quote = v.quote;
  r.comment = v.comment;
  r.level = named(v.level, harness::Level::kMust);
  r.verdict = named(v.outcome, harness::Verdict::kFail);
  r.failures = v.failures;
  r.inconclusive_reason = v.inconclusive_reason;
  r.error_reason = v.error_reason;
  r.line = v.line;
  r.skip_reason = v.skip_reason;
  r.skip_cause = named(v.skip_cause, harness::SkipCause::kNone);
  r.known_issue_reason = v.known_issue;
  r.duration_ms = v.duration_ms;
  r.repeats = v.repeats;
  r.repeat_failures = v.repeat_failures;
  return r;
}

void add_stopped_run(RunDocument& doc, const RunDocument& stopped) {
  std::vector<Liveness> liveness = stopped.liveness;
  liveness.insert(liveness.end(), doc.liveness.begin(), doc.liveness.end());
  doc.liveness = std::move(liveness);
  // The line figures of the whole run: the stopped part's exchanges too.
  if (doc.summary && stopped.summary) doc.summary->line += stopped.summary->line;
  for (const char* sum : {"bytes_sent", "bytes_received", "silence_windows"})
    if (const auto it = stopped.traffic.find(sum); it != stopped.traffic.end() && it->is_number_unsigned() && doc.traffic.contains(sum))
      doc.traffic[sum] = doc.traffic[sum].get<std::uint64_t>() + it->get<std::uint64_t>();
  if (const auto it = stopped.traffic.find("silence_listened_ms"); it != stopped.traffic.end() && it->is_number() &&
                                                                   doc.traffic.contains("silence_listened_ms"))
    doc.traffic["silence_listened_ms"] = doc.traffic["silence_listened_ms"].get<double>() + it->get<double>();
  if (const auto it = stopped.traffic.find("measured_turnaround_ms"); it != stopped.traffic.end() && it->is_number() &&
                                                                      doc.traffic.contains("measured_turnaround_ms"))
    doc.traffic["measured_turnaround_ms"] = std::max(doc.traffic["measured_turnaround_ms"].get<double>(), it->get<double>());
}

}  // namespace sabus::reports
