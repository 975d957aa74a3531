// The Markdown summary read back by cmark-gfm (GitHub Flavored Markdown,
// with its table extension, as a merge request shows it).
#include <cmark-gfm-core-extensions.h>
#include <cmark-gfm.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>

#include "sabus/reports/checks.hpp"
#include "sabus/reports/diff.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports::checks {
namespace {

struct NodeDeleter {
  void operator()(cmark_node* n) const { cmark_node_free(n); }
};

std::string type_of(cmark_node* n) { return cmark_node_get_type_string(n); }

// The text a node shows: its literals, a line break as a space.
std::string plain(cmark_node* n) {
  std::string out;
  cmark_iter* it = cmark_iter_new(n);
  for (cmark_event_type ev; (ev = cmark_iter_next(it)) != CMARK_EVENT_DONE;) {
    if (ev != CMARK_EVENT_ENTER) continue;
    cmark_node* c = cmark_iter_get_node(it);
    const std::string type = type_of(c);
    if (type == "text" || type == "code") out += cmark_node_get_literal(c);
    else if (type == "softbreak" || type == "linebreak") out += ' ';
  }
  cmark_iter_free(it);
  return out;
}

std::string rstrip(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.pop_back();
  return s;
}

// What the summary shows of a string: shown_text on one line.
std::string one_line(std::string_view s) {
  std::string out = shown(s);
  std::replace_if(out.begin(), out.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
  return out;
}

struct Parsed {
  std::vector<std::string> headings, items, paragraphs;
  std::vector<std::vector<std::string>> rows;  // the table's, header first
  std::vector<std::string> markup;             // node types a string could have made
  std::vector<std::string> strong;             // the text of each strong emphasis
};

Parsed parse(std::string_view md) {
  cmark_gfm_core_extensions_ensure_registered();
  cmark_parser* parser = cmark_parser_new(CMARK_OPT_DEFAULT);
  cmark_parser_attach_syntax_extension(parser, cmark_find_syntax_extension("table"));
  cmark_parser_attach_syntax_extension(parser, cmark_find_syntax_extension("strikethrough"));
  cmark_parser_feed(parser, md.data(), md.size());
  std::unique_ptr<cmark_node, NodeDeleter> doc(cmark_parser_finish(parser));
  cmark_parser_free(parser);

  Parsed p;
  cmark_iter* it = cmark_iter_new(doc.get());
  for (cmark_event_type ev; (ev = cmark_iter_next(it)) != CMARK_EVENT_DONE;) {
    if (ev != CMARK_EVENT_ENTER) continue;
    cmark_node* n = cmark_iter_get_node(it);
    const std::string type = type_of(n);
    if (type == "heading") p.headings.push_back(plain(n));
    else if (type == "paragraph" && type_of(cmark_node_parent(n)) == "document") p.paragraphs.push_back(plain(n));
    else if (type == "item") p.items.push_back(plain(n));
    else if (type == "table_row" || type == "table_header") {
      auto& row = p.rows.emplace_back();
      for (cmark_node* cell = cmark_node_first_child(n); cell; cell = cmark_node_next(cell)) row.push_back(plain(cell));
    } else if (type == "html_block" || type == "html_inline" || type == "link" || type == "image" ||
               type == "strikethrough") {
      p.markup.push_back(type);
    } else if (type == "emph") {
      p.markup.push_back(type);
    } else if (type == "strong") {
      p.strong.push_back(plain(n));
    }
  }
  cmark_iter_free(it);
  return p;
}

}  // namespace

Problems markdown_problems(std::string_view md, const RunDocument& doc) {
  Problems problems;
  const Parsed p = parse(md);
  for (const auto& m : p.markup) problems.push_back("Markdown: markup the summary does not write: " + m);
  // The summary's own emphasis: the verdict, and its labels.
  for (const auto& s : p.strong)
    if (s != doc.verdict() && s != "Failures" && s != "Errors" && s != "Inconclusive" && s != "Nothing ran" &&
        s != "Warning" && s != "Line errors")
      problems.push_back("Markdown: strong emphasis the summary does not write: " + s);
  // The line figures, when exchanges were counted, as a paragraph of their own.
  const Summary counts = doc.counts();
  if (const std::string line = line_text(counts);
      !line.empty() && std::find(p.paragraphs.begin(), p.paragraphs.end(), one_line(line)) == p.paragraphs.end())
    problems.push_back("Markdown: no paragraph reads \"" + line + "\"");
  if (p.headings.empty() || p.headings.front() != "SAbus conformance: " + doc.verdict())
    problems.push_back("Markdown: the heading is not \"SAbus conformance: " + doc.verdict() + "\"");

  // The per-level table: a header and a row per level that has vectors.
  std::map<std::string, Tally> levels;
  for (const auto& v : doc.vectors) levels[v.level].add(v);
  std::vector<std::vector<std::string>> want = {{"Level", "passed", "failed", "known", "errors", "inconclusive", "skipped"}};
  for (const char* level : {"must", "should", "informative"})
    if (auto t = levels.find(level); t != levels.end())
      want.push_back({level, std::to_string(t->second.passed), std::to_string(t->second.failed),
                      std::to_string(t->second.known), std::to_string(t->second.errors),
                      std::to_string(t->second.inconclusive), std::to_string(t->second.skipped)});
  if (p.rows != want) problems.push_back("Markdown: the per-level table is not the vectors' counts");

  // The failures, then the vectors in error, then the inconclusive ones,
  // each as one item with the document's text.
  std::vector<std::string> items;
  constexpr std::size_t kListed = 25;
  const auto list = [&](bool (VectorRecord::*listed)() const, std::string (*why)(const VectorRecord&)) {
    std::size_t n = 0;
    for (const auto& v : doc.vectors) {
      if (!(v.*listed)()) continue;
      if (++n > kListed) continue;
      std::string id = one_line(v.id);
      std::replace(id.begin(), id.end(), '`', '\'');
      items.push_back(rstrip(id + " §" + one_line(v.paragraph) + " " + one_line(v.level) + ": " + one_line(why(v))));
    }
    if (n > kListed) items.push_back("… and " + std::to_string(n - kListed) + " more");
  };
  list(&VectorRecord::is_failure, [](const VectorRecord& v) { return v.difference(); });
  list(&VectorRecord::is_error, [](const VectorRecord& v) { return v.error_reason; });
  list(&VectorRecord::is_inconclusive, [](const VectorRecord& v) { return v.inconclusive_reason; });
  std::vector<std::string> got;
  for (const auto& item : p.items) got.push_back(rstrip(item));
  if (got.size() != items.size()) {
    problems.push_back("Markdown: " + std::to_string(got.size()) + " list items for " + std::to_string(items.size()) +
                       " failures, vectors in error and inconclusive vectors listed");
  } else {
    for (std::size_t i = 0; i < items.size(); ++i)
      if (got[i] != items[i]) problems.push_back("Markdown: failure item " + std::to_string(i + 1) + " reads \"" + got[i] +
                                                 "\", the document has \"" + items[i] + "\"");
  }
  return problems;
}

Problems diff_markdown_problems(std::string_view md, const RunDiff& d) {
  Problems problems;
  const Parsed p = parse(md);
  for (const auto& m : p.markup) problems.push_back("diff Markdown: markup the diff does not write: " + m);
  // Its own emphasis: the verdict, each warning's label, each section's title.
  std::size_t sections = 0;
  std::vector<const DiffEntry*> entries;
  for (const auto* list : {&d.new_failures, &d.now_missing, &d.must_now_skipped, &d.fixes, &d.added, &d.other_changes,
                           &d.replies_changed, &d.timing_shifts}) {
    sections += !list->empty();
    for (const auto& e : *list) entries.push_back(&e);
  }
  if (p.strong.size() != 1 + d.warnings.size() + sections)
    problems.push_back("diff Markdown: " + std::to_string(p.strong.size()) + " strong emphases, the diff writes " +
                       std::to_string(1 + d.warnings.size() + sections));
  if (p.headings.size() != 1 || p.headings.front() != std::string("SAbus run diff: ") + (d.regressed() ? "regressed" : "no regression"))
    problems.push_back("diff Markdown: the heading is not the diff's verdict");
  // The run's changes as list items; each entry a row of its section's table.
  std::vector<std::string> items;
  for (const auto& c : d.run_changes) items.push_back(rstrip(one_line(c)));
  std::vector<std::string> got_items;
  for (const auto& item : p.items) got_items.push_back(rstrip(item));
  if (got_items != items) problems.push_back("diff Markdown: the list is not the runs' changes");
  std::vector<std::vector<std::string>> body;
  for (const auto& row : p.rows)
    if (!(row.size() == 5 && row[0] == "Vector" && row[1] == "§")) body.push_back(row);
  if (body.size() != entries.size()) {
    problems.push_back("diff Markdown: " + std::to_string(body.size()) + " table rows for " + std::to_string(entries.size()) +
                       " entries");
    return problems;
  }
  for (std::size_t i = 0; i < entries.size(); ++i) {
    std::string id = one_line(entries[i]->id);
    std::replace(id.begin(), id.end(), '`', '\'');
    const std::vector<std::string> want_cells = {id, one_line(entries[i]->paragraph), one_line(entries[i]->level),
                                                 rstrip(one_line(entries[i]->detail))};
    const std::vector<std::string> got_cells = {body[i][0], body[i][1], body[i][2], rstrip(body[i][4])};
    if (got_cells != want_cells)
      problems.push_back("diff Markdown: row " + std::to_string(i + 1) + " reads \"" + body[i][0] + " | " + body[i][4] +
                         "\", the diff has \"" + want_cells[0] + " | " + want_cells[3] + "\"");
  }
  return problems;
}

std::string shown(std::string_view s) { return shown_text(s); }

}  // namespace sabus::reports::checks
