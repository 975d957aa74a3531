// `sabus vectors sweep`: the whole suite against the reference controller on
// many random legal profiles (random_profile, profile_generator.hpp), each on
// the virtual clock with motion and destructive vectors allowed. Every vector
// must pass or be skipped: a failure on a legal profile is a vector that rests
// on something the spec does not fix and the profile does not say. Each
// profile prints how many vectors ran and why the others were skipped; a
// failing profile is written out, with its seed, for reproduction.
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "commands.hpp"
#include "sabus/harness/coverage.hpp"
#include "sabus/harness/profile_generator.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/selection.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "new_file.hpp"
#include "skip_causes.hpp"
#include "sweep.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

// The seed of the i-th profile of a sweep (splitmix64): distinct, and the same
// for the same --seed, so that one profile reproduces with --profile-seed.
std::uint64_t profile_seed(std::uint64_t seed, std::uint64_t i) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (i + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Why a vector was skipped, as a cause: "requires <key>" for a requirement,
// the capability for a profile expression ("needs a filled TLE slot"), the
// gate's words otherwise. The cause ends at the first ':' outside
// parentheses: "needs TLE 10 filled in the profile (a write there could not
// be undone: a slot cannot be emptied)" is one cause, its parenthesis closed.
std::string skip_cause(const std::string& reason) {
  if (reason.rfind("requires: ", 0) == 0) {
    const auto space = reason.find(' ', 10);
    return "requires " + reason.substr(10, space == std::string::npos ? std::string::npos : space - 10);
  }
  int depth = 0;
  for (std::size_t i = 0; i < reason.size(); ++i) {
    if (reason[i] == '(') ++depth;
    else if (reason[i] == ')' && depth > 0) --depth;
    else if (reason[i] == ':' && depth == 0) return reason.substr(0, i);
  }
  return reason;
}

// A seed for `--seed fresh`: a new one each run, printed, so that a sweep
// keeps exploring and what it finds reproduces (with --seed or --profile-seed).
std::uint64_t fresh_seed() {
  std::random_device device;
  return (std::uint64_t{device()} << 32) ^ device() ^
         static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
}

// "1234", or "fresh" for a seed drawn now; nullopt for anything else.
std::optional<std::uint64_t> sweep_seed(const std::string& text) {
  if (text == "fresh") return fresh_seed();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 20) return std::nullopt;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) return std::nullopt;
  return v;
}

struct ProfileOutcome {
  std::uint64_t seed = 0;
  Profile profile;
  std::size_t ran = 0, passed = 0, skipped = 0;
  std::map<std::string, std::size_t> skips;  // cause -> count
  std::set<std::string> ran_ids;             // the vectors not skipped: the field shares' sites
  std::vector<std::string> failures;         // "id: first failure"
  std::vector<std::string> inconclusive;     // "id: reason", on a controller that takes another side of the spec
  std::string aborted;
};

