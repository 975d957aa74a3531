// JUnit XML read back: libxml2 parses it (no network, no entities from
// outside) and validates it against reports/junit.xsd (embedded at build
// time); then its testcases are held against the document's vectors.
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlschemas.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "embedded_schemas.hpp"
#include "sabus/reports/checks.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports::checks {
namespace {

// libxml2's messages for one call, collected instead of printed.
void collect(void* problems, xmlErrorPtr error) {
  if (error == nullptr) return;
  std::string message = error->message ? error->message : "?";
  while (!message.empty() && message.back() == '\n') message.pop_back();
  static_cast<Problems*>(problems)->push_back("JUnit line " + std::to_string(error->line) + ": " + message);
}

struct SchemaDeleter {
  void operator()(xmlSchema* s) const { xmlSchemaFree(s); }
};
struct DocDeleter {
  void operator()(xmlDoc* d) const { xmlFreeDoc(d); }
};
struct ValidDeleter {
  void operator()(xmlSchemaValidCtxt* c) const { xmlSchemaFreeValidCtxt(c); }
};

const xmlSchema* junit_schema() {
  static const std::unique_ptr<xmlSchema, SchemaDeleter> schema = [] {
    xmlSchemaParserCtxtPtr parser =
        xmlSchemaNewMemParserCtxt(generated::kJunitXsd, static_cast<int>(std::char_traits<char>::length(generated::kJunitXsd)));
    xmlSchema* s = xmlSchemaParse(parser);
    xmlSchemaFreeParserCtxt(parser);
    if (s == nullptr) throw std::logic_error("reports/junit.xsd does not load");
    return std::unique_ptr<xmlSchema, SchemaDeleter>(s);
  }();
  return schema.get();
}

std::string attribute(xmlNode* node, const char* name) {
  xmlChar* value = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
  if (value == nullptr) return "";
  std::string out(reinterpret_cast<const char*>(value));
  xmlFree(value);
  return out;
}

bool named(xmlNode* node, const char* name) {
  return node->type == XML_ELEMENT_NODE && xmlStrcmp(node->name, reinterpret_cast<const xmlChar*>(name)) == 0;
}

// A text as an XML parser gives back an attribute holding it: line ends
// normalized to LF (XML 1.0 §2.11), then each LF and tab a space (§3.3.3).
std::string as_attribute(std::string_view text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') continue;  // CR LF: one line end
    out += c == '\r' || c == '\n' || c == '\t' ? ' ' : c;
  }
  return out;
}

struct Testcases {
  // What each vector's testcase says of it: "fail", "error", "skip" or "pass".
  std::map<std::string, std::string> vectors;
  // The message of each skipped testcase's <skipped>, and of each erring
  // one's <error>.
  std::map<std::string, std::string> skip_messages, error_messages;
  // The error messages of the run's own testcase (kJunitRunClassname): one
  // for a run that did not reach its end, none otherwise.
  std::vector<std::string> run_errors;
  int run_testcases = 0;
};

// A count attribute as a number; -1 when it is not one.
long count_attribute(xmlNode* node, const char* name) {
  const std::string text = attribute(node, name);
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 9) return -1;
  return std::stol(text);
}

// A testsuite's (or the testsuites') counts against its testcases: what a CI
// shows first is the counts, so they must be the testcases' own.
void check_counts(xmlNode* node, const std::string& what, long tests, long failures, long errors, long skipped,
                  Problems& problems) {
  const std::pair<const char*, long> counts[] = {{"tests", tests}, {"failures", failures}, {"errors", errors}, {"skipped", skipped}};
  for (const auto& [name, n] : counts) {
    if (std::string_view(name) == "skipped" && attribute(node, name).empty() && named(node, "testsuites")) continue;
    if (count_attribute(node, name) != n)
      problems.push_back("JUnit: " + what + " says " + name + "=\"" + attribute(node, name) + "\", its testcases have " +
                         std::to_string(n));
  }
}

