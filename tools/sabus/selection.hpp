// Which vectors a run takes, shared by `sabus run` and `sabus vectors list`
// (which previews a selection): --filter and --exclude globs over vector
// ids, and --paragraph for one spec paragraph exactly (the glob '3.2*' also
// takes §3.20-§3.25).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "sabus/harness/runner.hpp"
#include "sabus/harness/vector.hpp"

namespace sabus::cli {

struct SelectionOptions {
  std::vector<std::string> filters, excludes, paragraphs;
};

// Registers --filter, --exclude and --paragraph on `sub`.
void add_selection_options(CLI::App* sub, SelectionOptions& o);

struct Selection {
  // The vectors of the given paragraphs (all without --paragraph), in suite
  // order: what the runner is given. It passes over those the globs leave out.
  std::vector<harness::Vector> vectors;
  std::size_t selected = 0;  // of `vectors`, those the globs select too: what runs or is skipped
  // For the user, one line each: a glob or paragraph that selects nothing, a
  // glob whose vectors span several paragraphs.
  std::vector<std::string> notes;
};

// `run_options` carries the globs to the runner (filters, excludes).
Selection select_vectors(const std::vector<harness::Vector>& all, const SelectionOptions& o, harness::RunOptions& run_options);

// Why nothing is selected, for the line that ends the command: "no vector
// matches --filter '3.2-stauts*'".
std::string empty_selection_reason(const SelectionOptions& o);

}  // namespace sabus::cli
