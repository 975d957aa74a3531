// Tree text (vector_tree.hpp): reading it into YAML trees, writing trees and
// loaded vectors as tree text.
#include "vector_tree.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "sabus/harness/vector_loader.hpp"

namespace sabus::fuzz {
namespace {

using harness::Expectation;
using harness::FieldMatcher;
using harness::Modifiers;
using harness::Requirement;
using harness::Step;
using harness::Vector;

// ---------------------------------------------------------------------------
// Reading tree text
// ---------------------------------------------------------------------------

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool is_syntax(char c) { return std::string_view("{}[],:\"'").find(c) != std::string_view::npos; }
bool is_word_char(char c) { return !is_blank(c) && !is_syntax(c); }

class TreeReader {
 public:
  explicit TreeReader(std::string_view text) : t_(text) {}

  YAML::Node read() { return node(0); }

 private:
  bool at_end() const { return i_ >= t_.size(); }
  void skip_blanks() {
    while (!at_end() && is_blank(t_[i_])) ++i_;
  }

  // A node; consumes at least one character unless at the end or before a
  // character that closes or separates (the caller's to handle).
  YAML::Node node(std::size_t depth) {
    skip_blanks();
    if (at_end()) return YAML::Node(YAML::NodeType::Null);
    const char c = t_[i_];
    if ((c == '{' || c == '[') && depth >= kMaxTreeDepth) {
      ++i_;
      return YAML::Node(YAML::NodeType::Null);
    }
    if (c == '{' || c == '[') return completed(container(depth, c == '{'));
    if (c == '"') return quoted();
    if (c == '\'') return single_quoted();
    if (!is_word_char(c)) return YAML::Node(YAML::NodeType::Null);
    return word();
  }

  YAML::Node completed(YAML::Node n) {
    done_.push_back(n);
    return n;
  }

  // A map (`{`) or a list (`[`), up to its closing character or the end.
  YAML::Node container(std::size_t depth, bool map) {
    YAML::Node c(map ? YAML::NodeType::Map : YAML::NodeType::Sequence);
    const char close = map ? '}' : ']';
    const char other = map ? ']' : '}';
    ++i_;  // '{' or '['
    for (;;) {
      skip_blanks();
      if (at_end()) break;
      const char ch = t_[i_];
      if (ch == close) {
        ++i_;
        break;
      }
      if (ch == ',' || ch == ':' || ch == other) {  // a separator or a stray character
        ++i_;
        continue;
      }
      if (map) entry(c, depth);
      else c.push_back(node(depth + 1));
    }
    return c;
  }

  // key [: value] into a map; a value left out is null.
  void entry(YAML::Node& map, std::size_t depth) {
    const YAML::Node key = node(depth + 1);
    skip_blanks();
    bool has_value = false;
    if (!at_end() && t_[i_] == ':') {
      ++i_;
      skip_blanks();
      has_value = !at_end() && t_[i_] != ',' && t_[i_] != '}';
    }
    // (Never assigned: assigning a YAML::Node writes into the node it refers to.)
    const YAML::Node value = has_value ? node(depth + 1) : YAML::Node(YAML::NodeType::Null);
    map.force_insert(key, value);  // keeps a repeated key, as yaml-cpp does
  }

  static int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }

  YAML::Node quoted() {
    std::string s;
    ++i_;  // '"'
    while (!at_end() && t_[i_] != '"') {
      char c = t_[i_++];
      if (c == '\\' && !at_end()) {
        c = t_[i_++];
        if (c == 'n') c = '\n';
        else if (c == 't') c = '\t';
        else if (c == 'x' && i_ + 1 < t_.size() && hex_digit(t_[i_]) >= 0 && hex_digit(t_[i_ + 1]) >= 0) {
          c = static_cast<char>(hex_digit(t_[i_]) * 16 + hex_digit(t_[i_ + 1]));
          i_ += 2;
        }
      }
      s += c;
    }
    if (!at_end()) ++i_;  // '"'
    YAML::Node n(s);
    n.SetTag("!");  // as yaml-cpp tags a quoted scalar
    return n;
  }

  YAML::Node single_quoted() {
    std::string s;
    ++i_;  // '\''
    while (!at_end()) {
      if (t_[i_] == '\'') {
        if (i_ + 1 < t_.size() && t_[i_ + 1] == '\'') {
          s += '\'';
          i_ += 2;
          continue;
        }
        ++i_;
        break;
      }
      s += t_[i_++];
    }
    return YAML::Node(s);
  }

