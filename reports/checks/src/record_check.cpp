// A whole run's record read back (checks.hpp, run_record_problems).
#include <nlohmann/json.hpp>
#include <sstream>

#include "sabus/reports/checks.hpp"
#include "sabus/reports/diff.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports::checks {
namespace {

void add(Problems& all, const Problems& more) { all.insert(all.end(), more.begin(), more.end()); }

// The first line where two texts part, for a report of a difference.
std::string first_difference(const std::string& a, const std::string& b) {
  std::size_t i = 0, line = 1;
  for (; i < a.size() && i < b.size() && a[i] == b[i]; ++i) line += a[i] == '\n';
  return "line " + std::to_string(line) + ": \"" + a.substr(i, 60) + "\" against \"" + b.substr(i, 60) + "\"";
}

void same(Problems& problems, const std::string& what, const std::string& written, const std::string& rebuilt) {
  if (written != rebuilt) problems.push_back(what + " differs: " + first_difference(written, rebuilt));
}

}  // namespace

Problems run_record_problems(const RunDocument& doc, const std::string& journal, const RunDocument* baseline) {
  Problems problems = journal_problems(journal);
  std::istringstream journal_in(journal);
  std::ostringstream json_out;
  std::string error;
  if (!write_run_json_from_journal(journal_in, json_out, doc, error)) {
    problems.push_back("no run JSON from the journal: " + error);
    return problems;
  }
  const std::string json = json_out.str();
  add(problems, run_json_problems(json));

  const std::string junit = junit_xml(doc), html = html_report(doc), md = markdown_summary(doc);
  add(problems, junit_problems(junit, doc));
  add(problems, html_problems(html, doc));
  add(problems, markdown_problems(md, doc));

  // sabus report RUN.json: the same reports from the file.
  const nlohmann::json parsed = nlohmann::json::parse(json, nullptr, false);
  const auto back = parsed.is_discarded() ? std::nullopt : from_json(parsed, error);
  if (!back) {
    problems.push_back("sabus report cannot read the run JSON: " + (parsed.is_discarded() ? "not JSON" : error));
    return problems;
  }
  same(problems, "the JUnit XML rebuilt from the run JSON", junit, junit_xml(*back));
  same(problems, "the HTML report rebuilt from the run JSON", html, html_report(*back));
  same(problems, "the Markdown summary rebuilt from the run JSON", md, markdown_summary(*back));
  same(problems, "the run JSON written again from what was read", json, json_text(*back));

  // sabus report RUN.journal.jsonl --json F: a killed run's journal.
  std::istringstream again(journal);
  JournalNotes notes;
  const auto from_journal = read_journal(again, "journal", notes, error);
  if (!from_journal) problems.push_back("sabus report cannot read the journal: " + error);
  else same(problems, "the run JSON rebuilt from the journal", json, json_text(*from_journal));

  // sabus diff BASELINE RUN --md, from what the files say.
  if (baseline) {
    const RunDiff d = diff_runs(*baseline, *back, TimingThreshold{});
    add(problems, diff_markdown_problems(diff_markdown(d), d));
  }
  return problems;
}

}  // namespace sabus::reports::checks
