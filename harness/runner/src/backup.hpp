// The stored-data backup of destructive runs (backup.cpp), private to the runner.
#pragma once

#include <string>
#include <vector>

#include "session.hpp"

namespace sabus::harness::detail {

// Reads the STORE list's names (35h), the preset satellites (3Ah), TLEs (3Ch),
// signposts (44h, with the DVB option) and the navigation data (45h); writes
// the JSON to RunOptions::backup_path when one is set (a new file: never over
// one that is there). A file that cannot be written sets `error`; the backup
// is returned all the same.
StoredDataBackup take_backup(Session& s, std::string& error);
// Writes back what differs from the backup; appends one note per slot
// restored and per thing the protocol cannot restore (kept when the device
// is lost half way: TransportLost).
void restore_backup(Session& s, const StoredDataBackup& b, std::vector<std::string>& notes);

}  // namespace sabus::harness::detail