  YAML::Node word() {
    const std::size_t start = i_;
    while (!at_end() && is_word_char(t_[i_])) ++i_;
    const std::string_view w = t_.substr(start, i_ - start);
    if (w == "~") return YAML::Node(YAML::NodeType::Null);
    if (w.size() > 1 && w[0] == '*' && std::all_of(w.begin() + 1, w.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      if (done_.empty()) return YAML::Node(YAML::NodeType::Null);
      std::size_t n = 0;
      std::from_chars(w.data() + 1, w.data() + w.size(), n);  // a number too large reads as 0
      return done_[n % done_.size()];
    }
    return YAML::Node(std::string(w));
  }

  std::string_view t_;
  std::size_t i_ = 0;
  std::vector<YAML::Node> done_;  // the maps and lists completed so far, for *N
};

// ---------------------------------------------------------------------------
// Writing tree text
// ---------------------------------------------------------------------------

void write_quoted(const std::string& s, std::string& out) {
  out += '"';
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20 || u >= 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  out += '"';
}

// A plain scalar: a word when it reads back as that word, else '...'.
void write_plain(const std::string& s, std::string& out) {
  const bool word = !s.empty() && s != "~" && s[0] != '*' && std::all_of(s.begin(), s.end(), is_word_char);
  if (word) {
    out += s;
    return;
  }
  out += '\'';
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  out += '\'';
}

void write_tree(const YAML::Node& n, std::string& out);

// A sequence's or a map's entries between `open` and `close`, ", " apart.
template <class WriteEntry>
void write_collection(const YAML::Node& n, char open, char close, std::string& out, WriteEntry write_entry) {
  out += open;
  const char* separator = "";
  for (const auto& e : n) {
    out += separator;
    separator = ", ";
    write_entry(e);
  }
  out += close;
}

void write_tree(const YAML::Node& n, std::string& out) {
  switch (n.Type()) {
    case YAML::NodeType::Scalar:
      if (n.Tag() == "!") write_quoted(n.Scalar(), out);
      else write_plain(n.Scalar(), out);
      return;
    case YAML::NodeType::Sequence:
      return write_collection(n, '[', ']', out, [&](const auto& e) { write_tree(e, out); });
    case YAML::NodeType::Map:
      return write_collection(n, '{', '}', out, [&](const auto& e) {
        write_tree(e.first, out);
        out += ": ";
        write_tree(e.second, out);
      });
    default:
      out += '~';
      return;
  }
}

// ---------------------------------------------------------------------------
// Writing a loaded vector file (vectors/README.md is the schema)
// ---------------------------------------------------------------------------

// Written straight as tree text, without building a YAML::Node: the round
// trip then builds one tree only, the one it loads. A value is its text; a
// map or a list gathers its entries' texts as write_tree would write them.
struct Text {
  std::string s;
};

class Container {
 public:
  explicit Container(bool map) : map_(map) {}
  void push_back(const Text& value) {
    separate();
    body_ += value.s;
  }
  void force_insert(const Text& key, const Text& value) {
    separate();
    body_ += key.s;
    body_ += ": ";
    body_ += value.s;
  }
  std::size_t size() const { return size_; }
  operator Text() const { return Text{(map_ ? "{" : "[") + body_ + (map_ ? "}" : "]")}; }

 private:
  void separate() {
    if (size_++ > 0) body_ += ", ";
  }
  bool map_;
  std::string body_;
  std::size_t size_ = 0;
};

Text quoted(const std::string& s) {
  Text t;
  write_quoted(s, t.s);
  return t;
}
Text plain(const std::string& s) {
  Text t;
  write_plain(s, t.s);
  return t;
}
Text number(long long v) { return plain(std::to_string(v)); }
Text number(double d) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, d);  // the shortest text that reads back to d
  return plain(std::string(buf, r.ptr));
}
Container new_map() { return Container(true); }
Container new_list() { return Container(false); }
void put(Container& map, const char* key, const Text& value) { map.force_insert(plain(key), value); }

template <class T, class F>
Text list_of(const std::vector<T>& items, F&& write) {
  Container l = new_list();
  for (const auto& item : items) l.push_back(write(item));
  return l;
}

// A number as written, plain; a profile expression quoted.
Text number_or_expression(const std::string& v) { return harness::has_placeholder(v) ? quoted(v) : plain(v); }

