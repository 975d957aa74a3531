#include "selection.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "sabus/reports/writers.hpp"

namespace sabus::cli {

using harness::Vector;

namespace {

// "§3.2" and "3.2" name the same paragraph.
std::string paragraph_name(std::string p) {
  if (p.starts_with("§")) p.erase(0, std::string("§").size());
  return p;
}

// One glob, as the runner matches it (harness::is_selected).
bool glob_matches(const std::string& glob, const std::string& id) {
  harness::RunOptions one;
  one.filters = {glob};
  return harness::is_selected(one, id);
}

std::string quoted_list(const std::vector<std::string>& items, const char* option) {
  std::string out;
  for (const auto& i : items) out += fmt::format("{}{} '{}'", out.empty() ? "" : ", ", option, i);
  return out;
}

}  // namespace

void add_selection_options(CLI::App* sub, SelectionOptions& o) {
  sub->add_option("--filter", o.filters, "Only vectors whose id matches this glob (repeatable; '3.2*' also matches 3.20-3.25)")
      ->type_name("GLOB");
  sub->add_option("--exclude", o.excludes, "Leave out vectors whose id matches this glob (repeatable)")->type_name("GLOB");
  sub->add_option("--paragraph", o.paragraphs, "Only vectors of this spec paragraph, exactly: 3.2 (repeatable)")
      ->type_name("PARA");
}

Selection select_vectors(const std::vector<Vector>& all, const SelectionOptions& o, harness::RunOptions& run_options) {
  run_options.filters = o.filters;
  run_options.excludes = o.excludes;
  Selection s;
  std::set<std::string> paragraphs;
  for (const auto& p : o.paragraphs) paragraphs.insert(paragraph_name(p));
  for (const auto& p : paragraphs)
    if (std::none_of(all.begin(), all.end(), [&](const Vector& v) { return v.paragraph == p; }))
      s.notes.push_back(fmt::format("--paragraph {}: no vector of §{}", p, p));
  for (const Vector& v : all)
    if (paragraphs.empty() || paragraphs.count(v.paragraph)) s.vectors.push_back(v);
  for (const Vector& v : s.vectors) s.selected += harness::is_selected(run_options, v.id);

  for (const auto& glob : o.filters) {
    std::set<std::string, bool (*)(const std::string&, const std::string&)> spanned(&reports::paragraph_less);
    for (const Vector& v : s.vectors)
      if (glob_matches(glob, v.id)) spanned.insert(v.paragraph);
    if (spanned.empty()) {
      s.notes.push_back(fmt::format("--filter '{}' matches no vector id{}", glob, paragraphs.empty() ? "" : " of the paragraphs given"));
    } else if (spanned.size() > 1) {
      std::string list;
      for (const auto& p : spanned) list += (list.empty() ? "§" : ", §") + p;
      // '3.2*': the paragraph its literal start names is most likely the one meant.
      std::string start = glob.substr(0, glob.find_first_of("*?["));
      if (start.ends_with('-')) start.pop_back();
      const std::string hint = spanned.count(start) ? fmt::format("--paragraph {} selects §{} alone", start, start)
                                                    : std::string("--paragraph PARA selects one paragraph exactly");
      s.notes.push_back(fmt::format("--filter '{}' matches vectors of {} paragraphs ({}); {}", glob, spanned.size(), list, hint));
    }
  }
  for (const auto& glob : o.excludes)
    if (std::none_of(s.vectors.begin(), s.vectors.end(), [&](const Vector& v) { return glob_matches(glob, v.id); }))
      s.notes.push_back(fmt::format("--exclude '{}' matches no vector id", glob));
  return s;
}

std::string empty_selection_reason(const SelectionOptions& o) {
  std::vector<std::string> parts;
  if (!o.paragraphs.empty()) parts.push_back(quoted_list(o.paragraphs, "--paragraph"));
  if (!o.filters.empty()) parts.push_back(quoted_list(o.filters, "--filter"));
  if (!o.excludes.empty()) parts.push_back("not " + quoted_list(o.excludes, "--exclude"));
  if (parts.empty()) return "no vector was given";
  std::string all;
  for (const auto& p : parts) all += (all.empty() ? "" : " and ") + p;
  return "no vector matches " + all;
}

}  // namespace sabus::cli
