// Raw byte templates ("02 {addr} 31 03 {lrc}") and frame sketches: what a
// send puts on the wire, as far as it can be told before a run (its command,
// form, length and effects), and the bytes of a send or poll step at run time.
#include <algorithm>
#include <map>

#include "sabus/harness/expressions.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/lrc.hpp"
#include "sabus/protocol/structured.hpp"
#include "vector_loader_internal.hpp"

namespace sabus::harness::vector_loader_internal {
namespace {

// A run of hex text between placeholders; `offset` is where it starts in the
// template, for the message.
std::optional<std::string> append_hex(std::string_view run, std::size_t offset, std::vector<Element>& out) {
  auto bytes = parse_hex(run);
  if (!bytes) {
    const DecodeError& e = bytes.error();
    return "bad hex at character " + std::to_string(offset + e.offset + 1) + ": expected " + e.expected +
           (e.got.empty() ? "" : ", got " + quoted_clip(e.got));
  }
  for (auto b : *bytes) {
    // The line adds the parity bit (READING-NOTES 1); a template holds characters.
    if (b > 0x7F) return "byte " + hex_byte(b) + " is not a 7-bit character (use modify.parity_flip for a parity error)";
    out.push_back({Element::Kind::kByte, b, {}});
  }
  return std::nullopt;
}

// Byte 0 of the frame that ends at `end` (READING-NOTES 7); 0 when none.
std::size_t frame_start(ByteView bytes, std::size_t end) {
  return last_frame_start(bytes.first(std::min(end, bytes.size()))).value_or(0);
}

Expected<Bytes> expand(const std::vector<Element>& elements, std::uint8_t address,
                       const std::map<std::string, std::string>& captures) {
  Bytes out;
  for (const auto& e : elements) {
    switch (e.kind) {
      case Element::Kind::kByte: out.push_back(e.byte); break;
      case Element::Kind::kAddr: out.push_back(address); break;
      case Element::Kind::kLrc: {
        const std::size_t start = frame_start(out, out.size());
        out.push_back(lrc(ByteView(out).subspan(start)));  // E-5: from byte 0 through ETX
        break;
      }
      case Element::Kind::kCapture: {
        auto it = captures.find(e.capture);
        if (it == captures.end()) return DecodeError{out.size(), "raw", "a value captured as " + e.capture, ""};
        for (char c : it->second) {
          if (static_cast<unsigned char>(c) > 0x7F)
            return DecodeError{out.size(), "raw", "7-bit characters in " + e.capture, describe_byte(static_cast<std::uint8_t>(c))};
          out.push_back(static_cast<std::uint8_t>(c));
        }
        break;
      }
      case Element::Kind::kExpr:
        return DecodeError{out.size(), "raw", "the value of {" + e.capture + "} (profile expressions are expanded by the runner)", ""};
    }
  }
  return out;
}

bool is_builtin_placeholder(std::string_view name) { return name == "addr" || name == "lrc"; }

// "{name}", built by appending: g++ 12 -O3 warns -Wrestrict on "{" + s + "}".
std::string braced(std::string_view name) {
  std::string out;
  out.reserve(name.size() + 2);
  out += '{';
  out += name;
  out += '}';
  return out;
}

}  // namespace

std::string hex_byte(std::uint8_t b) {
  static constexpr char kHex[] = "0123456789abcdef";
  return std::string("0x") + kHex[b >> 4] + kHex[b & 0xF];
}

std::optional<std::string> parse_template(std::string_view hex, std::vector<Element>& out) {
  for (std::size_t pos = 0;;) {
    const std::size_t open = hex.find('{', pos);
    const std::string_view run = hex.substr(pos, open == std::string_view::npos ? std::string_view::npos : open - pos);
    if (auto e = append_hex(run, pos, out)) return e;
    if (open == std::string_view::npos) return std::nullopt;
    const std::size_t close = hex.find('}', open);
    if (close == std::string_view::npos)
      return "the placeholder at character " + std::to_string(open + 1) + " has no closing '}'";
    const std::string_view name = hex.substr(open + 1, close - open - 1);
    if (name == "addr") out.push_back({Element::Kind::kAddr, 0, {}});
    else if (name == "lrc") out.push_back({Element::Kind::kLrc, 0, {}});
    else if (is_capture_name(name)) out.push_back({Element::Kind::kCapture, 0, std::string(name)});
    else {
      // A profile expression: its syntax and functions here, the captures it
      // reads by the step reader (read_raw), its value at run time.
      const std::string placeholder = braced(name);
      if (auto e = check_template(placeholder, template_captures(placeholder)))
        return *e + " (a raw placeholder is {addr}, {lrc}, {$name} or a profile expression)";
      out.push_back({Element::Kind::kExpr, 0, std::string(name)});
    }
    pos = close + 1;
  }
}

FrameSketch sketch_of(Bytes bytes, bool complete) {
  FrameSketch s{std::move(bytes), complete, 0, nullptr, std::nullopt};
  s.start = frame_start(s.bytes, s.bytes.size());
  if (s.start + 2 < s.bytes.size()) s.command = find_command(s.bytes[s.start + 2]);
  if (s.command && s.command->form_selector_offset && s.start + *s.command->form_selector_offset < s.bytes.size())
    s.selector = s.bytes[s.start + *s.command->form_selector_offset];
  return s;
}

FrameSketch sketch_of(const std::vector<Element>& elements) {
  std::vector<Element> known;
  bool complete = true;
  for (const auto& e : elements) {
    if (e.kind == Element::Kind::kCapture || e.kind == Element::Kind::kExpr) {
      complete = false;
      break;
    }
    known.push_back(e);
  }
  auto bytes = expand(known, kSketchAddress, {});  // cannot fail: no captures, no expressions
  return sketch_of(bytes ? std::move(bytes).value() : Bytes{}, complete);
}

// What sending the frame can do on a bench (READING-NOTES 26): the form its
// selector byte chooses, or any form of the command.
std::optional<Effects> effects_of(const FrameSketch& s) {
  if (!s.command) return std::nullopt;
  if (s.selector)
    if (const FormInfo* f = s.command->form_for_selector(*s.selector)) return f->effects;
  return s.command->effects();
}

// Whether the length rule (check_length, vector_steps.cpp) applies to a send:
// a complete command frame of a code whose request length the catalog knows.
bool has_checked_length(const FrameSketch& k) {
  return k.complete && k.command && k.command->request_length && !k.bytes.empty() && k.bytes[k.start] == STX;
}

// §3 table: a raw command frame has its command's catalog length unless the
// step says `length_mismatch: true`. modify.extra_data_bytes and truncate

std::string build_error_text(const DecodeError& e) {
  return "the codecs cannot build this request: " + e.expected + (e.got.empty() ? "" : ", got " + e.got);
}

// The fields as a load-time check can build them: each profile expression
// expanded against the default profile, captures read as 0; a field the
// default profile cannot give (an unavailable capability) is left out, to
// the codec's default. The run builds the real values.
std::map<std::string, std::string> static_fields(const std::map<std::string, std::string>& fields) {
  static const Profile kDefault;
  std::map<std::string, std::string> out;
  for (const auto& [name, value] : fields) {
    if (!has_placeholder(value)) {
      out.emplace(name, value);
      continue;
    }
    const Expansion e = expand_template(value, ExprContext{kDefault, nullptr, {}});
    if (e.ok()) out.emplace(name, e.text);
  }
  return out;
}

// The frame a step sends, as far as it can be told without a device.
std::optional<FrameSketch> step_sketch(const Step& s, std::string& problem) {
  if (s.command) {
    const CommandInfo* info = find_command(s.command->command);
    if (!info) {
      problem = "unknown command " + quoted_clip(s.command->command);
      return std::nullopt;
    }
    auto built = build_request(*info, s.command->form, static_fields(s.command->fields));
    if (!built) {
      problem = build_error_text(built.error());
      return std::nullopt;
    }
    return sketch_of(encode_request(*built, s.command->address.value_or(kSketchAddress)), true);
  }
  if (s.raw) {
    std::vector<Element> elements;
    if (auto e = parse_template(s.raw->hex, elements)) {
      problem = *e;
      return std::nullopt;
    }
    return sketch_of(elements);
  }
  return std::nullopt;
}

}  // namespace sabus::harness::vector_loader_internal

