// The suite linter: what needs the whole suite or the errata beyond one file
// -- unique ids, flags against notes, errata entries, known tags, the spec
// quotes, and the motion/destructive tags that keep bench runs safe
// (READING-NOTES 26, ERRATA E-26).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <sstream>

#include "sabus/harness/errata.hpp"
#include "sabus/harness/expressions.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/enumerations.hpp"
#include "sabus/protocol/structured.hpp"
#include "sabus/harness/data_dir.hpp"
#include "vector_loader_internal.hpp"

namespace sabus::harness::vector_loader_internal {
namespace {

// Tags a run selects or skips vectors by (vectors/README.md). `motion` and
// `destructive` are required by the catalog's effects (READING-NOTES 26).
constexpr std::string_view kKnownTags[] = {"motion",          "destructive", "option:dvb", "pol:circular",
                                           "pol:single_port", "pol:dual_port", "parity",   "timing",
                                           "offline",         "multidrop",   "track",      "as-found",
                                           "power-on"};

// In the data directory (data_dir.hpp).
constexpr std::string_view kErrataFile = "protocol/ERRATA.md";
// The spec text the quotes come from (protocol/ERRATA.md: "the project reads
// it from ../shared/spec/"), by its file name (spec_text_path says where).
constexpr std::string_view kSpecTextName = "000_ebbe2d50858e9e24.txt";

// ERRATA.md entries by number ("### E-7: ..."), and whether each is withdrawn.
struct ErrataIndex {
  std::string path;
  std::optional<std::string> error;
  std::map<std::size_t, bool> withdrawn;
};

ErrataIndex read_errata() {
  ErrataIndex index;
  index.path = data_path(kErrataFile);
  std::string error;
  auto text = read_capped(index.path, 4 << 20, error);
  if (!text) {
    index.error = error;
    return index;
  }
  for (const auto& e : parse_errata(*text).entries)
    if (e.number) index.withdrawn[e.number] = e.withdrawn();
  return index;
}

// Whitespace runs as one blank: the spec text is extracted from a PDF with
// line breaks and tabs where the quote has blanks.
std::string squeezed(std::string_view s) {
  std::string out;
  for (char c : s) {
    const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// A quote is verbatim, or verbatim parts joined by "…" that appear in order.
bool quote_found(const std::string& spec, const std::string& quote) {
  static constexpr std::string_view kEllipsis = "\xE2\x80\xA6";
  std::size_t pos = 0;
  for (std::size_t from = 0;;) {
    const std::size_t at = quote.find(kEllipsis, from);
    const std::string part = squeezed(std::string_view(quote).substr(from, at == std::string::npos ? std::string::npos : at - from));
    if (!part.empty()) {
      const std::size_t hit = spec.find(part, pos);
      if (hit == std::string::npos) return false;
      pos = hit + part.size();
    }
    if (at == std::string::npos) return true;
    from = at + kEllipsis.size();
  }
}

LoadError vector_error(const Vector& v, std::string key, std::string message) {
  return LoadError{v.where, v.id, std::move(key), std::move(message)};
}

void lint_notes(const VectorFile& f, const ErrataIndex& errata, std::vector<LoadError>& errors) {
  std::set<std::string> used;
  for (const auto& v : f.vectors) used.insert(v.flags.begin(), v.flags.end());
  for (const auto& [flag, note] : f.notes) {
    if (!used.count(flag)) errors.push_back({note.where, "", "notes." + flag, "note " + quoted_clip(flag) + " is used by no vector"});
    if (note.errata.empty()) continue;
    std::size_t n = 0;
    const std::string key = "notes." + flag + ".errata";
    if (note.errata.rfind("E-", 0) != 0 || !parse_whole(std::string_view(note.errata).substr(2), n))
      errors.push_back({note.where, "", key, quoted_clip(note.errata) + " is not an errata entry id like E-7"});
    else if (errata.error)
      errors.push_back({note.where, "", key, "cannot check " + note.errata + ": " + errata.path + ": " + *errata.error});
    else if (!errata.withdrawn.count(n))
      errors.push_back({note.where, "", key, note.errata + " is not an entry of protocol/ERRATA.md"});
    else if (errata.withdrawn.at(n))
      errors.push_back({note.where, "", key, note.errata + " is withdrawn (protocol/ERRATA.md)"});
  }
}

void lint_flags_and_tags(const VectorFile& f, const Vector& v, std::vector<LoadError>& errors) {
  for (const auto& flag : v.flags)
    if (!f.notes.count(flag)) errors.push_back(vector_error(v, "flags", "flag " + quoted_clip(flag) + " is not defined in the file's notes"));
  for (const auto& tag : v.tags)
    if (!contains(kKnownTags, tag))
      errors.push_back(vector_error(v, "tags", "unknown tag " + quoted_clip(tag) + "; known tags: " + joined(kKnownTags)));
}


void lint_matchers(const Vector& v, const std::vector<FieldMatcher>& matchers, const CommandInfo* command,
                   const std::string& key, std::vector<LoadError>& errors) {
  if (!command) return;
  const auto names = reply_field_names(*command);
  for (const auto& m : matchers)
    if (!contains(names, m.field))
      errors.push_back({m.where, v.id, key, "unknown field " + quoted_clip(m.field) + " of the " + std::string(command->key) + " reply"});
}

// READING-NOTES 26 / ERRATA E-26: a vector that sends a command that can move
// the antenna or change stored data says so, so a bench run can leave it out.
void lint_effects(const Vector& v, const Step& s, const Effects& e, const std::string& key, const CommandInfo& c,
                  std::vector<LoadError>& errors) {
  const std::string what = std::string(c.key) + " (" + hex_byte(c.code) + ")";
  if (e.moves_antenna && !v.has_tag("motion"))
    errors.push_back({s.where, v.id, key, "sends " + what + ", which can move the antenna: tag the vector motion (READING-NOTES 26, E-26)"});
  if (e.changes_stored_data && !v.has_tag("destructive"))
    errors.push_back({s.where, v.id, key, "sends " + what + ", which changes stored data: tag the vector destructive (READING-NOTES 26, E-26)"});
}

// Where the antenna is (§3.2 bytes 14-31, §3.16, §3.17 bytes 49-50, §3.24
// bytes 4-9) and where it is sent (§3.3 forms 2A, 2B, 2C, 3): in a vector
// that moves the antenna these rest on the profile, never on literal values
// that fit the shipped profiles' speeds and ranges (vectors/README.md,
// "Profile expressions").
constexpr std::string_view kPositionReplyFields[] = {"azimuth",       "elevation",       "polarization",  "position",
                                                     "azimuth count", "elevation count", "az hundredths", "el hundredths"};
constexpr std::string_view kTargetRequestFields[] = {"azimuth", "elevation", "target", "pol target", "azimuth count",
                                                     "elevation count"};

bool literal_window(const FieldMatcher& m) {
  if (m.kind != FieldMatcher::Kind::kEq && m.kind != FieldMatcher::Kind::kOneOf && m.kind != FieldMatcher::Kind::kRange)
    return false;
  if (m.kind == FieldMatcher::Kind::kRange && m.values.empty()) return true;  // built in code with numbers
  return std::none_of(m.values.begin(), m.values.end(), [](const std::string& t) { return has_placeholder(t); });
}

// Positions in a vector that moves the antenna: matchers on position fields
// are near, jogged or ranges of profile expressions; targets the device acts
// on are expressions; a poll's timeout is derived (or an expression).
void lint_motion_positions(const Vector& v, const Step& s, const FrameSketch& sketch, const std::string& key,
                           std::vector<LoadError>& errors) {
  if (!v.has_tag("motion")) return;
  auto matchers = [&](const std::vector<FieldMatcher>& list, const std::string& where) {
    for (const auto& m : list)
      if (contains(kPositionReplyFields, m.field) && literal_window(m))
        errors.push_back({m.where, v.id, where + "." + m.field,
                          "a literal position window in a vector that moves the antenna: derive it from the profile "
                          "(near, jogged, or a range of profile expressions; vectors/README.md)"});
  };
  matchers(s.expect.fields, key + ".expect.fields");
  matchers(s.until, key + ".until");
  const bool acted_on = s.expect.kind == Expectation::Kind::kAck || s.expect.kind == Expectation::Kind::kAny;
  if (acted_on && s.command)
    for (const auto& [name, value] : s.command->fields)
      if (contains(kTargetRequestFields, name) && !has_placeholder(value))
        errors.push_back({s.where, v.id, key + ".send.fields." + name,
                          "a literal target in a vector that moves the antenna: derive it from the profile "
                          "(\"{home(az)}\", \"{at(el, 0.3)}\"; vectors/README.md)"});
  if (acted_on && s.raw && sketch.complete && sketch.command && sketch.command->code == 0x32) {
    // The selector byte cannot tell form 1 from 2A (both ' '): the codecs decode the frame.
    const FormInfo* form = classify_command(sketch.bytes).form;
    if (form && form->id != "1")  // form 1 names a stored satellite; the others carry a target
      errors.push_back({s.where, v.id, key + ".send.raw",
                        "a raw auto move to a literal target in a vector that moves the antenna: put the target in "
                        "a profile expression or build the command from fields"});
  }
  if (s.kind == Step::Kind::kPoll && s.timeout.count() > 0)
    errors.push_back({s.where, v.id, key + ".timeout_ms",
                      "a literal timeout in a vector that moves the antenna: leave it out (the runner derives it "
                      "from distance and speed) or write a profile expression"});
}

// ---- enumerated fields: no expectation wider than the spec's answer (issue 32)

// One enumerated field of a reply as its layout reads it: a byte the codecs
// read with an enumeration (the §3.17 mode, state and exit-status lists,
// EnumByte; a Choice of listed characters: band, axis, polarization, ...).
struct EnumeratedField {
  bool enumerated = false;
  // The field's list hangs on another byte of the reply (the state list on
  // the current mode, the exit-status list on the last exited mode): the
  // same codes are entries of every mode's list.
  bool by_mode = false;
  std::map<std::string, bool> entry;  // matcher text ("0x45") of each code 20h-7Eh -> whether it is an entry of the field's list
};

// The meaning the layout gives that byte with `code`.
std::string meaning_at(const Bytes& frame, std::size_t at, std::uint8_t code, std::string_view field) {
  const auto f = field_with_code(frame, at, code, field);
  return f ? f->meaning + (f->ok ? "" : " (invalid)") : "";
}

// Whether `meaning` is the name an enumeration list of §3.17 gives `code`.
bool names_entry(std::uint8_t code, const std::string& meaning) {
  if (auto n = enums::mode_names().name_of(code); n && *n == meaning) return true;
  for (const enums::EnumList* list : enums::all_lists())
    if (auto n = list->name_of(code); n && *n == meaning) return true;
  return false;
}

const EnumeratedField& enumerated_field(ReplyKind reply, const std::string& field) {
  static std::map<std::pair<ReplyKind, std::string>, EnumeratedField> cache;
  auto [it, fresh] = cache.try_emplace({reply, field});
  if (!fresh) return it->second;
  EnumeratedField& out = it->second;
  const auto sample = sample_reply(reply);
  if (!sample) return out;
  const auto fields = describe_frame(*sample).fields;
  const FieldDescription* f = nullptr;
  for (const auto& d : fields)
    if (d.name == field && d.first == d.last) f = &d;
  if (!f || (f->kind != fields::Kind::kEnumByte && f->kind != fields::Kind::kChoice)) return out;
  out.enumerated = true;
  // Hangs on another enumeration byte: a code's meaning changes with it.
  for (const auto& other : fields) {
    if (&other == f || other.kind != fields::Kind::kEnumByte || other.first != other.last) continue;
    Bytes with = *sample;
    for (std::uint8_t g = enums::kFirstValue; g < 0x60 && !out.by_mode; ++g) {
      with[other.first] = g;
      for (std::uint8_t c = enums::kFirstValue; c < 0x24 && !out.by_mode; ++c)
        out.by_mode = meaning_at(with, f->first, c, field) != meaning_at(*sample, f->first, c, field);
    }
  }
  for (int c = 0x20; c < 0x7F; ++c) {
    const auto code = static_cast<std::uint8_t>(c);
    if (const auto d = field_with_code(*sample, f->first, code, field))
      out.entry[matcher_text(*d)] = f->kind == fields::Kind::kChoice ? d->ok : names_entry(code, d->meaning);
  }
  return out;
}

// A range or a regex on an enumerated field accepts codes by their numbers,
// and the numbers of one list are the codes of the others: every list of
// §3.17 begins at 20h, so a range from 20h takes the first entry of every
// mode's exit list, and a controller that never writes the byte passes.
// Flagged: a range on an enumerated field; a regex on a field whose list
// hangs on a mode that picks some codes and not all (a value check that
// cannot say whose entries it takes); a regex that takes a code that is no
// entry of the field's list (another enumeration's). One_of the legal
// entries names them.
void lint_enumerated(const Vector& v, const std::vector<FieldMatcher>& matchers, ReplyKind reply, const std::string& key,
                     std::vector<LoadError>& errors) {
  for (const FieldMatcher& m : matchers) {
    if (m.kind != FieldMatcher::Kind::kRange && m.kind != FieldMatcher::Kind::kRegex) continue;
    const EnumeratedField& e = enumerated_field(reply, m.field);
    if (!e.enumerated) continue;
    const std::string where = key + "." + m.field;
    if (m.kind == FieldMatcher::Kind::kRange) {
      errors.push_back({m.where, v.id, where,
                        "a range on an enumerated field: its codes are names, and a range of them takes codes of "
                        "another enumeration or another mode (every §3.17 list begins at 0x20); write one_of the legal "
                        "entries (issue 32)"});
      continue;
    }
    std::size_t taken = 0;
    std::vector<std::string> foreign;
    try {
      const std::regex re(m.values.empty() ? std::string() : m.values[0]);
      for (const auto& [text, entry] : e.entry) {
        if (!std::regex_search(text, re)) continue;
        ++taken;
        if (!entry) foreign.push_back(text);
      }
    } catch (const std::regex_error&) {
      continue;  // the loader names a bad regex
    }
    if (e.by_mode && taken > 0 && taken < e.entry.size())
      errors.push_back({m.where, v.id, where,
                        "a regex that picks some codes of a field whose list hangs on the mode: the same codes are "
                        "entries of every mode's list (§3.17); write one_of the legal entries (issue 32)"});
    else if (!e.by_mode && !foreign.empty() && taken < e.entry.size())
      errors.push_back({m.where, v.id, where,
                        "a regex on an enumerated field that takes codes that are no entry of its list (" +
                            foreign.front() + (foreign.size() > 1 ? " and " + std::to_string(foreign.size() - 1) + " more" : "") +
                            "); take the list's entries only (one_of them, or a regex within the list; issue 32)"});
  }
}

void lint_step_list(const Vector& v, const std::vector<Step>& steps, const std::string& list, std::vector<LoadError>& errors) {
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    if (s.kind == Step::Kind::kWait) continue;
    const std::string key = list + "[" + std::to_string(i) + "]";
    std::string problem;
    auto sketch = step_sketch(s, problem);
    if (!problem.empty()) errors.push_back({s.where, v.id, key, problem});
    if (!sketch || !sketch->command) continue;
    if (auto e = effects_of(*sketch)) lint_effects(v, s, *e, key, *sketch->command, errors);
    lint_motion_positions(v, s, *sketch, key, errors);
    lint_matchers(v, s.expect.fields, sketch->command, key + ".expect.fields", errors);
    lint_matchers(v, s.until, sketch->command, key + ".until", errors);
    lint_enumerated(v, s.expect.fields, sketch->command->reply, key + ".expect.fields", errors);
    lint_enumerated(v, s.until, sketch->command->reply, key + ".until", errors);
  }
}

void lint_vector(const VectorFile& f, const Vector& v, const std::optional<std::string>& spec, std::vector<LoadError>& errors) {
  lint_flags_and_tags(f, v, errors);
  lint_step_list(v, v.setup, "setup", errors);
  lint_step_list(v, v.steps, "steps", errors);
  lint_step_list(v, v.teardown, "teardown", errors);
  if (spec && !quote_found(*spec, v.quote))
    errors.push_back(vector_error(v, "spec.quote", "not found verbatim in the spec text (" + spec_text_path() +
                                                       "; line breaks may be blanks, parts may be joined by \"\xE2\x80\xA6\")"));
}

}  // namespace
}  // namespace sabus::harness::vector_loader_internal

namespace sabus::harness {

using namespace vector_loader_internal;

std::string spec_text_path() {
  const DataDir data = require_data_dir();
  // The vendor's manual is not ours to ship: a source tree finds it where
  // the project keeps it, beside the repository; an installation (or any
  // data directory given) where its owner puts a copy, spec/ inside it.
  const std::filesystem::path dir = std::filesystem::path(*data.path) /
                                    (data.source == DataDirSource::kSourceTree ? "../shared/spec" : "spec");
  return (dir / kSpecTextName).lexically_normal().string();
}

std::optional<std::string> read_spec_text() {
  std::string error;
  return read_capped(spec_text_path(), 4 << 20, error);
}

std::vector<LoadError> lint(const std::vector<VectorFile>& files) {
  if (files.empty()) return {};  // the errata and the spec text are read only when there is something to check
  return lint(files, read_spec_text());
}

std::vector<LoadError> lint(const std::vector<VectorFile>& files, const std::optional<std::string>& spec_text) {
  std::vector<LoadError> errors;
  if (files.empty()) return errors;
  const ErrataIndex errata = read_errata();
  const std::optional<std::string> spec = spec_text ? std::optional(squeezed(*spec_text)) : std::nullopt;
  std::map<std::string, SourceLocation> first;
  for (const auto& f : files) {
    lint_notes(f, errata, errors);
    for (const auto& v : f.vectors) {
      auto [it, fresh] = first.emplace(v.id, v.where);
      if (!fresh) errors.push_back(vector_error(v, "id", "duplicate id; first at " + it->second.text()));
      lint_vector(f, v, spec, errors);
    }
  }
  return errors;
}

}  // namespace sabus::harness
