// `sabus decode`: feeds a capture through the receiver and prints every frame
// with its fields and every discarded run with its reason.
#include <fmt/format.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

// One event of the receiver, in stream order (the capture path, whose
// items are small).
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

// A capture is read and decoded this many bytes at a time: memory does not
// grow with the capture (a day of bench traffic is hundreds of MB).
constexpr std::size_t kChunk = 1 << 16;

// Hex text as capture files and the examples are written: '#' starts a
// comment to the end of the line. Fed character by character, it gives the
// text without its comments, each line ended by '\n' (a last line without
// one gets it), which is what the hex parser reads.
class CommentStripper {
 public:
  template <class Emit>
  void feed(char c, Emit&& emit) {
    last_ = c;
    seen_ = true;
    if (c == '\n') {
      in_comment_ = false;
      emit(c);
    } else if (c == '#') {
      in_comment_ = true;
    } else if (!in_comment_) {
      emit(c);
    }
  }
  template <class Emit>
  void finish(Emit&& emit) {
    if (seen_ && last_ != '\n') emit('\n');
  }

 private:
  bool in_comment_ = false, seen_ = false;
  char last_ = 0;
};

// Whether a character outside a comment can be part of hex text ("02 32",
// "0x02", "02:32", "02,32", "02-32"): a file of only these is hex text, any
// other is a raw capture.
bool hex_text_char(unsigned char c) {
  return std::isxdigit(c) || std::isspace(c) || c == ':' || c == ',' || c == 'x' || c == 'X' || c == '-';
}

// parse_hex (protocol/bytes.hpp) fed one character at a time, with the same
// rules and the same errors at the same offsets; each byte goes to `emit`.
class HexParser {
 public:
  // nullopt, or the error at this character.
  template <class Emit>
  std::optional<DecodeError> feed(char c, Emit&& emit) {
    const std::size_t at = pos_++;
    if (zero_at_) {  // a '0' waiting to see whether an 'x' follows: "0x" prefixes a byte
      const std::size_t zero = *zero_at_;
      zero_at_.reset();
      if (c == 'x' || c == 'X') return std::nullopt;
      if (auto e = digit(0, zero, emit)) return e;
    }
    if (c == '0' && high_ < 0) {
      zero_at_ = at;
      return std::nullopt;
    }
    if (std::isspace(static_cast<unsigned char>(c)) || c == ':' || c == ',' || c == '-') {
      if (high_ >= 0) return DecodeError{at, "hex text", "two hex digits per byte", std::string(1, c)};
      return std::nullopt;
    }
    const int v = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                  : (c >= 'a' && c <= 'f')                    ? c - 'a' + 10
                  : (c >= 'A' && c <= 'F')                    ? c - 'A' + 10
                                                              : -1;
    if (v < 0) return DecodeError{at, "hex text", "a hex digit", std::string(1, c)};
    return digit(v, at, emit);
  }
  template <class Emit>
  std::optional<DecodeError> finish(Emit&& emit) {
    if (zero_at_) {
      const std::size_t zero = *zero_at_;
      zero_at_.reset();
      if (auto e = digit(0, zero, emit)) return e;
    }
    if (high_ >= 0) return DecodeError{pos_, "hex text", "an even number of hex digits", ""};
    return std::nullopt;
  }

 private:
  template <class Emit>
  std::optional<DecodeError> digit(int v, std::size_t, Emit&& emit) {
    if (high_ < 0) {
      high_ = v;
    } else {
      emit(static_cast<std::uint8_t>(high_ << 4 | v));
      high_ = -1;
    }
    return std::nullopt;
  }
  int high_ = -1;
  std::size_t pos_ = 0;
  std::optional<std::size_t> zero_at_;
};

// The bytes of a capture in a file read by offset: the capture file itself
// (raw bytes), or a temporary file the hex text was parsed into. What the
// decoder needs to know before its first byte comes with it.
struct ByteFile {
  int fd = -1;
  std::FILE* temporary = nullptr;  // owned; removed when closed
  std::uint64_t size = 0;
  std::optional<std::uint8_t> first;
  bool any_high = false;  // a byte with bit 7 set

