#include "version.hpp"

#include "sabus/harness/data_dir.hpp"

namespace sabus::cli {

// Generated at build time (cmake/source_revision.cmake).
extern const char kSourceRevision[];

std::string full_version() { return std::string(SABUS_VERSION) + " (" + kSourceRevision + ")"; }

std::string version_text() {
  const harness::DataDir data = harness::find_data_dir();
  return "sabus " + full_version() + "\ndata: " + (data.path ? data.describe() : data.error());
}

}  // namespace sabus::cli
