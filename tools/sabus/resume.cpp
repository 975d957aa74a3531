#include "resume.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "commands.hpp"

namespace sabus::cli {

std::string resume_option_conflicts(const CLI::App& sub) {
  static const std::set<std::string> kTaken = {"--resume", "--port", "--tcp", "--sim", "--serial-backend"};
  std::string given;
  for (const CLI::Option* opt : sub.get_options()) {
    const std::string name = opt->get_name(false, false);
    if (opt->count() > 0 && !kTaken.count(name)) given += (given.empty() ? "" : ", ") + name;
  }
  if (given.empty()) return "";
  return "--resume continues the stopped run with its own options and reports; " + given +
         " cannot be given with it (only --port, --tcp, --sim and --serial-backend, to reach the device where it is now)";
}

std::optional<std::vector<harness::Vector>> vectors_left(const std::vector<harness::Vector>& selection,
                                                         const reports::StoppedRun& stopped, std::string& error) {
  std::map<std::string, const harness::Vector*> selected;
  for (const auto& v : selection) selected[v.id] = &v;
  std::set<std::string> kept;
  for (const auto& v : stopped.doc.vectors) {
    const auto it = selected.find(v.id);
    if (it == selected.end()) {
      error = "vector " + v.id + ", which the stopped run finished, is not in its selection now: the vectors changed since; " +
              "run it again";
      return std::nullopt;
    }
    // A killed run's journal ends before its end record, which names the
    // backup file: the restore at the end could not be complete.
    if (stopped.stop.stopped_by == "killed" && v.outcome != "skip" && it->second->has_tag("destructive")) {
      error = "the run was killed after a destructive vector (" + v.id +
              ") had run, and its journal does not name the stored-data backup it took before it: the restore at the end "
              "would not be complete; restore the device from that backup and run it again";
      return std::nullopt;
    }
    kept.insert(v.id);
  }
  std::vector<harness::Vector> left;
  for (const auto& v : selection)
    if (!kept.count(v.id)) left.push_back(v);
  return left;
}

int check_same_device(const reports::Identity& stopped, const reports::Identity& now, const std::string& file) {
  auto refuse = [&](int code, const std::string& why) {
    std::cerr << "sabus run: --resume " << file << ": " << why << "\n";
    return code;
  };
  if (!now.ok) {
    // No frame came back: the device is not there (exit 3); a frame that
    // says nothing of its identity cannot show it is the same device.
    const bool silent = now.reply_hex.empty();
    return refuse(silent ? kExitUnreachable : kExitUsage,
                  "the device type query (30h, §3.1) gives no identity: " + now.error +
                      (silent ? "" : "; cannot tell it is the device the run stopped on"));
  }
  if (!stopped.ok)
    return refuse(kExitUsage, "the stopped run recorded no device identity (" + stopped.error +
                                  "): cannot tell this device is the one it ran on");
  if (now.controller_type != stopped.controller_type || now.firmware_version != stopped.firmware_version)
    return refuse(kExitUsage, fmt::format("the run stopped on controller {}, firmware {}; this device answers controller {}, "
                                          "firmware {} (30h, §3.1): a resumed run is one run on one device, so it is not "
                                          "resumed here (`sabus run` runs the suite on this one)",
                                          stopped.controller_type, stopped.firmware_version, now.controller_type,
                                          now.firmware_version));
  return kExitOk;
}

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

}  // namespace sabus::cli
