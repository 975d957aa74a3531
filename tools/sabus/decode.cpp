// `sabus decode`: feeds a capture through the receiver and prints every frame
// with its fields and every discarded run with its reason.
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "json_output.hpp"
#include "sabus/harness/capture.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::cli {
namespace {

struct DecodeOptions {
  std::string hex;
  std::string file;
  std::string side = "auto";
  std::string parity = "auto";
  std::string address;
  bool json = false;
};

// One event of the receiver, in stream order.
struct Event {
  bool is_frame = false;
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  Bytes bytes;                          // frame: the 7-bit characters
  std::optional<Discard> discard;
};

struct Collector : ReceiverSink {
  std::vector<Event> events;
  void on_frame(const FrameView& f) override {
    events.push_back({true, f.offset, f.bytes.size(), Bytes(f.bytes.begin(), f.bytes.end()), std::nullopt});
  }
  void on_discard(const Discard& d) override { events.push_back({false, d.offset, d.length, {}, d}); }
};

// Hex text with '#' comments to the end of the line, as capture files and
// the examples are written.
std::string strip_comments(const std::string& text) {
  std::string out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) out += line.substr(0, line.find('#')) + "\n";
  return out;
}

bool looks_like_hex_text(const std::string& s) {
  for (unsigned char c : strip_comments(s))
    if (!std::isxdigit(c) && !std::isspace(c) && c != ':' && c != ',' && c != 'x' && c != 'X' && c != '-')
      return false;
  return true;
}

// Input that is a proxy log or a run JSON rather than bytes.
struct CaptureInput {
  std::string text;
};

std::optional<Bytes> read_input(const DecodeOptions& o, std::string& error, std::optional<CaptureInput>& capture) {
  std::string text;
  if (!o.hex.empty() && o.hex != "-") {
    text = o.hex;
  } else if (o.hex == "-") {
    text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    if (harness::looks_like_capture(text)) {
      capture = CaptureInput{std::move(text)};
      return Bytes{};
    }
  } else {
    std::ifstream in(o.file, std::ios::binary);
    if (!in) {
      error = "cannot read " + o.file;
      return std::nullopt;
    }
    std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (harness::looks_like_capture(content)) {
      capture = CaptureInput{std::move(content)};
      return Bytes{};
    }
    if (!looks_like_hex_text(content)) return Bytes(content.begin(), content.end());  // a raw capture
    text = std::move(content);
  }
  auto bytes = parse_hex(strip_comments(text));
  if (!bytes) {
    error = "bad hex input: " + bytes.error().message();
    return std::nullopt;
  }
  return std::move(bytes).value();
}

nlohmann::json field_json(const FieldDescription& f) {
  return {{"first", f.first}, {"last", f.last}, {"name", f.name},
          {"raw", f.raw},     {"meaning", f.meaning}, {"ok", f.ok}};
}

nlohmann::json fields_json(const FrameDescription& d) {
  nlohmann::json jf = nlohmann::json::array();
  for (const auto& f : d.fields) jf.push_back(field_json(f));
  return jf;
}

