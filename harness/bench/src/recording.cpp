// Regression vectors from a capture (recording.hpp).
#include "sabus/harness/recording.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <set>

#include "sabus/harness/expressions.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/harness/yaml_writer.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/frame.hpp"
#include "sabus/protocol/lrc.hpp"

namespace sabus::harness {

using fields::Kind;

// THE table of what changes between runs of one controller (vectors/README.md
// "Recorded regression vectors" explains it). Everything else is recorded as
// it came and must come back the same.
constexpr MaskRule kMaskRules[] = {
    {Kind::kAzimuth, "", Mask::kAny, "", "azimuth position or compass heading: follows the mount (§3.2 bytes 14-19)"},
    {Kind::kPosition, "", Mask::kAny, "", "elevation, polarization and jog positions: follow the mount (§3.2, §3.24)"},
    {Kind::kRightDecimal, "agc", Mask::kRegex, "^(  [0-9]| [0-9][0-9]|[0-9][0-9][0-9])$",
     "AGC level: the signal varies; its form (0-999, right-justified) does not (§3.2 bytes 41-43)"},
    {Kind::kDigits, "azimuth count|elevation count", Mask::kAny, "", "pulse counts: follow the mount (§3.16)"},
    {Kind::kRightDecimal, "az hundredths|el hundredths", Mask::kAny, "",
     "hundredths of a degree: follow the mount (§3.17 bytes 49-50; a blank without 0.01 deg feedback, ERRATA E-30)"},
    {Kind::kBits, "az status|el status|pol status", Mask::kAny, "",
     "drive status: movement in progress and its direction (§3.2 bytes 36-38)"},
    {Kind::kBits, "az limits|el limits|pol limits", Mask::kAny, "", "limit switches: depend on where the mount is (§3.2 bytes 32-34)"},
    {Kind::kEnumByte, "current mode|current state|last exited mode|exit status", Mask::kAny, "",
     "mode and state: change as moves start and end (§3.17 bytes 45-48)"},
    {Kind::kText, "row 1|row 2|row 3|row 4", Mask::kAny, "", "display text: shows positions and the clock (§3.8)"},
    {Kind::kDigits, "cursor row|cursor column", Mask::kAny, "", "display cursor: moves with the display (§3.8)"},
    {Kind::kChoice, "cursor status", Mask::kAny, "", "display cursor blinking (§3.8)"},
};

std::span<const MaskRule> mask_rules() { return kMaskRules; }

namespace {

bool name_listed(std::string_view names, std::string_view name) {
  while (!names.empty()) {
    const auto bar = names.find('|');
    if (names.substr(0, bar) == name) return true;
    if (bar == std::string_view::npos) break;
    names.remove_prefix(bar + 1);
  }
  return false;
}

}  // namespace

const MaskRule* mask_rule_for(const FieldDescription& field) {
  for (const auto& r : kMaskRules)
    if (r.kind == field.kind && (r.names.empty() || name_listed(r.names, field.name))) return &r;
  return nullptr;
}

namespace {

// Vector files name their paragraph; these do not test one paragraph.
constexpr std::string_view kCrossCutting[] = {"framing", "ignore", "nak", "offline", "parity", "multidrop", "timing", "pacing"};
// The quote of a recording that covers several commands (§1 Message Format).
constexpr std::string_view kFramingQuote =
    "Response messages are identical to command messages in format (but not content)";

struct Exchange {
  Bytes request;                  // 7-bit characters sent in one write (run JSON) or one frame (proxy log)
  std::vector<Bytes> replies;     // frames
  std::size_t ignored_replies = 0;
  double t_ms = 0;
};

struct RecordedVector {
  std::string source_id;          // run JSON: the vector's id
  std::string comment;
  std::vector<Exchange> steps;
};

// Data in the file (ids, raw templates, matcher values, paragraphs):
// double-quoted, exactly as it is.
struct Data {
  std::string_view text;
};
YAML::Emitter& operator<<(YAML::Emitter& e, const Data& d) { return e << YAML::DoubleQuoted << std::string(d.text); }
// Text for a person (the title, a vector's comment) may hold what a capture
// said (a run's vector id and outcome): printable, double-quoted.
struct Prose {
  std::string_view text;
};
YAML::Emitter& operator<<(YAML::Emitter& e, const Prose& p) {
  return e << YAML::DoubleQuoted << yaml_writer::printable_text(p.text);
}

std::string id_part(std::string_view s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_') ? c : '-';
  return out;
}

// The single well-formed frame `chars` is, if it is one.
std::optional<Frame> one_frame(const Bytes& chars) {
  auto f = decode_frame(chars);
  if (!f) return std::nullopt;
  return std::move(f).value();
}

// The command of a send's last frame, when its command byte can be read.
const CommandInfo* request_command(const Bytes& chars) {
  const auto start = last_frame_start(chars);
  return start && *start + 2 < chars.size() ? find_command(chars[*start + 2]) : nullptr;
}

// A raw template: one good frame to the session's address is written with
// {addr} and {lrc} (so the vector follows the profile's address); anything
// else exactly as it was sent.
std::string raw_template(const Bytes& chars, std::uint8_t session_address) {
  auto f = one_frame(chars);
  if (!f || f->kind != FrameKind::kCommand || f->address != session_address) return to_hex(chars);
  Bytes middle{f->command};
  middle.insert(middle.end(), f->data.begin(), f->data.end());
  return "02 {addr} " + to_hex(middle) + " 03 {lrc}";
}

// Effects of a send as the catalog tells them from its last frame's form
// byte (READING-NOTES 26), or of the command when the form cannot be told:
// the reading the linter enforces.
Effects effects_of(const Bytes& chars) {
  const CommandInfo* info = request_command(chars);
  if (!info) return {};
  const std::size_t start = *last_frame_start(chars);
  if (info->form_selector_offset && start + *info->form_selector_offset < chars.size())
    if (const FormInfo* form = info->form_for_selector(chars[start + *info->form_selector_offset])) return form->effects;
  return info->effects();
}

// How a reply field is checked on replay: its mask, or its text as it came
// (`eq`; `one_of` for the texts of several fields of one name).
void field_matcher(YAML::Emitter& e, const std::vector<const FieldDescription*>& same_name) {
  if (const MaskRule* rule = mask_rule_for(*same_name.front())) {
    if (rule->mask == Mask::kAny) e << "any";
    else e << YAML::Flow << YAML::BeginMap << YAML::Key << "regex" << YAML::Value << Data{rule->regex} << YAML::EndMap;
    return;
  }
  // A matcher's value is a template (vectors/README.md, "Profile
  // expressions"): a brace in the text (a satellite named "{X}") is doubled.
  std::vector<std::string> texts;
  for (const auto* f : same_name)
    if (const std::string t = literal_template(matcher_text(*f)); std::find(texts.begin(), texts.end(), t) == texts.end())
      texts.push_back(t);
  e << YAML::Flow << YAML::BeginMap;
  if (texts.size() == 1) {
    e << YAML::Key << "eq" << YAML::Value << Data{texts[0]};
  } else {
    e << YAML::Key << "one_of" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const auto& t : texts) e << Data{t};
    e << YAML::EndSeq;
  }
  e << YAML::EndMap;
}

// The expectation of one exchange: the value of a step's `expect`.
void expectation(YAML::Emitter& e, const Exchange& x, std::vector<std::string>& notes) {
  if (x.replies.empty()) {
    e << "silence";
    return;
  }
  if (x.replies.size() > 1) {
    notes.push_back(fmt::format("t={:.1f} ms: {} frames answered one request; recorded as `any`", x.t_ms, x.replies.size()));
    e << "any";
    return;
  }
  const Bytes& reply = x.replies.front();
  auto frame = one_frame(reply);
  const CommandInfo* asked = request_command(x.request);
  if (frame && frame->kind == FrameKind::kNak && reply.size() == kNakReplyLength) {
    e << "nak";
    return;
  }
  if (frame && is_offline_reply(*frame)) {
    e << "offline";
    return;
  }
  const FrameDescription d = describe_frame(reply);
  if (!frame || frame->kind != FrameKind::kAck || d.error || !asked || frame->command != asked->code ||
      !asked->reply_length || reply.size() != *asked->reply_length) {
    notes.push_back(fmt::format("t={:.1f} ms: the reply is not the command's normal reply ({}{}); recorded as `any`",
                                x.t_ms, d.summary, d.error ? ": " + d.error->message() : std::string()));
    e << "any";
    return;
  }
  // Field name -> every field of that name, in order.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const FieldDescription*>> by_name;
  for (const auto& f : d.fields) {
    if (f.kind == Kind::kHeader || f.kind == Kind::kUndescribed) continue;  // `ack` checks the frame itself
    if (!by_name.count(f.name)) order.push_back(f.name);
    by_name[f.name].push_back(&f);
  }
  e << YAML::BeginMap << YAML::Key << "reply" << YAML::Value << "ack";
  if (!order.empty()) {
    e << YAML::Key << "fields" << YAML::Value << YAML::BeginMap;
    for (const auto& name : order) {
      e << YAML::Key << Data{name} << YAML::Value;
      field_matcher(e, by_name[name]);
    }
    e << YAML::EndMap;
  }
  e << YAML::EndMap;
}

std::vector<RecordedVector> from_proxy_log(const Capture& c, std::vector<std::string>& notes) {
  std::vector<RecordedVector> out;
  std::map<std::uint64_t, std::size_t> by_seq;
  std::size_t ignored_requests = 0, unpaired = 0;
  for (const auto& item : c.segments.front().items) {
    if (item.dir == Direction::kToDevice) {
      if (item.ignored || !item.seq) {
        ++ignored_requests;
        continue;
      }
      RecordedVector v;
      v.steps.push_back({item.chars, {}, 0, item.t_ms});
      by_seq[*item.seq] = out.size();
      out.push_back(std::move(v));
      continue;
    }
    auto it = item.reply_to ? by_seq.find(*item.reply_to) : by_seq.end();
    if (it == by_seq.end()) {
      ++unpaired;
      continue;
    }
    Exchange& x = out[it->second].steps.front();
    if (item.ignored) ++x.ignored_replies;
    else x.replies.push_back(item.chars);
  }
  if (ignored_requests)
    notes.push_back(fmt::format("{} run(s) of request bytes the receiver ignored are not recorded (only frames are)", ignored_requests));
  if (unpaired) notes.push_back(fmt::format("{} device frame(s) or run(s) before the first request are not recorded", unpaired));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Exchange& x = out[i].steps.front();
    out[i].comment = fmt::format("Exchange {} of the recorded session, at {:.1f} ms: {}", i + 1, x.t_ms,
                                 describe_frame(x.request).summary);
  }
  return out;
}

