// `sabus vectors lint|list|coverage`: checks the conformance vector suite
// (vectors/*.yaml), lists its vectors and prints its coverage matrix. The loader and linter are sabus::vectors
// (vector_loader.hpp); this file only prints.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>

#include "commands.hpp"
#include "json_output.hpp"
#include "selection.hpp"
#include "sweep.hpp"
#include "sabus/harness/coverage.hpp"
#include "sabus/harness/errata.hpp"
#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/expressions.hpp"
#include "sabus/harness/files.hpp"
#include "sabus/harness/profile_generator.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/harness/vector_schema.hpp"

namespace sabus::cli {
namespace {

namespace fs = std::filesystem;

using harness::LoadError;
using harness::LoadResult;
using harness::Vector;

struct VectorsOptions {
  std::vector<std::string> paths;
  SelectionOptions selection;  // list: preview a selection as `sabus run` takes it
  bool json = false;
  bool missing_only = false;
  bool summary = false;
  std::string update, check;  // errata: the ERRATA.md to rewrite or compare
  std::string classes;        // errata: the ERRATA.md whose entries' classes to list
  // coverage: the random profiles the field shares are taken over, besides
  // the shipped ones (the sweep's profiles of that seed).
  std::uint64_t random_profiles = 100;
  std::uint64_t seed = 1;
  // coverage: the fields known to be checked only on some profiles (or only
  // on a literal profile value), one "reply field" a line: reported, not
  // failed; a listed field that is checked everywhere fails (the list shrinks).
  std::string known_gaps;
};

LoadResult load(const VectorsOptions& o) {
  return harness::load_vectors(o.paths.empty() ? std::vector<std::string>{harness::default_vectors_dir()} : o.paths);
}

// Files seen: loaded ones and those that failed (each error names its file).
std::size_t file_count(const LoadResult& r) {
  std::set<std::string> names;
  for (const auto& f : r.files) names.insert(f.path);
  for (const auto& e : r.errors) names.insert(e.where.file);
  return names.size();
}

std::size_t vector_count(const LoadResult& r) {
  std::size_t n = 0;
  for (const auto& f : r.files) n += f.vectors.size();
  return n;
}

int run_lint(const VectorsOptions& o) {
  LoadResult r = load(o);
  std::vector<LoadError> errors = r.errors;
  // Read once: lint checks the quotes against it, and its absence is said.
  const std::optional<std::string> spec = r.files.empty() ? std::nullopt : harness::read_spec_text();
  const auto more = harness::lint(r.files, spec);
  errors.insert(errors.end(), more.begin(), more.end());
  for (const auto& e : errors) std::cout << e.text() << "\n";
  if (!r.files.empty() && !spec)
    std::cout << "spec quotes not checked: no spec text at " << harness::spec_text_path() << "\n";
  std::cout << fmt::format("{} files, {} vectors, {} errors\n", file_count(r), vector_count(r), errors.size());
  return errors.empty() ? kExitOk : kExitFailed;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ",") + s;
  return out.empty() ? "-" : out;
}

nlohmann::json vector_json(const Vector& v) {
  nlohmann::json requires_ = nlohmann::json::object();
  for (const auto& r : v.requires_) requires_[r.key] = r.values;
  return {{"id", v.id},
          {"paragraph", v.paragraph},
          {"level", std::string(harness::to_string(v.level))},
          {"tags", v.tags},
          {"flags", v.flags},
          {"requires", requires_},
          {"file", v.where.file},
          {"line", v.where.line},
          {"steps", v.steps.size()}};
}

// One line a vector: id, paragraph, level, tags. With --filter, --exclude
// or --paragraph, only the vectors `sabus run` would take with them (a
// preview), the count and any note on stderr, and exit 5 when there are
// none. Load errors go to stderr and make the exit status 1; the vectors
// that loaded are listed anyway.
int run_list(const VectorsOptions& o) {
  LoadResult r = load(o);
  for (const auto& e : r.errors) std::cerr << e.text() << "\n";
  std::vector<Vector> all;
  for (const auto& f : r.files) all.insert(all.end(), f.vectors.begin(), f.vectors.end());
  const auto choice = selection_options(o.selection, "sabus vectors list");
  if (!choice) return kExitUsage;
  const harness::Selection selection = harness::select_vectors(all, *choice);
  const bool selecting = !o.selection.filters.empty() || !o.selection.excludes.empty() || !o.selection.paragraphs.empty() ||
                         choice->shard || choice->only || !choice->first.empty();
  std::vector<const Vector*> shown;
  for (const auto& v : selection.vectors) shown.push_back(&v);
  if (o.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const Vector* v : shown) out.push_back(vector_json(*v));
    std::cout << json_text(out);
  } else {
    for (const Vector* v : shown)
      std::cout << fmt::format("{:<44} §{:<5} {:<12} {}\n", v->id, v->paragraph, harness::to_string(v->level), joined(v->tags));
  }
  if (selecting) {
    for (const auto& note : selection.notes) std::cerr << "sabus vectors list: " << note << "\n";
    std::cerr << fmt::format("{} of {} vectors selected\n", shown.size(), all.size());
    if (shown.empty()) {
      std::cerr << "sabus vectors list: " << harness::empty_selection_reason(*choice) << "\n";
      if (r.errors.empty()) return kExitNothingRan;
    }
  }
  return r.errors.empty() ? kExitOk : kExitFailed;
}

