// The version of sabus: the suite's version (project VERSION in
// CMakeLists.txt) and the revision of the source tree it was built from
// (`git describe --always --dirty`, taken at build time by
// cmake/source_revision.cmake, or why there is none).
#pragma once

#include <string>

namespace sabus::cli {

// "0.1.0 (git aab3ef4-dirty)"; what `sabus --version` prints first and what
// every report carries (RunDocument::generator, "sabus " + this).
std::string full_version();

// `sabus --version`: the full version, then the data directory found (or the
// places looked in).
std::string version_text();

}  // namespace sabus::cli
