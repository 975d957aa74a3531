// What the gates run: the linted suite and the shipped profiles, loaded
// alike by each gate (suite_gates, noise_gates). A load error is printed
// and the gate exits 2.
#pragma once

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::gates {

// Every vector of the suite in `dir`, after the linter; nullopt (the errors
// printed) when a file does not load or lint.
inline std::optional<std::vector<harness::Vector>> load_linted_suite(const std::string& dir) {
  harness::LoadResult suite = harness::load_vectors({dir});
  auto lint_errors = harness::lint(suite.files);
  suite.errors.insert(suite.errors.end(), lint_errors.begin(), lint_errors.end());
  for (const auto& e : suite.errors) std::cerr << e.text() << "\n";
  if (!suite.ok()) return std::nullopt;
  std::vector<harness::Vector> vectors;
  for (const auto& f : suite.files) vectors.insert(vectors.end(), f.vectors.begin(), f.vectors.end());
  return vectors;
}

// The profiles (*.yaml) in `dir` by file name, `first` (if among them) at
// the front; nullopt (the error printed) when one does not load.
inline std::optional<std::vector<harness::Profile>> load_profiles(const std::filesystem::path& dir,
                                                                  const std::filesystem::path& first = {}) {
  std::vector<std::filesystem::path> paths;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".yaml") paths.push_back(e.path());
  std::sort(paths.begin(), paths.end());
  std::stable_partition(paths.begin(), paths.end(), [&](const std::filesystem::path& p) { return p == first; });
  std::vector<harness::Profile> profiles;
  for (const auto& p : paths) {
    harness::ProfileResult loaded = harness::load_profile_file(p.string());
    if (!loaded) {
      std::cerr << loaded.error->text() << "\n";
      return std::nullopt;
    }
    profiles.push_back(*loaded.profile);
  }
  return profiles;
}

}  // namespace sabus::gates
