// The errata document (protocol/ERRATA.md) read as data: one entry per
// "### E-N: title" heading with its fields (Paragraph, Spec text, Decision,
// Class, Alternatives, Level, Switch, Vectors), the rules every entry keeps
// (check_errata: every entry classified, every reading with its
// alternatives), and the index table at the top of the document, generated
// from the entries. Read by the suite linter (which entries exist and which
// are withdrawn), by `sabus vectors errata` and by the tests that keep the
// document classified. Pure functions of the text: no I/O.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sabus::harness {

// What the spec does with an entry's point (ERRATA.md header, "Class"):
// text -- the spec states one answer; reading -- silent, garbled with more
// than one plausible reconstruction, self-contradictory or loose, so a
// controller may take any listed alternative; withdrawn -- no longer applies.
enum class ErrataClass { kMissing, kUnknown, kText, kReading, kWithdrawn };
std::string_view to_string(ErrataClass c);

// One alternative of an entry: its label ("reference", "other", "other-2", ...)
// and what a controller does under it.
struct ErrataAlternative {
  std::string label;
  std::string text;
};

// One "- **Name:** text" field, its continuation lines joined by one blank.
struct ErrataField {
  std::string name;
  std::string text;
  std::size_t line = 0;  // 1-based
};

struct ErrataEntry {
  std::size_t number = 0;  // 7 for E-7
  std::string title;
  std::size_t line = 0;          // of the heading, 1-based
  bool heading_withdrawn = false;  // the heading says "withdrawn"
  std::vector<ErrataField> fields;  // in the order written
  ErrataClass cls = ErrataClass::kMissing;
  std::string class_text;  // the Class field as written ("text -- the table is ..." keeps its clause)
  std::vector<ErrataAlternative> alternatives;
  std::string today;  // the Alternatives' "Today:" item: how the vectors treat the point now
  // The `readings: {E-N: a|b}` key the Switch names, if any: the id as
  // written and the labels a profile may pin.
  std::optional<std::string> switch_reading_id;
  std::vector<std::string> switch_reading_labels;

  std::string id() const { return "E-" + std::to_string(number); }
  const ErrataField* field(std::string_view name) const;
  // Withdrawn by its heading or by its Class.
  bool withdrawn() const { return heading_withdrawn || cls == ErrataClass::kWithdrawn; }
};

struct ErrataDocument {
  std::vector<ErrataEntry> entries;  // in document order
  const ErrataEntry* find(std::size_t number) const;
};

// Never fails: a malformed field is kept as written and check_errata names it.
ErrataDocument parse_errata(std::string_view text);

// Every broken rule, one message each ("E-7: no Class field"):
// - every entry has the fields Paragraph, Spec text, Decision, Class, Level,
//   Switch, Vectors, in that order, with Alternatives (if any) right after Class;
// - Class is text, reading or withdrawn (withdrawn exactly when the heading says so);
// - a reading lists its Alternatives: `reference` first, then `other`, then
//   `other-2`, `other-3`, ..., each saying what a controller does, and a
//   "Today:" item saying how the vectors treat it now;
// - a text entry has Alternatives only with a `readings:` switch (a field the
//   text itself leaves free: the two controllers differ, no vector judges it);
// - a Switch that names `readings: {E-N: ...}` names the entry's own id and
//   exactly its alternatives' labels, and its entry is a reading or such a
//   text entry;
// - ids are unique.
std::vector<std::string> check_errata(const ErrataDocument& doc);

struct ErrataCounts {
  std::size_t text = 0, reading = 0, withdrawn = 0, unclassified = 0;
};
ErrataCounts count_classes(const ErrataDocument& doc);

// The index table (Markdown): id, title, class, level, switch (short), one
// row per entry by number.
std::string errata_index_table(const ErrataDocument& doc);

// The markers the index sits between in ERRATA.md.
inline constexpr std::string_view kErrataIndexBegin = "<!-- errata-index:begin -->";
inline constexpr std::string_view kErrataIndexEnd = "<!-- errata-index:end -->";

// `text` with the index between its markers rebuilt from the entries of
// `text`; nullopt when the markers are missing or out of order.
std::optional<std::string> with_errata_index(std::string_view text);

}  // namespace sabus::harness