ProfileOutcome sweep_one(const std::vector<Vector>& vectors, std::uint64_t seed, const std::string& reading) {
  ProfileOutcome o;
  o.seed = seed;
  o.profile = random_profile(seed);
  // --reading (checked in run_sweep): the controller takes those sides, and
  // the profile leaves those points open (a pin of its own would say the
  // device is not this controller).
  ReadingPins flips;
  if (!reading.empty()) (void)apply_reading_spec(reading, flips);
  for (const auto& [id, side] : flips) o.profile.readings.erase(id);
  ReadingPins sides = o.profile.readings;
  for (const auto& [id, side] : flips) sides[id] = side;
  hold_only_what_sides_allow(o.profile, sides);
  const Profile& p = o.profile;
  Profile controller = p;
  controller.readings = std::move(sides);
  auto transport = make_in_process_transport(bus_of(controller), {});
  const auto points = reading_points();
  const bool reference_sides = std::all_of(points.begin(), points.end(), [&](const ReadingPoint& point) {
    return side_taken(controller.readings, point.id) == ReadingSide::kReference;
  });
  RunOptions options;
  options.allow_motion = true;
  options.allow_destructive = true;
  options.keep_transcripts = false;
  options.record_transcripts = false;  // only the verdicts are read
  const RunResult r = Runner(*transport, p, options).run(vectors);
  if (r.aborted) o.aborted = r.abort_reason;
  for (const auto& v : r.vectors) {
    if (v.verdict == Verdict::kSkip) {
      ++o.skipped;
      ++o.skips[skip_cause(v.skip_reason)];
      continue;
    }
    ++o.ran;
    o.ran_ids.insert(v.id);
    // An inconclusive vector is no failure (its purpose was not reached). On
    // a controller that takes the reference side of every open point of the
    // spec it is a precondition that cannot hold, named as a failure of the
    // vector would be; where the controller takes the other side of one
    // (pinned, or --reading), the timing it chooses may leave the purpose
    // out of reach (E-90: a search over before the stop), and it is shown.
    if (v.verdict == Verdict::kPass) ++o.passed;
    else if (v.verdict == Verdict::kInconclusive && reference_sides) o.failures.push_back(v.id + ": inconclusive: " + v.inconclusive_reason);
    else if (v.verdict == Verdict::kInconclusive) o.inconclusive.push_back(v.id + ": " + v.inconclusive_reason);
    // A vector in error (the line left it unjudged) cannot happen on the
    // in-process controller, which has no line to garble: it is the
    // harness's fault, counted as a failure of the profile with its reason.
    else if (v.verdict == Verdict::kError) o.failures.push_back(v.id + ": error: " + v.error_reason);
    else o.failures.push_back(v.id + ": " + (v.failures.empty() ? std::string(to_string(v.verdict)) : v.failures.front()));
  }
  return o;
}