std::vector<RecordedVector> from_run_json(const Capture& c, std::vector<std::string>& notes) {
  std::vector<RecordedVector> out;
  for (const auto& s : c.segments) {
    RecordedVector v;
    v.source_id = s.id;
    for (const auto& item : s.items) {
      if (item.dir == Direction::kToDevice) {
        v.steps.push_back({item.chars, {}, 0, item.t_ms});
      } else if (!v.steps.empty()) {
        if (item.ignored) ++v.steps.back().ignored_replies;
        else v.steps.back().replies.push_back(item.chars);
      }
    }
    if (v.steps.empty()) {
      notes.push_back(s.id + ": nothing was sent (" + (s.outcome.empty() ? "no transcript" : s.outcome) + "); not recorded");
      continue;
    }
    v.comment = fmt::format("Recorded from run vector {} (§{}, {}, outcome {}).", s.id, s.paragraph, s.level, s.outcome);
    out.push_back(std::move(v));
  }
  return out;
}

// A capture holds 7-bit characters (the receiver takes the parity bit off;
// tools/PROXY-LOG.md), and so does a raw send (vectors/README.md): a
// request with a byte of 80h or more cannot be sent again as it was. Why
// not, naming the exchange, or "".
std::string eight_bit_request(const std::vector<RecordedVector>& vectors) {
  for (std::size_t i = 0; i < vectors.size(); ++i)
    for (const auto& x : vectors[i].steps)
      for (std::size_t k = 0; k < x.request.size(); ++k)
        if (x.request[k] > 0x7F)
          return fmt::format("{} (t={:.1f} ms): byte {} of the request is 0x{:02x}, not a 7-bit character; a capture holds "
                             "the characters sent, without the parity bit",
                             vectors[i].source_id.empty() ? fmt::format("exchange {}", i + 1)
                                                          : "vector " + yaml_writer::printable_text(vectors[i].source_id),
                             x.t_ms, k, x.request[k]);
  return "";
}

