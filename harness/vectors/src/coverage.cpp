// The coverage matrix of a vector suite (coverage.hpp).
#include "sabus/harness/coverage.hpp"

#include <algorithm>
#include <cstdio>

#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness {

std::string_view to_string(CoveragePath path) {
  switch (path) {
    case CoveragePath::kAck: return "ack";
    case CoveragePath::kNak: return "nak";
    case CoveragePath::kOffline: return "offline";
    case CoveragePath::kIgnore: return "ignore";
  }
  return "?";
}

namespace {

constexpr std::uint8_t kAnyAddress = 0x32;  // placeholders only decide bytes the matrix does not read

std::optional<CoveragePath> path_of(Expectation::Kind kind) {
  switch (kind) {
    case Expectation::Kind::kAck: return CoveragePath::kAck;
    case Expectation::Kind::kNak: return CoveragePath::kNak;
    case Expectation::Kind::kOffline: return CoveragePath::kOffline;
    case Expectation::Kind::kSilence: return CoveragePath::kIgnore;
    case Expectation::Kind::kAny:
    case Expectation::Kind::kAnswered: return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

CoverageMatrix coverage(const std::vector<VectorFile>& files) {
  CoverageMatrix m;
  for (const CommandInfo& c : catalog()) {
    for (const FormInfo& f : c.forms) m.rows.push_back({&c, &f, {}});
    if (c.forms.size() > 1) m.rows.push_back({&c, nullptr, {}});
  }
  for (NakRule rule : all_nak_rules()) m.nak_rules[std::string(name(rule))];
  auto add = [](std::vector<std::string>& ids, const std::string& id) {
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  };
  for (const VectorFile& file : files)
    for (const Vector& v : file.vectors)
      for (const auto* list : {&v.setup, &v.steps, &v.teardown})
        for (const Step& s : *list) {
          if (s.kind == Step::Kind::kWait) continue;
          if (!s.expect.nak_rule.empty()) add(m.nak_rules[s.expect.nak_rule], v.id);
          const auto path = path_of(s.expect.kind);
          // Captured values are not known before a run: a blank keeps the command byte.
          const auto bytes = step_bytes(s, kAnyAddress, {}, true);
          if (!path || !bytes) continue;
          const CommandForm cf = classify_command(bytes.value());
          if (!cf.info) {
            if (*path == CoveragePath::kNak) add(m.unknown_codes, v.id);
            continue;
          }
          auto row = std::find_if(m.rows.begin(), m.rows.end(),
                                  [&](const CoverageRow& r) { return r.command == cf.info && r.form == cf.form; });
          if (row != m.rows.end()) add(row->ids[static_cast<std::size_t>(*path)], v.id);
        }
  return m;
}

std::string command_label(const CommandInfo& c) {
  char code[8];
  std::snprintf(code, sizeof code, "%02Xh ", c.code);
  std::string s = code;
  s.append(c.key);
  return s;
}

std::string row_label(const CoverageRow& r) {
  std::string s = command_label(*r.command);
  if (r.command->forms.size() > 1) {
    s.push_back(' ');
    s.append(r.form ? r.form->id : std::string_view("(form unknown)"));
  }
  return s;
}

std::vector<std::string> CoverageMatrix::missing() const {
  std::vector<std::string> out;
  for (const CommandInfo& c : catalog()) {
    std::array<bool, 4> command_has{};
    for (const CoverageRow& r : rows) {
      if (r.command != &c) continue;
      for (std::size_t p = 0; p < command_has.size(); ++p) command_has[p] = command_has[p] || !r.ids[p].empty();
      if (r.form && r.ids[static_cast<std::size_t>(CoveragePath::kAck)].empty()) out.push_back(row_label(r) + ": ack");
    }
    for (CoveragePath p : {CoveragePath::kNak, CoveragePath::kOffline, CoveragePath::kIgnore})
      if (!command_has[static_cast<std::size_t>(p)]) out.push_back(command_label(c) + ": " + std::string(to_string(p)));
  }
  if (unknown_codes.empty()) out.push_back("a code outside 30h-48h: nak");
  for (const auto& [rule, ids] : nak_rules)
    if (ids.empty()) out.push_back("NAK rule " + rule + " (§" + std::string(paragraph(*find_nak_rule(rule))) + "): no vector names it");
  return out;
}

}  // namespace sabus::harness