  ByteFile() = default;
  ByteFile(const ByteFile&) = delete;
  ByteFile& operator=(const ByteFile&) = delete;
  ~ByteFile() {
    if (temporary) std::fclose(temporary);
    else if (fd >= 0) ::close(fd);
  }
  // Up to `n` bytes at `offset`; fewer only at the end.
  std::size_t read(std::uint64_t offset, std::uint8_t* out, std::size_t n) const {
    std::size_t got = 0;
    while (got < n) {
      const ssize_t r = ::pread(fd, out + got, n - got, static_cast<off_t>(offset + got));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) break;
      got += static_cast<std::size_t>(r);
    }
    return got;
  }
  void note(const std::uint8_t* p, std::size_t n) {
    if (n > 0 && !first) first = p[0];
    for (std::size_t i = 0; i < n; ++i) any_high |= (p[i] & 0x80) != 0;
    size += n;
  }
};

// Hex text from `in` (after `prefix`, what was read of it already) parsed
// into a temporary file; nullptr with `error` set on bad hex.
std::unique_ptr<ByteFile> parse_hex_stream(const std::string& prefix, std::istream& in, std::string& error) {
  auto out = std::make_unique<ByteFile>();
  out->temporary = std::tmpfile();
  if (out->temporary == nullptr) {
    error = std::string("cannot make a temporary file for the parsed bytes: ") + std::strerror(errno);
    return nullptr;
  }
  out->fd = ::fileno(out->temporary);
  CommentStripper strip;
  HexParser hex;
  std::vector<std::uint8_t> bytes;
  bytes.reserve(kChunk);
  std::optional<DecodeError> bad;
  bool write_failed = false;
  auto flush = [&] {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), out->temporary) != bytes.size()) write_failed = true;
    out->note(bytes.data(), bytes.size());
    bytes.clear();
  };
  auto emit_byte = [&](std::uint8_t b) {
    bytes.push_back(b);
    if (bytes.size() == kChunk) flush();
  };
  auto emit_char = [&](char c) {
    if (!bad) bad = hex.feed(c, emit_byte);
  };
  for (char c : prefix) strip.feed(c, emit_char);
  std::vector<char> buf(kChunk);
  while (!bad && in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    for (std::streamsize i = 0; i < in.gcount() && !bad; ++i) strip.feed(buf[static_cast<std::size_t>(i)], emit_char);
  }
  if (!bad) strip.finish(emit_char);
  if (!bad) bad = hex.finish(emit_byte);
  if (bad) {
    error = "bad hex input: " + bad->message();
    return nullptr;
  }
  flush();
  if (write_failed || std::fflush(out->temporary) != 0) {
    error = std::string("cannot write the parsed bytes to a temporary file: ") + std::strerror(errno);
    return nullptr;
  }
  return out;
}

// Input that is a proxy log or a run JSON rather than bytes. Such a file is
// read whole: its records are decoded once all of it is known to be one.
struct CaptureInput {
  std::string text;
  bool proxy_log_file = false;  // the file is a proxy log, read a record at a time
};

std::string read_all(std::istream& in) { return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()}; }

