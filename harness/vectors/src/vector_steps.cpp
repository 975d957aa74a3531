// The step schema of a vector: steps (send, poll, wait), sends (a structured
// command or a raw template), frame modifiers, expectations and field
// matchers, each checked against the command catalog and the codecs.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <map>
#include <regex>

#include "sabus/harness/expressions.hpp"
#include "sabus/harness/motion.hpp"
#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/readings.hpp"
#include "sabus/harness/profile_records.hpp"
#include "sabus/harness/vector_schema.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"
#include "vector_loader_internal.hpp"

namespace sabus::harness::vector_loader_internal {
namespace {

constexpr std::pair<std::string_view, Expectation::Kind> kReplyKinds[] = {{"ack", Expectation::Kind::kAck},
                                                                          {"nak", Expectation::Kind::kNak},
                                                                          {"offline", Expectation::Kind::kOffline},
                                                                          {"silence", Expectation::Kind::kSilence},
                                                                          {"any", Expectation::Kind::kAny},
                                                                          {"answered", Expectation::Kind::kAnswered}};

// --- field matchers ---

// A text that may hold profile expressions ("{home(az)}"): their syntax,
// functions and the captures they read, which earlier steps must make.
void check_expressions(const std::string& text, const At& at, const StepContext& cx) {
  if (auto e = check_template(text, cx.captures)) fail(at, *e);
}

// describe_frame writes a one-byte field as 0x and two lower-case digits: an
// upper-case "0x4A" could never match.
std::string to_match_text(const YAML::Node& v, const At& at, const StepContext& cx) {
  const std::string& s = scalar(v, at, "a value");
  check_expressions(s, at, cx);
  const bool hex_byte_text = s.size() == 4 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X') &&
                             std::isxdigit(static_cast<unsigned char>(s[2])) && std::isxdigit(static_cast<unsigned char>(s[3]));
  if (hex_byte_text && (s[1] == 'X' || std::any_of(s.begin() + 2, s.end(), [](char c) { return c >= 'A' && c <= 'F'; })))
    fail(at, quoted_clip(s) + ": write one-byte values as describe_frame does, lower case (0x4a)");
  return s;
}

// std::regex expands bounded repeats ("a{5}") into states: their product is
// capped so that a pattern cannot make compiling it take all memory.
std::optional<std::string> repeat_problem(std::string_view p) {
  std::size_t states = 1;
  bool in_class = false;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const char c = p[i];
    if (c == '\\') ++i;
    else if (c == '[') in_class = true;
    else if (c == ']') in_class = false;
    else if (c == '{' && !in_class) {
      std::size_t bound = 0, j = i + 1;
      for (std::size_t n = 0; j < p.size() && (std::isdigit(static_cast<unsigned char>(p[j])) || p[j] == ','); ++j) {
        if (p[j] == ',') {
          n = 0;
          continue;
        }
        n = std::min<std::size_t>(n * 10 + static_cast<std::size_t>(p[j] - '0'), kMaxRegexStates);
        bound = std::max(bound, n);
      }
      states = std::min(states * (bound + 1), kMaxRegexStates + 1);
      if (states > kMaxRegexStates) return "its bounded repeats ({n,m}) are too large";
    }
  }
  return std::nullopt;
}

std::string to_regex(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a regular expression");
  if (s.empty() || s.size() > kMaxRegex) fail(at, "a regex has 1 to " + std::to_string(kMaxRegex) + " characters");
  if (auto e = repeat_problem(s)) fail(at, "regex " + quoted_clip(s) + ": " + *e);
  try {
    std::regex re(s, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    fail(at, "bad regex " + quoted_clip(s) + " (ECMAScript): " + e.what());
  }
  return s;
}

// A number, or a text with profile expressions that gives one at run time.
std::string to_number_text(const YAML::Node& v, const At& at, const StepContext& cx, std::optional<double>& literal) {
  const std::string& s = scalar(v, at, "a number or a profile expression");
  if (has_placeholder(s)) {
    check_expressions(s, at, cx);
    literal.reset();
  } else {
    literal = to_number(v, at);
  }
  return s;
}

void read_range(const YAML::Node& v, const At& at, FieldMatcher& m, const StepContext& cx) {
  if (!v.IsSequence() || v.size() != 2) fail(at, "expected [low, high], got " + kind_of(v));
  std::optional<double> low, high;
  m.values = {to_number_text(v[0], at, cx, low), to_number_text(v[1], at, cx, high)};
  if (low) m.low = *low;
  if (high) m.high = *high;
  if (low && high && m.low > m.high) fail(at, "low " + number_text(m.low) + " is above high " + number_text(m.high));
}

// near: a position within the axis's arrival tolerance; the axis is the
// field's, or named ({value, axis}) for a field that is not an axis position.
void read_near(const YAML::Node& v, const At& at, FieldMatcher& m, const StepContext& cx) {
  std::optional<double> literal;
  if (v.IsScalar()) {
    m.values = {to_number_text(v, at, cx, literal)};
  } else {
    MapReader r(v, at, schema_keys(SchemaNode::kNear));
    require_keys(r, at, {"value"}, "near");
    r.with("value", [&](const YAML::Node& n, const At& a) { m.values = {to_number_text(n, a, cx, literal)}; });
    r.with("axis", [&](const YAML::Node& n, const At& a) {
      m.near_axis = scalar(n, a, "an axis");
      if (!motion::axis_named(m.near_axis)) fail(a, quoted_clip(m.near_axis) + " is not an axis: az, el or pol");
    });
  }
  if (m.near_axis.empty() && !motion::axis_of_field(m.field))
    fail(at, "near on " + quoted_clip(m.field) + ", which is not an axis position: give {value, axis}");
}

// jogged: where a jog of §3.4 can leave the axis (motion.hpp).
void read_jogged(const YAML::Node& v, const At& at, FieldMatcher& m, const StepContext& cx) {
  MapReader r(v, at, schema_keys(SchemaNode::kJogged));
  require_keys(r, at, {"jog", "speed", "from", "ms"}, "jogged");
  std::string from, ms;
  std::optional<double> literal;
  r.with("jog", [&](const YAML::Node& n, const At& a) {
    const std::string& t = scalar(n, a, "a jog direction");
    if (t.size() != 1 || !motion::jog_direction(t[0])) fail(a, quoted_clip(t) + " is not a jog direction: E, W, D, U, O or L");
    m.jog = t[0];
  });
  r.with("speed", [&](const YAML::Node& n, const At& a) {
    const std::string& t = scalar(n, a, "F or S");
    if (t != "F" && t != "S") fail(a, quoted_clip(t) + ": the speed is F or S");
    m.speed = t[0];
  });
  r.with("from", [&](const YAML::Node& n, const At& a) { from = to_number_text(n, a, cx, literal); });
  r.with("ms", [&](const YAML::Node& n, const At& a) { ms = to_number_text(n, a, cx, literal); });
  m.values = {from, ms};
  const auto axis = motion::jog_direction(m.jog)->axis;
  if (m.field != motion::name_of(axis))
    fail(at, std::string("a '") + m.jog + "' jog moves the " + std::string(motion::name_of(axis)) + ", not " + quoted_clip(m.field));
}

FieldMatcher read_matcher(const std::string& name, const YAML::Node& v, const At& at, StepContext& cx) {
  FieldMatcher m;
  m.field = name;
  m.where = cx.file.loc(at.mark);
  if (v.IsNull()) fail(at, "expected a value, any, or a map of eq, one_of, regex, range, near, jogged, capture");
  if (v.IsScalar()) {
    if (!is_quoted(v) && v.Scalar() == "any") return m;
    m.kind = FieldMatcher::Kind::kEq;
    m.values = {to_match_text(v, at, cx)};
    return m;
  }
  MapReader r(v, at, schema_keys(SchemaNode::kMatcher));
  const int tests = r.has("eq") + r.has("one_of") + r.has("regex") + r.has("range") + r.has("near") + r.has("jogged");
  if (tests > 1) fail(at, "give one of eq, one_of, regex, range, near, jogged");
  if (tests == 0 && !r.has("capture")) fail(at, "expected eq, one_of, regex, range, near, jogged or capture");
  r.with("eq", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kEq;
    m.values = {to_match_text(n, a, cx)};
  });
  r.with("one_of", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kOneOf;
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) { m.values.push_back(to_match_text(e, ea, cx)); });
    if (m.values.empty()) fail(a, "no value given");
  });
  r.with("near", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kNear;
    read_near(n, a, m, cx);
  });
  r.with("jogged", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kJogged;
    read_jogged(n, a, m, cx);
  });
  r.with("regex", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kRegex;
    cx.file.spend(a, kCostRegex);
    m.values = {to_regex(n, a)};
  });
  r.with("range", [&](const YAML::Node& n, const At& a) {
    m.kind = FieldMatcher::Kind::kRange;
    read_range(n, a, m, cx);
  });
  r.with("capture", [&](const YAML::Node& n, const At& a) {
    m.capture = scalar(n, a, "a capture name");
    if (!is_capture_name(m.capture)) fail(a, quoted_clip(m.capture) + " is not a capture name ($name)");
  });
  return m;
}

