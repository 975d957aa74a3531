// An earlier run read back for a re-run (`sabus run --last-failed FILE`,
// `--failed-first FILE`): the ids of the vectors that failed or ended in
// error in it.
#pragma once

#include <optional>
#include <set>
#include <string>

namespace sabus::reports {

struct EarlierRun {
  std::string file;              // the file read (DIR/run.json for a folder)
  // VectorRecord::is_failure() (fail, unexpected pass; a lost device's is a
  // fail) or is_error() (the line left it unjudged)
  std::set<std::string> failed;
  std::size_t vectors = 0;       // vectors it holds
};

// Reads a run JSON, or the journal of a run that did not end, through the
// run document's own readers (read_run_or_journal); a folder means its
// run.json. nullopt with `error` naming the file and what is wrong.
std::optional<EarlierRun> read_earlier_run(const std::string& path, std::string& error);

}  // namespace sabus::reports
