// Console lines of `sabus run`: the progress line (on a terminal), one line
// per vector as it finishes, and the closing summary with the skips by cause.
#include <fmt/format.h>

#include <array>
#include <utility>

#include "sabus/reports/writers.hpp"

namespace sabus::reports {

namespace {

// The skip causes (harness SkipCause, the run JSON's skip_cause) in the
// order the summary names them, each with what it takes to run those vectors.
constexpr std::array<std::pair<std::string_view, std::string_view>, 6> kSkipCauses{{
    {"level", "above --level"},
    {"profile", "need another profile"},
    {"motion", "need --allow-motion"},
    {"destructive", "need --allow-destructive"},
    {"parity", "need an 8N1 port"},
    {"fresh", "need --fresh-device"},
}};

// ANSI SGR colours of the verdict words.
std::string_view colour_of(std::string_view word) {
  if (word == "PASS") return "\033[32m";       // green
  if (word == "FAIL") return "\033[1;31m";     // bold red
  if (word == "KNOWN") return "\033[35m";      // magenta
  if (word == "INCONCLUSIVE") return "\033[36m";  // cyan
  if (word == "ERROR") return "\033[1;34m";       // bold blue: the bench's, not the firmware's red
  return "\033[33m";                           // SKIP: yellow
}

}  // namespace

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

std::string_view verdict_word(const VectorRecord& v) {
  if (v.is_failure()) return "FAIL";
  if (v.outcome == "known failure") return "KNOWN";
  if (v.outcome == "skip") return "SKIP";
  if (v.is_inconclusive()) return "INCONCLUSIVE";
  if (v.is_error()) return "ERROR";
  return "PASS";
}

std::string verdict_line(const VectorRecord& v, bool colour) {
  const std::string_view word = verdict_word(v);
  std::string line = colour ? fmt::format("{}{}\033[0m", colour_of(word), word) : std::string(word);
  line += fmt::format(" {} §{} {}", v.id, v.paragraph, v.level);
  if (word == "FAIL") line += ": " + v.difference();
  else if (word == "KNOWN") line += ": " + v.difference() + " (known issue: " + v.known_issue + ")";
  else if (word == "SKIP") line += ": " + v.skip_reason;
  else if (word == "INCONCLUSIVE") line += ": " + v.inconclusive_reason;
  else if (word == "ERROR") line += ": " + v.error_reason;
  return line;
}

std::string skip_causes_text(const Summary& s) {
  std::string out;
  std::size_t named = 0;
  for (const auto& [cause, text] : kSkipCauses)
    if (const auto it = s.skipped_by_cause.find(std::string(cause)); it != s.skipped_by_cause.end() && it->second > 0) {
      out += fmt::format("{}{} {}", out.empty() ? "" : ", ", it->second, text);
      named += it->second;
    }
  // A document written before causes were recorded names none.
  if (named == 0) return "";
  if (named < s.skipped) out += fmt::format(", {} for other reasons", s.skipped - named);
  return out;
}

std::string summary_line(const Summary& s) {
  std::string line = fmt::format("{} passed, {} failed, {} skipped", s.passed, s.failed + s.unexpected, s.skipped);
  if (const std::string causes = skip_causes_text(s); !causes.empty()) line += " (" + causes + ")";
  if (s.known) line += fmt::format(", {} known failures", s.known);
  if (s.inconclusive) line += fmt::format(", {} inconclusive", s.inconclusive);
  if (s.errors) line += fmt::format(", {} {}", s.errors, s.errors == 1 ? "error" : "errors");
  return line;
}

namespace {
// 0.0021 -> "0.21%".
std::string rate_text(double rate) { return fmt::format("{:.2f}%", rate * 100); }
}  // namespace

std::string line_text(const Summary& s) {
  if (s.line.exchanges == 0) return "";
  return harness::describe(s.line) + " (fault rate " + rate_text(line_fault_rate(s.line)) + ")";
}

std::string line_warning(const Summary& s) {
  const double rate = line_fault_rate(s.line);
  if (rate <= harness::kHealthyLineFaultRate) return "";
  return "the line's fault rate " + rate_text(rate) + " is above a healthy line's " + rate_text(harness::kHealthyLineFaultRate) +
         ": check the cable, the adapter and the port settings; failures on such a line may be the line's";
}

std::string line_error_text(const Summary& s) {
  if (s.errors == 0) return "";
  const std::size_t judged = s.passed + s.failed + s.known + s.unexpected;
  const char* them = s.errors == 1 ? "it" : "them";
  // No vector that ran was judged (an inconclusive one checked nothing
  // either): the run says nothing of the firmware.
  if (judged == 0 && s.inconclusive == 0)
    return fmt::format("nothing was judged: {} that ran ended in error: the line, not the firmware, left {} unjudged",
                       s.errors == 1 ? "the one vector" : fmt::format("all {} vectors", s.errors), them);
  if (judged == 0)
    return fmt::format("nothing was judged: {} ended in error (the line, not the firmware, left {} unjudged), {} inconclusive",
                       s.errors == 1 ? "1 vector" : fmt::format("{} vectors", s.errors), them, s.inconclusive);
  return fmt::format("{} {} ended in error: the line, not the firmware, left {} unjudged", s.errors,
                     s.errors == 1 ? "vector" : "vectors", them);
}

std::string nothing_ran_reason(const Summary& s) {
  if (s.skipped == 0 && s.inconclusive == 0) return "no vector was selected";
  const std::string causes = skip_causes_text(s);
  const std::string why = causes.empty() ? "" : " (" + causes + ")";
  // Vectors that ran but reached no test purpose checked nothing either.
  if (s.inconclusive > 0) {
    const std::string skipped = s.skipped == 0 ? "" : fmt::format("; {} skipped{}", s.skipped, why);
    if (s.inconclusive == 1) return "the one vector that ran ended inconclusive (its test purpose was not reached)" + skipped;
    return fmt::format("all {} vectors that ran ended inconclusive (their test purposes were not reached){}", s.inconclusive,
                       skipped);
  }
  if (s.skipped == 1) return "the one vector selected was skipped" + why;
  return fmt::format("all {} vectors selected were skipped{}", s.skipped, why);
}

}  // namespace sabus::reports