// The fields a reply can show, as describe_frame names them. A NAK or offline
// reply has only the frame fields every reply has (§3): reply_field_names
// lists them first (start, address, command) and last (offline, ETX, check
// byte). nullopt: the command is unknown, names are not checked.
struct ReplyFields {
  std::vector<std::string> names;
  std::string what;  // "the status reply"
};

std::optional<ReplyFields> reply_fields(const CommandInfo* command, Expectation::Kind kind) {
  if (kind == Expectation::Kind::kNak || kind == Expectation::Kind::kOffline) {
    const std::vector<std::string> all = reply_field_names(*find_command(kFirstCommand));
    const std::size_t tail = kind == Expectation::Kind::kNak ? 2 : 3;  // without / with "offline"
    std::vector<std::string> names(all.begin(), all.begin() + 3);
    names.insert(names.end(), all.end() - static_cast<std::ptrdiff_t>(tail), all.end());
    return ReplyFields{names, kind == Expectation::Kind::kNak ? "the NAK reply (§3)" : "the offline reply (§3)"};
  }
  if (!command) return std::nullopt;
  return ReplyFields{reply_field_names(*command), "the " + std::string(command->key) + " reply"};
}

std::vector<FieldMatcher> read_matchers(const YAML::Node& v, const At& at, const std::optional<ReplyFields>& reply,
                                        StepContext& cx) {
  std::vector<FieldMatcher> out;
  for_each_entry(v, at, kMaxEntries, [&](const std::string& name, const YAML::Node& value, const At& fa) {
    cx.file.spend(fa);
    if (reply && !contains(reply->names, name))
      fail(fa, "unknown field " + quoted_clip(name) + " of " + reply->what + "; its fields (as describe_frame names them): " +
                   joined(reply->names));
    // A list: several matchers of one field, each of which must hold.
    if (value.IsSequence()) {
      for_each_element(value, fa, kMaxValues, [&](const YAML::Node& e, const At& ea) {
        if (e.IsSequence()) fail(ea, "a list of matchers holds matchers, not lists");
        out.push_back(read_matcher(name, e, ea, cx));
      });
      if (value.size() == 0) fail(fa, "no matcher given");
      return;
    }
    out.push_back(read_matcher(name, value, fa, cx));
  });
  if (out.empty()) fail(at, "no field given");
  return out;
}