// The profiles a field's value check must reach (issue 32): the shipped
// ones (vectors/profiles/*.yaml) and the sweep's random ones of a seed, each
// with the vectors whose requirements hold there.
std::vector<harness::ProfileSite> coverage_sites(const VectorsOptions& o, const LoadResult& r) {
  std::vector<harness::ProfileSite> sites;
  std::vector<fs::path> shipped;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(harness::default_vectors_dir()) / "profiles", ec))
    if (e.path().extension() == ".yaml") shipped.push_back(e.path());
  std::sort(shipped.begin(), shipped.end());
  for (const auto& path : shipped) {
    const harness::ProfileResult p = harness::load_profile_file(path.string());
    if (p) sites.push_back(harness::requirement_site(r.files, *p.profile, path.filename().string()));
    else std::cerr << "sabus vectors coverage: " << path.string() << ": not a profile: " << p.error->message << "\n";
  }
  for (std::uint64_t i = 0; i < o.random_profiles; ++i) {
    const std::uint64_t seed = sweep_profile_seed(o.seed, i);
    sites.push_back(harness::requirement_site(r.files, harness::random_profile(seed),
                                              fmt::format("sweep seed {} profile {} (--profile-seed {})", o.seed, i + 1, seed)));
  }
  return sites;
}

// The field labels of a known-gaps file ("status azimuth"), one a line; '#'
// starts a comment. nullopt when the file cannot be read.
std::optional<std::set<std::string>> read_known_gaps(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::set<std::string> out;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    const auto start = line.find_first_not_of(" \t");
    if (start != std::string::npos) out.insert(line.substr(start));
  }
  return out;
}

// "a, b, c and 4 more"
std::string some_of(const std::vector<std::string>& items, std::size_t shown = 6) {
  std::string out;
  for (std::size_t i = 0; i < items.size() && i < shown; ++i) out += (i ? ", " : "") + items[i];
  if (items.size() > shown) out += fmt::format(" and {} more", items.size() - shown);
  return out;
}

