// Console lines of `sabus run`: the progress line (on a terminal), one line
// per failure, and the closing summary.
#include <fmt/format.h>

#include "sabus/reports/writers.hpp"

namespace sabus::reports {

std::string clock_text(std::chrono::milliseconds d) {
  const long long s = d.count() / 1000;
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

std::string progress_line(const Progress& p, std::size_t width) {
  const int digits = static_cast<int>(fmt::format("{}", p.total).size());
  std::string line = fmt::format("[{:>{}}/{}] {} pass {} fail {} skip  {} elapsed", p.done, digits, p.total, p.passed,
                                 p.failed, p.skipped, clock_text(p.elapsed));
  if (p.done > 0 && p.total >= p.done) {
    const auto left = std::chrono::milliseconds(p.elapsed.count() * static_cast<long long>(p.total - p.done) /
                                                static_cast<long long>(p.done));
    line += "  ~" + clock_text(left) + " left";
  }
  if (!p.current.empty()) line += "  " + p.current;
  if (line.size() > width) line.resize(width);  // one terminal line: \r rewrites it
  return line;
}

std::string failure_line(const VectorRecord& v) {
  return fmt::format("FAIL {} §{} {}: {}", v.id, v.paragraph, v.level, v.difference());
}

std::string summary_line(const Summary& s) {
  std::string line = fmt::format("{} passed, {} failed, {} skipped", s.passed, s.failed + s.unexpected, s.skipped);
  if (s.known) line += fmt::format(", {} known failures", s.known);
  return line;
}

}  // namespace sabus::reports
