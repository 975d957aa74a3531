// protocol/ERRATA.md as data (errata.hpp): the entries, their fields, the
// Class and Alternatives of each, the rules they keep and the index table.
#include "sabus/harness/errata.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <map>
#include <set>

namespace sabus::harness {
namespace {

// The fields of an entry in the order they are written; Alternatives is the
// only optional one.
constexpr std::array<std::string_view, 8> kFieldOrder = {"Paragraph", "Spec text", "Decision", "Class",
                                                         "Alternatives", "Level", "Switch", "Vectors"};
constexpr std::string_view kOptionalField = "Alternatives";
constexpr std::string_view kTodayItem = "Today:";

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

void append(std::string& to, std::string_view more) {
  more = trimmed(more);
  if (more.empty()) return;
  if (!to.empty()) to += ' ';
  to += more;
}

std::size_t indent_of(std::string_view line) {
  std::size_t n = 0;
  while (n < line.size() && line[n] == ' ') ++n;
  return n;
}

ErrataClass class_of(std::string_view text) {
  std::size_t n = 0;
  while (n < text.size() && text[n] >= 'a' && text[n] <= 'z') ++n;
  const std::string_view word = text.substr(0, n);
  if (word.empty()) return text.empty() ? ErrataClass::kMissing : ErrataClass::kUnknown;
  if (word == "text") return ErrataClass::kText;
  if (word == "reading") return ErrataClass::kReading;
  if (word == "withdrawn") return ErrataClass::kWithdrawn;
  return ErrataClass::kUnknown;
}

// "profile `readings: {E-90: reference|other}` (unpinned: ...)": the id and labels.
void read_switch(ErrataEntry& e, std::string_view text) {
  constexpr std::string_view kKey = "readings: {";
  const std::size_t at = text.find(kKey);
  if (at == std::string_view::npos) return;
  std::string_view rest = text.substr(at + kKey.size());
  const std::size_t close = rest.find('}');
  const std::size_t colon = rest.find(':');
  if (close == std::string_view::npos || colon == std::string_view::npos || colon > close) {
    e.switch_reading_id = std::string(trimmed(rest.substr(0, std::min(close, rest.size()))));
    return;
  }
  e.switch_reading_id = std::string(trimmed(rest.substr(0, colon)));
  std::string_view labels = rest.substr(colon + 1, close - colon - 1);
  while (true) {
    const std::size_t bar = labels.find('|');
    e.switch_reading_labels.emplace_back(trimmed(labels.substr(0, bar)));
    if (bar == std::string_view::npos) break;
    labels.remove_prefix(bar + 1);
  }
}

// One line of the Alternatives' sub-list: "  - `label`: text", "  - Today: text",
// or a continuation of the item before it.
void read_alternatives_line(ErrataEntry& e, std::string_view line, bool& in_today) {
  const std::string_view item = trimmed(line);
  if (starts_with(item, "- `")) {
    const std::string_view rest = item.substr(3);
    const std::size_t tick = rest.find('`');
    ErrataAlternative a;
    a.label = std::string(rest.substr(0, tick));
    if (tick != std::string_view::npos) {
      std::string_view after = rest.substr(tick + 1);
      if (starts_with(after, ":")) after.remove_prefix(1);
      append(a.text, after);
    }
    e.alternatives.push_back(std::move(a));
    in_today = false;
  } else if (starts_with(item, "- ") && starts_with(trimmed(item.substr(2)), kTodayItem)) {
    append(e.today, trimmed(item.substr(2)).substr(kTodayItem.size()));
    in_today = true;
  } else if (in_today) {
    append(e.today, item);
  } else if (!e.alternatives.empty()) {
    append(e.alternatives.back().text, item);
  }
}

std::string escaped_cell(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

bool has_word(std::string_view text, std::string_view word, std::size_t& at) {
  for (std::size_t from = 0;;) {
    const std::size_t hit = text.find(word, from);
    if (hit == std::string_view::npos) return false;
    auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
    const bool start = hit == 0 || !letter(text[hit - 1]);
    const bool end = hit + word.size() == text.size() || !letter(text[hit + word.size()]);
    if (start && end) {
      at = hit;
      return true;
    }
    from = hit + 1;
  }
}

// "must; informative for ..." -> "must, informative": the levels named, in order.
std::string short_level(const ErrataEntry& e) {
  const ErrataField* f = e.field("Level");
  if (!f) return "";
  std::vector<std::pair<std::size_t, std::string_view>> found;
  for (std::string_view w : {"must", "should", "informative"})
    if (std::size_t at = 0; has_word(f->text, w, at)) found.emplace_back(at, w);
  std::sort(found.begin(), found.end());
  std::string out;
  for (const auto& [at, w] : found) out += (out.empty() ? "" : ", ") + std::string(w);
  return out;
}

// What kind of switch selects the entry's reading: readings, receiver, profile, tool, none.
std::string short_switch(const ErrataEntry& e) {
  const ErrataField* f = e.field("Switch");
  if (!f) return "";
  std::vector<std::string> kinds;
  if (e.switch_reading_id) kinds.push_back("`readings`");
  if (f->text.find("receiver option") != std::string::npos) kinds.push_back("receiver");
  const std::string rest = e.switch_reading_id ? f->text.substr(f->text.find('}') + 1) : f->text;
  if (rest.find("profile") != std::string::npos) kinds.push_back("profile");
  if (f->text.find("`sabus ") != std::string::npos) kinds.push_back("tool");
  if (kinds.empty()) kinds.push_back(starts_with(f->text, "none") ? "none" : "other");
  std::string out;
  for (const auto& k : kinds) out += (out.empty() ? "" : ", ") + k;
  return out;
}

}  // namespace

std::string_view to_string(ErrataClass c) {
  switch (c) {
    case ErrataClass::kMissing: return "missing";
    case ErrataClass::kUnknown: return "unknown";
    case ErrataClass::kText: return "text";
    case ErrataClass::kReading: return "reading";
    case ErrataClass::kWithdrawn: return "withdrawn";
  }
  return "unknown";
}

const ErrataField* ErrataEntry::field(std::string_view name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

const ErrataEntry* ErrataDocument::find(std::size_t number) const {
  for (const auto& e : entries)
    if (e.number == number) return &e;
  return nullptr;
}

ErrataDocument parse_errata(std::string_view text) {
  ErrataDocument doc;
  ErrataEntry* entry = nullptr;
  ErrataField* field = nullptr;
  bool in_today = false;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (starts_with(line, "### E-")) {
      ErrataEntry e;
      const std::size_t colon = line.find(':');
      const std::string_view digits = line.substr(6, colon == std::string_view::npos ? std::string_view::npos : colon - 6);
      const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), e.number);
      if (ec != std::errc() || end != digits.data() + digits.size()) e.number = 0;
      e.title = colon == std::string_view::npos ? std::string() : std::string(trimmed(line.substr(colon + 1)));
      e.line = line_no;
      std::string lower(line);
      std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(c | 0x20); });
      e.heading_withdrawn = lower.find("withdrawn") != std::string::npos;
      doc.entries.push_back(std::move(e));
      entry = &doc.entries.back();
      field = nullptr;
      continue;
    }
    if (starts_with(line, "#")) {  // another heading ends the entry
      entry = nullptr;
      field = nullptr;
      continue;
    }
    if (!entry) continue;
    if (trimmed(line).empty()) {
      field = nullptr;
      continue;
    }
    if (starts_with(line, "- **")) {
      const std::size_t close = line.find(":**");
      if (close == std::string_view::npos) {
        field = nullptr;
        continue;
      }
      entry->fields.push_back({std::string(line.substr(4, close - 4)), std::string(trimmed(line.substr(close + 3))), line_no});
      field = &entry->fields.back();
      in_today = false;
      continue;
    }
    if (!field || indent_of(line) == 0) {
      field = nullptr;
      continue;
    }
    if (field->name == "Alternatives") read_alternatives_line(*entry, line, in_today);
    append(field->text, line);
  }
  for (auto& e : doc.entries) {
    if (const ErrataField* c = e.field("Class")) {
      e.class_text = c->text;
      e.cls = class_of(c->text);
    }
    if (const ErrataField* s = e.field("Switch")) read_switch(e, s->text);
  }
  return doc;
}