void keep_captures(const std::vector<FieldMatcher>& matchers, StepContext& cx) {
  for (const auto& m : matchers)
    if (!m.capture.empty()) cx.captures.insert(m.capture);
}

// --- expectations ---

Expectation::Kind to_reply_kind(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "ack, nak, offline, silence, any or answered");
  for (const auto& [name, kind] : kReplyKinds)
    if (s == name) return kind;
  fail(at, quoted_clip(s) + " is not a reply: expected ack, nak, offline, silence, any or answered");
}


// A whole expected reply must fit the catalog: ACK or NAK first, the step's
// command byte, and the length of that kind of reply (§3 NAK and offline replies).
void check_reply_bytes(const FrameSketch& s, Expectation::Kind kind, const CommandInfo* command, const At& at) {
  if (kind == Expectation::Kind::kAny || s.bytes.empty()) return;
  const std::uint8_t start = kind == Expectation::Kind::kNak ? NAK : ACK;
  if (s.bytes[0] != start)
    fail(at, "a " + std::string(to_string(kind)) + " reply starts with " + describe_byte(start) + ", not " + describe_byte(s.bytes[0]));
  if (command && s.bytes.size() > 2 && s.bytes[2] != command->code)
    fail(at, "the reply's command byte is " + hex_byte(s.bytes[2]) + "; the step sends " + hex_byte(command->code));
  if (!s.complete) return;
  std::optional<std::size_t> want = command ? command->reply_length : std::nullopt;
  std::string what = command ? "the catalog's reply to " + std::string(command->key) : "";
  if (kind == Expectation::Kind::kNak) {
    want = kNakReplyLength;
    what = "the NAK reply, §3";
  } else if (kind == Expectation::Kind::kOffline) {
    want = kOfflineReplyLength;
    what = "the offline reply, §3";
  }
  if (want && s.bytes.size() != *want)
    fail(at, "the reply is " + std::to_string(s.bytes.size()) + " bytes, not " + std::to_string(*want) + " (" + what + ")");
}

RawBytes read_raw(const YAML::Node& v, const At& at, StepContext& cx, std::vector<Element>& elements) {
  const std::string& hex = scalar(v, at, "hex bytes");
  if (hex.size() > kMaxHex) fail(at, "has " + std::to_string(hex.size()) + " characters, at most " + std::to_string(kMaxHex));
  if (auto e = parse_template(hex, elements)) fail(at, *e);
  if (elements.empty()) fail(at, "no bytes given");
  for (const auto& e : elements) {
    if (e.kind == Element::Kind::kCapture && !cx.captures.count(e.capture))
      fail(at, "{" + e.capture + "}: no earlier step captures " + e.capture);
    if (e.kind == Element::Kind::kExpr) check_expressions("{" + e.capture + "}", at, cx);
  }
  return RawBytes{hex, cx.file.loc(at.mark)};
}

