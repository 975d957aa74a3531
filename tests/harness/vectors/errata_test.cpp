// protocol/ERRATA.md read as data (errata.hpp): every entry classified,
// every reading with its alternatives, `readings:` switches only where an
// alternative can be pinned, the index current; and the parser and the rules
// on small documents, each rule broken once.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

#include "sabus/harness/errata.hpp"
#include "sabus/harness/readings.hpp"

namespace sabus::harness {
namespace {

std::string errata_text() {
  std::ifstream in(SABUS_SOURCE_DIR "/protocol/ERRATA.md");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

bool mentions(const std::vector<std::string>& problems, const std::string& part) {
  return std::any_of(problems.begin(), problems.end(), [&](const std::string& p) { return p.find(part) != std::string::npos; });
}

// One well-formed reading, to break one piece at a time.
const std::string kReading =
    "### E-5: A reading\n"
    "- **Paragraph:** §1\n"
    "- **Spec text:** `quote`\n"
    "- **Decision:** the project's\n"
    "  reading, wrapped.\n"
    "- **Class:** reading\n"
    "- **Alternatives:**\n"
    "  - `reference`: the controller NAKs,\n"
    "    and says why.\n"
    "  - `other`: it ACKs.\n"
    "  - Today: the vectors accept both.\n"
    "- **Level:** should\n"
    "- **Switch:** profile `readings: {E-5: reference|other}` (unpinned: the vectors accept both)\n"
    "- **Vectors:** — (no vector yet)\n";

const std::string kText =
    "### E-6: A text entry\n"
    "- **Paragraph:** §2\n"
    "- **Spec text:** `quote`\n"
    "- **Decision:** as written.\n"
    "- **Class:** text — one reconstruction\n"
    "- **Level:** must\n"
    "- **Switch:** none (the text)\n"
    "- **Vectors:** `v-1`, `v-2`\n";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// ---- the project's document ------------------------------------------------------

TEST(Errata, EveryEntryIsClassifiedAndTheCountsArePrinted) {
  const std::string text = errata_text();
  ASSERT_FALSE(text.empty()) << "cannot read " SABUS_SOURCE_DIR "/protocol/ERRATA.md";
  const ErrataDocument doc = parse_errata(text);
  ASSERT_GE(doc.entries.size(), 95u);
  for (const auto& e : doc.entries)
    EXPECT_TRUE(e.cls == ErrataClass::kText || e.cls == ErrataClass::kReading || e.cls == ErrataClass::kWithdrawn)
        << e.id() << " (line " << e.line << "): Class is " << to_string(e.cls) << " (\"" << e.class_text << "\")";
  const ErrataCounts n = count_classes(doc);
  EXPECT_EQ(n.unclassified, 0u);
  EXPECT_EQ(n.text + n.reading + n.withdrawn, doc.entries.size());
  // For the CI log.
  std::cout << "errata: " << n.text << " text, " << n.reading << " reading, " << n.withdrawn << " withdrawn\n";
}

TEST(Errata, EveryReadingListsItsReferenceAndAnotherAlternative) {
  const ErrataDocument doc = parse_errata(errata_text());
  for (const auto& e : doc.entries) {
    if (e.cls != ErrataClass::kReading) continue;
    ASSERT_GE(e.alternatives.size(), 2u) << e.id();
    EXPECT_EQ(e.alternatives[0].label, "reference") << e.id();
    EXPECT_EQ(e.alternatives[1].label, "other") << e.id();
    for (const auto& a : e.alternatives) EXPECT_FALSE(a.text.empty()) << e.id() << " `" << a.label << "`";
    EXPECT_FALSE(e.today.empty()) << e.id() << ": no Today item";
  }
}

// A `readings:` key pins an alternative: only a reading has them, or a text
// entry whose text leaves the value free and lists what the controllers do
// (E-95); its key names the entry itself and its alternatives' labels.
TEST(Errata, AReadingsSwitchIsOnAnEntryWithAlternatives) {
  const ErrataDocument doc = parse_errata(errata_text());
  std::size_t switches = 0;
  for (const auto& e : doc.entries) {
    if (!e.switch_reading_id) continue;
    ++switches;
    EXPECT_TRUE(e.cls == ErrataClass::kReading || (e.cls == ErrataClass::kText && !e.alternatives.empty())) << e.id();
    EXPECT_EQ(*e.switch_reading_id, e.id());
    ASSERT_EQ(e.switch_reading_labels.size(), e.alternatives.size()) << e.id();
    for (std::size_t k = 0; k < e.alternatives.size(); ++k)
      EXPECT_EQ(e.switch_reading_labels[k], e.alternatives[k].label) << e.id();
  }
  // Which entries have one is readings.hpp's table
  // (Errata.ItsReadingsSwitchesAreTheControllersTable).
  EXPECT_EQ(switches, reading_points().size());
}

TEST(Errata, TheDocumentKeepsEveryRule) {
  const auto problems = check_errata(parse_errata(errata_text()));
  EXPECT_TRUE(problems.empty()) << joined(problems);
}

TEST(Errata, TheIndexIsCurrent) {
  const std::string text = errata_text();
  const auto indexed = with_errata_index(text);
  ASSERT_TRUE(indexed.has_value()) << "no index markers";
  EXPECT_TRUE(*indexed == text) << "the index is not current: run tools/update-suite-docs.sh (sabus vectors errata --update)";
}

// Removing any entry's Class line breaks the rules, naming that entry.
TEST(Errata, RemovingAnyClassLineFails) {
  const std::string text = errata_text();
  const ErrataDocument doc = parse_errata(text);
  std::size_t tried = 0;
  for (const auto& e : doc.entries) {
    const ErrataField* c = e.field("Class");
    ASSERT_NE(c, nullptr) << e.id();
    // The Class line and its continuation lines.
    std::size_t begin = 0;
    for (std::size_t line = 1; line < c->line; ++line) begin = text.find('\n', begin) + 1;
    std::size_t end = text.find('\n', begin) + 1;
    while (text.compare(end, 2, "  ") == 0) end = text.find('\n', end) + 1;
    const std::string without = text.substr(0, begin) + text.substr(end);
    const auto problems = check_errata(parse_errata(without));
    EXPECT_TRUE(mentions(problems, e.id() + ": no Class")) << e.id() << ":\n" << joined(problems);
    ++tried;
  }
  EXPECT_EQ(tried, doc.entries.size());
}

// ---- the parser ------------------------------------------------------------------------

TEST(ErrataParser, ReadsFieldsClassAlternativesAndSwitch) {
  const ErrataDocument doc = parse_errata("# Title\n\nProse.\n\n## Section\n\n" + kReading + "\n" + kText);
  ASSERT_EQ(doc.entries.size(), 2u);
  const ErrataEntry& r = doc.entries[0];
  EXPECT_EQ(r.number, 5u);
  EXPECT_EQ(r.title, "A reading");
  EXPECT_EQ(r.line, 7u);
  EXPECT_EQ(r.cls, ErrataClass::kReading);
  ASSERT_NE(r.field("Decision"), nullptr);
  EXPECT_EQ(r.field("Decision")->text, "the project's reading, wrapped.");
  ASSERT_EQ(r.alternatives.size(), 2u);
  EXPECT_EQ(r.alternatives[0].label, "reference");
  EXPECT_EQ(r.alternatives[0].text, "the controller NAKs, and says why.");
  EXPECT_EQ(r.alternatives[1].label, "other");
  EXPECT_EQ(r.alternatives[1].text, "it ACKs.");
  EXPECT_EQ(r.today, "the vectors accept both.");
  ASSERT_TRUE(r.switch_reading_id.has_value());
  EXPECT_EQ(*r.switch_reading_id, "E-5");
  EXPECT_EQ(r.switch_reading_labels, (std::vector<std::string>{"reference", "other"}));
  const ErrataEntry& t = doc.entries[1];
  EXPECT_EQ(t.cls, ErrataClass::kText);
  EXPECT_EQ(t.class_text, "text — one reconstruction");
  EXPECT_TRUE(t.alternatives.empty());
  EXPECT_FALSE(t.switch_reading_id.has_value());
  EXPECT_TRUE(check_errata(doc).empty()) << joined(check_errata(doc));
  const ErrataCounts n = count_classes(doc);
  EXPECT_EQ(n.text, 1u);
  EXPECT_EQ(n.reading, 1u);
}

TEST(ErrataParser, TheIndexHasARowPerEntryByNumber) {
  const ErrataDocument doc = parse_errata(kText + "\n" + kReading);
  EXPECT_EQ(errata_index_table(doc),
            "| id | title | class | level | switch |\n|---|---|---|---|---|\n"
            "| E-5 | A reading | reading | should | `readings` |\n"
            "| E-6 | A text entry | text | must | none |\n");
  const std::string text = "# T\n\n" + std::string(kErrataIndexBegin) + "\nold\n" + std::string(kErrataIndexEnd) + "\n\n" + kText;
  const auto indexed = with_errata_index(text);
  ASSERT_TRUE(indexed.has_value());
  EXPECT_NE(indexed->find("| E-6 | A text entry | text | must | none |\n" + std::string(kErrataIndexEnd)), std::string::npos)
      << *indexed;
  EXPECT_EQ(indexed->find("old"), std::string::npos);
  EXPECT_FALSE(with_errata_index(kText).has_value()) << "no markers";
}

// ---- each rule, broken once ----------------------------------------------------------

struct Broken {
  std::string name, from, to, problem;
};

TEST(ErrataRules, EachBrokenRuleIsNamed) {
  const std::vector<Broken> cases = {
      {"no class", "- **Class:** reading\n", "", "E-5: no Class"},
      {"unknown class", "- **Class:** reading\n", "- **Class:** maybe\n", "is none of text, reading, withdrawn"},
      {"reading without alternatives",
       "- **Alternatives:**\n  - `reference`: the controller NAKs,\n    and says why.\n  - `other`: it ACKs.\n  - Today: the vectors accept both.\n",
       "", "a reading with no Alternatives"},
      {"only the reference", "  - `other`: it ACKs.\n", "", "fewer than two"},
      {"other first", "`reference`: the controller", "`other`: the controller", "alternative 1 is `other`, not `reference`"},
      {"a label out of turn", "`other`: it ACKs.", "`other-2`: it ACKs.", "alternative 2 is `other-2`, not `other`"},
      {"an empty alternative", "`other`: it ACKs.", "`other`:", "alternative `other` says nothing"},
      {"no today", "  - Today: the vectors accept both.\n", "", "no \"Today:\" item"},
      {"switch names another entry", "{E-5: reference|other}", "{E-7: reference|other}", "names E-7, not E-5"},
      {"switch labels differ", "{E-5: reference|other}", "{E-5: reference|other|other-2}", "are not the alternatives"},
      {"a fixed reading", "- **Switch:** profile `readings: {E-5: reference|other}` (unpinned: the vectors accept both)\n",
       "- **Switch:** none (fixed reading)\n", "a reading whose Switch says \"fixed reading\""},
      {"field out of order", "- **Level:** should\n", "- **Vectors:** x\n- **Level:** should\n", "out of order"},
      {"no level", "- **Level:** should\n", "", "no Level field"},
      {"withdrawn class, heading not", "- **Class:** reading\n", "- **Class:** withdrawn\n",
       "Class withdrawn but the heading does not say so"},
  };
  for (const auto& c : cases) {
    const auto problems = check_errata(parse_errata(replaced(kReading, c.from, c.to) + "\n" + kText));
    EXPECT_TRUE(mentions(problems, c.problem)) << c.name << ":\n" << joined(problems);
  }
  // On the text entry: alternatives need a `readings:` switch; a `readings:`
  // switch needs alternatives.
  const std::string with_alternatives = replaced(
      kText, "- **Level:**", "- **Alternatives:**\n  - `reference`: a.\n  - `other`: b.\n  - Today: c.\n- **Level:**");
  EXPECT_TRUE(mentions(check_errata(parse_errata(with_alternatives)), "a text entry with Alternatives but no `readings:` switch"));
  const std::string free_field =
      replaced(with_alternatives, "none (the text)", "profile `readings: {E-6: reference|other}` (unpinned: the vectors accept both)");
  EXPECT_TRUE(check_errata(parse_errata(free_field)).empty()) << joined(check_errata(parse_errata(free_field)));
  const std::string switch_only =
      replaced(kText, "none (the text)", "profile `readings: {E-6: reference|other}` (unpinned: the vectors accept both)");
  EXPECT_TRUE(mentions(check_errata(parse_errata(switch_only)), "a `readings:` switch on an entry of class text"));
  // Ids are unique; a withdrawn heading needs a withdrawn class.
  EXPECT_TRUE(mentions(check_errata(parse_errata(kText + "\n" + kText)), "E-6: the id is used twice"));
  const std::string withdrawn = replaced(kText, "A text entry", "A text entry (withdrawn)");
  EXPECT_TRUE(mentions(check_errata(parse_errata(withdrawn)), "the heading says withdrawn but the Class is text"));
  EXPECT_TRUE(check_errata(parse_errata(replaced(withdrawn, "- **Class:** text — one reconstruction", "- **Class:** withdrawn")))
                  .empty());
}

}  // namespace
}  // namespace sabus::harness

namespace sabus::harness {
namespace {

// The entries whose Switch is a `readings:` key are exactly the table the
// profile loader, the reference controller and the vectors use
// (readings.hpp), each with the sides that table knows (a third, other-2,
// where the entry lists one).
TEST(Errata, ItsReadingsSwitchesAreTheControllersTable) {
  std::ifstream in(SABUS_SOURCE_DIR "/protocol/ERRATA.md");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const ErrataDocument doc = parse_errata(text);
  std::vector<std::string> switched;
  for (const ErrataEntry& e : doc.entries)
    if (e.switch_reading_id) {
      switched.push_back(*e.switch_reading_id);
      EXPECT_NE(find_reading_point(*e.switch_reading_id), nullptr)
          << e.id() << " has a readings: switch the controller does not take (readings.hpp)";
      if (const ReadingPoint* point = find_reading_point(*e.switch_reading_id)) {
        std::vector<std::string> sides;
        for (ReadingSide side : sides_of(*point)) sides.emplace_back(to_string(side));
        EXPECT_EQ(e.switch_reading_labels, sides) << e.id();
      }
    }
  for (const ReadingPoint& p : reading_points())
    EXPECT_NE(std::find(switched.begin(), switched.end(), std::string(p.id)), switched.end())
        << p.id << " is in readings.hpp but its ERRATA entry has no readings: switch";
}

}  // namespace
}  // namespace sabus::harness