// The matrix command x form x path, one line a cell with its vector ids;
// exit 1 when a cell the spec defines has none (CoverageMatrix::missing),
// a field's value is checked by no vector on capabilities, or is left
// unchecked on a profile where it exists (field_shares).
int run_coverage(const VectorsOptions& o) {
  LoadResult r = load(o);
  for (const auto& e : r.errors) std::cerr << e.text() << "\n";
  if (!r.errors.empty()) return kExitUsage;
  const harness::CoverageMatrix m = harness::coverage(r.files);
  const auto missing = m.missing();
  const auto missing_values = m.missing_values();
  const auto sites = coverage_sites(o, r);
  const auto shares = harness::field_shares(m, sites);
  std::set<std::string> known;
  if (!o.known_gaps.empty()) {
    auto read = read_known_gaps(o.known_gaps);
    if (!read) {
      std::cerr << "sabus vectors coverage: --known-gaps: cannot read " << o.known_gaps << "\n";
      return kExitUsage;
    }
    known = std::move(*read);
  }
  // A field with a gap: checked by no vector on capabilities, or left
  // unchecked on a profile where it exists. A known one is reported only.
  std::set<std::string> gaps;
  for (const auto& row : m.fields)
    if (value_required(row.field->cls) && row.ids.empty()) gaps.insert(harness::field_label(*row.field));
  for (const auto& s : shares)
    if (s.checked < s.exists) gaps.insert(harness::field_label(*s.field));
  std::vector<std::string> unknown_gaps, stale_gaps;
  for (const auto& g : gaps)
    if (!known.count(g)) unknown_gaps.push_back(g);
  for (const auto& k : known)
    if (!gaps.count(k)) stale_gaps.push_back(k);
  const auto partial = std::count_if(shares.begin(), shares.end(), [](const harness::FieldShare& s) { return s.checked < s.exists; });
  if (o.json) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : m.rows) {
      nlohmann::json cells = nlohmann::json::object();
      for (auto p : harness::kCoveragePaths) cells[std::string(to_string(p))] = row.ids[static_cast<std::size_t>(p)];
      rows.push_back({{"command", fmt::format("{:02X}h", row.command->code)},
                      {"key", row.command->key},
                      {"paragraph", row.command->paragraph},
                      {"form", row.form ? std::string(row.form->id) : std::string()},
                      {"cells", cells}});
    }
    nlohmann::json fields = nlohmann::json::array();
    for (const auto& f : m.fields)
      fields.push_back({{"reply", std::string(to_string(f.field->reply))},
                        {"field", std::string(f.field->field)},
                        {"class", std::string(to_string(f.field->cls))},
                        {"paragraph", std::string(f.field->paragraph)},
                        {"required", value_required(f.field->cls)},
                        {"vectors", f.ids},
                        {"literal_vectors", f.literal_ids}});
    nlohmann::json shares_json = nlohmann::json::array();
    for (const auto& s : shares)
      shares_json.push_back({{"reply", std::string(to_string(s.field->reply))},
                             {"field", std::string(s.field->field)},
                             {"exists", s.exists},
                             {"checked", s.checked},
                             {"unchecked", s.unchecked}});
    std::cout << json_text({{"rows", rows},
                            {"unknown_codes", {{"nak", m.unknown_codes}}},
                            {"nak_rules", m.nak_rules},
                            {"fields", fields},
                            {"missing", missing},
                            {"missing_values", missing_values},
                            {"shares", shares_json}});
  } else {
    std::size_t covered = 0, cells = 0;
    for (const auto& row : m.rows) {
      for (auto p : harness::kCoveragePaths) {
        const auto& ids = row.ids[static_cast<std::size_t>(p)];
        ++cells;
        covered += !ids.empty();
        if (o.missing_only) continue;
        std::cout << fmt::format("{:<36} §{:<5} {:<8} {:>3}  {}\n", harness::row_label(row), row.command->paragraph,
                                 to_string(p), ids.size(), ids.empty() ? "-" : fmt::format("{}", fmt::join(ids, " ")));
      }
    }
    if (!o.missing_only)
      std::cout << fmt::format("{:<36} §{:<5} {:<8} {:>3}  {}\n", "other codes", "3", "nak", m.unknown_codes.size(),
                               m.unknown_codes.empty() ? "-" : fmt::format("{}", fmt::join(m.unknown_codes, " ")));
    if (!o.missing_only)
      for (const auto& [rule, ids] : m.nak_rules)
        std::cout << fmt::format("{:<36} §{:<5} {:<8} {:>3}  {}\n", "NAK rule " + rule,
                                 harness::paragraph(*harness::find_nak_rule(rule)), "nak", ids.size(),
                                 ids.empty() ? "-" : fmt::format("{}", fmt::join(ids, " ")));
    // The field-value matrix: each reply field, what its value rests on, and
    // the vectors that check that value.
    std::size_t checked = 0, required = 0;
    for (const auto& f : m.fields) {
      required += value_required(f.field->cls);
      checked += value_required(f.field->cls) && !f.ids.empty();
      if (o.missing_only) continue;
      std::cout << fmt::format("{:<36} §{:<5} {:<8} {:>3}  {}\n", "value " + harness::field_label(*f.field), f.field->paragraph,
                               to_string(f.field->cls), f.ids.size(),
                               !value_required(f.field->cls) ? "(left to the device)"
                               : f.ids.empty()               ? "-"
                                                             : fmt::format("{}", fmt::join(f.ids, " ")));
    }
    for (const auto& line : missing) std::cout << "MISSING " << line << "\n";
    auto known_gap = [&](const ReplyFieldClass& f) { return known.count(harness::field_label(f)) ? "KNOWN GAP: " : ""; };
    for (const auto& line : missing_values)  // "status azimuth (motion, §3.2): ..."
      std::cout << (known.count(line.substr(0, line.find(" ("))) ? "KNOWN GAP: " : "") << "MISSING value of " << line << "\n";
    // The field shares: a field checked only on some profiles (issue 32).
    for (const auto& s : shares)
      if (s.checked < s.exists)
        std::cout << fmt::format("{}UNCHECKED value of {} (§{}) on {} of the {} profiles where it exists: {}\n",
                                 known_gap(*s.field), harness::field_label(*s.field), s.field->paragraph,
                                 s.exists - s.checked, s.exists, some_of(s.unchecked));
    for (const auto& k : stale_gaps)
      std::cout << "STALE known gap " << k << ": its value is checked on every profile where it exists; take it off "
                << o.known_gaps << "\n";
    std::cout << fmt::format("{} of {} cells covered; {} required cell(s) without a vector\n", covered, cells,
                             missing.size());
    std::cout << fmt::format("{} of {} fields the device's state decides have their value checked; {} without a vector\n",
                             checked, required, missing_values.size());
    std::cout << fmt::format("{} of {} such fields checked on every profile where they exist; {} checked only on some "
                             "({} profiles: {} shipped, {} random of seed {})\n",
                             shares.size() - static_cast<std::size_t>(partial), shares.size(), partial, sites.size(),
                             sites.size() - o.random_profiles, o.random_profiles, o.seed);
    if (!o.known_gaps.empty())
      std::cout << fmt::format("{} field(s) with a gap, {} of them known ({}); {} not known, {} known gap(s) closed\n",
                               gaps.size(), gaps.size() - unknown_gaps.size(), o.known_gaps, unknown_gaps.size(),
                               stale_gaps.size());
  }
  // A required cell or a state-decided field without a vector fails the
  // coverage gate (gate.coverage).
  // A required cell without a vector, or a field with a gap that is not
  // known (or a known gap that is closed) fails the coverage gate
  // (gate.coverage).
  return missing.empty() && unknown_gaps.empty() && stale_gaps.empty() ? kExitOk : kExitFailed;
}