std::vector<std::string> check_errata(const ErrataDocument& doc) {
  std::vector<std::string> problems;
  std::set<std::size_t> seen;
  for (const auto& e : doc.entries) {
    const std::string id = e.number ? e.id() : "line " + std::to_string(e.line);
    auto fail = [&](const std::string& message) { problems.push_back(id + ": " + message); };
    if (!e.number) fail("the heading is not \"### E-N: title\"");
    else if (!seen.insert(e.number).second) fail("the id is used twice");
    // The fields, once each, in their order.
    std::size_t last = 0;
    std::set<std::string> names;
    for (const auto& f : e.fields) {
      const auto it = std::find(kFieldOrder.begin(), kFieldOrder.end(), f.name);
      if (it == kFieldOrder.end()) {
        fail("unknown field \"" + f.name + "\" (line " + std::to_string(f.line) + ")");
        continue;
      }
      if (!names.insert(f.name).second) fail("field \"" + f.name + "\" given twice");
      const auto index = static_cast<std::size_t>(it - kFieldOrder.begin());
      if (index < last) fail("field \"" + f.name + "\" out of order (the order: Paragraph, Spec text, Decision, Class, Alternatives, Level, Switch, Vectors)");
      last = std::max(last, index);
    }
    for (std::string_view name : kFieldOrder)
      if (name != kOptionalField && !names.count(std::string(name))) fail("no " + std::string(name) + " field");
    // The class.
    if (e.cls == ErrataClass::kUnknown)
      fail("Class \"" + e.class_text + "\" is none of text, reading, withdrawn");
    if (e.heading_withdrawn && e.cls != ErrataClass::kWithdrawn && e.cls != ErrataClass::kMissing)
      fail("the heading says withdrawn but the Class is " + std::string(to_string(e.cls)));
    if (e.cls == ErrataClass::kWithdrawn && !e.heading_withdrawn) fail("Class withdrawn but the heading does not say so");
    // The alternatives.
    const bool listed = e.field("Alternatives") != nullptr;
    if (e.cls == ErrataClass::kReading && !listed) fail("a reading with no Alternatives");
    if (e.cls == ErrataClass::kText && listed && !e.switch_reading_id)
      fail("a text entry with Alternatives but no `readings:` switch (a text entry lists them only for a field the text leaves free)");
    if (e.cls == ErrataClass::kWithdrawn && listed) fail("a withdrawn entry with Alternatives");
    if (listed) {
      if (e.alternatives.size() < 2) fail("Alternatives lists fewer than two (`reference` and `other`)");
      for (std::size_t k = 0; k < e.alternatives.size(); ++k) {
        const std::string want = k == 0 ? "reference" : k == 1 ? "other" : "other-" + std::to_string(k);
        if (e.alternatives[k].label != want)
          fail("alternative " + std::to_string(k + 1) + " is `" + e.alternatives[k].label + "`, not `" + want + "`");
        if (e.alternatives[k].text.empty()) fail("alternative `" + e.alternatives[k].label + "` says nothing");
      }
      if (e.today.empty()) fail("Alternatives has no \"Today:\" item (how the vectors treat the point now)");
    }
    // The switch.
    if (const ErrataField* s = e.field("Switch"); s && e.cls == ErrataClass::kReading &&
                                                  s->text.find("fixed reading") != std::string::npos)
      fail("a reading whose Switch says \"fixed reading\"");
    if (e.switch_reading_id) {
      if (*e.switch_reading_id != e.id()) fail("the Switch's `readings:` key names " + *e.switch_reading_id + ", not " + e.id());
      std::vector<std::string> labels;
      for (const auto& a : e.alternatives) labels.push_back(a.label);
      if (e.switch_reading_labels != labels) {
        std::string named, listed_labels;
        for (const auto& l : e.switch_reading_labels) named += (named.empty() ? "" : "|") + l;
        for (const auto& l : labels) listed_labels += (listed_labels.empty() ? "" : "|") + l;
        fail("the Switch's `readings:` labels " + named + " are not the alternatives " + listed_labels);
      }
      if (e.cls != ErrataClass::kReading && !(e.cls == ErrataClass::kText && listed))
        fail("a `readings:` switch on an entry of class " + std::string(to_string(e.cls)));
    }
    if (e.cls == ErrataClass::kMissing) fail("no Class (text, reading or withdrawn)");
  }
  return problems;
}

