// Fuzz target: the conformance vector loader and linter (vectors/*.yaml) on
// any text.
// Oracles: a malformed file gives errors that name the file, a line and why
// (never a crash, a hang or an unbounded allocation: the run's
// -malloc_limit_mb and -rss_limit_mb catch those); a file with errors is left
// out of the result; the linter runs on whatever loaded; loading is
// deterministic.
#include <cstdlib>
#include <string>

#include "sabus/harness/vector_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto r = sabus::harness::load_vector_text(text, "fuzz.yaml");
  for (const auto& e : r.errors)
    if (e.message.empty() || e.where.file != "fuzz.yaml") std::abort();  // an error must say why and where
  if (!r.ok() && !r.files.empty()) std::abort();                          // a half-read file is not kept
  if (r.ok() && r.files.size() != 1) std::abort();
  const auto lint = sabus::harness::lint(r.files);
  for (const auto& e : lint)
    if (e.message.empty()) std::abort();
  const auto again = sabus::harness::load_vector_text(text, "fuzz.yaml");
  if (again.errors.size() != r.errors.size() || again.files.size() != r.files.size()) std::abort();
  for (std::size_t i = 0; i < r.errors.size(); ++i)
    if (again.errors[i].text() != r.errors[i].text()) std::abort();  // loading is not deterministic
  return 0;
}
