// Where sabus finds the data it reads at run time: the vector suite
// (vectors/), the device profiles (vectors/profiles/) and the errata the
// linter checks flags against (protocol/ERRATA.md). A data directory has the
// source tree's layout for these files, so a source tree is one and an
// installation copies them to <prefix>/share/sabus.
//
// The places, in order:
//   1. the --data-dir option (set_data_dir_option),
//   2. the SABUS_DATA_DIR environment variable,
//   3. share/sabus beside the running executable's bin/ (an installation),
//   4. the source tree the program was built from.
// The first two are the user's explicit choice: when one is given and holds
// no data, that is the error, with no fall-through to a place not asked for.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sabus::harness {

enum class DataDirSource { kOption, kEnvironment, kInstalled, kSourceTree };

// The candidate of each place; an empty string is a place not set (no
// option, no variable, no executable path known).
struct DataDirPlaces {
  std::string option;
  std::string environment;
  std::string installed;    // <exe dir>/../share/sabus (the relative part from the install layout)
  std::string source_tree;
};

struct DataDir {
  std::optional<std::string> path;  // the directory found
  DataDirSource source = DataDirSource::kSourceTree;
  // One line per place looked in, with why it was not taken ("--data-dir
  // /x: no vectors/ directory there"); for the error and for --version.
  std::vector<std::string> looked_in;
  // "no sabus data directory (vectors, profiles, errata) found; looked in: ..."
  std::string error() const;
  // "/usr/share/sabus (installed beside the executable)"
  std::string describe() const;
};

// Pure but for the file-system checks: the first place that holds the data.
DataDir find_data_dir(const DataDirPlaces& places);

// The places of this process: the option given, $SABUS_DATA_DIR, the
// executable's installation (/proc/self/exe) and the source tree it was built
// from.
DataDirPlaces this_process_places();
DataDir find_data_dir();

// --data-dir: takes precedence over every other place for this process.
void set_data_dir_option(std::string dir);

// Thrown by data_path when no place holds the data; what() is DataDir::error().
struct DataDirNotFound : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `relative` (e.g. "vectors/profiles") inside this process's data directory.
std::string data_path(std::string_view relative);
// The data directory found, and where it came from; throws DataDirNotFound.
DataDir require_data_dir();

}  // namespace sabus::harness