// The capture's bytes, a proxy log or a run JSON in `capture`, or nullptr
// with `error` set. Hex text (from --hex, stdin or a file) is parsed into a
// temporary file as it is read; a raw capture file is read where it is.
std::unique_ptr<ByteFile> read_input(const DecodeOptions& o, std::string& error, std::optional<CaptureInput>& capture) {
  if (!o.hex.empty() && o.hex != "-") {
    std::istringstream none;
    return parse_hex_stream(o.hex, none, error);
  }
  if (o.hex == "-") {
    // A proxy log or a run JSON starts with '{' (after blanks): read whole.
    std::string prefix;
    for (int c; (c = std::cin.peek()) != EOF && std::isspace(c);) prefix += static_cast<char>(std::cin.get());
    if (std::cin.peek() == '{') {
      std::string text = prefix + read_all(std::cin);
      if (harness::looks_like_capture(text)) {
        capture = CaptureInput{std::move(text)};
        return nullptr;
      }
      std::istringstream none;
      return parse_hex_stream(text, none, error);
    }
    return parse_hex_stream(prefix, std::cin, error);
  }
  std::ifstream in(o.file, std::ios::binary);
  if (!in) {
    error = "cannot read " + o.file;
    return nullptr;
  }
  // One pass over the file: its first character that is not blank, whether
  // it is hex text, and whether a byte has bit 7 set (a raw capture's parity).
  auto file = std::make_unique<ByteFile>();
  CommentStripper strip;
  bool hex_like = true;
  char first_text = 0;
  std::vector<char> buf(kChunk);
  auto check = [&](char c) {
    hex_like = hex_like && hex_text_char(static_cast<unsigned char>(c));
    if (first_text == 0 && !std::isspace(static_cast<unsigned char>(c))) first_text = c;
  };
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    file->note(reinterpret_cast<const std::uint8_t*>(buf.data()), n);
    for (std::size_t i = 0; i < n; ++i) strip.feed(buf[i], check);
  }
  if (first_text == '{') {
    in.clear();
    in.seekg(0);
    std::string first_line;
    for (int c; (c = in.peek()) != EOF && std::isspace(c);) in.get();
    std::getline(in, first_line);
    if (harness::is_proxy_log_header(first_line)) {
      capture = CaptureInput{"", true};
      return nullptr;
    }
    in.clear();
    in.seekg(0);
    std::string text = read_all(in);
    if (harness::looks_like_capture(text)) {
      capture = CaptureInput{std::move(text)};
      return nullptr;
    }
  }
  if (hex_like) {
    in.clear();
    in.seekg(0);
    return parse_hex_stream("", in, error);
  }
  file->fd = ::open(o.file.c_str(), O_RDONLY | O_CLOEXEC);  // a raw capture
  if (file->fd < 0) {
    error = "cannot read " + o.file;
    return nullptr;
  }
  return file;
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

// What the decoder writes, buffered: the standard output is written a
// chunk at a time, whatever the capture's size.
class Output {
 public:
  ~Output() { flush(); }
  Output& operator<<(std::string_view s) {
    buf_.append(s);
    if (buf_.size() >= kChunk) flush();
    return *this;
  }
  void flush() {
    if (!buf_.empty()) std::cout.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }

 private:
  std::string buf_;
};

// The bytes the receiver was fed last: the chunk it is reading and the one
// before, so that a discarded run is written from memory, and only a run
// longer than that is read again from the file.
struct Window {
  std::vector<std::uint8_t> bytes;
  std::uint64_t offset = 0;  // of bytes[0]
  bool holds(std::uint64_t at, std::uint64_t length) const {
    return at >= offset && at + length <= offset + bytes.size();
  }
};

// "02 32 31" as to_hex writes it, appended to `out`.
void append_hex(std::string& out, const std::uint8_t* p, std::size_t n) {
  static constexpr char kDigits[] = "0123456789abcdef";
  const std::size_t at = out.size();
  out.resize(at + (n == 0 ? 0 : 3 * n - 1));
  char* o = out.data() + at;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) *o++ = ' ';
    *o++ = kDigits[p[i] >> 4];
    *o++ = kDigits[p[i] & 0xF];
  }
}

// The hex of bytes [offset, offset + length) of the capture, from the
// window or else read from the file a piece at a time: a discarded run can
// be as long as the capture.
void write_hex(Output& out, const Window& window, const ByteFile& in, std::uint64_t offset, std::uint64_t length) {
  std::string hex;
  if (window.holds(offset, length)) {
    append_hex(hex, window.bytes.data() + (offset - window.offset), static_cast<std::size_t>(length));
    out << hex;
    return;
  }
  std::uint8_t buf[4096];
  for (std::uint64_t done = 0; done < length;) {
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(sizeof buf, length - done));
    const std::size_t got = in.read(offset + done, buf, want);
    if (got == 0) break;
    hex.clear();
    if (done > 0) hex += ' ';
    append_hex(hex, buf, got);
    out << hex;
    done += got;
  }
}

// One element of the JSON's "events" array, indented as json_text indents
// the whole document (an element of a member of the top object).
std::string event_json(const nlohmann::json& event) {
  const std::string text = event.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out = "    ";
  for (char c : text) {
    out += c;
    if (c == '\n') out += "    ";
  }
  return out;
}

