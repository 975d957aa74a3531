// `sabus vectors sweep` (sweep.cpp): the suite on random legal profiles.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace sabus::cli {

struct SweepOptions {
  std::uint64_t profiles = 50;
  std::string seed = "1";  // a number, or "fresh": one drawn for this run and printed
  std::optional<std::uint64_t> profile_seed;
  std::vector<std::string> vectors;
  std::string out = "sweep-failures";
  std::string write_profiles;  // when set: every profile written there, failing or not
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  // The side of the spec's open points the reference controller takes
  // (readings.hpp; "" the profile's own); the verdicts keep the profile's pins.
  std::string reading;
  // --shard K/N: only the profiles in this slice (by seed; selection.hpp Shard).
  std::string shard;
  CLI::App* command = nullptr;  // the subcommand, to tell whether it was given
};

// The seed of the i-th profile of a sweep of seed `seed` (random_profile):
// `sabus vectors coverage` draws the same profiles.
std::uint64_t sweep_profile_seed(std::uint64_t seed, std::uint64_t i);

// Registers `sweep` under `sabus vectors`.
void add_sweep_subcommand(CLI::App& vectors, std::shared_ptr<SweepOptions> options);
int run_sweep(const SweepOptions& options);

}  // namespace sabus::cli