// A proxy log or a run JSON: every frame with its time and direction (and,
// for a run, its vector). Frames of a run's transcript are framed again by
// the receiver (a send may hold several, or none).
int run_decode_capture(const DecodeOptions& o, const std::string& text) {
  std::string error;
  auto capture = harness::read_capture(text, error);
  if (!capture) {
    std::cerr << "sabus decode: " << (o.file.empty() ? std::string("stdin") : o.file) << ": " << error << "\n";
    return kExitUsage;
  }
  bool all_valid = true;
  std::size_t frames = 0, ignored = 0;
  nlohmann::json jevents = nlohmann::json::array();
  if (!o.json)
    std::cout << fmt::format("{}{}\n", to_string(capture->source), capture->device.empty() ? "" : " of " + capture->device);
  for (const auto& seg : capture->segments) {
    if (!seg.id.empty() && !o.json) std::cout << fmt::format("vector {} (§{}, {}): {}\n", seg.id, seg.paragraph, seg.level, seg.outcome);
    for (const auto& item : seg.items) {
      const std::string when = item.wall.empty() ? fmt::format("{:10.3f} ms", item.t_ms)
                                                 : fmt::format("{:10.3f} ms {}", item.t_ms, item.wall);
      nlohmann::json base = {{"t_ms", item.t_ms}, {"wall", item.wall}, {"dir", std::string(to_string(item.dir))}};
      if (!seg.id.empty()) base["vector"] = seg.id;
      if (item.ignored) {
        ++ignored;
        all_valid = false;
        if (o.json) {
          base.update({{"type", "discard"}, {"hex", to_hex(item.chars)}, {"message", item.note}});
          jevents.push_back(base);
        } else {
          std::cout << fmt::format("{} {} ignored: {}{}\n", when, to_string(item.dir), item.note,
                                   item.chars.empty() ? "" : "\n  " + to_hex(item.chars));
        }
        continue;
      }
      ReceiverOptions ro = item.dir == harness::Direction::kToDevice ? ReceiverOptions::slave_any_address()
                                                                     : ReceiverOptions::master();
      ro.parity = Parity::kNone;  // both formats hold 7-bit characters
      Receiver receiver(ro);
      Collector events;
      receiver.feed(item.chars, events);
      receiver.finish(events);
      for (const auto& e : events.events) {
        nlohmann::json j = base;
        if (e.is_frame) {
          ++frames;
          const FrameDescription d = describe_frame(e.bytes);
          all_valid &= !d.error.has_value();
          if (o.json) {
            j.update({{"type", "frame"}, {"hex", to_hex(e.bytes)}, {"summary", d.summary}, {"fields", fields_json(d)},
                      {"error", d.error ? nlohmann::json(d.error->message()) : nlohmann::json()}});
            if (item.seq) j["seq"] = *item.seq;
            if (item.reply_to) j["reply_to"] = *item.reply_to;
            jevents.push_back(j);
          } else {
            std::cout << fmt::format("{} {} {}\n", when, to_string(item.dir), d.summary);
            for (const auto& f : d.fields) std::cout << "  " << f.line() << "\n";
            if (d.error) std::cout << "  error: " << d.error->message() << "\n";
          }
        } else {
          ++ignored;
          all_valid = false;
          const std::string hex = to_hex(ByteView(item.chars).subspan(e.offset, e.length));
          if (o.json) {
            j.update({{"type", "discard"}, {"hex", hex}, {"reason", std::string(to_string(e.discard->reason))},
                      {"message", e.discard->message()}});
            jevents.push_back(j);
          } else {
            std::cout << fmt::format("{} {} ignored: {}\n  {}\n", when, to_string(item.dir), e.discard->message(), hex);
          }
        }
      }
    }
  }
  for (const auto& ev : capture->events)
    if (!o.json) std::cout << "event: " << ev << "\n";
  if (o.json) {
    nlohmann::json out = {{"source", std::string(to_string(capture->source))},
                          {"device", capture->device},
                          {"frames", frames},
                          {"ignored_runs", ignored},
                          {"valid", all_valid},
                          {"session_events", capture->events},
                          {"events", jevents}};
    std::cout << json_text(out);
  } else {
    std::cout << fmt::format("{} frame(s), {} ignored run(s)\n", frames, ignored);
  }
  return all_valid && frames > 0 ? kExitOk : kExitFailed;
}