Text matcher_text(const FieldMatcher& m) {
  if (m.kind == FieldMatcher::Kind::kAny && m.capture.empty()) return plain("any");
  Container t = new_map();
  switch (m.kind) {
    case FieldMatcher::Kind::kEq: put(t, "eq", quoted(m.values.at(0))); break;
    case FieldMatcher::Kind::kOneOf: put(t, "one_of", list_of(m.values, quoted)); break;
    case FieldMatcher::Kind::kRegex: put(t, "regex", quoted(m.values.at(0))); break;
    case FieldMatcher::Kind::kRange: {
      Container range = new_list();
      if (m.values.size() == 2) {
        for (const auto& v : m.values) range.push_back(number_or_expression(v));
      } else {
        range.push_back(number(m.low));
        range.push_back(number(m.high));
      }
      put(t, "range", range);
      break;
    }
    case FieldMatcher::Kind::kNear: {
      if (m.near_axis.empty()) {
        put(t, "near", number_or_expression(m.values.at(0)));
        break;
      }
      Container near = new_map();
      put(near, "value", number_or_expression(m.values.at(0)));
      put(near, "axis", plain(m.near_axis));
      put(t, "near", near);
      break;
    }
    case FieldMatcher::Kind::kJogged: {
      Container jogged = new_map();
      put(jogged, "jog", plain(std::string(1, m.jog)));
      put(jogged, "speed", plain(std::string(1, m.speed)));
      put(jogged, "from", number_or_expression(m.values.at(0)));
      put(jogged, "ms", number_or_expression(m.values.at(1)));
      put(t, "jogged", jogged);
      break;
    }
    case FieldMatcher::Kind::kAny: break;
  }
  if (!m.capture.empty()) put(t, "capture", quoted(m.capture));
  return t;
}

// Matchers of one field after another are one list (each must hold).
Text matchers_text(const std::vector<FieldMatcher>& matchers) {
  Container t = new_map();
  for (std::size_t i = 0; i < matchers.size();) {
    std::size_t j = i + 1;
    while (j < matchers.size() && matchers[j].field == matchers[i].field) ++j;
    if (j - i == 1) {
      t.force_insert(quoted(matchers[i].field), matcher_text(matchers[i]));
    } else {
      Container l = new_list();
      for (std::size_t k = i; k < j; ++k) l.push_back(matcher_text(matchers[k]));
      t.force_insert(quoted(matchers[i].field), l);
    }
    i = j;
  }
  return t;
}

Text expectation_text(const Expectation& e) {
  Container t = new_map();
  put(t, "reply", plain(std::string(harness::to_string(e.kind))));
  if (e.bytes) put(t, "bytes", quoted(e.bytes->hex));
  if (!e.fields.empty()) put(t, "fields", matchers_text(e.fields));
  if (!e.nak_rule.empty()) put(t, "rule", quoted(e.nak_rule));
  if (!e.from_profile.empty()) put(t, "from_profile", number_or_expression(e.from_profile));
  // Each other side whole, with its reply: read back as written, not merged.
  if (!e.readings.empty()) {
    Container r = new_map();
    for (const auto& alt : e.readings) r.force_insert(plain(harness::reading_key(alt.errata, alt.side)), expectation_text(alt.expect));
    put(t, "readings", r);
  }
  return t;
}

Text send_text(const Step& s) {
  Container t = new_map();
  if (s.raw) {
    put(t, "raw", quoted(s.raw->hex));
    return t;
  }
  const harness::StructuredCommand& c = *s.command;
  put(t, "command", quoted(c.command));
  if (!c.form.empty()) put(t, "form", quoted(c.form));
  if (!c.fields.empty()) {
    Container fields = new_map();
    for (const auto& [name, value] : c.fields) fields.force_insert(quoted(name), quoted(value));
    put(t, "fields", fields);
  }
  if (c.address) put(t, "address", number(static_cast<long long>(*c.address)));
  if (!c.from_profile.empty()) put(t, "from_profile", number_or_expression(c.from_profile));
  return t;
}