bool is_cross_cutting(std::string_view p) {
  return std::find(std::begin(kCrossCutting), std::end(kCrossCutting), p) != std::end(kCrossCutting);
}

bool is_paragraph(std::string_view p) {
  if (p == "1" || p == "2" || p == "3" || p == "4") return true;
  for (const auto& c : catalog())
    if (c.paragraph == p) return true;
  return false;
}

// The §3 Command Set table row of a command ("31 Device Status Poll"): a
// verbatim quote for every command (the table spaces the jog's slashes).
std::string command_quote(const CommandInfo& c) {
  std::string name;
  for (char ch : c.name) name += ch == '/' ? std::string(" / ") : std::string(1, ch);
  return fmt::format("{:02X} {}", c.code, name);
}

const CommandInfo* command_of_paragraph(std::string_view p) {
  for (const auto& c : catalog())
    if (c.paragraph == p) return &c;
  return nullptr;
}

// The one command every step of `v` sends, if there is one.
const CommandInfo* single_command(const std::vector<Exchange>& steps) {
  const CommandInfo* one = nullptr;
  for (const auto& x : steps) {
    const CommandInfo* c = request_command(x.request);
    if (!c || (one && one != c)) return nullptr;
    one = c;
  }
  return one;
}

}  // namespace

std::optional<Recording> record_vectors(const Capture& capture, const RecordOptions& options, std::string& error) {
  Recording rec;
  if (options.name.empty() || id_part(options.name) != options.name) {
    error = "the name \"" + options.name + "\" must be letters, digits, '.', '-', '_'";
    return std::nullopt;
  }
  std::vector<RecordedVector> vectors = capture.source == Capture::Source::kProxyLog
                                            ? from_proxy_log(capture, rec.notes)
                                            : from_run_json(capture, rec.notes);
  if (vectors.empty()) {
    error = "no request/reply exchange to record in the " + std::string(to_string(capture.source));
    return std::nullopt;
  }
  if (error = eight_bit_request(vectors); !error.empty()) return std::nullopt;
  // The session's address: that of the first well-formed request.
  std::optional<std::uint8_t> address;
  std::vector<Exchange> all;
  for (const auto& v : vectors)
    for (const auto& x : v.steps) {
      all.push_back(x);
      if (auto f = one_frame(x.request); f && f->kind == FrameKind::kCommand && !address) address = f->address;
    }

  // The file's paragraph: the command's for a recording of one command,
  // otherwise `framing` (vectors/README.md).
  if (!options.paragraph.empty()) {
    if (!is_paragraph(options.paragraph) && !is_cross_cutting(options.paragraph)) {
      error = "--paragraph \"" + options.paragraph + "\" is neither a spec paragraph (3.2) nor a cross-cutting topic (framing, ...)";
      return std::nullopt;
    }
    rec.paragraph = options.paragraph;
  } else {
    const CommandInfo* one = single_command(all);
    rec.paragraph = one ? std::string(one->paragraph) : "framing";
  }
  const bool cross = is_cross_cutting(rec.paragraph);

  YAML::Emitter y;
  y << YAML::Comment(yaml_writer::printable_text(
      "Regression vectors recorded by `sabus record` from " + (options.source.empty() ? std::string("a capture") : options.source) +
      " (" + std::string(to_string(capture.source)) + (capture.device.empty() ? "" : ", device " + capture.device) + ").\n" +
      "What that controller answered then; fields that change between runs are masked\n" +
      "(vectors/README.md, \"Recorded regression vectors\"). Schema: vectors/README.md."));
  y << YAML::BeginMap;
  y << YAML::Key << "paragraph" << YAML::Value << Data{rec.paragraph};
  y << YAML::Key << "title" << YAML::Value
    << Prose{"Regression " + options.name + ": " + std::to_string(vectors.size()) + " recorded " +
             (capture.source == Capture::Source::kProxyLog ? "exchange(s)" : "vector(s)")};
  if (address)
    y << YAML::Key << "requires" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "address" << YAML::Value
      << static_cast<int>(*address) << YAML::EndMap;
  y << YAML::Key << "vectors" << YAML::Value << YAML::BeginSeq;

  std::set<std::string> ids;
  for (std::size_t i = 0; i < vectors.size(); ++i) {
    const RecordedVector& v = vectors[i];
    std::string id = rec.paragraph + "-" + options.name + "-" +
                     (v.source_id.empty() ? fmt::format("{:03}", i + 1) : id_part(v.source_id));
    if (!ids.insert(id).second) id += fmt::format("-{}", i + 1);
    const CommandInfo* one = single_command(v.steps);
    std::string spec_paragraph = rec.paragraph, quote;
    if (cross) {
      spec_paragraph = one ? std::string(one->paragraph) : "1";
      quote = one ? command_quote(*one) : std::string(kFramingQuote);
    } else if (const CommandInfo* c = command_of_paragraph(rec.paragraph)) {
      quote = command_quote(*c);
    } else {
      quote = kFramingQuote;
    }
    Effects e;
    for (const auto& x : v.steps) {
      const Effects one_e = effects_of(x.request);
      e.moves_antenna |= one_e.moves_antenna;
      e.changes_stored_data |= one_e.changes_stored_data;
    }
    y << YAML::BeginMap;
    y << YAML::Key << "id" << YAML::Value << Data{id};
    y << YAML::Key << "comment" << YAML::Value << Prose{v.comment};
    y << YAML::Key << "spec" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "paragraph" << YAML::Value
      << Data{spec_paragraph} << YAML::Key << "quote" << YAML::Value << Data{quote} << YAML::EndMap;
    y << YAML::Key << "level" << YAML::Value << "must";
    if (e.moves_antenna || e.changes_stored_data) {
      y << YAML::Key << "tags" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      if (e.moves_antenna) y << "motion";
      if (e.changes_stored_data) y << "destructive";
      y << YAML::EndSeq;
    }
    y << YAML::Key << "steps" << YAML::Value << YAML::BeginSeq;
    for (const auto& x : v.steps) {
      y << YAML::BeginMap;
      y << YAML::Key << "send" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "raw" << YAML::Value
        << Data{raw_template(x.request, address.value_or(0))} << YAML::EndMap;
      if (needs_length_mismatch(x.request)) y << YAML::Key << "length_mismatch" << YAML::Value << true;
      y << YAML::Key << "expect" << YAML::Value;
      expectation(y, x, rec.notes);
      y << YAML::EndMap;
      ++rec.steps;
    }
    y << YAML::EndSeq << YAML::EndMap;
    ++rec.vectors;
  }
  y << YAML::EndSeq << YAML::EndMap;
  rec.yaml = yaml_writer::document(y);
  return rec;
}

}  // namespace sabus::harness
