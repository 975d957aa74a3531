// The one lookup of the data directory (data_dir.hpp says the order and why).
#include "sabus/harness/data_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace sabus::harness {
namespace {

namespace fs = std::filesystem;

// What makes a directory a data directory: the suite's folder. Everything
// else is looked up below it, and a missing file is reported by its reader
// with its own path.
constexpr std::string_view kMarker = "vectors";

// The --data-dir of this process (set_data_dir_option), set by the CLI
// before any command runs.
std::string& option_dir() {
  static std::string dir;
  return dir;
}

// Why `dir` is not a data directory, or nullopt when it is one.
std::optional<std::string> not_data_dir(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return "no such directory";
  if (!fs::is_directory(fs::path(dir) / kMarker, ec)) return "no " + std::string(kMarker) + "/ directory there";
  return std::nullopt;
}

std::string place_name(DataDirSource source) {
  switch (source) {
    case DataDirSource::kOption: return "--data-dir";
    case DataDirSource::kEnvironment: return "$SABUS_DATA_DIR";
    case DataDirSource::kInstalled: return "installed beside the executable";
    case DataDirSource::kSourceTree: return "source tree of this build";
  }
  return "";
}

}  // namespace

std::string DataDir::error() const {
  std::string out = "no sabus data directory (vectors/, vectors/profiles/, protocol/ERRATA.md) found; looked in:";
  for (const auto& l : looked_in) out += "\n  " + l;
  out += "\ngive one with --data-dir DIR or the environment variable SABUS_DATA_DIR";
  return out;
}

std::string DataDir::describe() const {
  if (!path) return "none found";
  const bool given = source == DataDirSource::kOption || source == DataDirSource::kEnvironment;
  return *path + " (" + (given ? "from " : "") + place_name(source) + ")";
}

DataDir find_data_dir(const DataDirPlaces& places) {
  struct Place {
    DataDirSource source;
    const std::string& dir;
    bool explicit_choice;  // given by the user: a wrong one is the error, no fall-through
  };
  const Place order[] = {{DataDirSource::kOption, places.option, true},
                         {DataDirSource::kEnvironment, places.environment, true},
                         {DataDirSource::kInstalled, places.installed, false},
                         {DataDirSource::kSourceTree, places.source_tree, false}};
  DataDir found;
  for (const auto& p : order) {
    if (p.dir.empty()) {
      found.looked_in.push_back(place_name(p.source) + ": not given");
      continue;
    }
    fs::path normal = fs::path(p.dir).lexically_normal();
    if (!normal.has_filename() && normal.has_relative_path()) normal = normal.parent_path();  // "dir/" -> "dir"
    const std::string dir = normal.string();
    const auto why_not = not_data_dir(dir);
    if (!why_not) {
      found.path = dir;
      found.source = p.source;
      return found;
    }
    found.looked_in.push_back(place_name(p.source) + " " + dir + ": " + *why_not);
    if (p.explicit_choice) return found;
  }
  return found;
}

DataDirPlaces this_process_places() {
  DataDirPlaces places;
  places.option = option_dir();
  if (const char* env = std::getenv("SABUS_DATA_DIR")) places.environment = env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  // SABUS_DATA_FROM_BIN: the install layout's data directory relative to its
  // bin directory (harness/data/CMakeLists.txt), so a moved prefix still works.
  if (!ec) places.installed = (exe.parent_path() / SABUS_DATA_FROM_BIN).string();
  places.source_tree = SABUS_SOURCE_DIR;
  return places;
}

DataDir find_data_dir() { return find_data_dir(this_process_places()); }

void set_data_dir_option(std::string dir) { option_dir() = std::move(dir); }

DataDir require_data_dir() {
  DataDir d = find_data_dir();
  if (!d.path) throw DataDirNotFound(d.error());
  return d;
}

std::string data_path(std::string_view relative) {
  return (fs::path(*require_data_dir().path) / relative).lexically_normal().string();
}

}  // namespace sabus::harness