// The record `from_profile` names: a slot index (a number or a profile
// expression) for an indexed list, "navigation" for 45h/46h.
std::string to_record(const YAML::Node& v, const At& at, const CommandInfo& command, const StepContext& cx) {
  const std::string& s = scalar(v, at, "a slot index or navigation");
  if (!record_is_indexed(command.code)) {
    if (s != "navigation") fail(at, std::string(command.key) + " has one record: write from_profile: navigation");
    return s;
  }
  if (has_placeholder(s)) check_expressions(s, at, cx);
  else (void)to_integer_in(v, at, 1, max_record_index(command.code));
  return s;
}

// A field matcher list with `overrides` put in: a field they name loses
// the base's matchers (a field may have several) for theirs.
std::vector<FieldMatcher> merged(std::vector<FieldMatcher> base, const std::vector<FieldMatcher>& overrides) {
  auto overridden = [&](const FieldMatcher& b) {
    return std::any_of(overrides.begin(), overrides.end(), [&](const FieldMatcher& m) { return m.field == b.field; });
  };
  base.erase(std::remove_if(base.begin(), base.end(), overridden), base.end());
  base.insert(base.end(), overrides.begin(), overrides.end());
  return base;
}

// `expect:` of a send or poll; with `base`, an alternative under `readings:`
// (the other side of an open point of the spec): it inherits the base's
// reply kind and checks unless it names its own reply, and its fields
// replace the base's of the same name.
Expectation read_expectation(const YAML::Node& v, const At& at, const CommandInfo* command, StepContext& cx,
                             const Expectation* base = nullptr) {
  Expectation e;
  e.where = cx.file.loc(at.mark);
  if (v.IsScalar()) {
    e.kind = to_reply_kind(v, at);
    return e;
  }
  MapReader r(v, at, schema_keys(base ? SchemaNode::kReading : SchemaNode::kExpect));
  if (base && !r.has("reply")) {
    e = *base;
    e.readings.clear();
    e.where = cx.file.loc(at.mark);
  } else {
    require_keys(r, at, {"reply"}, "expect");
  }
  r.read("reply", e.kind, to_reply_kind);
  r.with("rule", [&](const YAML::Node& n, const At& a) {
    if (e.kind != Expectation::Kind::kNak) fail(a, "only a nak reply names a rule");
    const std::string& s = scalar(n, a, "a NAK rule");
    if (!find_nak_rule(s)) {
      std::string names;
      for (NakRule rule : all_nak_rules()) names += (names.empty() ? "" : ", ") + std::string(name(rule));
      fail(a, quoted_clip(s) + " is not a NAK rule of harness/controller/include/sabus/harness/nak_rules.hpp: " + names);
    }
    e.nak_rule = s;
  });
  if (e.kind == Expectation::Kind::kSilence || e.kind == Expectation::Kind::kAnswered)
    for (auto k : {"bytes", "fields"})
      if (r.has(k)) fail(r.at(k), std::string(to_string(e.kind)) + " has no " + k);
  r.with("bytes", [&](const YAML::Node& n, const At& a) {
    std::vector<Element> elements;
    e.bytes = read_raw(n, a, cx, elements);
    check_reply_bytes(sketch_of(elements), e.kind, command, a);
  });
  r.with("fields", [&](const YAML::Node& n, const At& a) {
    e.fields = merged(std::move(e.fields), read_matchers(n, a, reply_fields(command, e.kind), cx));
  });
  r.with("from_profile", [&](const YAML::Node& n, const At& a) {
    if (e.kind != Expectation::Kind::kAck) fail(a, "from_profile is an ack reply's");
    if (r.has("bytes")) fail(a, "give bytes or from_profile, not both");
    const bool read = command && takes_profile_record(command->code) && command->forms.front().effects.changes_stored_data == false;
    if (!read) fail(a, "from_profile checks the reply of a read of stored data: 35h, 3Ah, 3Ch, 44h or 45h");
    e.from_profile = to_record(n, a, *command, cx);
  });
  if (base) {
    r.read("ends", e.ends, to_bool);
    if (r.has("ends") && !e.ends) fail(r.at("ends"), "ends: false is the default; leave it out");
    if (e.ends && !cx.steps) fail(r.at("ends"), "ends ends a vector's steps: not in a setup or teardown");
  }
  // The other side of open points of the spec (ERRATA class reading,
  // readings.hpp): what a controller of that side answers instead.
  // The key is the entry's id for its `other` side, ID/other-2 for a third.
  r.with("readings", [&](const YAML::Node& n, const At& a) {
    std::vector<std::string> keys;
    std::vector<std::pair<std::string, ReadingSide>> sides;
    for (const ReadingPoint& p : reading_points())
      for (ReadingSide side : sides_besides(p.id, ReadingSide::kReference)) {
        keys.push_back(reading_key(p.id, side));
        sides.emplace_back(p.id, side);
      }
    const std::vector<std::string_view> key_views(keys.begin(), keys.end());
    MapReader alternatives(n, a, key_views);
    for (std::size_t k = 0; k < keys.size(); ++k)
      alternatives.with(keys[k], [&](const YAML::Node& alt, const At& alt_at) {
        e.readings.push_back(ReadingAlternative{sides[k].first, read_expectation(alt, alt_at, command, cx, &e), sides[k].second});
      });
  });
  keep_captures(e.fields, cx);
  return e;
}