// Paragraph order: numbers by their parts (3.2 < 3.10), then the topics.
bool paragraph_less(const std::string& a, const std::string& b) {
  auto key = [](const std::string& p) {
    std::vector<int> parts;
    std::size_t at = 0;
    while (at < p.size() && std::isdigit(static_cast<unsigned char>(p[at]))) {
      std::size_t end = at;
      while (end < p.size() && std::isdigit(static_cast<unsigned char>(p[end]))) ++end;
      parts.push_back(std::stoi(p.substr(at, end - at)));
      at = end + (end < p.size() && p[end] == '.' ? 1 : 0);
    }
    return std::make_pair(parts.empty(), parts.empty() ? std::vector<int>{} : parts);
  };
  const auto ka = key(a), kb = key(b);
  if (ka != kb) return ka < kb;
  return a < b;
}

// The suite by paragraph as a Markdown table: vectors/README.md carries it.
int run_summary(const VectorsOptions& o) {
  LoadResult r = load(o);
  for (const auto& e : r.errors) std::cerr << e.text() << "\n";
  struct Counts {
    std::set<std::string> files;
    std::size_t must = 0, should = 0, informative = 0;
  };
  std::map<std::string, Counts, decltype(&paragraph_less)> by(&paragraph_less);
  Counts all;
  for (const auto& f : r.files)
    for (const auto& v : f.vectors)
      for (Counts* c : {&by[v.paragraph], &all}) {
        c->files.insert(fs::path(f.path).filename().string());
        (v.level == harness::Level::kMust ? c->must : v.level == harness::Level::kShould ? c->should : c->informative)++;
      }
  std::cout << "| paragraph | file | must | should | informative | total |\n|---|---|---:|---:|---:|---:|\n";
  auto row = [](const std::string& name, const std::string& files, const Counts& c) {
    std::cout << fmt::format("| {} | {} | {} | {} | {} | {} |\n", name, files, c.must, c.should, c.informative,
                             c.must + c.should + c.informative);
  };
  for (const auto& [paragraph, c] : by) {
    std::string files;
    for (const auto& f : c.files) files += (files.empty() ? "" : ", ") + fmt::format("`{}`", f);
    row(std::isdigit(static_cast<unsigned char>(paragraph[0])) ? "§" + paragraph : paragraph, files, c);
  }
  row("**all**", fmt::format("{} files", all.files.size()), all);
  return r.errors.empty() ? kExitOk : kExitFailed;
}

