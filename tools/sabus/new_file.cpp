// New files under names a command makes (new_file.hpp): the folder made,
// then harness/files' write_new_file, the one writer of new files.
#include "new_file.hpp"

#include "sabus/harness/files.hpp"

namespace sabus::cli {

namespace fs = std::filesystem;

std::optional<fs::path> write_new_file(const fs::path& dir, const std::string& stem, const std::string& extension,
                                       const std::string& text, std::string& error) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    error = "cannot create the folder " + dir.string() + ": " + ec.message();
    return std::nullopt;
  }
  const auto written = harness::write_new_file((dir / (stem + extension)).string(), text, error);
  if (!written) return std::nullopt;
  return fs::path(*written);
}

}  // namespace sabus::cli
