// The HTML report read back by an HTML5 parser (Gumbo): no parse error, only
// the markup the writer makes, and the document's strings shown as text.
#include <gumbo.h>

#include <algorithm>
#include <set>
#include <string>

#include "sabus/reports/checks.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports::checks {
namespace {

// Gumbo keeps the declaration of its error records out of its installed
// header (gumbo.h: "the GumboError header isn't part of the public API").
// Their first members in Gumbo 0.10 (src/error.h), all this file reads: the
// kind and where.
struct GumboErrorStart {
  int type;
  GumboSourcePosition position;
};

// The elements html_report writes (the parser adds html, head, body and
// tbody where the page leaves them implicit); anything else is markup that
// came from a string.
const std::set<std::string> kElements = {
    "html", "head", "meta", "title", "style", "body", "h1", "h2", "h3", "p", "span", "b", "small", "nav", "a",
    "table", "tbody", "tr", "th", "td", "details", "summary", "ul", "li", "div", "blockquote", "pre", "code", "br",
    "form", "label", "select", "option", "output", "script", "svg", "line", "text", "rect", "g"};

std::string tag_name(const GumboElement& e) {
  if (e.tag != GUMBO_TAG_UNKNOWN) return gumbo_normalized_tagname(e.tag);
  GumboStringPiece original = e.original_tag;
  gumbo_tag_from_original_text(&original);
  std::string name(original.data, original.length);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return name;
}

struct Walk {
  Problems& problems;
  std::string text;  // every text node, in document order
  std::size_t scripts = 0;

  void node(const GumboNode* n) {
    switch (n->type) {
      case GUMBO_NODE_TEXT:
      case GUMBO_NODE_WHITESPACE:
      case GUMBO_NODE_CDATA:
        text += n->v.text.text;
        text += '\n';  // no string runs on from one node into the next
        return;
      case GUMBO_NODE_COMMENT:
        problems.push_back("HTML: a comment (the writer writes none): " + std::string(n->v.text.text).substr(0, 60));
        return;
      case GUMBO_NODE_DOCUMENT:
      case GUMBO_NODE_ELEMENT:
      case GUMBO_NODE_TEMPLATE:
        break;
    }
    const GumboVector& children = n->type == GUMBO_NODE_DOCUMENT ? n->v.document.children : n->v.element.children;
    if (n->type != GUMBO_NODE_DOCUMENT) element(n->v.element);
    for (unsigned i = 0; i < children.length; ++i) node(static_cast<const GumboNode*>(children.data[i]));
  }

  void element(const GumboElement& e) {
    const std::string name = tag_name(e);
    if (!kElements.count(name)) problems.push_back("HTML: an element the writer does not write: <" + name + ">");
    if (name == "script") ++scripts;
    for (unsigned i = 0; i < e.attributes.length; ++i) {
      const auto* a = static_cast<const GumboAttribute*>(e.attributes.data[i]);
      const std::string attr = a->name, value = a->value;
      if (attr.rfind("on", 0) == 0) problems.push_back("HTML: an event handler attribute " + attr + " on <" + name + ">");
      if (attr == "src" || attr == "srcdoc" || attr == "formaction" || attr == "action")
        problems.push_back("HTML: a " + attr + " attribute on <" + name + "> (the page loads nothing)");
      if (attr == "href" && value.rfind("#", 0) != 0)
        problems.push_back("HTML: a link out of the page on <" + name + ">: " + value.substr(0, 60));
    }
  }
};

// What a string reads as in the DOM: as the writer shows it, with the line
// ends the HTML5 parser normalizes.
std::string in_dom(std::string_view s) {
  std::string out;
  const std::string text = shown(s);
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\r') {
      out += '\n';
      if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
    } else {
      out += text[i];
    }
  }
  return out;
}

// The strings the page must show: the run's line figures when it counted
// any; every vector's id; for an inconclusive one why; for one in error what
// the line did; for a failing vector its failures, its frames' notes and its
// replies' fields.
std::vector<std::string> strings_shown(const RunDocument& doc) {
  std::vector<std::string> out;
  if (const std::string line = line_text(doc.counts()); !line.empty()) out.push_back(line);
  for (const auto& v : doc.vectors) {
    out.push_back(v.id);
    if (v.is_inconclusive()) out.push_back("inconclusive: " + v.inconclusive_reason);
    if (v.is_error()) out.push_back("error: " + v.error_reason);
    if (!v.has_failed_steps()) continue;
    for (const auto& f : v.failures) out.push_back(f);
    for (const auto& f : v.transcript) {
      out.push_back(f.note);
      if (f.dir != "rx") continue;
      for (const auto& x : f.fields) {
        out.push_back(x.raw);
        out.push_back(x.meaning);
      }
    }
  }
  return out;
}

}  // namespace

Problems html_problems(std::string_view html, const RunDocument& doc) {
  Problems problems;
  GumboOptions options = kGumboDefaultOptions;
  options.max_errors = 20;
  GumboOutput* out = gumbo_parse_with_options(&options, html.data(), html.size());
  for (unsigned i = 0; i < out->errors.length; ++i) {
    const auto* e = static_cast<const GumboErrorStart*>(out->errors.data[i]);
    const std::size_t at = std::min<std::size_t>(e->position.offset, html.size());
    problems.push_back("HTML line " + std::to_string(e->position.line) + " column " + std::to_string(e->position.column) +
                       ": parse error (Gumbo error " + std::to_string(e->type) + ") at \"" +
                       std::string(html.substr(at, 40)) + "\"");
  }
  Walk walk{problems, "", 0};
  walk.node(out->document);
  gumbo_destroy_output(&options, out);
  if (walk.scripts != 1) problems.push_back("HTML: " + std::to_string(walk.scripts) + " scripts, the writer writes one");
  for (const auto& s : strings_shown(doc)) {
    const std::string want = in_dom(s);
    if (!want.empty() && walk.text.find(want) == std::string::npos)
      problems.push_back("HTML: the text \"" + want.substr(0, 80) + "\" is not shown as text");
  }
  return problems;
}

}  // namespace sabus::reports::checks