// --- sends ---

struct Send {
  std::optional<StructuredCommand> command;
  std::optional<RawBytes> raw;
  At raw_at;
  FrameSketch sketch;
};

std::string form_ids(const CommandInfo& info) {
  std::string out;
  for (const auto& f : info.forms) out += (out.empty() ? "" : ", ") + std::string(f.id);
  return out;
}

const CommandInfo& to_command(const YAML::Node& v, const At& at) {
  const std::string& s = scalar(v, at, "a command");
  if (const CommandInfo* c = find_command(s)) return *c;
  std::string keys;
  for (const auto& c : catalog()) keys += (keys.empty() ? "" : ", ") + std::string(c.key);
  fail(at, "unknown command " + quoted_clip(s) + ": expected a catalog key (" + keys + "), name or code (\"31h\")");
}

// The catalog's spelling of the form ("2a" -> "2A"); "" for one-form commands.
std::string to_form(const MapReader& r, const At& at, const CommandInfo& info) {
  std::string text;
  r.read("form", text, [](const YAML::Node& n, const At& a) { return scalar(n, a, "a form"); });
  if (info.forms.size() <= 1) {
    if (!text.empty()) fail(r.at("form"), std::string(info.key) + " has one form: leave form out");
    return "";
  }
  if (!r.has("form")) fail_missing(at, "form", std::string(info.key) + " needs form: one of " + form_ids(info));
  const FormInfo* f = info.form_by_id(text);
  if (!f) fail(r.at("form"), "unknown form " + quoted_clip(text) + " of " + std::string(info.key) + ": expected one of " + form_ids(info));
  return std::string(f->id);
}

// A field value is its text as written: 45.6, -152.5, 0x47, "SBS 6", or a
// text with profile expressions: "{home(az)}".
std::string to_field_value(const YAML::Node& v, const At& at, const StepContext& cx) {
  if (!v.IsScalar()) fail(at, "expected a value, got " + kind_of(v) + " (quote \"\" for an empty text)");
  check_expressions(v.Scalar(), at, cx);
  return v.Scalar();
}

// Where build_request's error points: `field "NAME": ...` names a field key.
At build_error_at(const DecodeError& e, const std::map<std::string, At>& field_at, const At& fallback) {
  for (const auto& [name, at] : field_at)
    if (e.expected.rfind("field \"" + name + "\"", 0) == 0) return at;
  return fallback;
}


StructuredCommand read_structured(const MapReader& r, const At& at, StepContext& cx, FrameSketch& sketch) {
  StructuredCommand sc;
  sc.where = cx.file.loc(at.mark);
  const CommandInfo* info = nullptr;
  r.with("command", [&](const YAML::Node& n, const At& a) {
    info = &to_command(n, a);
    sc.command = n.Scalar();
  });
  sc.form = to_form(r, at, *info);
  const std::vector<std::string> names = request_field_names(*info, sc.form);
  std::map<std::string, At> field_at;
  r.with("fields", [&](const YAML::Node& n, const At& a) {
    for_each_entry(n, a, kMaxEntries, [&](const std::string& name, const YAML::Node& value, const At& fa) {
      if (!contains(names, name))
        fail(fa, "unknown field " + quoted_clip(name) + " of " + std::string(info->key) +
                     (sc.form.empty() ? "" : " form " + sc.form) + "; its fields: " + joined(names));
      sc.fields[name] = to_field_value(value, fa, cx);
      field_at.emplace(name, fa);
    });
  });
  r.with("address", [&](const YAML::Node& n, const At& a) { sc.address = to_address(n, a); });
  r.with("from_profile", [&](const YAML::Node& n, const At& a) {
    if (!takes_profile_record(info->code) || !info->forms.front().effects.changes_stored_data)
      fail(a, "from_profile sends a record of the profile with a write of stored data: 39h, 3Bh, 43h or 46h");
    if (r.has("fields")) fail(a, "give fields or from_profile, not both");
    sc.from_profile = to_record(n, a, *info, cx);
  });
  auto built = build_request(*info, sc.form, static_fields(sc.fields));
  if (!built) fail(build_error_at(built.error(), field_at, r.at("fields")), build_error_text(built.error()));
  sketch = sketch_of(encode_request(*built, sc.address.value_or(kSketchAddress)), true);
  return sc;
}