ErrataCounts count_classes(const ErrataDocument& doc) {
  ErrataCounts n;
  for (const auto& e : doc.entries) {
    switch (e.cls) {
      case ErrataClass::kText: ++n.text; break;
      case ErrataClass::kReading: ++n.reading; break;
      case ErrataClass::kWithdrawn: ++n.withdrawn; break;
      case ErrataClass::kMissing:
      case ErrataClass::kUnknown: ++n.unclassified; break;
    }
  }
  return n;
}

std::string errata_index_table(const ErrataDocument& doc) {
  std::vector<const ErrataEntry*> by_number;
  for (const auto& e : doc.entries) by_number.push_back(&e);
  std::stable_sort(by_number.begin(), by_number.end(), [](const auto* a, const auto* b) { return a->number < b->number; });
  std::string out = "| id | title | class | level | switch |\n|---|---|---|---|---|\n";
  for (const ErrataEntry* e : by_number)
    out += "| " + e->id() + " | " + escaped_cell(e->title) + " | " + std::string(to_string(e->cls)) + " | " +
           short_level(*e) + " | " + short_switch(*e) + " |\n";
  return out;
}

std::optional<std::string> with_errata_index(std::string_view text) {
  const std::size_t begin = text.find(kErrataIndexBegin);
  if (begin == std::string_view::npos) return std::nullopt;
  const std::size_t after_begin = text.find('\n', begin);
  const std::size_t end = text.find(kErrataIndexEnd, begin);
  if (after_begin == std::string_view::npos || end == std::string_view::npos || end < after_begin) return std::nullopt;
  std::string out(text.substr(0, after_begin + 1));
  out += errata_index_table(parse_errata(text));
  out += text.substr(end);
  return out;
}

}  // namespace sabus::harness