int run_decode(const DecodeOptions& o) {
  std::string error;
  std::optional<CaptureInput> capture;
  auto input = read_input(o, error, capture);
  if (capture) return run_decode_capture(o, capture->text);
  if (!input) {
    std::cerr << "sabus decode: " << error << "\n";
    return kExitUsage;
  }
  const Bytes& bytes = *input;

  // --side: which start bytes begin a frame. "auto" guesses from byte 0.
  std::string side = o.side;
  if (side == "auto") {
    const std::uint8_t first = bytes.empty() ? STX : bytes[0] & 0x7F;  // without a parity bit
    side = first == STX ? "slave" : (first == ACK || first == NAK) ? "master" : "both";
  }
  ReceiverOptions ro = side == "slave" ? ReceiverOptions::slave_any_address() : ReceiverOptions::master();
  if (side == "both") ro.starts = StartBytes::kAny;
  if (!o.address.empty()) {
    auto a = parse_address(o.address);
    if (!a) {
      std::cerr << "sabus decode: --address: " << a.error().message() << "\n";
      return kExitUsage;
    }
    ro.addresses.reset();
    ro.accept_address(a.value());
  }
  // --parity: "auto" takes bit 7 as even parity when any byte has it set
  // (a capture from a port opened 8N1), and 7-bit characters otherwise.
  bool any_high = false;
  for (auto b : bytes) any_high |= (b & 0x80) != 0;
  const bool even = o.parity == "even" || (o.parity == "auto" && any_high);
  ro.parity = even ? Parity::kEvenBit7 : Parity::kNone;

  Receiver receiver(ro);
  Collector events;
  receiver.feed(bytes, events);
  receiver.finish(events);

  bool all_valid = true;
  nlohmann::json jevents = nlohmann::json::array();
  std::size_t frames = 0, discarded = 0, discarded_bytes = 0;
  for (const auto& e : events.events) {
    if (e.is_frame) {
      ++frames;
      FrameDescription d = describe_frame(e.bytes);
      all_valid &= !d.error.has_value();
      if (o.json) {
        nlohmann::json jf = nlohmann::json::array();
        for (const auto& f : d.fields) jf.push_back(field_json(f));
        jevents.push_back({{"type", "frame"},
                           {"offset", e.offset},
                           {"length", e.length},
                           {"hex", to_hex(e.bytes)},
                           {"summary", d.summary},
                           {"fields", jf},
                           {"error", d.error ? nlohmann::json(d.error->message()) : nlohmann::json()}});
      } else {
        std::cout << fmt::format("frame at offset {} ({} bytes): {}\n", e.offset, e.length, d.summary);
        for (const auto& f : d.fields) std::cout << "  " << f.line() << "\n";
        if (d.error) std::cout << "  error: " << d.error->message() << "\n";
      }
    } else {
      ++discarded;
      discarded_bytes += e.length;
      all_valid = false;
      if (o.json) {
        jevents.push_back({{"type", "discard"},
                           {"offset", e.offset},
                           {"length", e.length},
                           {"reason", std::string(to_string(e.discard->reason))},
                           {"hex", to_hex(ByteView(bytes).subspan(e.offset, e.length))},
                           {"message", e.discard->message()}});
      } else {
        std::cout << fmt::format("discarded {}\n  {}\n", e.discard->message(),
                                 to_hex(ByteView(bytes).subspan(e.offset, e.length)));
      }
    }
  }
  if (o.json) {
    nlohmann::json out = {{"side", side},
                          {"parity", even ? "even" : "none"},
                          {"bytes", bytes.size()},
                          {"frames", frames},
                          {"discarded_runs", discarded},
                          {"discarded_bytes", discarded_bytes},
                          {"valid", all_valid},
                          {"events", jevents}};
    std::cout << json_text(out);
  } else {
    std::cout << fmt::format("{} bytes: {} frame(s), {} discarded run(s) ({} bytes); side {}, parity {}\n",
                             bytes.size(), frames, discarded, discarded_bytes, side, even ? "even" : "none");
  }
  return all_valid && !bytes.empty() ? kExitOk : kExitFailed;
}

}  // namespace

Command add_decode_command(CLI::App& app) {
  auto opts = std::make_shared<DecodeOptions>();
  CLI::App* sub = app.add_subcommand("decode", "Decode SAbus frames from a capture, field by field");
  sub->add_option("--hex", opts->hex, "Hex bytes (\"02 32 31 03 02\"; spaces optional), or - for hex text, a proxy log or a run JSON on stdin");
  sub->add_option("file", opts->file, "A capture file: hex text ('#' comments allowed), raw bytes, a proxy log (sabus proxy) or a run JSON (sabus run --json)")
      ->check(CLI::ExistingFile);
  sub->add_option("--side", opts->side, "slave: command frames; master: replies; both; auto guesses from byte 0")
      ->check(CLI::IsMember({"auto", "slave", "master", "both"}));
  sub->add_option("--parity", opts->parity, "even: bit 7 is even parity; none: 7-bit characters; auto")
      ->check(CLI::IsMember({"auto", "even", "none"}));
  sub->add_option("--address", opts->address, "Only accept this address (49-111, the character, or 0x31-0x6f)");
  sub->add_flag("--json", opts->json, "Print JSON");
  sub->callback([opts] {
    if (opts->hex.empty() && opts->file.empty()) throw CLI::RequiredError("--hex or a capture file");
  });
  return {sub, [opts] { return run_decode(*opts); }};
}

}  // namespace sabus::cli