Send read_send(const YAML::Node& v, const At& at, StepContext& cx) {
  MapReader r(v, at, schema_keys(SchemaNode::kSend));
  Send s;
  if (r.has("raw")) {
    for (auto k : {"command", "form", "fields", "address", "from_profile"})
      if (r.has(k)) fail(r.at(k), std::string("a raw send has no ") + k + ": write the bytes in raw");
    r.with("raw", [&](const YAML::Node& n, const At& a) {
      std::vector<Element> elements;
      s.raw = read_raw(n, a, cx, elements);
      s.raw_at = a;
      s.sketch = sketch_of(elements);
    });
    return s;
  }
  if (!r.has("command")) fail(at, "a send needs command (a catalog command) or raw (hex bytes)");
  cx.file.spend(at, kCostBuild);
  s.command = read_structured(r, at, cx, s.sketch);
  return s;
}

// make a wrong length out of a right frame and need no flag.
void check_length(const Send& s, const std::optional<At>& mismatch_at) {
  if (s.command) {
    if (mismatch_at) fail(*mismatch_at, "length_mismatch is for raw sends: a command built from fields has its catalog length");
    return;
  }
  const FrameSketch& k = s.sketch;
  if (!has_checked_length(k)) return;
  const std::size_t got = k.bytes.size() - k.start, want = *k.command->request_length;
  const std::string key(k.command->key);
  if (got != want && !mismatch_at)
    fail(s.raw_at, "the frame is " + std::to_string(got) + " bytes; the catalog says " + std::to_string(want) + " for " + key +
                       " (§" + std::string(k.command->paragraph) + "). If that is the test, write length_mismatch: true on the step");
  if (got == want && mismatch_at)
    fail(*mismatch_at, "length_mismatch: true, but the frame has the catalog length of " + key + " (" + std::to_string(want) + " bytes)");
}

// --- modifiers ---

// Any 7-bit character: modify.address sends to other or invalid addresses on purpose.
std::uint8_t to_modified_address(const YAML::Node& v, const At& at) {
  if (is_quoted(v) && v.Scalar().size() == 1) {
    const auto c = static_cast<std::uint8_t>(v.Scalar()[0]);
    if (c < 0x20 || c > 0x7F) fail(at, "expected a printable address character, got " + describe_byte(c));
    return c;
  }
  return static_cast<std::uint8_t>(to_integer_or_hex_in(v, at, 0x20, 0x7F));
}

std::size_t to_index(const YAML::Node& v, const At& at, std::optional<std::size_t> length) {
  const long long hi = length ? static_cast<long long>(*length) - 1 : 1000;
  if (hi < 0) fail(at, "the frame has no bytes left");
  return static_cast<std::size_t>(to_integer_in(v, at, 0, hi));
}

// Length checks follow the order the runner applies the modifiers in
// (vectors/README.md): address, extra_data_bytes, lrc_xor, replace, truncate,
// parity_flip, then chunks.
Modifiers read_modifiers(const YAML::Node& v, const At& at, std::optional<std::size_t> length) {
  MapReader r(v, at, schema_keys(SchemaNode::kModify));
  Modifiers m;
  auto byte = [](const YAML::Node& n, const At& a, long long lo) { return static_cast<std::uint8_t>(to_integer_or_hex_in(n, a, lo, 0x7F)); };
  r.read("lrc_xor", m.lrc_xor, [&](const YAML::Node& n, const At& a) { return byte(n, a, 1); });
  r.with("address", [&](const YAML::Node& n, const At& a) {
    if (n.IsScalar() && has_placeholder(n.Scalar())) {
      if (auto e = check_template(n.Scalar(), {})) fail(a, *e);
      m.address_text = n.Scalar();
    } else {
      m.address = to_modified_address(n, a);
    }
  });
  r.read("extra_data_bytes", m.extra_data_bytes, [](const YAML::Node& n, const At& a) { return static_cast<std::size_t>(to_integer_in(n, a, 1, 200)); });
  if (length) *length += m.extra_data_bytes;
  r.with("replace", [&](const YAML::Node& n, const At& a) {
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) {
      if (!e.IsSequence() || e.size() != 2) fail(ea, "expected [index, byte], got " + kind_of(e));
      m.replace.emplace_back(to_index(e[0], ea, length), byte(e[1], ea, 0));
    });
  });
  r.read("truncate", m.truncate, [&](const YAML::Node& n, const At& a) {
    return static_cast<std::size_t>(to_integer_in(n, a, 1, length ? static_cast<long long>(*length) - 1 : 1000));
  });
  if (length) *length -= m.truncate;
  r.with("parity_flip", [&](const YAML::Node& n, const At& a) {
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) {
      const std::size_t i = to_index(e, ea, length);
      if (std::find(m.parity_flip.begin(), m.parity_flip.end(), i) != m.parity_flip.end()) fail(ea, "index " + std::to_string(i) + " is listed twice");
      m.parity_flip.push_back(i);
    });
  });
  r.with("chunks", [&](const YAML::Node& n, const At& a) {
    std::size_t total = 0;
    for_each_element(n, a, kMaxValues, [&](const YAML::Node& e, const At& ea) {
      m.chunks.push_back(static_cast<std::size_t>(to_integer_in(e, ea, 1, 1000)));
      total += m.chunks.back();
    });
    if (m.chunks.empty()) fail(a, "no chunk size given");
    if (length && total > *length) fail(a, "the chunks add up to " + std::to_string(total) + " bytes; the frame has " + std::to_string(*length));
  });
  r.with("pause_ms", [&](const YAML::Node& n, const At& a) {
    if (m.chunks.empty()) fail(a, "pause_ms is the pause between chunks: give chunks too");
    m.pause = std::chrono::milliseconds(to_integer_in(n, a, 1, 60000));
  });
  if (m == Modifiers{}) fail(at, "no change given; leave modify out");
  return m;
}

