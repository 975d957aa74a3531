// The coverage matrix of a vector suite (coverage.hpp).
#include "sabus/harness/coverage.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <regex>
#include <variant>

#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/lrc.hpp"
#include "vector_loader_internal.hpp"

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

namespace {

// A reply of each kind, as its codec encodes the defaults, to the first
// command that answers with it.
template <std::size_t... I>
std::map<ReplyKind, Bytes> sample_replies(std::index_sequence<I...>) {
  std::map<ReplyKind, Bytes> out;
  auto one = [&]<class T>(std::type_identity<T>) {
    if constexpr (requires { T::kKind; }) {
      for (const CommandInfo& info : catalog()) {
        if (info.reply != T::kKind) continue;
        if (auto frame = reply_frame(Reply{T{}}, kAnyAddress, info.code)) out.emplace(T::kKind, encode_frame(frame.value()));
        break;
      }
    }
  };
  (one(std::type_identity<std::variant_alternative_t<I, Reply>>{}), ...);
  return out;
}

// The texts a one-byte field of a reply can hold (as a matcher reads them,
// matcher_text): each 7-bit character put at its byte that the codec reads
// as valid. Empty for a field of several bytes.
std::vector<std::string> one_byte_values(ReplyKind reply, std::string_view field) {
  const auto sample = vector_loader_internal::sample_reply(reply);
  if (!sample) return {};
  std::optional<std::size_t> at;
  for (const FieldDescription& f : describe_frame(*sample).fields) {
    if (f.name != field) continue;
    if (f.first != f.last || (at && *at != f.first)) return {};  // several bytes, or two fields of the name
    at = f.first;
  }
  if (!at) return {};
  std::vector<std::string> out;
  for (int c = 0x20; c < 0x7F; ++c)
    if (const auto f = vector_loader_internal::field_with_code(*sample, *at, static_cast<std::uint8_t>(c), field); f && f->ok)
      out.push_back(matcher_text(*f));
  return out;
}

// Whether a regex picks some of a one-byte field's values and not all: a
// check of its value (the bits of a status byte), not of its form.
bool regex_narrows(const FieldMatcher& m, ReplyKind reply) {
  static std::map<std::pair<ReplyKind, std::string>, std::vector<std::string>> cache;
  auto [it, fresh] = cache.try_emplace({reply, m.field});
  if (fresh) it->second = one_byte_values(reply, m.field);
  const std::vector<std::string>& values = it->second;
  if (values.empty() || m.values.empty()) return false;
  try {
    const std::regex re(m.values[0]);
    const auto n = std::count_if(values.begin(), values.end(), [&](const std::string& v) { return std::regex_search(v, re); });
    return n > 0 && static_cast<std::size_t>(n) < values.size();
  } catch (const std::regex_error&) {
    return false;  // the linter names it
  }
}

}  // namespace

bool checks_value(const FieldMatcher& m, ReplyKind reply) {
  switch (m.kind) {
    case FieldMatcher::Kind::kEq:
    case FieldMatcher::Kind::kOneOf:
    case FieldMatcher::Kind::kNear:
    case FieldMatcher::Kind::kJogged:
      return true;
    case FieldMatcher::Kind::kRange:
      // A range of constants is the field's form (0-999); one bounded by the
      // profile or an earlier reading is its value.
      return std::any_of(m.values.begin(), m.values.end(),
                         [](const std::string& v) { return v.find('{') != std::string::npos || v.find('$') != std::string::npos; });
    case FieldMatcher::Kind::kRegex:
      return regex_narrows(m, reply);
    case FieldMatcher::Kind::kAny:
      return false;
  }
  return false;
}

namespace {

// The fields of `reply` a step's ACK expectation checks the value of: in
// the row's ids, or its literal_ids when the vector requires a literal
// profile value (issue 32).
void add_value_checks(CoverageMatrix& m, ReplyKind reply, const Step& s, const Vector& v) {
  const std::string& id = v.id;
  const bool literal = std::any_of(v.requires_.begin(), v.requires_.end(), literal_requirement);
  auto add = [&](FieldValueRow& row) {
    auto& ids = literal ? row.literal_ids : row.ids;
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  };
  for (FieldValueRow& row : m.fields) {
    if (row.field->reply != reply) continue;
    const bool whole = s.expect.bytes.has_value();
    const bool record = !s.expect.from_profile.empty() &&
                        (row.field->cls == FieldClass::kStored || row.field->cls == FieldClass::kEcho);
    bool matched = false;
    for (const auto* list : {&s.expect.fields, &s.until})
      for (const FieldMatcher& fm : *list) matched = matched || (fm.field == row.field->field && checks_value(fm, reply));
    if (whole || record || matched) add(row);
  }
}

}  // namespace

