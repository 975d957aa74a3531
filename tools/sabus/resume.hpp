// `sabus run --resume FILE`: what the command line may add to a stopped
// run's own options, the vectors left to run, the device checked to be the
// one the stopped run ran on, and the stopped run's stored-data backup read
// back. The stopped run itself is read by reports (resume.hpp); run.cpp
// turns its options back into the command's.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/runner.hpp"
#include "sabus/harness/vector.hpp"
#include "sabus/reports/document.hpp"
#include "sabus/reports/resume.hpp"

namespace sabus::cli {

// A stopped run to continue, and the stored-data backup it took (empty when
// it took none).
struct Resume {
  reports::StoppedRun stopped;
  std::shared_ptr<const harness::StoredDataBackup> backup;
};

// --resume FILE: the stopped run and its backup read back; nullopt after
// printing why not (exit 2). The options of `sabus run` that --resume takes
// besides the stopped run's own are where the device is now (an adapter that
// came back as another port, a terminal server on another address) and the
// serial backend; any other given with it is an error naming it: the
// stopped run's options say what the one run checks, and its reports where
// they go.
std::optional<Resume> read_resume(const std::string& file, const CLI::App& sub);

// The vectors of `selection` the stopped run did not finish, in selection
// order; nullopt after printing why not (exit 2): a vector it finished is
// not selected now (the suite or the vector files changed since), or it was
// killed after a destructive vector ran and its journal has no backup
// record naming the backup file (a journal of an earlier sabus).
std::optional<std::vector<harness::Vector>> vectors_left(const std::vector<harness::Vector>& selection, const Resume& r);

// Whether `now` (the device type reply, 30h, §3.1) is the device the stopped
// run ran on: kExitOk, or the exit status after printing why: 3 when the
// device does not answer, 2 when it is another controller type or firmware
// (or cannot say which it is).
int check_same_device(const Resume& r, const reports::Identity& now);

// The resumed run's document before its journal is opened: the stopped
// run's start, its earlier stops and this one.
void resume_document(reports::RunDocument& doc, const Resume& r);
// After the journal is opened with the kept vectors: the same in the
// document (compacted for the reports), and for the runner to count as its
// own (RunOptions::kept), with the backup to restore (RunOptions::backup).
void keep_vectors(reports::RunDocument& doc, harness::RunOptions& ro, const Resume& r);
// The console's line: "resuming F, stopped by SIGINT at T: 9 vector(s) kept, 14 vector(s) to run"
// ("resuming F, killed at T: ..." for a run killed outright).
std::string resume_line(const Resume& r, std::size_t to_run);

}  // namespace sabus::cli