// Errata entry -> the vectors that rest on it: through their flags (the
// notes' `errata`), by accepting the other side of a reading (an
// expectation's `readings:`), or by a precondition that side may leave
// unmet (`precondition_reading`).
std::map<std::string, std::vector<std::string>> errata_vectors(const LoadResult& r) {
  std::map<std::string, std::vector<std::string>> out;
  auto add = [&](const std::string& entry, const std::string& id) {
    auto& ids = out[entry];
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  };
  for (const auto& f : r.files)
    for (const auto& v : f.vectors) {
      for (const auto& flag : v.flags)
        if (auto n = f.notes.find(flag); n != f.notes.end() && !n->second.errata.empty()) add(n->second.errata, v.id);
      for (const auto* steps : {&v.setup, &v.steps, &v.teardown})
        for (const harness::Step& s : *steps) {
          for (const auto& alt : s.expect.readings) add(alt.errata, v.id);
          if (!s.precondition_reading.empty()) add(s.precondition_reading, v.id);
        }
    }
  return out;
}

// One line per entry of an ERRATA.md: its id, class and the labels of its
// alternatives ("E-10 reading reference|other"), then the counts
// ("errata: 37 text, 50 reading, 0 withdrawn"); exit 1 when the document
// breaks a rule of check_errata (each printed to stderr).
int run_errata_classes(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "sabus vectors errata: cannot read " << path << "\n";
    return kExitUsage;
  }
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const auto doc = harness::parse_errata(text);
  for (const auto& e : doc.entries) {
    std::string labels;
    for (const auto& a : e.alternatives) labels += (labels.empty() ? " " : "|") + a.label;
    std::cout << e.id() << " " << harness::to_string(e.cls) << labels << "\n";
  }
  const auto n = harness::count_classes(doc);
  std::cout << fmt::format("errata: {} text, {} reading, {} withdrawn\n", n.text, n.reading, n.withdrawn);
  const auto problems = harness::check_errata(doc);
  for (const auto& p : problems) std::cerr << path << ": " << p << "\n";
  return problems.empty() ? kExitOk : kExitFailed;
}

