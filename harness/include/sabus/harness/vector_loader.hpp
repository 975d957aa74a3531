// Reads vector files (vectors/*.yaml) and lints the suite. Every error names
// file:line:column, the vector id and the key: unknown keys, wrong types,
// duplicate keys (which yaml-cpp accepts silently), commands, forms and fields
// the codecs do not know, lengths that contradict the catalog.
#pragma once

#include <string>
#include <vector>

#include "sabus/harness/vector.hpp"

namespace sabus::harness {

struct LoadResult {
  std::vector<VectorFile> files;
  std::vector<LoadError> errors;
  bool ok() const { return errors.empty(); }
};

LoadResult load_vector_text(const std::string& yaml, const std::string& name);
LoadResult load_vector_file(const std::string& path);
// Files, or directories searched recursively for *.yaml (except profiles/ and examples/).
LoadResult load_vectors(const std::vector<std::string>& paths);

// Suite-wide checks beyond one file: unique ids, every flag defined in its
// file's notes, every referenced command, form and field known to the codecs.
std::vector<LoadError> lint(const std::vector<VectorFile>& files);

// vectors/ in the source tree.
std::string default_vectors_dir();

}  // namespace sabus::harness
