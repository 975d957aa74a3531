// A live-fuzzer finding as a conformance vector (vectors/README.md) that
// `sabus run --vectors FILE` replays and `sabus vectors lint` accepts.
#include <sstream>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness::live_fuzz {
namespace {

using namespace std::chrono_literals;

std::string yaml_quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

struct FrameEnds : ReceiverSink {
  std::vector<std::uint64_t> cuts;  // stream offsets of byte 0 of each accepted frame and one past it
  void on_frame(const FrameView& f) override {
    cuts.push_back(f.offset);
    cuts.push_back(f.offset + f.bytes.size());
  }
  void on_discard(const Discard&) override {}
};

// The writes cut before and after each frame the reference receiver accepts,
// so that every step of the vector draws at most one reply (the runner's
// rule) and bytes the device must ignore are a step of their own. The device
// sees the same byte stream.
std::vector<FuzzFrame> one_reply_each(const std::vector<FuzzFrame>& writes, const Profile& profile) {
  Receiver rx(receiver_options(profile, FaultSet{}, Parity::kEvenBit7));
  std::vector<FuzzFrame> out;
  for (const FuzzFrame& w : writes) {
    const std::uint64_t base = rx.offset();
    FrameEnds ends;
    rx.feed(with_software_parity(w.chars, w.wrong_parity), ends);
    std::size_t from = 0;
    auto cut = [&](std::size_t to) {
      if (to <= from) return;
      FuzzFrame s{Bytes(w.chars.begin() + static_cast<std::ptrdiff_t>(from), w.chars.begin() + static_cast<std::ptrdiff_t>(to)),
                  {}, w.what};
      for (std::size_t i : w.wrong_parity)
        if (i >= from && i < to) s.wrong_parity.push_back(i - from);
      out.push_back(std::move(s));
      from = to;
    };
    for (std::uint64_t e : ends.cuts)
      if (e >= base) cut(static_cast<std::size_t>(e - base));
    cut(w.chars.size());
  }
  return out;
}

struct ReplySink : ReceiverSink {
  std::vector<Frame> frames;
  bool garbage = false;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard&) override { garbage = true; }
};

// What the reference controller (this profile, no faults) answers each step.
std::vector<std::string> reference_expectations(const std::vector<FuzzFrame>& steps, const Profile& profile) {
  auto t = make_in_process_transport({profile});
  std::vector<std::string> out;
  for (const FuzzFrame& s : steps) {
    t->send(s.chars, s.wrong_parity);
    ReceiverOptions ro = ReceiverOptions::master();
    Receiver rx(ro);
    ReplySink sink;
    std::uint8_t buf[512];
    for (std::size_t n; (n = t->receive(buf, 1ms)) > 0;) rx.feed(ByteView(buf, n), sink);
    rx.finish(sink);
    if (sink.garbage || sink.frames.size() > 1) out.push_back("any");
    else if (sink.frames.empty()) out.push_back("silence");
    else if (sink.frames[0].kind == FrameKind::kNak) out.push_back("nak");
    else if (is_offline_reply(sink.frames[0])) out.push_back("offline");
    else out.push_back("ack");
  }
  return out;
}

}  // namespace

std::string finding_vector_yaml(const Finding& finding, const Profile& profile, const FindingContext& context) {
  const std::vector<FuzzFrame>& writes = finding.reproducer.empty() ? finding.history : finding.reproducer;
  const std::vector<FuzzFrame> steps = one_reply_each(writes, profile);
  const std::vector<std::string> expect = reference_expectations(steps, profile);
  bool parity = false, motion = false, destructive = false;
  for (const FuzzFrame& s : steps) {
    parity |= !s.wrong_parity.empty();
    motion |= !is_safe_to_send(s.chars, false, true);
    destructive |= !is_safe_to_send(s.chars, true, false);
  }
  const std::string kind(to_string(finding.kind));
  std::ostringstream y;
  y << "# A finding of sabus fuzz (" << kind << "), seed " << context.seed << ":\n";
  y << "#   " << context.command_line << "\n";
  y << "# " << finding.message << "\n";
  y << "# " << (finding.reproduced ? "Minimized by delta debugging from " : "NOT reproduced on replay; the last ")
    << finding.history.size() << " writes" << (finding.reproduced ? "" : " are kept") << ". Schema: vectors/README.md.\n";
  y << "paragraph: framing\n";
  y << "title: " << yaml_quoted("sabus fuzz finding " + std::to_string(context.number) + ": " + kind) << "\n";
  y << "vectors:\n";
  y << "  - id: framing-fuzz-" << context.seed << "-" << context.number << "-" << kind << "\n";
  y << "    comment: " << yaml_quoted(finding.message + " (§" + std::string(paragraph_of(finding.kind)) + "; found by sabus fuzz, seed " +
                                      std::to_string(context.seed) + "; expectations from the reference controller)")
    << "\n";
  y << "    spec:\n";
  y << "      paragraph: " << yaml_quoted(paragraph_of(finding.kind)) << "\n";
  y << "      quote: " << yaml_quoted(quote_of(finding.kind)) << "\n";
  y << "    level: must\n";
  std::vector<std::string> tags;
  if (motion) tags.push_back("motion");
  if (destructive) tags.push_back("destructive");
  if (parity) tags.push_back("parity");
  if (!tags.empty()) {
    y << "    tags: [";
    for (std::size_t i = 0; i < tags.size(); ++i) y << (i ? ", " : "") << tags[i];
    y << "]\n";
  }
  y << "    steps:\n";
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const FuzzFrame& s = steps[i];
    y << "      - send: {raw: " << yaml_quoted(to_hex(s.chars)) << "}   # " << s.what << "\n";
    if (!s.wrong_parity.empty()) {
      y << "        modify: {parity_flip: [";
      for (std::size_t k = 0; k < s.wrong_parity.size(); ++k) y << (k ? ", " : "") << s.wrong_parity[k];
      y << "]}\n";
    }
    if (needs_length_mismatch(s.chars)) y << "        length_mismatch: true\n";
    y << "        expect: " << expect[i] << "\n";
  }
  return y.str();
}

}  // namespace sabus::harness::live_fuzz
