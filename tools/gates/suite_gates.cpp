// The vector suite's gates (issue "The vector suite"), run by the test command:
//  1. profiles: every vector passes (or is skipped by its requirements) on
//     the reference controller with every shipped profile (vectors/profiles);
//  2. mutation: for every injected fault (faults.hpp), the suite fails at
//     least one must-level vector on some shipped profile, as
//     `sabus run --sim --fault NAME --profile P --allow-motion
//     --allow-destructive` would. Prints the score, caught / faults.
// Exit 0 when every profile passes, the score is 100% and there are at least
// kMinFaults faults; 1 otherwise; 2 when the suite or a profile does not load.
//
// usage: suite_gates [VECTORS_DIR [PROFILES_DIR]]
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/faults.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

constexpr std::size_t kMinFaults = 25;

RunResult run_suite(const Profile& profile, const std::vector<Vector>& vectors, FaultSet faults) {
  auto transport = make_in_process_transport(bus_of(profile), faults);
  RunOptions o;
  o.allow_motion = true;
  o.allow_destructive = true;
  return Runner(*transport, profile, o).run(vectors);
}

std::vector<std::string> failed_must_vectors(const RunResult& r) {
  std::vector<std::string> ids;
  for (const auto& v : r.vectors)
    if (v.verdict == Verdict::kFail && v.level == Level::kMust) ids.push_back(v.id);
  return ids;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string vectors_dir = argc > 1 ? argv[1] : default_vectors_dir();
  const fs::path profiles_dir = argc > 2 ? fs::path(argv[2]) : fs::path(default_profile_path()).parent_path();

  LoadResult suite = load_vectors({vectors_dir});
  auto lint_errors = lint(suite.files);
  suite.errors.insert(suite.errors.end(), lint_errors.begin(), lint_errors.end());
  for (const auto& e : suite.errors) std::cerr << e.text() << "\n";
  if (!suite.ok()) return 2;
  std::vector<Vector> vectors;
  for (const auto& f : suite.files) vectors.insert(vectors.end(), f.vectors.begin(), f.vectors.end());

  // The default profile first: most faults show there, and the search stops
  // at the first profile that catches a fault.
  std::vector<Profile> profiles;
  std::vector<fs::path> paths;
  for (const auto& e : fs::directory_iterator(profiles_dir))
    if (e.path().extension() == ".yaml") paths.push_back(e.path());
  std::sort(paths.begin(), paths.end());
  std::stable_partition(paths.begin(), paths.end(),
                        [](const fs::path& p) { return p == fs::path(default_profile_path()); });
  for (const auto& p : paths) {
    ProfileResult loaded = load_profile_file(p.string());
    if (!loaded) {
      std::cerr << loaded.error->text() << "\n";
      return 2;
    }
    profiles.push_back(*loaded.profile);
  }

  bool ok = true;
  std::cout << fmt::format("== profiles: {} vectors on each shipped profile\n", vectors.size());
  for (const Profile& p : profiles) {
    const RunResult r = run_suite(p, vectors, {});
    const bool pass = r.failed == 0 && r.unexpected == 0 && !r.aborted && r.exit_code() == 0;
    ok = ok && pass;
    std::cout << fmt::format("{:<28} {:>4} passed, {} failed, {:>4} skipped{}{}\n", p.name, r.passed, r.failed, r.skipped,
                             r.aborted ? ", ABORTED: " + r.abort_reason : "", pass ? "" : "  FAIL");
    for (const auto& v : r.vectors)
      if (v.verdict == Verdict::kFail)
        std::cout << fmt::format("    {} ({}): {}\n", v.id, to_string(v.level), v.failures.empty() ? "" : v.failures[0]);
  }

  std::cout << "== mutation: each injected fault must fail a must-level vector\n";
  std::size_t caught = 0;
  const auto faults = all_faults();
  for (const FaultInfo& f : faults) {
    FaultSet set;
    set.set(f.fault);
    std::string where;
    for (const Profile& p : profiles) {
      const auto failed = failed_must_vectors(run_suite(p, vectors, set));
      if (failed.empty()) continue;
      where = fmt::format("{}: {} must vector(s), e.g. {}", p.name, failed.size(), failed.front());
      break;
    }
    caught += !where.empty();
    std::cout << fmt::format("{:<30} {}\n", f.name, where.empty() ? "NOT CAUGHT: " + std::string(f.description) : where);
  }
  const double score = faults.empty() ? 0.0 : 100.0 * static_cast<double>(caught) / static_cast<double>(faults.size());
  std::cout << fmt::format("mutation score: {}/{} faults caught ({:.1f}%)\n", caught, faults.size(), score);
  if (faults.size() < kMinFaults) {
    std::cout << fmt::format("FAIL: {} faults, the gate needs at least {}\n", faults.size(), kMinFaults);
    ok = false;
  }
  if (caught != faults.size()) ok = false;
  std::cout << (ok ? "suite gates: pass\n" : "suite gates: FAIL\n");
  return ok ? 0 : 1;
}
