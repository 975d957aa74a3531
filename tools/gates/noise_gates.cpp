// The noise gates (issue 34): the suite over an emulated noisy line
// (InProcessTransport::set_line_faults, what `sabus run --sim --line-faults`
// uses) against the reference controller, with motion and destructive
// vectors allowed, on every shipped profile:
//  1. at a byte error rate of 1e-3 with the runner's line default (one
//     repeat, RunOptions::retries = 1): every vector has its clean line's
//     verdict (none fails, none is in error) and every line fault was
//     recovered, the runner's own exchanges' too (the line survey's garbled
//     replies are its measure, counted apart: LineFaultCounts::surveyed).
//     On the fixed seed: a vector in error is a legal outcome on a noisy
//     line, and over 40 seeds 10 of 262,600 vectors ended in error (a key or
//     jog whose every attempt met a fault the header does not settle: a
//     silence, or a reply garbled in its header or in the data the step
//     reads): the gate runs the fixed seed, and `noise_gates SEED` measures
//     another;
//  2. the same line with --retries 0: the run fails, and says the faults
//     were the line's;
//  3. mutation under noise: every injected fault (faults.hpp) still fails a
//     must-level vector on some shipped profile over the 1e-3 line;
//  4. the figures at 1e-3 and 1e-2 (exchanges, faults injected, faults seen
//     and recovered, vectors in error, time on the virtual clock against a
//     clean line), printed; 1e-2 is measured, not gated.
// Exit 0 when 1-3 hold; 1 otherwise; 2 when the suite or a profile does not load.
//
// usage: noise_gates [SEED]   (the line's seed; default 1)
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"

#include "shipped.hpp"

namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

struct NoisyRun {
  RunResult result;
  LineFaultTally injected;
  double virtual_s = 0;  // the run's time on the controller's clock
};

NoisyRun run_suite(const Profile& profile, const std::vector<Vector>& vectors, FaultSet faults,
                   std::optional<LineFaultSpec> line, int retries) {
  auto transport = make_in_process_transport(bus_of(profile), faults);
  if (line) transport->set_line_faults(*line);
  RunOptions o;
  o.allow_motion = true;
  o.allow_destructive = true;
  // SABUS_NOISE_EXPLAIN=1: the transcripts are kept, and a problem's shown.
  const bool explain = std::getenv("SABUS_NOISE_EXPLAIN") != nullptr;
  o.keep_transcripts = explain;
  o.record_transcripts = explain;
  o.retries = retries;
  const TimePoint t0 = transport->now();
  NoisyRun r;
  r.result = Runner(*transport, profile, o).run(vectors);
  r.injected = transport->injected_faults();
  r.virtual_s = std::chrono::duration<double>(transport->now() - t0).count();
  return r;
}

bool fails_must(const RunResult& r) {
  return std::any_of(r.vectors.begin(), r.vectors.end(),
                     [](const VectorResult& v) { return v.verdict == Verdict::kFail && v.level == Level::kMust; });
}

std::string first_words(const VectorResult& v) {
  return v.verdict == Verdict::kError ? v.error_reason : v.failures.empty() ? std::string() : v.failures.front();
}

struct Totals {
  std::size_t exchanges = 0, injected = 0, seen = 0, recovered = 0, surveyed = 0, errors = 0, vectors = 0;
  double clean_s = 0, noisy_s = 0;
};

}  // namespace

