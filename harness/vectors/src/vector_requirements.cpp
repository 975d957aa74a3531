// Requirements: the device profile a vector needs (`requires`), read with the
// profile loader's own schema, and checked against a profile before a run.
#include <algorithm>
#include <deque>
#include <span>

#include "sabus/harness/profile_loader.hpp"
#include "vector_loader_internal.hpp"

namespace sabus::harness::vector_loader_internal {
namespace {

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> out;
  for (std::size_t pos = 0;;) {
    const std::size_t at = s.find(sep, pos);
    out.emplace_back(s.substr(pos, at == std::string_view::npos ? std::string_view::npos : at - pos));
    if (at == std::string_view::npos) return out;
    pos = at + 1;
  }
}

// The values at a key path: a scalar's text, or each element of a list of
// scalars (bus_peers); nullopt when the path leads nowhere or to a map.
std::optional<std::vector<std::string>> values_at(const YAML::Node& node, std::span<const std::string> path) {
  if (path.empty()) {
    if (node.IsScalar()) return std::vector<std::string>{node.Scalar()};
    if (!node.IsSequence()) return std::nullopt;
    std::vector<std::string> out;
    for (const auto& e : node) {
      if (!e.IsScalar()) return std::nullopt;
      out.push_back(e.Scalar());
    }
    return out;
  }
  if (!node.IsMap()) return std::nullopt;
  const YAML::Node child = node[path.front()];  // const lookup: never inserts
  if (!child.IsDefined()) return std::nullopt;
  return values_at(child, path.subspan(1));
}

// The profile as to_yaml writes it, read back: the one place its keys and
// value spellings live. Reading that text is most of what a requirement
// costs, and the same few profiles come back again and again (a run checks
// every vector against one profile; a file repeats its requirement values),
// so the last few are kept, keyed by the profile itself: comparing two
// profiles costs far less than writing one (to_yaml for every requirement
// of every vector was a tenth of a sweep), and equal profiles write the same
// text. Per thread: the sweep runs profiles in parallel. (A deque: assigning
// a YAML::Node writes into the node it refers to, so kept entries are never
// assigned, only added and dropped.)
YAML::Node written_profile(const Profile& profile) {
  constexpr std::size_t kKept = 16;
  struct Written {
    Profile profile;
    YAML::Node root;
  };
  thread_local std::deque<Written> kept;
  for (auto w = kept.rbegin(); w != kept.rend(); ++w)  // the newest first: a run asks for its own again and again
    if (w->profile == profile) return w->root;
  YAML::Node root = YAML::Load(to_yaml(profile));
  if (kept.size() == kKept) kept.pop_front();
  kept.push_back({profile, root});
  return root;
}

// A key's value as to_yaml writes it: the text requirements compare. A list
// key (bus_peers) is required to contain the value, so one value is given.
std::optional<std::string> written_value(const Profile& profile, const std::vector<std::string>& path) {
  const auto values = values_at(written_profile(profile), path);
  if (!values || values->size() != 1) return std::nullopt;
  return values->front();
}

bool is_plain_word(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return is_alnum(c) || c == '_' || c == '.' || c == '+' || c == '-';
  });
}

std::string yaml_double_quoted(std::string_view s, const At& at) {
  std::string out = "\"";
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) fail(at, "a requirement value cannot hold control characters");
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The profile schema is the profile loader's: the requirement is written into
// a profile of one key and loaded, so a key the schema lacks or a value it
// rejects is an error here too; the value is then read back as to_yaml writes
// it, so 50, 0x32 and "2" are one address (vectors/profiles/README.md).
std::string canonical_profile_value(const std::vector<std::string>& path, const YAML::Node& value, const At& at) {
  const std::string& text = scalar(value, at, "a profile value");
  std::string yaml_value;
  if (is_quoted(value)) yaml_value = yaml_double_quoted(text, at);
  else if (is_plain_word(text)) yaml_value = text;
  else fail(at, quoted_clip(text) + " is not a plain word or number; quote it");
  std::string doc;
  for (std::size_t i = 0; i < path.size(); ++i)
    doc += std::string(2 * i, ' ') + path[i] + ":" + (i + 1 == path.size() ? " " + yaml_value : "") + "\n";
  ProfileResult p = load_profile_text(doc, "requires");
  if (!p) fail(at, "not a device profile setting: " + (p.error->key.empty() ? "" : p.error->key + ": ") + p.error->message);
  auto written = written_value(*p.profile, path);
  if (!written) fail(at, "not a single value of a device profile (vectors/profiles/README.md)");
  return *written;
}

