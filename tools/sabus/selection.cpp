#include "selection.hpp"

#include <iostream>

#include "sabus/reports/rerun.hpp"

namespace sabus::cli {

void add_selection_options(CLI::App* sub, SelectionOptions& o) {
  sub->add_option("--filter", o.filters, "Only vectors whose id matches this glob (repeatable; '3.2*' also matches 3.20-3.25)")
      ->type_name("GLOB");
  sub->add_option("--exclude", o.excludes, "Leave out vectors whose id matches this glob (repeatable)")->type_name("GLOB");
  sub->add_option("--paragraph", o.paragraphs, "Only vectors of this spec paragraph, exactly: 3.2 (repeatable)")
      ->type_name("PARA");
  sub->add_option("--shard", o.shard,
                  "Only the K-th of N stable slices of the selection (by vector id), for a CI matrix or several benches")
      ->type_name("K/N");
  auto* last = sub->add_option("--last-failed", o.last_failed,
                               "Only the vectors that failed or ended in error in this earlier run (its run.json, a journal, or its "
                               "report folder)")
                   ->type_name("RUN.json");
  auto* first = sub->add_option("--failed-first", o.failed_first,
                                "The vectors that failed or ended in error in this earlier run first, then the rest")
                    ->type_name("RUN.json");
  last->excludes(first);
  first->excludes(last);
}

std::optional<harness::SelectionOptions> selection_options(const SelectionOptions& o, const std::string& command) {
  harness::SelectionOptions s;
  s.filters = o.filters;
  s.excludes = o.excludes;
  s.paragraphs = o.paragraphs;
  std::string error;
  if (!o.shard.empty()) {
    s.shard = harness::parse_shard(o.shard, error);
    if (!s.shard) {
      std::cerr << command << ": " << error << "\n";
      return std::nullopt;
    }
  }
  for (const auto& [option, path] : {std::pair{"--last-failed", o.last_failed}, std::pair{"--failed-first", o.failed_first}}) {
    if (path.empty()) continue;
    const auto run = reports::read_earlier_run(path, error);
    if (!run) {
      std::cerr << command << ": " << option << ": " << error << "\n";
      return std::nullopt;
    }
    if (std::string(option) == "--last-failed") {
      s.only = run->failed;
      s.only_from = run->file;
    } else {
      s.first = run->failed;
    }
  }
  return s;
}

}  // namespace sabus::cli