// The generated parts of protocol/ERRATA.md, from the suite and the entries:
// the "- **Vectors:**" line of every entry and the index table at the top.
// Printed (the vector lists only), written back (--update) or compared
// (--check, exit 1 when the file is not current); both also check the
// entries' rules (check_errata: every entry classified, every reading with
// its alternatives) and exit 1 when one is broken. --check prints the counts
// of each class ("errata: 25 text, 70 reading, 0 withdrawn") for CI logs.
int run_errata(const VectorsOptions& o) {
  if (!o.classes.empty()) return run_errata_classes(o.classes);
  LoadResult r = load(o);
  for (const auto& e : r.errors) std::cerr << e.text() << "\n";
  if (!r.errors.empty()) return kExitUsage;
  const auto by_entry = errata_vectors(r);
  const std::string path = !o.update.empty() ? o.update : o.check;
  if (path.empty()) {
    for (const auto& [entry, ids] : by_entry) std::cout << entry << ": " << fmt::format("{}", fmt::join(ids, " ")) << "\n";
    return kExitOk;
  }
  std::ifstream in(path);
  if (!in) {
    std::cerr << "sabus vectors errata: cannot read " << path << "\n";
    return kExitUsage;
  }
  std::string out, entry, line;
  std::size_t stale = 0;
  bool in_vectors_line = false;
  while (std::getline(in, line)) {
    if (in_vectors_line && line.rfind("  ", 0) == 0) continue;  // a wrapped continuation of the old line
    in_vectors_line = false;
    if (line.rfind("### E-", 0) == 0) entry = line.substr(4, line.find(':') - 4);
    if (line.rfind("- **Vectors:**", 0) == 0) {
      const auto it = by_entry.find(entry);
      std::string ids;
      if (it != by_entry.end())
        for (const auto& id : it->second) ids += (ids.empty() ? "`" : ", `") + id + "`";
      const std::string fresh = "- **Vectors:** " + (ids.empty() ? std::string("— (no vector yet)") : ids);
      if (fresh != line) {
        ++stale;
        if (!o.check.empty()) std::cout << path << ": " << entry << ": the vector list is not current\n";
      }
      out += fresh + "\n";
      in_vectors_line = true;
      continue;
    }
    out += line + "\n";
  }
  // The index, from the entries as they now read; a document with entries
  // and no index markers is broken.
  const auto doc = harness::parse_errata(out);
  auto problems = harness::check_errata(doc);
  bool index_stale = false;
  if (auto indexed = harness::with_errata_index(out)) {
    index_stale = *indexed != out;
    out = std::move(*indexed);
  } else if (!doc.entries.empty()) {
    problems.push_back(fmt::format("no index: the lines {} and {} are missing or out of order", harness::kErrataIndexBegin,
                                   harness::kErrataIndexEnd));
  }
  for (const auto& p : problems) std::cerr << path << ": " << p << "\n";
  if (!o.check.empty()) {
    if (index_stale) std::cout << path << ": the index is not current\n";
    const auto n = harness::count_classes(doc);
    std::cout << fmt::format("errata: {} text, {} reading, {} withdrawn\n", n.text, n.reading, n.withdrawn);
    if (stale || index_stale)
      std::cout << stale << " entr" << (stale == 1 ? "y" : "ies") << (index_stale ? " and the index" : "")
                << " to update: sabus vectors errata --update " << path << "\n";
    return stale || index_stale || !problems.empty() ? kExitFailed : kExitOk;
  }
  // Whole or not at all: ERRATA.md is a document people edit, and a write
  // cut short (a full disk) would have left it truncated.
  std::string error;
  if (!harness::replace_file(path, out, error)) {
    std::cerr << "sabus vectors errata: " << error << "\n";
    return kExitFailed;
  }
  std::cout << "updated " << stale << " entr" << (stale == 1 ? "y" : "ies") << (index_stale ? " and the index" : "") << " of "
            << path << "\n";
  return problems.empty() ? kExitOk : kExitFailed;
}

// The expression functions' one table (expressions.cpp): name(arguments) and what it gives.
int run_functions() {
  for (const auto& f : harness::expression_functions())
    std::cout << f.name << "(" << f.arguments << ")\n    " << f.description << "\n";
  return kExitOk;
}

}  // namespace

