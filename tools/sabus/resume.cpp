#include "resume.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "commands.hpp"

namespace sabus::cli {
namespace {

bool refuse(const std::string& why) {
  std::cerr << "sabus run: " << why << "\n";
  return false;
}

// The options given besides those --resume takes; "" when none.
std::string options_besides_resume(const CLI::App& sub) {
  static const std::set<std::string> kTaken = {"--resume", "--port", "--tcp", "--sim", "--serial-backend"};
  std::string given;
  for (const CLI::Option* opt : sub.get_options()) {
    const std::string name = opt->get_name(false, false);
    if (opt->count() > 0 && !kTaken.count(name)) given += (given.empty() ? "" : ", ") + name;
  }
  return given;
}

// The stopped run's stored-data backup (its `backup`) read back; an empty
// pointer when it took none; nullopt with `error` when the file cannot be
// read (the restore at the end would not be complete without it).
std::optional<std::shared_ptr<const harness::StoredDataBackup>> stopped_backup(const reports::RunDocument& stopped,
                                                                               std::string& error) {
  if (stopped.backup.empty()) return std::shared_ptr<const harness::StoredDataBackup>{};
  std::ifstream in(stopped.backup, std::ios::binary);
  if (!in) {
    error = stopped.backup + ": cannot read the stopped run's stored-data backup (the restore at the end needs it)";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  auto backup = harness::StoredDataBackup::from_json(text.str(), error);
  if (!backup) {
    error = stopped.backup + ": not a stored-data backup: " + error;
    return std::nullopt;
  }
  backup->taken = true;
  backup->file = stopped.backup;
  return std::make_shared<const harness::StoredDataBackup>(std::move(*backup));
}

}  // namespace

std::optional<Resume> read_resume(const std::string& file, const CLI::App& sub) {
  if (const std::string given = options_besides_resume(sub); !given.empty()) {
    refuse("--resume continues the stopped run with its own options and reports; " + given +
           " cannot be given with it (only --port, --tcp, --sim and --serial-backend, to reach the device where it is now)");
    return std::nullopt;
  }
  std::string error;
  auto stopped = reports::read_stopped_run(file, error);
  std::optional<std::shared_ptr<const harness::StoredDataBackup>> backup;
  if (stopped) backup = stopped_backup(stopped->doc, error);
  if (!backup) {
    refuse("--resume " + error);
    return std::nullopt;
  }
  return Resume{std::move(*stopped), std::move(*backup)};
}

std::optional<std::vector<harness::Vector>> vectors_left(const std::vector<harness::Vector>& selection, const Resume& r) {
  std::map<std::string, const harness::Vector*> selected;
  for (const auto& v : selection) selected[v.id] = &v;
  const std::string file = "--resume " + r.stopped.json + ": ";
  std::set<std::string> kept;
  for (const auto& v : r.stopped.doc.vectors) {
    const auto it = selected.find(v.id);
    if (it == selected.end()) {
      refuse(file + "vector " + v.id + ", which the stopped run finished, is not in its selection now: the vectors changed "
                    "since; run it again");
      return std::nullopt;
    }
    // A killed run has no end record; its journal names the backup file in
    // a backup record, written before the first destructive vector ran. A
    // journal without one (a killed run of an earlier sabus) cannot say what
    // the device held before: the restore at the end could not be complete.
    if (r.stopped.stop.stopped_by == "killed" && r.stopped.doc.backup.empty() && v.outcome != "skip" &&
        it->second->has_tag("destructive")) {
      refuse(file + "the run was killed after a destructive vector (" + v.id +
             ") had run, and its journal does not name the stored-data backup it took before it (no backup record): the "
             "restore at the end would not be complete; restore the device from that backup and run it again");
      return std::nullopt;
    }
    kept.insert(v.id);
  }
  std::vector<harness::Vector> left;
  for (const auto& v : selection)
    if (!kept.count(v.id)) left.push_back(v);
  return left;
}

int check_same_device(const Resume& r, const reports::Identity& now) {
  const reports::Identity& stopped = r.stopped.doc.identity;
  const std::string file = "--resume " + r.stopped.json + ": ";
  if (!now.ok) {
    // No frame came back: the device is not there (exit 3); a frame that
    // says nothing of its identity cannot show it is the same device.
    const bool silent = now.reply_hex.empty();
    refuse(file + "the device type query (30h, §3.1) gives no identity: " + now.error +
           (silent ? "" : "; cannot tell it is the device the run stopped on"));
    return silent ? kExitUnreachable : kExitUsage;
  }
  if (!stopped.ok) {
    refuse(file + "the stopped run recorded no device identity (" + stopped.error +
           "): cannot tell this device is the one it ran on");
    return kExitUsage;
  }
  if (now.controller_type != stopped.controller_type || now.firmware_version != stopped.firmware_version) {
    refuse(file + fmt::format("the run stopped on controller {}, firmware {}; this device answers controller {}, firmware {} "
                              "(30h, §3.1): a resumed run is one run on one device, so it is not resumed here (`sabus run` "
                              "runs the suite on this one)",
                              stopped.controller_type, stopped.firmware_version, now.controller_type, now.firmware_version));
    return kExitUsage;
  }
  return kExitOk;
}

void resume_document(reports::RunDocument& doc, const Resume& r) {
  doc.started_at = r.stopped.doc.started_at;
  doc.resumptions = r.stopped.doc.resumptions;
  doc.resumptions.push_back(r.stopped.stop);
  doc.resumptions.back().resumed_at = reports::utc_now();
}

void keep_vectors(reports::RunDocument& doc, harness::RunOptions& ro, const Resume& r) {
  for (const auto& v : r.stopped.doc.vectors) {
    ro.kept.push_back(reports::kept_result(v));
    doc.vectors.push_back(v);
    reports::compact_for_reports(doc.vectors.back());
  }
  ro.backup = r.backup;
}

std::string resume_line(const Resume& r, std::size_t to_run) {
  const reports::StoppedRun& s = r.stopped;
  const std::string how = s.stop.stopped_by == "killed" ? "killed" : "stopped by " + s.stop.stopped_by;
  return fmt::format("resuming {}, {} at {}: {} vector(s) kept, {} vector(s) to run{}", s.json, how, s.stop.stopped_at,
                     s.doc.vectors.size(), to_run,
                     s.rerun.empty() ? std::string() : " (" + s.rerun.front() + " again: the device was lost in it)");
}

}  // namespace sabus::cli
