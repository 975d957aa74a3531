// `sabus diff OLD.json NEW.json`: new failures, fixes, vectors whose replies
// changed though both pass, and timing shifts between two runs. Exit 1 when
// anything regressed.
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "sabus/reports/diff.hpp"
#include "sabus/reports/journal.hpp"

namespace sabus::cli {
namespace {

struct DiffOptions {
  std::string old_run, new_run, threshold = "100ms";
  bool md = false;
};

int run_diff(const DiffOptions& o) {
  const auto threshold = reports::parse_timing_threshold(o.threshold);
  if (!threshold) {
    std::cerr << "sabus diff: --timing-threshold takes milliseconds (\"50ms\", \"50\") or a percentage (\"20%\"), got \""
              << o.threshold << "\"\n";
    return kExitUsage;
  }
  std::string error;
  reports::JournalNotes notes;  // a killed run's journal compares as a run that did not end
  const auto a = reports::read_run_or_journal(o.old_run, notes, error);
  if (!a) {
    std::cerr << "sabus diff: " << error << "\n";
    return kExitUsage;
  }
  const auto b = reports::read_run_or_journal(o.new_run, notes, error);
  if (!b) {
    std::cerr << "sabus diff: " << error << "\n";
    return kExitUsage;
  }
  const reports::RunDiff d = reports::diff_runs(*a, *b, *threshold);
  std::cout << (o.md ? reports::diff_markdown(d) : reports::diff_text(d));
  return d.regressed() ? kExitFailed : kExitOk;
}

}  // namespace

Command add_diff_command(CLI::App& app) {
  auto o = std::make_shared<DiffOptions>();
  CLI::App* sub = app.add_subcommand("diff", "Compare two runs' JSON: regressions, fixes, changed replies, timing");
  sub->add_option("OLD", o->old_run, "The earlier run's JSON")->required();
  sub->add_option("NEW", o->new_run, "The later run's JSON")->required();
  sub->add_flag("--md", o->md, "Markdown instead of text");
  sub->add_option("--timing-threshold", o->threshold,
                  "Report a vector whose duration moved more than this: ms (\"50ms\") or percent (\"20%\"); default 100ms");
  return {sub, [o] { return run_diff(*o); }};
}

}  // namespace sabus::cli
