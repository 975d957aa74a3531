// `sabus report RUN.json --html F --junit F --md F`: regenerates any report
// from a run's JSON (the source of truth, reports/SCHEMA.md).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::cli {
namespace {

struct ReportOptions {
  std::string run, html, junit, md;
};

int run_report(const ReportOptions& o) {
  if (o.html.empty() && o.junit.empty() && o.md.empty()) {
    std::cerr << "sabus report: give at least one of --html F, --junit F, --md F\n";
    return kExitUsage;
  }
  std::string error;
  const auto doc = reports::read_run_file(o.run, error);
  if (!doc) {
    std::cerr << "sabus report: " << error << "\n";
    return kExitUsage;
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
  std::cout << doc->verdict() << ": " << reports::summary_line(doc->counts()) << " (" << doc->status << ")\n";
  return ok ? kExitOk : kExitFailed;
}

}  // namespace

Command add_report_command(CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* sub = app.add_subcommand("report", "Write HTML, JUnit or Markdown reports from a run's JSON");
  sub->add_option("RUN", o->run, "The JSON a run wrote (sabus run --json)")->required();
  sub->add_option("--html", o->html, "Write the HTML report");
  sub->add_option("--junit", o->junit, "Write JUnit XML");
  sub->add_option("--md", o->md, "Write the Markdown summary");
  return {sub, [o] { return run_report(*o); }};
}

}  // namespace sabus::cli
