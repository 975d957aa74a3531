// The known-issues file (`sabus run --known-issues FILE`): vectors expected
// to fail, with reasons; the runner turns their verdicts into known failures
// or unexpected passes.
#include <fmt/format.h>

#include <fstream>

#include "sabus/harness/selection.hpp"

namespace sabus::harness {

KnownIssues read_known_issues(const std::string& path, const std::set<std::string>& ids) {
  KnownIssues out;
  std::ifstream in(path);
  if (!in) {
    out.errors.push_back(path + ": cannot read");
    return out;
  }
  std::size_t line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    line = line.substr(0, line.find('#'));
    const auto a = line.find_first_not_of(" \t");
    if (a == std::string::npos) continue;
    const auto b = line.find_first_of(": \t", a);
    const std::string id = line.substr(a, b == std::string::npos ? std::string::npos : b - a);
    if (!ids.count(id)) {
      out.errors.push_back(fmt::format("{}:{}: no vector has the id \"{}\"", path, line_number, id));
      continue;
    }
    std::string reason = b == std::string::npos ? "" : line.substr(b + 1);
    reason.erase(0, reason.find_first_not_of(" \t:"));
    out.reasons[id] = reason.empty() ? "listed as a known issue" : reason;
  }
  return out;
}

}  // namespace sabus::harness
