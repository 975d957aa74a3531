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

// The options of `sabus run` that --resume takes besides the stopped run's
// own: where the device is now (an adapter that came back as another port, a
// terminal server on another address), the serial backend. Any other option
// given with --resume is an error naming it: the stopped run's options say
// what the one run checks, and its reports where they go.
std::string resume_option_conflicts(const CLI::App& sub);

// The vectors of `selection` the stopped run did not finish, in selection
// order; nullopt with `error` when a vector it finished is not selected now
// (the suite or the vector files changed since), or when it was killed after
// a destructive vector ran (its journal does not name the backup file).
std::optional<std::vector<harness::Vector>> vectors_left(const std::vector<harness::Vector>& selection,
                                                         const reports::StoppedRun& stopped, std::string& error);

// Whether `now` (the device type reply, 30h, §3.1) is the device the stopped
// run ran on: kExitOk, or the exit status after printing why: 3 when the
// device does not answer, 2 when it is another controller type or firmware
// (or cannot say which it is).
int check_same_device(const reports::Identity& stopped, const reports::Identity& now, const std::string& file);

// The stopped run's stored-data backup (its `backup`), read back; an empty
// pointer when it took none; nullopt with `error` when the file cannot be
// read (the restore at the end would not be complete without it).
std::optional<std::shared_ptr<const harness::StoredDataBackup>> stopped_backup(const reports::RunDocument& stopped,
                                                                               std::string& error);

}  // namespace sabus::cli
