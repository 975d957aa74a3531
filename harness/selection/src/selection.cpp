// select_vectors: paragraphs, then globs, then an earlier run's failures,
// then the shard; the notes that tell the user what selected nothing.
#include <fmt/format.h>
#include <fnmatch.h>

#include <algorithm>
#include <set>

#include "sabus/harness/selection.hpp"

namespace sabus::harness {

namespace {

// "§3.2" and "3.2" name the same paragraph.
std::string paragraph_name(std::string p) {
  if (p.starts_with("§")) p.erase(0, std::string("§").size());
  return p;
}

std::string quoted_list(const std::vector<std::string>& items, const char* option) {
  std::string out;
  for (const auto& i : items) out += fmt::format("{}{} '{}'", out.empty() ? "" : ", ", option, i);
  return out;
}

bool selected_by_globs(const SelectionOptions& o, const std::string& id) {
  auto matches = [&](const std::string& glob) { return glob_matches(glob, id); };
  const bool in = o.filters.empty() || std::any_of(o.filters.begin(), o.filters.end(), matches);
  return in && std::none_of(o.excludes.begin(), o.excludes.end(), matches);
}

}  // namespace

bool glob_matches(const std::string& glob, const std::string& id) { return fnmatch(glob.c_str(), id.c_str(), 0) == 0; }

Selection select_vectors(const std::vector<Vector>& all, const SelectionOptions& o) {
  Selection s;
  std::set<std::string> paragraphs;
  for (const auto& p : o.paragraphs) paragraphs.insert(paragraph_name(p));
  for (const auto& p : paragraphs)
    if (std::none_of(all.begin(), all.end(), [&](const Vector& v) { return v.paragraph == p; }))
      s.notes.push_back(fmt::format("--paragraph {}: no vector of §{}", p, p));
  std::vector<const Vector*> of_paragraphs;
  for (const Vector& v : all)
    if (paragraphs.empty() || paragraphs.count(v.paragraph)) of_paragraphs.push_back(&v);

  for (const auto& glob : o.filters) {
    // The paragraphs the glob's vectors belong to, in suite order.
    std::vector<std::string> spanned;
    for (const Vector* v : of_paragraphs)
      if (glob_matches(glob, v->id) && std::find(spanned.begin(), spanned.end(), v->paragraph) == spanned.end())
        spanned.push_back(v->paragraph);
    if (spanned.empty()) {
      s.notes.push_back(fmt::format("--filter '{}' matches no vector id{}", glob, paragraphs.empty() ? "" : " of the paragraphs given"));
    } else if (spanned.size() > 1) {
      std::string list;
      for (const auto& p : spanned) list += (list.empty() ? "§" : ", §") + p;
      // '3.2*': the paragraph its literal start names is most likely the one meant.
      std::string start = glob.substr(0, glob.find_first_of("*?["));
      if (start.ends_with('-')) start.pop_back();
      const bool named = std::find(spanned.begin(), spanned.end(), start) != spanned.end();
      const std::string hint = named ? fmt::format("--paragraph {} selects §{} alone", start, start)
                                                    : std::string("--paragraph PARA selects one paragraph exactly");
      s.notes.push_back(fmt::format("--filter '{}' matches vectors of {} paragraphs ({}); {}", glob, spanned.size(), list, hint));
    }
  }
  for (const auto& glob : o.excludes)
    if (std::none_of(of_paragraphs.begin(), of_paragraphs.end(), [&](const Vector* v) { return glob_matches(glob, v->id); }))
      s.notes.push_back(fmt::format("--exclude '{}' matches no vector id", glob));

  if (o.only) {
    std::vector<std::string> gone;
    for (const auto& id : *o.only)
      if (std::none_of(all.begin(), all.end(), [&](const Vector& v) { return v.id == id; })) gone.push_back(id);
    if (!gone.empty()) {
      std::string list;
      for (const auto& id : gone) list += (list.empty() ? "" : ", ") + id;
      s.notes.push_back(fmt::format("--last-failed {}: {} vector(s) that failed there are not in the suite: {}", o.only_from,
                                    gone.size(), list));
    }
  }

  std::vector<const Vector*> taken, later;
  for (const Vector* v : of_paragraphs) {
    if (!selected_by_globs(o, v->id)) continue;
    if (o.only && !o.only->count(v->id)) continue;
    if (o.shard && !in_shard(*o.shard, v->id)) continue;
    (o.first.count(v->id) ? taken : later).push_back(v);
  }
  taken.insert(taken.end(), later.begin(), later.end());
  s.vectors.reserve(taken.size());
  for (const Vector* v : taken) s.vectors.push_back(*v);
  return s;
}

std::string empty_selection_reason(const SelectionOptions& o) {
  std::vector<std::string> parts;
  if (!o.paragraphs.empty()) parts.push_back(quoted_list(o.paragraphs, "--paragraph"));
  if (!o.filters.empty()) parts.push_back(quoted_list(o.filters, "--filter"));
  if (!o.excludes.empty()) parts.push_back("not " + quoted_list(o.excludes, "--exclude"));
  if (o.only)
    parts.push_back(o.only->empty() ? fmt::format("--last-failed {} (no vector failed in that run)", o.only_from)
                                    : fmt::format("--last-failed {} ({} failed there)", o.only_from, o.only->size()));
  if (o.shard) parts.push_back(fmt::format("--shard {}/{}", o.shard->index, o.shard->count));
  if (parts.empty()) return "no vector was given";
  std::string all;
  for (const auto& p : parts) all += (all.empty() ? "" : " and ") + p;
  return "no vector matches " + all;
}

}  // namespace sabus::harness
