// A stopped run read back to be continued (`sabus run --resume FILE`), and
// the resumed run's record made one run with it: the vectors the stopped run
// finished kept as they were, its counts, liveness probes and traffic added
// to the resumed run's, the stop noted (reports/SCHEMA.md, `resumptions`).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/runner.hpp"
#include "sabus/reports/document.hpp"

namespace sabus::reports {

struct StoppedRun {
  // The run JSON the resumed run writes: FILE, or for a journal FILE the
  // JSON it is beside (RUN.journal.jsonl -> RUN.json).
  std::string json;
  // The stopped run's header. Its vectors are the ones it finished, whole
  // (transcripts with their fields), in run order, less the one the device
  // was lost in (VectorRecord::lost_device): that one did not finish, and
  // runs again.
  RunDocument doc;
  // Ids of the vectors left out of doc.vectors to run again.
  std::vector<std::string> rerun;
  // The stop, for the resumed run's `resumptions` (resumed_at left "").
  Resumption stop;
};

// Reads the run JSON or the journal of a stopped run (a folder means its
// run.json; a run JSON whose run was killed, status "running", is read from
// its journal). Only a run the bench stopped (exit 4: SIGINT, SIGTERM, a
// lost device) or that was killed (a journal without an end record) can be
// resumed: a run that ran to its end, or was aborted by what it found (no
// answer to liveness probes, --exitfirst), is refused, and so is a document
// that does not record how it was run (`invocation`, written since --resume
// exists). nullopt with `error` naming the file and why.
std::optional<StoppedRun> read_stopped_run(const std::string& path, std::string& error);

// A kept vector as the runner's result (vector_record's inverse, less the
// transcript), for harness::RunOptions::kept: the runner counts it as its
// own, so that RunResult::exit_code and the summary judge the whole run.
harness::VectorResult kept_result(const VectorRecord& v);

// After finish(doc, run, ...) of the resumed run: the stopped run's liveness
// probes before the resumed run's, and its traffic added to the resumed
// run's (bytes and silence summed, the longest turnaround).
void add_stopped_run(RunDocument& doc, const RunDocument& stopped);

}  // namespace sabus::reports