std::string skip_line(const ProfileOutcome& o) {
  std::vector<std::pair<std::size_t, std::string>> by_count;
  for (const auto& [cause, n] : o.skips) by_count.emplace_back(n, cause);
  std::sort(by_count.begin(), by_count.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string out;
  for (const auto& [n, cause] : by_count) out += (out.empty() ? "" : "; ") + fmt::format("{} {}", n, cause);
  return out;
}

// Writes a profile (a failing one with its failures) with its seed, so that
// `sabus run --sim --profile FILE --allow-motion --allow-destructive` or
// `sabus vectors sweep --profile-seed SEED` reproduces it: a new file, never
// one that is there (new_file.hpp). The failures, which hold what the vectors
// and the controller said, are comment lines that the profile loader skips.
// The file's path, or nullopt with `error`.
std::optional<fs::path> write_profile(const fs::path& dir, const ProfileOutcome& o, std::string& error) {
  std::string comment = fmt::format("A random legal profile (random_profile seed 0x{:016x}){}\n", o.seed,
                                    o.failures.empty() && o.aborted.empty() ? "" : " on which vectors failed:");
  for (const auto& f : o.failures) comment += "  " + f + "\n";
  if (!o.aborted.empty()) comment += "  run aborted: " + o.aborted + "\n";
  comment += fmt::format("Reproduce: sabus vectors sweep --profile-seed {}", o.seed);
  return write_new_file(dir, fmt::format("sweep-{:016x}", o.seed), ".yaml", to_yaml(o.profile, comment), error);
}

std::size_t percentile(std::vector<std::size_t> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace

std::uint64_t sweep_profile_seed(std::uint64_t seed, std::uint64_t i) { return profile_seed(seed, i); }

int run_sweep(const SweepOptions& opts) {
  LoadResult suite = load_vectors(opts.vectors.empty() ? std::vector<std::string>{default_vectors_dir()} : opts.vectors);
  if (!suite.ok()) {
    for (const auto& e : suite.errors) std::cerr << e.text() << "\n";
    std::cerr << "sabus vectors sweep: " << suite.errors.size() << " vector error(s)\n";
    return kExitUsage;
  }
  // Which vectors check which field's value (coverage.hpp), for the shares.
  const CoverageMatrix matrix = coverage(suite.files);
  std::vector<Vector> vectors;
  for (auto& f : suite.files)
    for (auto& v : f.vectors) vectors.push_back(std::move(v));

  if (ReadingPins pins; !opts.reading.empty())
    if (auto why = apply_reading_spec(opts.reading, pins)) {
      std::cerr << "sabus vectors sweep: --reading: " << *why << "\n";
      return kExitUsage;
    }
  const std::optional<std::uint64_t> seed = sweep_seed(opts.seed);
  if (!seed) {
    std::cerr << "sabus vectors sweep: --seed " << opts.seed << ": a whole number below 2^64, or fresh\n";
    return kExitUsage;
  }
  std::optional<Shard> shard;
  if (!opts.shard.empty()) {
    std::string error;
    shard = parse_shard(opts.shard, error);
    if (!shard) {
      std::cerr << "sabus vectors sweep: " << error << "\n";
      return kExitUsage;
    }
  }
  std::vector<std::uint64_t> seeds;
  if (opts.profile_seed) seeds.push_back(*opts.profile_seed);
  else {
    // A shard takes the profiles whose seed falls in its slice: the N shards
    // of one --seed and --profiles run each profile exactly once.
    for (std::uint64_t i = 0; i < opts.profiles; ++i)
      if (const std::uint64_t s = profile_seed(*seed, i); !shard || in_shard(*shard, std::to_string(s))) seeds.push_back(s);
    std::cout << fmt::format("sweep seed {}{}: {} profiles{} (reproduce: --seed {} --profiles {}{})\n", *seed,
                             opts.seed == "fresh" ? " (fresh)" : "", seeds.size(),
                             shard ? fmt::format(" of {}, shard {}/{}", opts.profiles, shard->index, shard->count) : "",
                             *seed, opts.profiles, shard ? " --shard " + opts.shard : "");
  }

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<ProfileOutcome> outcomes(seeds.size());
  std::atomic<std::size_t> next{0};
  std::mutex print;
  auto worker = [&] {
    for (std::size_t i = next++; i < seeds.size(); i = next++) {
      outcomes[i] = sweep_one(vectors, seeds[i], opts.reading);
      const ProfileOutcome& o = outcomes[i];
      const std::lock_guard lock(print);
      std::cout << fmt::format("profile {} seed {}: {} ran, {} failed, {}{} skipped ({})\n", i + 1, o.seed, o.ran,
                               o.failures.size(),
                               o.inconclusive.empty() ? "" : fmt::format("{} inconclusive, ", o.inconclusive.size()),
                               o.skipped, skip_line(o));
      for (const auto& f : o.failures) std::cout << "  FAIL " << f << "\n";
      for (const auto& i : o.inconclusive) std::cout << "  INCONCLUSIVE " << i << "\n";
      if (!o.aborted.empty()) std::cout << "  ABORTED " << o.aborted << "\n";
      const bool failed = !o.failures.empty() || !o.aborted.empty();
      if (failed || !opts.write_profiles.empty()) {
        std::string error;
        const auto file = write_profile(failed ? opts.out : opts.write_profiles, o, error);
        if (!file) std::cerr << "sabus vectors sweep: the profile of seed " << o.seed << " is not written: " << error << "\n";
        else if (failed) std::cout << "  profile written to " << file->string() << "\n";
      }
      std::cout.flush();
    }
  };
  const unsigned jobs = std::max(1u, std::min<unsigned>(opts.jobs, static_cast<unsigned>(seeds.size())));
  std::vector<std::thread> threads;
  for (unsigned j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();

  std::vector<std::size_t> ran, skipped;
  std::size_t failed_profiles = 0, inconclusive = 0;
  ProfileOutcome all;  // the skips of every profile, by cause
  for (const auto& o : outcomes) {
    inconclusive += o.inconclusive.size();
    ran.push_back(o.ran);
    skipped.push_back(o.skipped);
    failed_profiles += !o.failures.empty() || !o.aborted.empty();
    for (const auto& [cause, n] : o.skips) all.skips[cause] += n;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << fmt::format(
      "sweep: {} profiles, {} failed; vectors run per profile min {} median {} max {}; skipped min {} median {} max {}; "
      "{} vectors; {:.1f} s\n",
      outcomes.size(), failed_profiles, percentile(ran, 0), percentile(ran, 0.5), percentile(ran, 1),
      percentile(skipped, 0), percentile(skipped, 0.5), percentile(skipped, 1), vectors.size(), seconds);
  if (inconclusive > 0)
    std::cout << fmt::format("sweep: {} vector run(s) inconclusive on controllers that take another side of the spec\n",
                             inconclusive);
  // Per field, the share of profiles on which a vector that checks its
  // value ran, of those where its reply was asked for (issue 32; the target
  // is 100%, `sabus vectors coverage` gates it on the requirements alone).
  std::vector<ProfileSite> sites;
  for (const auto& o : outcomes) sites.push_back({fmt::format("seed {}", o.seed), o.ran_ids, undetermined_fields(o.profile)});
  std::size_t whole = 0, asked = 0;
  for (const FieldShare& share : field_shares(matrix, sites)) {
    asked += share.exists > 0;
    whole += share.exists > 0 && share.checked == share.exists;
    std::cout << fmt::format("field share {:<36} §{:<5} {:>5} of {:>5} profiles ({:.0f}%){}\n", field_label(*share.field),
                             share.field->paragraph, share.checked, share.exists,
                             share.exists ? 100.0 * static_cast<double>(share.checked) / static_cast<double>(share.exists) : 0.0,
                             share.checked < share.exists ? fmt::format("; unchecked on profile seeds: {}",
                                                                        [&] {
                                                                          std::string list;
                                                                          for (std::size_t i = 0; i < share.unchecked.size() && i < 4; ++i)
                                                                            list += (i ? ", " : "") + share.unchecked[i].substr(5);
                                                                          if (share.unchecked.size() > 4) list += fmt::format(" and {} more", share.unchecked.size() - 4);
                                                                          return list;
                                                                        }())
                                                          : "");
  }
  std::cout << fmt::format("sweep field shares: {} of {} fields asked for have their value checked on every profile where "
                           "their reply was asked for\n",
                           whole, asked);
  // Grouped by wording: each profile's numbers make causes of their own.
  std::cout << "sweep skips by cause (vector runs): " << (all.skips.empty() ? "none" : skip_causes_line(all.skips))
            << "\n";
  return failed_profiles == 0 ? kExitOk : kExitFailed;
}

void add_sweep_subcommand(CLI::App& vectors, std::shared_ptr<SweepOptions> o) {
  CLI::App* sub = vectors.add_subcommand(
      "sweep", "Run the suite against the reference controller on random legal profiles; exit 1 when a vector fails");
  sub->add_option("--profiles", o->profiles, "How many random profiles (default 50)")->check(CLI::Range(1, 1000000));
  sub->add_option("--seed", o->seed,
                  "Seed of the sweep: the same seed draws the same profiles; 'fresh' draws a new one, printed (default 1)");
  sub->add_option("--profile-seed", o->profile_seed, "Run only the profile of this seed (as a sweep prints it)");
  sub->add_option("--vectors", o->vectors, "Vector files or folders (default vectors/)")->check(CLI::ExistingPath);
  sub->add_option("--out", o->out, "Where failing profiles are written (default sweep-failures/)");
  sub->add_option("--write-profiles", o->write_profiles,
                  "Write every profile (not only the failing ones) to this folder as sweep-SEED.yaml");
  sub->add_option("--reading", o->reading, kReadingHelp);
  sub->add_option("--shard", o->shard, "Only the K-th of N stable slices of the profiles (by seed), to split a sweep")
      ->type_name("K/N");
  sub->add_option("--jobs", o->jobs, "Profiles run at once (default: the machine's cores)")->check(CLI::Range(1, 256));
  o->command = sub;
}

}  // namespace sabus::cli