Requirement read_requirement(const std::string& key, const YAML::Node& value, const At& at, const FileInfo& file) {
  Requirement r{key, {}, file.loc(at.mark)};
  const std::vector<std::string> path = split(key, '.');
  if (path.size() > 3 || !std::all_of(path.begin(), path.end(), [](const std::string& s) { return is_key_segment(s); }))
    fail(at, quoted_clip(key) + " is not a profile key path (polarization, errata.implements_iess)");
  // A vector judges any controller whose profile has what it needs; a
  // profile's name says nothing about the controller (vectors/README.md).
  if (key == "name")
    fail(at, "a vector requires capabilities, never a profile's name: require the keys that matter, or find a "
             "slot or a position with a profile expression ({first_filled(presets)}, {home(el)})");
  if (value.IsMap()) fail(at, "expected a value or a list of values; write nested profile keys dotted (errata.implements_iess)");
  auto one = [&](const YAML::Node& n, const At& a) {
    file.spend(a, kCostRequirement);
    std::string v = canonical_profile_value(path, n, a);
    if (!contains(r.values, v)) r.values.push_back(std::move(v));
  };
  if (value.IsSequence()) {
    for_each_element(value, at, kMaxValues, one);
    if (r.values.empty()) fail(at, "no value given");
  } else {
    one(value, at);
  }
  return r;
}

}  // namespace

// A map of key path -> value(s), or a list of such maps: every one must hold.
std::vector<Requirement> read_requires(const YAML::Node& v, const At& at, const FileInfo& file) {
  std::vector<Requirement> out;
  auto read_map = [&](const YAML::Node& m, const At& ma) {
    for_each_entry(m, ma, kMaxEntries, [&](const std::string& key, const YAML::Node& value, const At& ka) {
      out.push_back(read_requirement(key, value, ka, file));
    });
  };
  if (v.IsSequence()) for_each_element(v, at, kMaxEntries, read_map);
  else read_map(v, at);
  if (out.empty()) fail(at, "no requirement given; leave requires out");
  return out;
}

}  // namespace sabus::harness::vector_loader_internal

namespace sabus::harness {

using namespace vector_loader_internal;

std::optional<std::string> unmet_requirement(const Profile& profile, const Requirement& r) {
  try {
    // A scalar key holds one of the values; a list key (bus_peers) holds one
    // of them among its elements.
    const auto values = values_at(written_profile(profile), split(r.key, '.'));
    if (!values) return "the profile has no key " + r.key;
    for (const auto& v : *values)
      if (contains(r.values, v)) return std::nullopt;
    std::string wanted, has;
    for (const auto& w : r.values) wanted += (wanted.empty() ? "" : " or ") + w;
    for (const auto& v : *values) has += (has.empty() ? "" : ", ") + v;
    if (values->size() != 1) return r.key + " is [" + has + "], needs one of " + wanted;
    return r.key + " is " + has + ", needs " + wanted;
  } catch (const YAML::Exception& e) {
    return std::string("cannot read the profile: ") + e.what();
  }
}

bool requirements_hold(const Profile& profile, const std::vector<Requirement>& requirements) {
  for (const auto& r : requirements)
    if (unmet_requirement(profile, r)) return false;
  return true;
}

}  // namespace sabus::harness