// --- steps ---

Step read_send_step(const MapReader& r, const At& at, StepContext& cx) {
  Step step;
  step.kind = Step::Kind::kSend;
  Send send;
  r.with("send", [&](const YAML::Node& n, const At& a) { send = read_send(n, a, cx); });
  step.command = send.command;
  step.raw = send.raw;
  const std::optional<std::size_t> length =
      send.sketch.complete ? std::optional<std::size_t>(send.sketch.bytes.size()) : std::nullopt;
  r.with("modify", [&](const YAML::Node& n, const At& a) { step.modifiers = read_modifiers(n, a, length); });
  bool mismatch = false;
  r.read("length_mismatch", mismatch, to_bool);
  check_length(send, mismatch ? std::optional<At>(r.at("length_mismatch")) : std::nullopt);
  if (r.has("length_mismatch") && !mismatch) fail(r.at("length_mismatch"), "length_mismatch: false is the default; leave it out");
  require_keys(r, at, {"expect"}, "a send");
  r.with("expect", [&](const YAML::Node& n, const At& a) { step.expect = read_expectation(n, a, send.sketch.command, cx); });
  return step;
}

// A wait or a poll timeout: 1 ms to an hour, or a profile expression
// ("{jog_ms(az, F) + 1000}") the runner computes.
void read_ms(const YAML::Node& v, const At& at, const StepContext& cx, Step& step) {
  if (v.IsScalar() && has_placeholder(v.Scalar())) {
    check_expressions(v.Scalar(), at, cx);
    step.timeout_text = v.Scalar();
    return;
  }
  step.timeout = std::chrono::milliseconds(to_integer_in(v, at, 1, kMaxMs));
}

// A step that sends one frame again and again (a poll, a survey): its
// `send` and its `interval_ms` (§4, E-3), read alike by each.
Step repeated_send(const MapReader& r, const At& at, StepContext& cx, Step::Kind kind, Send& send) {
  Step step;
  step.kind = kind;
  r.with("send", [&](const YAML::Node& n, const At& a) { send = read_send(n, a, cx); });
  check_length(send, std::nullopt);
  step.command = send.command;
  step.raw = send.raw;
  step.expect.where = cx.file.loc(at.mark);
  r.read("interval_ms", step.interval, [](const YAML::Node& n, const At& a) {
    return std::chrono::milliseconds(to_integer_in(n, a, kMinPollIntervalMs, kMaxMs));  // §4, E-3
  });
  return step;
}

Step read_poll(const YAML::Node& v, const At& at, StepContext& cx) {
  MapReader r(v, at, schema_keys(SchemaNode::kPoll));
  require_keys(r, at, {"send", "until"}, "a poll");
  Send send;
  Step step = repeated_send(r, at, cx, Step::Kind::kPoll, send);
  r.with("expect", [&](const YAML::Node& n, const At& a) {
    step.expect = read_expectation(n, a, send.sketch.command, cx);
    if (step.expect.kind == Expectation::Kind::kSilence) fail(a, "a poll needs a reply to test until against");
    for (const ReadingAlternative& alt : step.expect.readings)
      if (alt.expect.ends) fail(a, "a poll's readings cannot end the vector (ends): put it on a send");
  });
  r.with("until", [&](const YAML::Node& n, const At& a) {
    step.until = read_matchers(n, a, reply_fields(send.sketch.command, step.expect.kind), cx);
  });
  keep_captures(step.until, cx);
  r.with("timeout_ms", [&](const YAML::Node& n, const At& a) { read_ms(n, a, cx, step); });
  if (step.timeout.count() > 0 && step.interval > step.timeout) fail(r.at("interval_ms"), "interval_ms is longer than timeout_ms");
  return step;
}

