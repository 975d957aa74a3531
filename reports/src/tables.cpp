// Summary tables shared by the HTML and Markdown reports.
#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include "sabus/protocol/catalog.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::reports {

void Tally::add(const VectorRecord& v) {
  if (v.outcome == "pass") ++passed;
  else if (v.outcome == "known failure") ++known;
  else if (v.is_failure()) ++failed;
  else if (v.is_inconclusive()) ++inconclusive;
  else if (v.is_error()) ++errors;
  else ++skipped;
}

bool paragraph_less(const std::string& a, const std::string& b) {
  // "3.2" < "3.10": compare dot-separated numbers, then text.
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t ei = i, ej = j;
      while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
      while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
      const std::string na = a.substr(i, ei - i), nb = b.substr(j, ej - j);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = ei;
      j = ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::map<std::string, std::map<std::string, Tally>, bool (*)(const std::string&, const std::string&)> paragraph_levels(
    const RunDocument& doc) {
  std::map<std::string, std::map<std::string, Tally>, bool (*)(const std::string&, const std::string&)> out(
      &paragraph_less);
  for (const auto& v : doc.vectors) out[v.paragraph][v.level].add(v);
  return out;
}

std::vector<CoverageRow> coverage(const RunDocument& doc) {
  std::vector<CoverageRow> rows;
  for (const auto& c : catalog()) {
    auto row = [&](std::string_view form) {
      return CoverageRow{std::string(c.key), std::string(c.name), std::string(c.paragraph), std::string(form), {}};
    };
    if (c.forms.empty()) rows.push_back(row(""));
    for (const auto& f : c.forms) rows.push_back(row(f.id));
  }
  auto find_row = [&](const FrameRecord& f) {
    return std::find_if(rows.begin(), rows.end(),
                        [&](const CoverageRow& r) { return r.command == f.command && r.form == f.form; });
  };
  // A form the selector does not pick (a malformed command) gets its own row
  // after the command's catalog forms.
  for (const auto& v : doc.vectors)
    for (const auto& f : v.transcript) {
      if (f.dir != "tx" || f.path.empty() || f.command.empty() || find_row(f) != rows.end()) continue;
      auto last = std::find_if(rows.begin(), rows.end(), [&](const CoverageRow& r) { return r.command == f.command; });
      if (last == rows.end()) continue;
      CoverageRow extra{last->command, last->name, last->paragraph, f.form, {}};
      while (last != rows.end() && last->command == f.command) ++last;
      rows.insert(last, extra);
    }
  for (const auto& v : doc.vectors) {
    // A vector counts once per cell, however many frames of that kind it sent.
    std::set<std::pair<std::size_t, std::string>> cells;
    for (const auto& f : v.transcript) {
      if (f.dir != "tx" || f.path.empty() || f.command.empty()) continue;
      if (auto it = find_row(f); it != rows.end()) cells.insert({static_cast<std::size_t>(it - rows.begin()), f.path});
    }
    for (const auto& [row, path] : cells) rows[row].paths[path].add(v);
  }
  return rows;
}

}  // namespace sabus::reports

namespace sabus::reports {

std::vector<FailureGroup> failure_groups(const RunDocument& doc) {
  std::vector<FailureGroup> groups;
  std::map<std::string, std::size_t> index;  // reason -> position in groups
  for (const auto& v : doc.vectors) {
    if (!v.is_failure()) continue;
    const std::string reason = v.difference();
    const auto [it, added] = index.emplace(reason, groups.size());
    if (added) groups.push_back({reason, {}});
    groups[it->second].vectors.push_back(&v);
  }
  // Largest first; equal sizes keep the order of their first failure.
  std::stable_sort(groups.begin(), groups.end(),
                   [](const FailureGroup& a, const FailureGroup& b) { return a.vectors.size() > b.vectors.size(); });
  return groups;
}

std::vector<Turnaround> turnaround_by_command(const RunDocument& doc) {
  std::map<std::string, std::vector<double>> samples;  // command key -> ms
  for (const auto& v : doc.vectors) {
    const auto& t = v.transcript;
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t[i].dir != "tx" || t[i].command.empty()) continue;
      // The first reply frame before the next command; ignore notes have no bytes.
      for (std::size_t j = i + 1; j < t.size() && t[j].dir == "rx"; ++j)
        if (!t[j].hex.empty()) {
          samples[t[i].command].push_back(t[j].t_ms - t[i].t_ms);
          break;
        }
    }
  }
  std::vector<Turnaround> rows;
  for (const auto& c : catalog()) {
    auto it = samples.find(std::string(c.key));
    if (it == samples.end()) continue;
    auto& s = it->second;
    std::sort(s.begin(), s.end());
    const std::size_t n = s.size();
    const double median = n % 2 ? s[n / 2] : (s[n / 2 - 1] + s[n / 2]) / 2;
    rows.push_back({std::string(c.key), std::string(c.name), std::string(c.paragraph), n, s.front(), median, s.back()});
  }
  return rows;
}

}  // namespace sabus::reports