Text modifiers_text(const Modifiers& m) {
  auto size = [](std::size_t n) { return number(static_cast<long long>(n)); };
  Container t = new_map();
  if (m.lrc_xor) put(t, "lrc_xor", number(static_cast<long long>(*m.lrc_xor)));
  if (m.address) put(t, "address", number(static_cast<long long>(*m.address)));
  if (!m.address_text.empty()) put(t, "address", quoted(m.address_text));
  if (m.extra_data_bytes) put(t, "extra_data_bytes", size(m.extra_data_bytes));
  if (!m.replace.empty())
    put(t, "replace", list_of(m.replace, [&](const std::pair<std::size_t, std::uint8_t>& r) {
          Container pair = new_list();
          pair.push_back(size(r.first));
          pair.push_back(number(static_cast<long long>(r.second)));
          return pair;
        }));
  if (m.truncate) put(t, "truncate", size(m.truncate));
  if (!m.parity_flip.empty()) put(t, "parity_flip", list_of(m.parity_flip, size));
  if (!m.chunks.empty()) put(t, "chunks", list_of(m.chunks, size));
  if (m.pause.count()) put(t, "pause_ms", number(static_cast<long long>(m.pause.count())));
  return t;
}

// Whether the loader asks `length_mismatch: true` of this send: its raw
// frame, complete, is not its command's catalog length (at address 50, as
// the loader sketches frames).
bool needs_mismatch_flag(const Step& s) {
  if (!s.raw) return false;
  const auto bytes = harness::expand_raw_bytes(s.raw->hex, '2');
  return bytes && harness::needs_length_mismatch(bytes.value());
}

Text step_text(const Step& s) {
  Container t = new_map();
  switch (s.kind) {
    case Step::Kind::kWait:
      put(t, "wait_ms", s.timeout_text.empty() ? number(static_cast<long long>(s.timeout.count())) : quoted(s.timeout_text));
      break;
    case Step::Kind::kSend:
      put(t, "send", send_text(s));
      if (s.modifiers != Modifiers{}) put(t, "modify", modifiers_text(s.modifiers));
      if (needs_mismatch_flag(s)) put(t, "length_mismatch", plain("true"));
      put(t, "expect", expectation_text(s.expect));
      break;
    case Step::Kind::kPoll: {
      Container poll = new_map();
      put(poll, "send", send_text(s));
      put(poll, "until", matchers_text(s.until));
      if (!s.timeout_text.empty()) put(poll, "timeout_ms", quoted(s.timeout_text));
      else if (s.timeout.count() > 0) put(poll, "timeout_ms", number(static_cast<long long>(s.timeout.count())));
      put(poll, "interval_ms", number(static_cast<long long>(s.interval.count())));
      put(poll, "expect", expectation_text(s.expect));
      put(t, "poll", poll);
      break;
    }
    case Step::Kind::kSurvey: {
      Container survey = new_map();
      put(survey, "send", send_text(s));
      put(survey, "count", number(static_cast<long long>(s.survey_count)));
      put(survey, "interval_ms", number(static_cast<long long>(s.interval.count())));
      put(t, "survey", survey);
      break;
    }
  }
  if (!s.precondition.empty()) put(t, "precondition", quoted(s.precondition));
  return t;
}

Text steps_text(const std::vector<Step>& steps, std::size_t from, std::size_t to) {
  Container l = new_list();
  for (std::size_t i = from; i < to; ++i) l.push_back(step_text(steps[i]));
  return l;
}

// A requirement value as the loader reads it back: a plain word, else quoted.
Text requirement_value(const std::string& v) {
  const bool word = !v.empty() && std::all_of(v.begin(), v.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
           c == '+' || c == '-';
  });
  return word ? plain(v) : quoted(v);
}

// Requirements as maps of one key path each at most once and kMaxEntries
// entries, in order: as few maps as the order allows.
std::vector<Container> requirement_maps(const std::vector<Requirement>& requirements) {
  std::vector<Container> maps;
  std::set<std::string> keys;
  for (const auto& r : requirements) {
    if (maps.empty() || keys.count(r.key) || keys.size() >= harness::kMaxEntries) {
      maps.push_back(new_map());
      keys.clear();
    }
    maps.back().force_insert(plain(r.key), list_of(r.values, requirement_value));
    keys.insert(r.key);
  }
  return maps;
}

// A list of up to `max` of `items` from `from`; `from` moves past them.
Container next_maps(const std::vector<Container>& items, std::size_t& from, std::size_t max) {
  Container l = new_list();
  for (; from < items.size() && l.size() < max; ++from) l.push_back(items[from]);
  return l;
}

Text names_text(const std::vector<std::string>& names, std::size_t from, std::size_t to) {
  Container l = new_list();
  for (std::size_t i = from; i < to; ++i) l.push_back(quoted(names[i]));
  return l;
}