Command add_vectors_command(CLI::App& app) {
  auto opts = std::make_shared<VectorsOptions>();
  CLI::App* sub = app.add_subcommand("vectors", "Check and list the conformance vectors (vectors/*.yaml)");
  sub->require_subcommand(1);
  // Not looked up here: the data directory may be given after this (--data-dir).
  const std::string where = "vector files or directories (default: vectors/ in the data directory, see sabus --version)";
  CLI::App* lint = sub->add_subcommand("lint", "Load and lint the vectors; print every error, then a summary");
  lint->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  CLI::App* list = sub->add_subcommand(
      "list", "List the vectors: id, paragraph, level, tags; with --filter, --exclude, --paragraph the ones `sabus run` would take");
  list->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  list->add_flag("--json", opts->json, "Print JSON");
  list->add_flag("--summary", opts->summary, "Print the suite by paragraph with counts per level (Markdown)");
  add_selection_options(list, opts->selection);
  CLI::App* errata = sub->add_subcommand(
      "errata", "The vectors resting on each errata entry (their flags' notes); the generated parts of ERRATA.md; its classes");
  errata->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  auto* update = errata->add_option("--update", opts->update, "Rewrite the Vectors lines and the index of this ERRATA.md");
  auto* check = errata
                    ->add_option("--check", opts->check,
                                 "Exit 1 when the Vectors lines or the index of this ERRATA.md are not current, or an "
                                 "entry breaks a rule (unclassified, a reading without its alternatives)")
                    ->excludes(update);
  errata
      ->add_option("--classes", opts->classes,
                   "List each entry of this ERRATA.md with its class and alternatives, then the counts; exit 1 when an "
                   "entry is unclassified or a reading lacks its alternatives")
      ->excludes(update)
      ->excludes(check);
  CLI::App* cov = sub->add_subcommand(
      "coverage", "Print the matrix command x form x path (ack/nak/offline/ignore) -> vector ids and the reply fields whose "
                  "value each vector checks; exit 1 when a cell the spec defines has no vector, or a field's value is "
                  "checked only on a literal profile value or only on some of the profiles where it exists");
  cov->add_option("paths", opts->paths, where)->check(CLI::ExistingPath);
  cov->add_flag("--json", opts->json, "Print JSON");
  cov->add_flag("--missing", opts->missing_only, "Print only the cells without a vector");
  cov->add_option("--profiles", opts->random_profiles,
                  "Random profiles (the sweep's, of --seed) that field values must be checked on, besides the shipped "
                  "ones (default 100)")
      ->check(CLI::Range(0, 100000));
  cov->add_option("--known-gaps", opts->known_gaps,
                  "A file of fields (\"status azimuth\", one a line) known to be checked only on some profiles: "
                  "reported, not failed; a listed field checked everywhere fails")
      ->check(CLI::ExistingFile);
  cov->add_option("--seed", opts->seed, "Seed of those random profiles, as `sabus vectors sweep --seed` (default 1)");
  CLI::App* functions =
      sub->add_subcommand("functions", "List the functions of profile expressions (\"{home(az)}\", vectors/README.md)");
  CLI::App* schema = sub->add_subcommand(
      "schema", "Print every key a vector file may hold, node by node, as Markdown (the loader's own table)");
  auto sweep = std::make_shared<SweepOptions>();
  add_sweep_subcommand(*sub, sweep);
  return {sub, [opts, lint, cov, errata, functions, schema, sweep] {
            if (sweep->command->parsed()) return run_sweep(*sweep);
            if (functions->parsed()) return run_functions();
            if (schema->parsed()) return (std::cout << harness::schema_markdown(), kExitOk);
            if (lint->parsed()) return run_lint(*opts);
            if (cov->parsed()) return run_coverage(*opts);
            if (errata->parsed()) return run_errata(*opts);
            return opts->summary ? run_summary(*opts) : run_list(*opts);
          }};
}

}  // namespace sabus::cli
