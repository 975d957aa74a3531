// The failures of an earlier run, read back through the run document's
// readers, for --last-failed and --failed-first.
#include "sabus/reports/rerun.hpp"

#include <filesystem>

#include "sabus/reports/journal.hpp"

namespace sabus::reports {

std::optional<EarlierRun> read_earlier_run(const std::string& path, std::string& error) {
  namespace fs = std::filesystem;
  EarlierRun run;
  std::error_code ec;
  run.file = fs::is_directory(path, ec) ? (fs::path(path) / "run.json").string() : path;
  if (!fs::exists(run.file, ec)) {
    error = run.file + ": no such file (give the run.json of an earlier `sabus run --json` or --report-dir)";
    return std::nullopt;
  }
  JournalNotes notes;
  const auto doc = read_run_or_journal(run.file, notes, error);
  if (!doc) return std::nullopt;
  run.vectors = doc->vectors.size();
  // The vectors that failed or ended in error (issue 34): a vector the line
  // left unjudged is one to run again as much as a failure.
  for (const auto& v : doc->vectors)
    if (v.is_failure() || v.is_error()) run.failed.insert(v.id);
  return run;
}

}  // namespace sabus::reports
