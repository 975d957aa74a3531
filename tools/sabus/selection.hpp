// The selection options of `sabus run` and `sabus vectors list` (which
// previews a selection): --filter, --exclude, --paragraph, --shard,
// --last-failed, --failed-first. What they select is decided by the
// selection library (sabus/harness/selection.hpp); this file only turns the
// command line into its options, reading the earlier run's JSON.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/selection.hpp"

namespace sabus::cli {

struct SelectionOptions {
  std::vector<std::string> filters, excludes, paragraphs;
  std::string shard, last_failed, failed_first;
};

// Registers the options on `sub`.
void add_selection_options(CLI::App* sub, SelectionOptions& o);

// The library's options; nullopt after printing an error that names the
// option and the file ("sabus run: --last-failed out/run.json: no such file").
std::optional<harness::SelectionOptions> selection_options(const SelectionOptions& o, const std::string& command);

}  // namespace sabus::cli