CoverageMatrix coverage(const std::vector<VectorFile>& files) {
  CoverageMatrix m;
  for (const ReplyFieldClass& f : reply_field_classes()) m.fields.push_back({&f, {}, {}});
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
          if (*path == CoveragePath::kAck) {
            add(m.acked[cf.info->reply], v.id);
            add_value_checks(m, cf.info->reply, s, v);
          }
        }
  return m;
}

bool literal_requirement(const Requirement& r) {
  // As the requirement reader writes the values (to_yaml's spelling): true,
  // false and the schema's choices are lower-case words.
  return std::any_of(r.values.begin(), r.values.end(), [](const std::string& v) {
    return v.empty() || !std::all_of(v.begin(), v.end(), [](char c) { return (c >= 'a' && c <= 'z') || c == '_'; });
  });
}

std::set<std::string> undetermined_fields(const Profile& profile) {
  // E-85: a count's scale is the profile's only where the azimuth sensor
  // counts (a pulse or resolver sensor); the elevation's is taken to be of
  // the same kind. (Read from the profile itself: a requirement judged
  // writes the profile out, which the sweep would pay once a profile.)
  if (profile.az_sensor == AzSensor::kPulse || profile.az_sensor == AzSensor::kResolver) return {};
  std::set<std::string> out;
  for (const ReplyFieldClass& f : reply_field_classes())
    if (f.reply == ReplyKind::kPulseCount) out.insert(field_label(f));
  return out;
}

ProfileSite requirement_site(const std::vector<VectorFile>& files, const Profile& profile, std::string label) {
  ProfileSite site{std::move(label), {}, undetermined_fields(profile)};
  // Most vectors share their file's or group's requirements: each set is
  // judged once (a judgement writes the profile out).
  std::map<std::string, bool> judged;
  for (const VectorFile& f : files)
    for (const Vector& v : f.vectors) {
      std::string key;
      for (const Requirement& r : v.requires_) {
        key += r.key + "=";
        for (const auto& value : r.values) key += value + "|";
        key += ";";
      }
      auto [it, fresh] = judged.try_emplace(key, false);
      if (fresh) it->second = requirements_hold(profile, v.requires_);
      if (it->second) site.runs.insert(v.id);
    }
  return site;
}

std::vector<FieldShare> field_shares(const CoverageMatrix& m, const std::vector<ProfileSite>& sites) {
  std::vector<FieldShare> out;
  for (const FieldValueRow& row : m.fields) {
    if (!value_required(row.field->cls)) continue;
    FieldShare share{row.field, 0, 0, {}};
    const auto acked = m.acked.find(row.field->reply);
    for (const ProfileSite& site : sites) {
      auto runs_one = [&](const std::vector<std::string>& ids) {
        return std::any_of(ids.begin(), ids.end(), [&](const std::string& id) { return site.runs.count(id) > 0; });
      };
      if (acked == m.acked.end() || !runs_one(acked->second)) continue;  // the reply is never asked for here
      if (site.undetermined.count(field_label(*row.field))) continue;     // no value to check here
      ++share.exists;
      if (runs_one(row.ids)) ++share.checked;
      else share.unchecked.push_back(site.label);
    }
    out.push_back(std::move(share));
  }
  return out;
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

std::string field_label(const ReplyFieldClass& f) { return std::string(to_string(f.reply)) + " " + std::string(f.field); }

std::vector<std::string> CoverageMatrix::missing_values() const {
  std::vector<std::string> out;
  for (const FieldValueRow& row : fields)
    if (value_required(row.field->cls) && row.ids.empty()) {
      std::string line = field_label(*row.field) + " (" + std::string(to_string(row.field->cls)) + ", §" +
                         std::string(row.field->paragraph) + ")";
      if (row.literal_ids.empty()) line += ": no vector checks it";
      else {
        line += ": checked only by vectors that require a literal profile value, which judge only the controllers that have it:";
        for (const auto& id : row.literal_ids) line += " " + id;
      }
      out.push_back(std::move(line));
    }
  return out;
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

namespace sabus::harness::vector_loader_internal {

std::optional<Bytes> sample_reply(ReplyKind reply) {
  static const auto samples = sample_replies(std::make_index_sequence<std::variant_size_v<Reply>>{});
  const auto it = samples.find(reply);
  if (it == samples.end()) return std::nullopt;
  return it->second;
}

std::optional<FieldDescription> field_with_code(Bytes frame, std::size_t at, std::uint8_t code, std::string_view field) {
  frame[at] = code;
  frame.back() = lrc(ByteView(frame.data(), frame.size() - 1));
  for (FieldDescription& f : describe_frame(frame).fields)
    if (f.first == at && f.name == field) return std::move(f);
  return std::nullopt;
}

}  // namespace sabus::harness::vector_loader_internal