Testcases testcases(xmlNode* root, Problems& problems) {
  Testcases out;
  long all_tests = 0, all_failures = 0, all_errors = 0;
  for (xmlNode* suite = root->children; suite; suite = suite->next) {
    if (!named(suite, "testsuite")) continue;
    long tests = 0, failures = 0, erring = 0, skipped = 0;
    for (xmlNode* test = suite->children; test; test = test->next) {
      if (!named(test, "testcase")) continue;
      std::string verdict = "pass";
      std::vector<std::string> errors;
      std::string skip_message;
      for (xmlNode* c = test->children; c; c = c->next) {
        if (named(c, "failure")) verdict = "fail";
        if (named(c, "skipped")) {
          verdict = "skip";
          skip_message = attribute(c, "message");
        }
        if (named(c, "error")) {
          verdict = "error";
          errors.push_back(attribute(c, "message"));
        }
      }
      ++tests;
      failures += verdict == "fail";
      erring += verdict == "error";
      skipped += verdict == "skip";
      if (attribute(test, "classname") == kJunitRunClassname) {
        ++out.run_testcases;
        out.run_errors.insert(out.run_errors.end(), errors.begin(), errors.end());
        continue;
      }
      const std::string name = attribute(test, "name");
      if (!out.vectors.emplace(name, verdict).second) problems.push_back("JUnit: testcase \"" + name + "\" twice");
      if (verdict == "skip") out.skip_messages[name] = skip_message;
      if (verdict == "error" && !errors.empty()) out.error_messages[name] = errors.front();
    }
    check_counts(suite, "testsuite \"" + attribute(suite, "name") + "\"", tests, failures, erring, skipped, problems);
    all_tests += tests;
    all_failures += failures;
    all_errors += erring;
  }
  check_counts(root, "testsuites", all_tests, all_failures, all_errors, 0, problems);
  return out;
}

}  // namespace

Problems junit_problems(std::string_view xml, const RunDocument& doc) {
  Problems problems;
  xmlSetStructuredErrorFunc(&problems, collect);
  std::unique_ptr<xmlDoc, DocDeleter> parsed(
      xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "junit.xml", nullptr, XML_PARSE_NONET));
  if (parsed) {
    std::unique_ptr<xmlSchemaValidCtxt, ValidDeleter> valid(xmlSchemaNewValidCtxt(const_cast<xmlSchema*>(junit_schema())));
    xmlSchemaSetValidStructuredErrors(valid.get(), collect, &problems);
    if (xmlSchemaValidateDoc(valid.get(), parsed.get()) != 0 && problems.empty())
      problems.push_back("JUnit: not valid against reports/junit.xsd");
  } else if (problems.empty()) {
    problems.push_back("JUnit: not XML");
  }
  xmlSetStructuredErrorFunc(nullptr, nullptr);
  if (!problems.empty()) return problems;

  // Every vector a testcase, with its verdict.
  const Testcases all = testcases(xmlDocGetRootElement(parsed.get()), problems);
  const auto& cases = all.vectors;
  if (cases.size() != doc.vectors.size())
    problems.push_back("JUnit: " + std::to_string(cases.size()) + " testcases for " + std::to_string(doc.vectors.size()) +
                       " vectors");
  // A run that did not reach its end is one error naming why, never a
  // failure of a vector; a complete run has no such testcase.
  const std::string unfinished = doc.unfinished_reason();
  if (unfinished.empty() && all.run_testcases > 0)
    problems.push_back("JUnit: the run is complete, but has a testcase of class " + std::string(kJunitRunClassname));
  if (!unfinished.empty() && (all.run_testcases != 1 || all.run_errors.size() != 1))
    problems.push_back("JUnit: the run is " + doc.status + " (" + unfinished + "), but has " +
                       std::to_string(all.run_errors.size()) + " error(s) in " + std::to_string(all.run_testcases) +
                       " testcase(s) of class " + std::string(kJunitRunClassname) + ", not one");
  else if (!unfinished.empty() && all.run_errors.front() != as_attribute(shown(unfinished)))
    problems.push_back("JUnit: the run's error says \"" + all.run_errors.front() + "\", not why the run ended: \"" +
                       as_attribute(shown(unfinished)) + "\"");
  for (const auto& v : doc.vectors) {
    const std::string want = v.lost_device() || v.is_error()         ? "error"
                             : v.is_failure()                        ? "fail"
                             : v.is_skip() || v.is_inconclusive()    ? "skip"
                                                                     : "pass";
    const auto it = cases.find(shown(v.id));
    if (it == cases.end()) problems.push_back("JUnit: no testcase for " + v.id);
    else if (it->second != want) problems.push_back("JUnit: testcase " + v.id + " is a " + it->second + ", the vector a " + want);
    // An inconclusive vector is a skip that says so, and why.
    else if (v.is_inconclusive() && all.skip_messages.at(shown(v.id)) != as_attribute(shown("inconclusive: " + v.inconclusive_reason)))
      problems.push_back("JUnit: the skipped testcase " + v.id + " says \"" + all.skip_messages.at(shown(v.id)) +
                         "\", not \"inconclusive: " + v.inconclusive_reason + "\"");
    // A vector in error is an <error> whose message is what the line did.
    else if (v.is_error() && all.error_messages.at(shown(v.id)) != as_attribute(shown(v.error_reason)))
      problems.push_back("JUnit: the error of testcase " + v.id + " says \"" + all.error_messages.at(shown(v.id)) + "\", not \"" +
                         v.error_reason + "\"");
  }
  return problems;
}

}  // namespace sabus::reports::checks
