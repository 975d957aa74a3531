// Fuzz target: the vector loader's schema layer (load_vector_tree: files,
// groups, vectors, steps, sends, modifiers, expectations, matchers,
// requirements) on YAML trees read from tree text (vector_tree.hpp), so no
// YAML parsing stands between the input and the schema. fuzz_vector_loader
// covers the parser and the linter on whole files.
// Oracles: every error names the file and says why; a file with errors is
// left out and a file without is kept; each loaded vector (the first
// kRoundTrips of a file) written back as a file of its own
// (vector_file_text) loads again without error, and writes back the same
// text: the loader keeps everything it reads, the same way each time.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sabus/harness/vector_loader.hpp"
#include "vector_tree.hpp"

namespace {

using sabus::fuzz::parse_tree;
using sabus::fuzz::vector_file_text;

// Aliases can make a file of thousands of vectors; a few show the round trip.
constexpr std::size_t kRoundTrips = 8;
const std::string kName = "fuzz.yaml";

[[noreturn]] void fail(const std::string& why, const std::string& detail) {
  std::fprintf(stderr, "%s\n%s\n", why.c_str(), detail.c_str());
  std::abort();
}

void round_trip(const sabus::harness::VectorFile& file, const sabus::harness::Vector& vector) {
  const std::string written = vector_file_text(file, vector);
  const auto again = sabus::harness::load_vector_tree(parse_tree(written), kName);
  if (!again.ok()) fail("a loaded vector written back does not load: " + again.errors.front().text(), written);
  const auto& file2 = again.files.front();
  if (file2.vectors.size() != 1) fail("a vector written back loads as " + std::to_string(file2.vectors.size()), written);
  const std::string rewritten = vector_file_text(file2, file2.vectors.front());
  if (written != rewritten) fail("a loaded vector written back loads as another vector", written + "\n" + rewritten);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const YAML::Node tree = parse_tree({reinterpret_cast<const char*>(data), size});
  const auto r = sabus::harness::load_vector_tree(tree, kName);
  for (const auto& e : r.errors)
    if (e.message.empty() || e.where.file != kName) fail("an error without its file or reason", e.text());
  if (r.ok() != (r.files.size() == 1)) fail("a file with errors kept, or one without left out", "");
  if (!r.ok()) return 0;
  const auto& file = r.files.front();
  for (std::size_t i = 0; i < file.vectors.size() && i < kRoundTrips; ++i) round_trip(file, file.vectors[i]);
  return 0;
}
