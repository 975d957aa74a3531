// What a real RC3000 keeps in non-volatile memory, saved to and restored from
// a JSON file, so that a restarted `sabus sim` keeps it too: the STORE list,
// preset satellites, TLEs, signposts, navigation data, and where the antenna
// stands (a powered-off antenna does not move).
#pragma once

#include <string>
#include <vector>

#include "sabus/harness/controller.hpp"

namespace sabus::harness {

// One JSON document for all controllers of a bus, keyed by decimal address.
std::string save_state(const std::vector<const Controller*>& controllers);
// Restores every controller whose address is in the document; false with
// `error` set when the document is not a state file.
bool load_state(const std::string& json, const std::vector<Controller*>& controllers, std::string& error);

// Whole or not at all (replace_file, files.hpp): a reader finds the old
// state or the new one, and no file beside PATH is replaced.
bool write_state_file(const std::string& path, const std::vector<const Controller*>& controllers, std::string& error);
// A missing file is not an error (first start); returns true.
bool read_state_file(const std::string& path, const std::vector<Controller*>& controllers, std::string& error);

}  // namespace sabus::harness
