// `sabus report RUN --html F --junit F --md F --json F`: regenerates any
// report from a run's JSON (the source of truth, reports/SCHEMA.md) or from
// the journal of a run that was killed before it could write its JSON.
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::cli {
namespace {

struct ReportOptions {
  std::string run, html, junit, md, json;
};

int run_report(const ReportOptions& o) {
  if (o.html.empty() && o.junit.empty() && o.md.empty() && o.json.empty()) {
    std::cerr << "sabus report: give at least one of --html F, --junit F, --md F, --json F\n";
    return kExitUsage;
  }
  if (const std::string why = reports::report_paths_problem({{"--html", o.html}, {"--junit", o.junit}, {"--md", o.md}, {"--json", o.json}});
      !why.empty()) {
    std::cerr << "sabus report: " << why << "\n";
    return kExitUsage;
  }
  // A report on standard output keeps it to itself.
  const bool to_stdout = o.html == "-" || o.junit == "-" || o.md == "-" || o.json == "-";
  std::string error;
  reports::JournalNotes notes;
  const auto doc = reports::read_run_or_journal(o.run, notes, error);
  const bool journal = notes.journal;
  if (!doc) {
    std::cerr << "sabus report: " << error << "\n";
    return kExitUsage;
  }
  if (journal) {
    for (const auto& n : notes.notes) std::cerr << "sabus report: " << o.run << ": " << n << "\n";
    if (!notes.ended)
      std::cerr << "sabus report: " << o.run << " has no end record: the run was killed (or still goes on); "
                << notes.vectors << " finished vector(s), status \"" << doc->status << "\"\n";
  }
  bool ok = true;
  auto write = [&](const std::string& path, const std::string& text) {
    if (path.empty()) return;
    if (!reports::write_file(path, text, error)) {
      std::cerr << "sabus report: " << error << "\n";
      ok = false;
    }
  };
  write(o.html, reports::html_report(*doc));
  write(o.junit, reports::junit_xml(*doc));
  write(o.md, reports::markdown_summary(*doc));
  if (!o.json.empty()) {
    if (!reports::write_run_json(o.json, *doc, error)) {
      std::cerr << "sabus report: " << error << "\n";
      ok = false;
    }
  }
  std::ostream& out = to_stdout ? std::cerr : std::cout;
  const reports::Summary counts = doc->counts();
  out << doc->verdict() << ": " << reports::summary_line(counts) << " (" << doc->status << ")\n";
  // The line figures of a run over a line, real or emulated (run.cpp's
  // finish_console): the in-process controller's own exchanges never fault.
  const bool on_a_line = doc->device.rfind("in-process", 0) != 0 || doc->device.find("line faults:") != std::string::npos;
  if (const std::string line = reports::line_text(counts); !line.empty() && (on_a_line || counts.line.faults > 0))
    out << line << "\n";
  return ok ? kExitOk : kExitFailed;
}

}  // namespace

Command add_report_command(CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* sub = app.add_subcommand("report", "Write HTML, JUnit, Markdown or JSON reports from a run's JSON or journal");
  sub->add_option("RUN", o->run, "The JSON a run wrote (sabus run --json), or its journal (RUN.journal.jsonl)")->required();
  sub->add_option("--html", o->html, "Write the HTML report (- : standard output)");
  sub->add_option("--junit", o->junit, "Write JUnit XML (- : standard output)");
  sub->add_option("--md", o->md, "Write the Markdown summary (- : standard output)");
  sub->add_option("--json", o->json, "Write the run JSON (from a journal: the run a killed process left; - : standard output)");
  return {sub, [o] { return run_report(*o); }};
}

}  // namespace sabus::cli