namespace sabus::harness {

using namespace vector_loader_internal;

Expected<Bytes> expand_raw_bytes(std::string_view hex, std::uint8_t address, const std::map<std::string, std::string>& captures) {
  std::vector<Element> elements;
  if (auto e = parse_template(hex, elements)) return DecodeError{0, "raw", *e, ""};
  return expand(elements, address, captures);
}

Expected<Bytes> step_bytes(const Step& s, std::uint8_t address, const std::map<std::string, std::string>& captures,
                           bool blank_missing_captures) {
  if (s.raw) {
    if (!blank_missing_captures) return expand_raw_bytes(s.raw->hex, address, captures);
    // Static analysis: a value known only at run time is one blank.
    std::string hex = s.raw->hex;
    for (std::size_t at = hex.find('{'); at != std::string::npos; at = hex.find('{', at)) {
      const auto end = hex.find('}', at);
      if (end == std::string::npos) break;
      const std::string name = hex.substr(at + 1, end - at - 1);
      if (is_builtin_placeholder(name) || captures.count(name)) {
        at = end;
        continue;
      }
      hex.replace(at, end - at + 1, "20");
    }
    return expand_raw_bytes(hex, address, captures);
  }
  if (!s.command) return DecodeError{0, "step", "a send with a command or raw bytes", "neither"};
  const CommandInfo* info = find_command(s.command->command);
  if (!info) return DecodeError{0, "command", "a command of the catalog", s.command->command};
  // Statically, a profile expression's value is not known: the default profile's stands in.
  auto r = build_request(*info, s.command->form, blank_missing_captures ? static_fields(s.command->fields) : s.command->fields);
  if (!r) return r.error();
  return encode_request(r.value(), s.command->address.value_or(address));
}

Expansion expand_raw_expressions(std::string_view hex, const ExprContext& cx) {
  std::string out;
  for (std::size_t pos = 0;;) {
    const std::size_t open = hex.find('{', pos);
    out.append(hex.substr(pos, open == std::string_view::npos ? std::string_view::npos : open - pos));
    if (open == std::string_view::npos) return {Expansion::Kind::kValue, out};
    const std::size_t close = hex.find('}', open);
    if (close == std::string_view::npos) return {Expansion::Kind::kValue, out + std::string(hex.substr(open))};
    const std::string_view name = hex.substr(open + 1, close - open - 1);
    if (is_builtin_placeholder(name) || is_capture_name(name)) {
      out.append(hex.substr(open, close - open + 1));
    } else {
      const Expansion e = expand_template(braced(name), cx);
      if (!e.ok()) return e;
      for (char c : e.text) {
        out += ' ';
        out += hex_byte(static_cast<std::uint8_t>(c)).substr(2);
        out += ' ';
      }
    }
    pos = close + 1;
  }
}

bool needs_length_mismatch(ByteView raw_send) {
  const FrameSketch k = sketch_of(Bytes(raw_send.begin(), raw_send.end()), true);
  return has_checked_length(k) && k.bytes.size() - k.start != *k.command->request_length;
}

}  // namespace sabus::harness