// A survey (Step::Kind::kSurvey): a send repeated `count` times, each reply
// an ACK, the garbled ones counted by the runner.
Step read_survey(const YAML::Node& v, const At& at, StepContext& cx) {
  MapReader r(v, at, schema_keys(SchemaNode::kSurvey));
  require_keys(r, at, {"send", "count"}, "a survey");
  Send send;
  Step step = repeated_send(r, at, cx, Step::Kind::kSurvey, send);
  step.expect.kind = Expectation::Kind::kAck;
  r.with("count", [&](const YAML::Node& n, const At& a) { step.survey_count = static_cast<std::size_t>(to_integer_in(n, a, 10, 1000)); });
  return step;
}

// `precondition`: the words of what the step establishes for the vector's
// test purpose (vectors/README.md "Preconditions"; TTCN-3's `inconc`). Only a
// send or a poll checks something, and a teardown runs after the purpose is
// decided.
std::string read_precondition(const MapReader& r, const StepContext& cx) {
  std::string text;
  r.with("precondition", [&](const YAML::Node& n, const At& a) {
    if (!r.has("send") && !r.has("poll")) fail(a, "a precondition belongs to a send or a poll step: a wait checks nothing");
    if (cx.teardown)
      fail(a, "a teardown step has no precondition: the teardown runs after the vector's test purpose is decided; "
              "move the step into setup or steps");
    text = scalar(n, a, "text: what must hold for the test purpose");
    if (text.empty()) fail(a, "say in words what must hold for the test purpose");
    if (text.size() > kMaxText) fail(a, "has " + std::to_string(text.size()) + " characters, at most " + std::to_string(kMaxText));
  });
  return text;
}

// `precondition_reading`: the switchable ERRATA entry (readings.hpp) whose
// other side lets the precondition fail; a pin of its reference side makes
// the step strict (runner.cpp, record).
std::string read_precondition_reading(const MapReader& r) {
  std::string id;
  r.with("precondition_reading", [&](const YAML::Node& n, const At& a) {
    if (!r.has("precondition")) fail(a, "names the reading a precondition rests on: add the precondition");
    id = scalar(n, a, "an ERRATA entry id with a readings: switch (E-100)");
    if (!find_reading_point(id))
      fail(a, quoted_clip(id) + " is no ERRATA entry with a readings: switch (harness/profile/include/sabus/harness/readings.hpp)");
  });
  return id;
}

Step read_step(const YAML::Node& v, const At& at, StepContext& cx) {
  cx.file.spend(at);
  MapReader r(v, at, schema_keys(SchemaNode::kStep));
  const int kinds = r.has("send") + r.has("poll") + r.has("survey") + r.has("wait") + r.has("wait_ms");
  if (kinds != 1) fail(at, "a step is one of send, poll, survey, wait or wait_ms");
  if (!r.has("send"))
    for (auto k : {"modify", "expect", "length_mismatch"})
      if (r.has(k)) fail(r.at(k), std::string(k) + " belongs to a send step (a poll has its own expect)");
  Step step;
  if (r.has("send")) {
    step = read_send_step(r, at, cx);
  } else if (r.has("poll")) {
    r.with("poll", [&](const YAML::Node& n, const At& a) { step = read_poll(n, a, cx); });
  } else if (r.has("survey")) {
    r.with("survey", [&](const YAML::Node& n, const At& a) { step = read_survey(n, a, cx); });
  } else {
    step.kind = Step::Kind::kWait;
    r.with("wait_ms", [&](const YAML::Node& n, const At& a) { read_ms(n, a, cx, step); });
    r.with("wait", [&](const YAML::Node& n, const At& a) {
      MapReader w(n, a, schema_keys(SchemaNode::kWait));
      require_keys(w, a, {"ms"}, "wait");
      w.with("ms", [&](const YAML::Node& wn, const At& wa) { read_ms(wn, wa, cx, step); });
    });
  }
  step.precondition = read_precondition(r, cx);
  step.precondition_reading = read_precondition_reading(r);
  step.where = cx.file.loc(at.mark);
  return step;
}

}  // namespace

std::vector<Step> read_steps(const YAML::Node& v, const At& at, StepContext& cx) {
  std::vector<Step> out;
  for_each_element(v, at, kMaxSteps, [&](const YAML::Node& e, const At& ea) { out.push_back(read_step(e, ea, cx)); });
  return out;
}

}  // namespace sabus::harness::vector_loader_internal

namespace sabus::harness {

std::string_view to_string(Expectation::Kind k) {
  for (const auto& [name, kind] : vector_loader_internal::kReplyKinds)
    if (kind == k) return name;
  return "?";
}

}  // namespace sabus::harness
