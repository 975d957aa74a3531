// Skip causes grouped by wording (skip_causes.hpp).
#include "skip_causes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <utility>
#include <vector>

namespace sabus::cli {

namespace {
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }
}  // namespace

std::string cause_wording(const std::string& cause) {
  std::string out;
  std::size_t i = 0;
  while (i < cause.size()) {
    const bool starts_word = i == 0 || !word_char(cause[i - 1]);
    const bool hex = starts_word && cause.compare(i, 2, "0x") == 0 && i + 2 < cause.size() &&
                     std::isxdigit(static_cast<unsigned char>(cause[i + 2]));
    const bool sign = starts_word && (cause[i] == '-' || cause[i] == '+') && i + 1 < cause.size() && digit(cause[i + 1]);
    if (hex) {
      i += 2;
      while (i < cause.size() && std::isxdigit(static_cast<unsigned char>(cause[i]))) ++i;
    } else if (sign || (digit(cause[i]) && starts_word)) {
      if (sign) ++i;
      while (i < cause.size() && digit(cause[i])) ++i;
      if (i + 1 < cause.size() && cause[i] == '.' && digit(cause[i + 1])) {
        ++i;
        while (i < cause.size() && digit(cause[i])) ++i;
      }
    } else {
      out += cause[i++];
      continue;
    }
    out += "…";
  }
  return out;
}

std::string skip_causes_line(const std::map<std::string, std::size_t>& skips, std::size_t top) {
  std::map<std::string, std::size_t> groups;
  for (const auto& [cause, n] : skips) groups[cause_wording(cause)] += n;
  std::vector<std::pair<std::size_t, std::string>> by_count;
  for (const auto& [wording, n] : groups) by_count.emplace_back(n, wording);
  std::sort(by_count.begin(), by_count.end(),
            [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
  std::string out;
  std::size_t rest = 0, rest_runs = 0;
  for (std::size_t k = 0; k < by_count.size(); ++k) {
    if (k < top) out += (out.empty() ? "" : "; ") + fmt::format("{} {}", by_count[k].first, by_count[k].second);
    else ++rest, rest_runs += by_count[k].first;
  }
  if (rest > 0)
    out += fmt::format("; and {} more cause{} ({} vector run{})", rest, rest == 1 ? "" : "s", rest_runs,
                       rest_runs == 1 ? "" : "s");
  return out;
}

}  // namespace sabus::cli
