// The Markdown summary: short, for a merge request or a release note.
#include <fmt/format.h>


#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

std::string md(std::string_view s) { return markdown_text(s); }
std::string code(std::string_view s) { return markdown_code(s); }

constexpr std::size_t kMaxListed = 25;

}  // namespace

std::string markdown_summary(const RunDocument& d) {
  const Summary c = d.counts();
  std::string out = fmt::format("### SAbus conformance: **{}**\n\n", d.verdict());
  const std::string who = d.identity.ok ? "controller " + md(d.identity.controller_type) + ", firmware " +
                                              md(d.identity.firmware_version)
                                        : "identity unknown (" + md(d.identity.error) + ")";
  out += fmt::format("{} · {} · profile {} · {} · {}\n\n", who, md(d.device), md(d.profile), md(d.started_at),
                     md(d.generator));
  out += summary_line(c) + "\n\n";
  // The line figures whenever exchanges were counted, a warning above a
  // healthy line's fault rate, and what the vectors in error mean.
  if (const std::string line = line_text(c); !line.empty()) out += md(line) + "\n\n";
  if (const std::string warning = line_warning(c); !warning.empty()) out += "**Warning**: " + md(warning) + "\n\n";
  // Vectors in error, also beside failures; with none of those (exit 6) the
  // run has no verdict on the firmware.
  if (const std::string errors = line_error_text(c); !errors.empty())
    out += "**Line errors**: " + md(errors) + "." +
           (c.exit_code == harness::kLineErrorExitCode ? " The firmware is neither accepted nor rejected." : "") + "\n\n";
  if (c.exit_code == harness::kNothingRanExitCode)
    out += "**Nothing ran**: " + md(nothing_ran_reason(c)) + ". A run that checked nothing is not a success.\n\n";
  if (!d.abort_reason.empty())
    out += (d.stopped() ? "Stopped before its end: " : "Aborted: ") + md(d.abort_reason) + "\n\n";
  out += "| Level | passed | failed | known | errors | inconclusive | skipped |\n|---|---:|---:|---:|---:|---:|---:|\n";
  std::map<std::string, Tally> levels;
  for (const auto& v : d.vectors) levels[v.level].add(v);
  for (const char* level : {"must", "should", "informative"})
    if (auto it = levels.find(level); it != levels.end())
      out += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", level, it->second.passed, it->second.failed, it->second.known,
                         it->second.errors, it->second.inconclusive, it->second.skipped);
  std::vector<const VectorRecord*> failures;
  for (const auto& v : d.vectors)
    if (v.is_failure()) failures.push_back(&v);
  if (!failures.empty()) {
    out += "\n**Failures**\n\n";
    for (std::size_t i = 0; i < failures.size() && i < kMaxListed; ++i)
      out += fmt::format("- `{}` §{} {}: {}\n", code(failures[i]->id), md(failures[i]->paragraph), md(failures[i]->level),
                         md(failures[i]->difference()));
    if (failures.size() > kMaxListed) out += fmt::format("- … and {} more\n", failures.size() - kMaxListed);
  }
  if (c.known) out += fmt::format("\n{} known failure(s) listed in the known-issues file.\n", c.known);
  // The vectors the line left unjudged (TTCN-3 error), each with what the
  // line did: the ones to run again on a sound line.
  std::vector<const VectorRecord*> errors;
  for (const auto& v : d.vectors)
    if (v.is_error()) errors.push_back(&v);
  if (!errors.empty()) {
    out += "\n**Errors**\n\n";
    for (std::size_t i = 0; i < errors.size() && i < kMaxListed; ++i)
      out += fmt::format("- `{}` §{} {}: {}\n", code(errors[i]->id), md(errors[i]->paragraph), md(errors[i]->level),
                         md(errors[i]->error_reason));
    if (errors.size() > kMaxListed) out += fmt::format("- … and {} more\n", errors.size() - kMaxListed);
  }
  // Test purposes this device did not reach (TTCN-3 inconc), each with why.
  std::vector<const VectorRecord*> inconclusive;
  for (const auto& v : d.vectors)
    if (v.is_inconclusive()) inconclusive.push_back(&v);
  if (!inconclusive.empty()) {
    out += "\n**Inconclusive**\n\n";
    for (std::size_t i = 0; i < inconclusive.size() && i < kMaxListed; ++i)
      out += fmt::format("- `{}` §{} {}: {}\n", code(inconclusive[i]->id), md(inconclusive[i]->paragraph),
                         md(inconclusive[i]->level), md(inconclusive[i]->inconclusive_reason));
    if (inconclusive.size() > kMaxListed) out += fmt::format("- … and {} more\n", inconclusive.size() - kMaxListed);
  }
  return out;
}

}  // namespace sabus::reports