int main(int argc, char** argv) {
  const std::uint64_t seed = argc > 1 ? std::stoull(argv[1]) : 1;
  const auto suite = sabus::gates::load_linted_suite(default_vectors_dir());
  if (!suite) return 2;
  const std::vector<Vector>& vectors = *suite;
  const auto shipped = sabus::gates::load_profiles(fs::path(default_profile_path()).parent_path());
  if (!shipped) return 2;
  const std::vector<Profile>& profiles = *shipped;

  bool ok = true;
  std::vector<NoisyRun> clean_runs;  // each profile's suite on a clean line
  for (const Profile& p : profiles) clean_runs.push_back(run_suite(p, vectors, {}, std::nullopt, 1));
  for (double rate : {1e-3, 1e-2}) {
    const bool gated = rate == 1e-3;
    std::cout << fmt::format("== the suite over a line with byte error rate {:g} (seed {}), --retries 1{}\n", rate, seed,
                             gated ? "" : " (measured, not gated)");
    Totals t;
    for (std::size_t i = 0; i < profiles.size(); ++i) {
      const Profile& p = profiles[i];
      const RunResult& clean = clean_runs[i].result;
      t.clean_s += clean_runs[i].virtual_s;
      const NoisyRun noisy = run_suite(p, vectors, {}, LineFaultSpec{rate, kAllLineFaultKinds, seed + i}, 1);
      std::vector<std::string> problems;
      for (std::size_t k = 0; k < noisy.result.vectors.size() && k < clean.vectors.size(); ++k) {
        const VectorResult& n = noisy.result.vectors[k];
        const VectorResult& c = clean.vectors[k];
        if (n.id != c.id) {
          problems.push_back("the runs ran different vectors: " + n.id + " / " + c.id);
          break;
        }
        if (n.verdict == Verdict::kError) {
          // The same verdicts as a clean line: at the gated rate an error is
          // a verdict the clean line did not give.
          if (gated) problems.push_back(fmt::format("ERROR {}: {}", n.id, n.error_reason));
          continue;
        }
        if (n.verdict == Verdict::kFail && c.verdict != Verdict::kFail) {
          problems.push_back(fmt::format("FALSE FAILURE {}: {}", n.id, first_words(n)));
        } else if (n.verdict != c.verdict) {
          problems.push_back(fmt::format("CHANGED {}: {} -> {}: {}", n.id, to_string(c.verdict), to_string(n.verdict),
                                         first_words(n)));
        }
        if (n.line.recovered != n.line.faults) {
          problems.push_back(fmt::format("UNRECOVERED {}: {} of {} faults", n.id, n.line.faults - n.line.recovered, n.line.faults));
          for (const auto& e : n.transcript) problems.back() += fmt::format("\n      {} {}", e.sent ? ">" : "<", e.note);
        }
      }
      // The runner's own exchanges (liveness, the stop after motion, the
      // backup reads) too.
      if (noisy.result.line.recovered != noisy.result.line.faults)
        problems.push_back(fmt::format("UNRECOVERED in the run: {} of {} faults", noisy.result.line.faults - noisy.result.line.recovered,
                                       noisy.result.line.faults));
      if (noisy.result.vectors.size() != clean.vectors.size())
        problems.push_back(fmt::format("{} vectors ran, {} on a clean line{}", noisy.result.vectors.size(), clean.vectors.size(),
                                       noisy.result.aborted ? ": " + noisy.result.abort_reason : ""));
      const bool pass = problems.empty();
      if (gated) ok = ok && pass;
      t.exchanges += noisy.result.line.exchanges;
      t.injected += noisy.injected.total();
      t.seen += noisy.result.line.faults;
      t.recovered += noisy.result.line.recovered;
      t.surveyed += noisy.result.line.surveyed;
      t.errors += noisy.result.errors;
      t.vectors += noisy.result.vectors.size();
      t.noisy_s += noisy.virtual_s;
      std::cout << fmt::format("{:<28} {}; injected {}; {} in error; {:.0f} s{}\n", p.name, describe(noisy.result.line),
                               noisy.injected.total(), noisy.result.errors, noisy.virtual_s,
                               pass ? "" : gated ? "  FAIL" : "");
      for (std::size_t k = 0; k < problems.size() && k < 8; ++k) std::cout << "    " << problems[k] << "\n";
      for (const auto& v : noisy.result.vectors)
        if (v.verdict == Verdict::kError && !gated) std::cout << fmt::format("    error {}: {}\n", v.id, v.error_reason);
    }
    std::cout << fmt::format(
        "rate {:g}: {} exchanges, {} faults injected, {} exchanges with a fault seen, {} recovered, {} garbled replies counted "
        "by the line survey, {} vectors of {} in error; "
        "{:.0f} s on the controller's clock against {:.0f} s on a clean line ({:+.1f}%)\n",
        rate, t.exchanges, t.injected, t.seen, t.recovered, t.surveyed, t.errors, t.vectors, t.noisy_s, t.clean_s,
        t.clean_s > 0 ? 100.0 * (t.noisy_s - t.clean_s) / t.clean_s : 0.0);
  }

  std::cout << "== the same 1e-3 line with --retries 0: the run fails and says the faults were the line's\n";
  {
    const NoisyRun r = run_suite(profiles.front(), vectors, {}, LineFaultSpec{1e-3, kAllLineFaultKinds, seed}, 0);
    std::size_t said = 0;
    for (const auto& v : r.result.vectors)
      for (const auto& f : v.failures) said += f.find("the reply showed a line fault") != std::string::npos;
    const bool pass = r.result.exit_code() == 1 && said > 0;
    ok = ok && pass;
    std::cout << fmt::format("{}: exit {}, {} failed, {} failures name a line fault{}\n", profiles.front().name,
                             r.result.exit_code(), r.result.failed, said, pass ? "" : "  FAIL");
  }

  std::cout << "== mutation over the 1e-3 line: each injected fault fails a must-level vector\n";
  std::size_t caught = 0;
  for (const FaultInfo& f : all_faults()) {
    FaultSet set;
    set.set(f.fault);
    std::string where;
    for (std::size_t i = 0; i < profiles.size() && where.empty(); ++i)
      if (fails_must(run_suite(profiles[i], vectors, set, LineFaultSpec{1e-3, kAllLineFaultKinds, seed + i}, 1).result))
        where = profiles[i].name;
    // A fault that is itself a legal side of an open point (left-justified-
    // position is E-33's other side) is a defect only where the profile pins
    // the reference side, as in suite_gates.
    for (std::size_t i = 0; i < profiles.size() && where.empty(); ++i) {
      Profile strict = profiles[i];
      (void)apply_reading_spec("reference", strict.readings);  // every point pinned to reference
      if (fails_must(run_suite(strict, vectors, set, LineFaultSpec{1e-3, kAllLineFaultKinds, seed + i}, 1).result))
        where = profiles[i].name + " (every reading pinned to reference)";
    }
    caught += !where.empty();
    std::cout << fmt::format("{:<30} {}\n", f.name, where.empty() ? "NOT CAUGHT" : where);
  }
  std::cout << fmt::format("mutation score over the noisy line: {}/{}\n", caught, all_faults().size());
  if (caught != all_faults().size()) ok = false;
  std::cout << (ok ? "noise gates: pass\n" : "noise gates: FAIL\n");
  return ok ? 0 : 1;
}
