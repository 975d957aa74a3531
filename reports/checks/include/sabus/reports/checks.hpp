// Readers that prove what sabus writes: every file format of a run parsed
// by a library that knows the format (nlohmann, and valijson with
// reports/run.schema.json, for the run JSON and its journal; libxml2 and
// reports/junit.xsd for JUnit; Gumbo's HTML5 parser for the HTML report;
// cmark-gfm for the Markdown summary), and held against what the run
// document says it must show. The tests, the suite gate (tools/gates) and
// fuzz_record use them; sabus itself does not.
//
// Each returns the problems found, one line each, empty when there are none.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sabus/reports/diff.hpp"
#include "sabus/reports/document.hpp"

namespace sabus::reports::checks {

using Problems = std::vector<std::string>;

// ---- the run JSON and the journal ------------------------------------------------

// A run JSON (reports/SCHEMA.md): JSON, valid against reports/run.schema.json,
// and consistent where a schema cannot say (every field's byte range inside
// its frame, vector ids unique, the summary's counts those of the vectors).
Problems run_json_problems(std::string_view text);
// A journal: each line one JSON text; the first a header record, the last
// (when the run ended) an end record, each run against the schema's header;
// at most one backup record between them, naming the file the end record's
// `backup` names; every other line a vector against the schema's vector.
Problems journal_problems(std::string_view text);

// ---- the reports of a document ---------------------------------------------------

// JUnit XML: well-formed, valid against reports/junit.xsd, a testcase per
// vector of `doc` with its failure, error or skip (an inconclusive vector a
// skip whose message is "inconclusive: " and why, a vector in error an
// error whose message is what the line did), and each testsuite's counts
// (tests, failures, errors, skipped) its testcases'.
Problems junit_problems(std::string_view xml, const RunDocument& doc);
// The HTML report: parsed by an HTML5 parser without a parse error; only the
// elements and attributes the writer uses (one script, no event handler
// attribute, links within the page only); and every string of `doc` that
// came from the device or the vectors (ids, failures, inconclusive and error
// reasons, notes, the fields of failing vectors' replies) and the run's line
// figures shown as text, never as markup.
Problems html_problems(std::string_view html, const RunDocument& doc);
// The Markdown summary, parsed as GitHub Flavored Markdown: no raw HTML,
// the verdict in the heading, the line figures, the per-level table's
// counts, and each listed failure's, vector in error's and inconclusive
// vector's text as the document has it.
Problems markdown_problems(std::string_view md, const RunDocument& doc);

// The Markdown of a diff of two runs (`sabus diff --md`), parsed as GitHub
// Flavored Markdown: no markup but its own, the runs' changes as its list,
// each entry of each section a table row with the entry's text.
Problems diff_markdown_problems(std::string_view md, const RunDiff& diff);

// ---- a whole run ----------------------------------------------------------------

// Everything a run leaves, as `sabus run --json --junit --html --md` writes
// it from `doc` (its document, each vector compacted for the reports as the
// run compacts it) and `journal` (its journal's text), read back: the
// journal; the run JSON made from it; the JUnit, HTML and Markdown of `doc`;
// then, as `sabus report` reads them, the same three rebuilt from that run
// JSON, and the run JSON rebuilt from the journal (a killed run's), each the
// same text as before. With `baseline`, also the diff of `doc` against it
// (`sabus diff BASELINE RUN --md`): diff_markdown_problems.
Problems run_record_problems(const RunDocument& doc, const std::string& journal, const RunDocument* baseline = nullptr);

// What a string of the document reads as in every report: shown_text (the
// reports' writers' own) as the parsers give it back.
std::string shown(std::string_view s);

}  // namespace sabus::reports::checks