// A file's paragraph, title and notes.
void put_file_keys(Container& root, const harness::VectorFile& file) {
  put(root, "paragraph", quoted(file.paragraph));
  put(root, "title", quoted(file.title));
  if (file.notes.empty()) return;
  Container notes = new_map();
  for (const auto& [flag, note] : file.notes) {
    Container n = new_map();
    put(n, "description", quoted(note.description));
    if (!note.errata.empty()) put(n, "errata", quoted(note.errata));
    notes.force_insert(quoted(flag), n);
  }
  put(root, "notes", notes);
}

// A vector's id, comment, spec and level.
void put_vector_keys(Container& vector, const Vector& v) {
  put(vector, "id", quoted(v.id));
  put(vector, "comment", quoted(v.comment));
  Container spec = new_map();
  put(spec, "paragraph", quoted(v.paragraph));
  put(spec, "quote", quoted(v.quote));
  put(vector, "spec", spec);
  put(vector, "level", plain(std::string(harness::to_string(v.level))));
  if (!v.needs.empty()) put(vector, "needs", list_of(v.needs, quoted));
}

// A vector's lists are its file's, its group's and its own together
// (vector.hpp), each part within its list bound; what does not fit the
// vector's own list goes to a group of its own: the first flags and tags,
// the first setup steps (the group's own setup among them, so its captures
// stay in reach) and the last teardown steps (the group's own). Requirements
// fill the file's list, the group's and the vector's, in order.
void put_lists(Container& root, Container& group, Container& vector, const Vector& v) {
  using harness::kMaxEntries;
  using harness::kMaxSteps;
  const std::vector<Container> requirements = requirement_maps(v.requires_);
  std::size_t next = 0;
  if (requirements.size() > 2 * kMaxEntries) put(root, "requires", next_maps(requirements, next, kMaxEntries));
  if (requirements.size() - next > kMaxEntries) put(group, "requires", next_maps(requirements, next, kMaxEntries));
  if (next < requirements.size()) put(vector, "requires", next_maps(requirements, next, kMaxEntries));
  for (const auto& [key, names] : {std::pair<const char*, const std::vector<std::string>*>{"flags", &v.flags},
                                   {"tags", &v.tags}}) {
    const std::size_t in_group = names->size() > kMaxEntries ? names->size() - kMaxEntries : 0;
    if (in_group) put(group, key, names_text(*names, 0, in_group));
    if (in_group < names->size()) put(vector, key, names_text(*names, in_group, names->size()));
  }
  const bool group_steps = v.setup.size() > kMaxSteps || v.teardown.size() > kMaxSteps;
  const std::size_t setup_in_group = group_steps ? std::min(v.setup.size(), kMaxSteps) : 0;
  const std::size_t own_teardown = group_steps ? std::min(v.teardown.size(), kMaxSteps) : v.teardown.size();
  if (setup_in_group) put(group, "setup", steps_text(v.setup, 0, setup_in_group));
  if (own_teardown < v.teardown.size()) put(group, "teardown", steps_text(v.teardown, own_teardown, v.teardown.size()));
  if (setup_in_group < v.setup.size()) put(vector, "setup", steps_text(v.setup, setup_in_group, v.setup.size()));
  if (!v.each_slot.empty()) put(vector, "each_slot", quoted(v.each_slot));
  put(vector, "steps", steps_text(v.steps, 0, v.steps.size()));
  if (own_teardown) put(vector, "teardown", steps_text(v.teardown, 0, own_teardown));
}

Text one_vector_file(const harness::VectorFile& file, const Vector& v) {
  Container root = new_map();
  put_file_keys(root, file);
  Container group = new_map();
  Container vector = new_map();
  put_vector_keys(vector, v);
  put_lists(root, group, vector, v);
  Container vectors = new_list();
  vectors.push_back(vector);
  if (group.size() == 0) {
    put(root, "vectors", vectors);
    return root;
  }
  put(group, "vectors", vectors);
  Container groups = new_list();
  groups.push_back(group);
  put(root, "groups", groups);
  return root;
}

}  // namespace

YAML::Node parse_tree(std::string_view text) { return TreeReader(text).read(); }

std::string tree_text(const YAML::Node& node) {
  std::string out;
  write_tree(node, out);
  return out;
}

std::string vector_file_text(const harness::VectorFile& file, const harness::Vector& vector) {
  return one_vector_file(file, vector).s;
}

}  // namespace sabus::fuzz