// A value of the document at some depth: json's dump, each line after the
// first indented by `indent` (what json_text gives it inside the whole).
std::string indented(const nlohmann::json& value, std::string_view indent) {
  const std::string text = value.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '\n') out += indent;
  }
  return out;
}

std::string json_string(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Counts of a pass of the receiver that only counts (the JSON gives them
// before its events).
struct Counter : ReceiverSink {
  std::size_t frames = 0, discarded = 0, discarded_bytes = 0;
  void on_frame(const FrameView&) override { ++frames; }
  void on_discard(const Discard& d) override {
    ++discarded;
    discarded_bytes += d.length;
  }
};

// Each event written as the receiver reports it: nothing of the capture is
// kept but the receiver's own state.
struct Printer : ReceiverSink {
  Printer(Output& out, const ByteFile& in, bool json) : out(out), in(in), json(json) {}
  Output& out;
  const ByteFile& in;
  Window window;
  bool json;
  bool all_valid = true;
  std::size_t frames = 0, discarded = 0, discarded_bytes = 0;

  void separator() {
    if (json) out << (frames + discarded == 0 ? "\n" : ",\n");
  }
  void on_frame(const FrameView& f) override {
    const FrameDescription d = describe_frame(f.bytes);
    all_valid &= !d.error.has_value();
    separator();
    ++frames;
    if (json) {
      nlohmann::json jf = nlohmann::json::array();
      for (const auto& field : d.fields) jf.push_back(field_json(field));
      out << event_json({{"type", "frame"},
                         {"offset", f.offset},
                         {"length", f.bytes.size()},
                         {"hex", to_hex(f.bytes)},
                         {"summary", d.summary},
                         {"fields", jf},
                         {"error", d.error ? nlohmann::json(d.error->message()) : nlohmann::json()}});
    } else {
      out << fmt::format("frame at offset {} ({} bytes): {}\n", f.offset, f.bytes.size(), d.summary);
      for (const auto& field : d.fields) out << "  " << field.line() << "\n";
      if (d.error) out << "  error: " << d.error->message() << "\n";
    }
  }
  void on_discard(const Discard& d) override {
    all_valid = false;
    separator();
    ++discarded;
    discarded_bytes += d.length;
    if (json) {
      // Written member by member (the keys in json's order) so that the hex
      // of a long run is not held whole; the strings through json's dump.
      const auto text = [](const std::string& s) {
        return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      };
      out << "    {\n      \"hex\": \"";
      write_hex(out, window, in, d.offset, d.length);
      out << fmt::format("\",\n      \"length\": {},\n      \"message\": {},\n      \"offset\": {},\n      \"reason\": {},\n"
                         "      \"type\": \"discard\"\n    }}",
                         d.length, text(d.message()), d.offset, text(std::string(to_string(d.reason))));
    } else {
      out << "discarded " << d.message() << "\n  ";
      write_hex(out, window, in, d.offset, d.length);
      out << "\n";
    }
  }
};

// The capture through a receiver, a chunk at a time, the last two chunks
// kept in `window`.
void feed_all(const ByteFile& in, const ReceiverOptions& ro, ReceiverSink& sink, Window& window) {
  Receiver receiver(ro);
  window.bytes.reserve(2 * kChunk);
  for (std::uint64_t offset = 0; offset < in.size;) {
    if (window.bytes.size() > kChunk) {  // the chunk before the last goes
      const std::size_t drop = window.bytes.size() - kChunk;
      window.bytes.erase(window.bytes.begin(), window.bytes.begin() + static_cast<std::ptrdiff_t>(drop));
      window.offset += drop;
    }
    const std::size_t kept = window.bytes.size();
    window.bytes.resize(kept + kChunk);
    const std::size_t got = in.read(offset, window.bytes.data() + kept, kChunk);
    window.bytes.resize(kept + got);
    if (got == 0) break;
    receiver.feed(ByteView(window.bytes.data() + kept, got), sink);
    offset += got;
  }
  receiver.finish(sink);
}

// A proxy log or a run JSON: every frame with its time and direction (and,
// for a run, its vector), each item written as it comes. Frames of a run's
// transcript are framed again by the receiver (a send may hold several, or
// none).
struct CapturePrinter {
  CapturePrinter(Output& out, bool json) : out(out), json(json) {}
  Output& out;
  bool json;
  bool all_valid = true;
  std::size_t frames = 0, ignored = 0, events = 0;

  // The document's start, before its first item.
  void start(const harness::Capture& c) {
    if (json) out << "{\n  \"device\": " << json_string(c.device) << ",\n  \"events\": [";
    else out << fmt::format("{}{}\n", to_string(c.source), c.device.empty() ? "" : " of " + c.device);
  }
  void segment(const harness::CapturedSegment& seg) {
    if (!seg.id.empty() && !json) out << fmt::format("vector {} (§{}, {}): {}\n", seg.id, seg.paragraph, seg.level, seg.outcome);
  }
  void event(const nlohmann::json& j) {
    out << (events++ == 0 ? "\n" : ",\n") << event_json(j);
  }
  void item(const harness::CapturedItem& item, const std::string& vector_id) {
    const std::string when = item.wall.empty() ? fmt::format("{:10.3f} ms", item.t_ms)
                                               : fmt::format("{:10.3f} ms {}", item.t_ms, item.wall);
    nlohmann::json base = {{"t_ms", item.t_ms}, {"wall", item.wall}, {"dir", std::string(to_string(item.dir))}};
    if (!vector_id.empty()) base["vector"] = vector_id;
    if (item.ignored) {
      ++ignored;
      all_valid = false;
      if (json) {
        base.update({{"type", "discard"}, {"hex", to_hex(item.chars)}, {"message", item.note}});
        event(base);
      } else {
        out << fmt::format("{} {} ignored: {}{}\n", when, to_string(item.dir), item.note,
                           item.chars.empty() ? "" : "\n  " + to_hex(item.chars));
      }
      return;
    }
    ReceiverOptions ro = item.dir == harness::Direction::kToDevice ? ReceiverOptions::slave_any_address()
                                                                   : ReceiverOptions::master();
    ro.parity = Parity::kNone;  // both formats hold 7-bit characters
    Receiver receiver(ro);
    Collector collected;
    receiver.feed(item.chars, collected);
    receiver.finish(collected);
    for (const auto& e : collected.events) {
      nlohmann::json j = base;
      if (e.is_frame) {
        ++frames;
        const FrameDescription d = describe_frame(e.bytes);
        all_valid &= !d.error.has_value();
        if (json) {
          j.update({{"type", "frame"}, {"hex", to_hex(e.bytes)}, {"summary", d.summary}, {"fields", fields_json(d)},
                    {"error", d.error ? nlohmann::json(d.error->message()) : nlohmann::json()}});
          if (item.seq) j["seq"] = *item.seq;
          if (item.reply_to) j["reply_to"] = *item.reply_to;
          event(j);
        } else {
          out << fmt::format("{} {} {}\n", when, to_string(item.dir), d.summary);
          for (const auto& f : d.fields) out << "  " << f.line() << "\n";
          if (d.error) out << "  error: " << d.error->message() << "\n";
        }
      } else {
        ++ignored;
        all_valid = false;
        const std::string hex = to_hex(ByteView(item.chars).subspan(e.offset, e.length));
        if (json) {
          j.update({{"type", "discard"}, {"hex", hex}, {"reason", std::string(to_string(e.discard->reason))},
                    {"message", e.discard->message()}});
          event(j);
        } else {
          out << fmt::format("{} {} ignored: {}\n  {}\n", when, to_string(item.dir), e.discard->message(), hex);
        }
      }
    }
  }
  // The document's end, after its last item; the exit status.
  int finish(const harness::Capture& c) {
    if (json) {
      out << (events == 0 ? "]" : "\n  ]") << ",\n  \"frames\": " << std::to_string(frames)
          << ",\n  \"ignored_runs\": " << std::to_string(ignored) << ",\n  \"session_events\": "
          << indented(nlohmann::json(c.events), "  ") << ",\n  \"source\": " << json_string(std::string(to_string(c.source)))
          << ",\n  \"valid\": " << (all_valid ? "true" : "false") << "\n}\n";
    } else {
      for (const auto& ev : c.events) out << "event: " << ev << "\n";
      out << fmt::format("{} frame(s), {} ignored run(s)\n", frames, ignored);
    }
    out.flush();
    std::cout.flush();
    return all_valid && frames > 0 ? kExitOk : kExitFailed;
  }
};

// A proxy log or a run JSON held whole (stdin, a run JSON).
int run_decode_capture(const DecodeOptions& o, const std::string& text) {
  std::string error;
  auto capture = harness::read_capture(text, error);
  if (!capture) {
    std::cerr << "sabus decode: " << (o.file.empty() ? std::string("stdin") : o.file) << ": " << error << "\n";
    return kExitUsage;
  }
  Output out;
  CapturePrinter printer(out, o.json);
  printer.start(*capture);
  for (const auto& seg : capture->segments) {
    printer.segment(seg);
    for (const auto& item : seg.items) printer.item(item, seg.id);
  }
  return printer.finish(*capture);
}

// A proxy log file, which a day at the bench makes hundreds of MB long: read
// a record at a time, twice: once to check every line (a bad one is an error
// before anything is printed, as for a log held whole), once to decode.
int run_decode_proxy_log(const DecodeOptions& o) {
  std::string error;
  harness::Capture capture;
  {
    std::ifstream in(o.file, std::ios::binary);
    if (!in || !harness::read_proxy_log(in, capture, [](harness::CapturedItem&&) {}, error)) {
      std::cerr << "sabus decode: " << o.file << ": " << (in ? error : "cannot read it again") << "\n";
      return kExitUsage;
    }
  }
  capture = {};
  Output out;
  CapturePrinter printer(out, o.json);
  std::ifstream in(o.file, std::ios::binary);
  // The device side comes from the header: read it first, then start.
  bool started = false;
  auto start = [&] {
    if (!started) printer.start(capture);
    started = true;
  };
  if (!harness::read_proxy_log(in, capture, [&](harness::CapturedItem&& item) {
        start();
        printer.item(item, "");
      }, error)) {
    out.flush();
    std::cerr << "sabus decode: " << o.file << ": " << error << " (the file changed while it was read)\n";
    return kExitUsage;
  }
  start();
  return printer.finish(capture);
}

int run_decode(const DecodeOptions& o) {
  std::string error;
  std::optional<CaptureInput> capture;
  auto input = read_input(o, error, capture);
  if (capture) return capture->proxy_log_file ? run_decode_proxy_log(o) : run_decode_capture(o, capture->text);
  if (!input) {
    std::cerr << "sabus decode: " << error << "\n";
    return kExitUsage;
  }
  const ByteFile& bytes = *input;

  // --side: which start bytes begin a frame. "auto" guesses from byte 0.
  std::string side = o.side;
  if (side == "auto") {
    const std::uint8_t first = bytes.first.value_or(STX) & 0x7F;  // without a parity bit
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
  const bool even = o.parity == "even" || (o.parity == "auto" && bytes.any_high);
  ro.parity = even ? Parity::kEvenBit7 : Parity::kNone;

  Output out;
  Printer printer(out, bytes, o.json);
  if (o.json) {
    // The JSON's members in json's (sorted) order: the discard counts come
    // before the events, so a first pass counts them.
    Counter counts;
    Window unused;
    feed_all(bytes, ro, counts, unused);
    out << fmt::format("{{\n  \"bytes\": {},\n  \"discarded_bytes\": {},\n  \"discarded_runs\": {},\n  \"events\": [",
                       bytes.size, counts.discarded_bytes, counts.discarded);
    feed_all(bytes, ro, printer, printer.window);
    out << (printer.frames + printer.discarded == 0 ? "]" : "\n  ]");
    out << fmt::format(",\n  \"frames\": {},\n  \"parity\": \"{}\",\n  \"side\": \"{}\",\n  \"valid\": {}\n}}\n", printer.frames,
                       even ? "even" : "none", side, printer.all_valid ? "true" : "false");
  } else {
    feed_all(bytes, ro, printer, printer.window);
    out << fmt::format("{} bytes: {} frame(s), {} discarded run(s) ({} bytes); side {}, parity {}\n", bytes.size,
                       printer.frames, printer.discarded, printer.discarded_bytes, side, even ? "even" : "none");
  }
  out.flush();
  std::cout.flush();
  return printer.all_valid && bytes.size > 0 ? kExitOk : kExitFailed;
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
