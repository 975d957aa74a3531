// A live-fuzzer finding as a conformance vector (vectors/README.md) that
// `sabus run --vectors FILE` replays and `sabus vectors lint` accepts.
#include <yaml-cpp/yaml.h>

#include "sabus/harness/controller.hpp"
#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/harness/yaml_writer.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus::harness::live_fuzz {
namespace {

using namespace std::chrono_literals;

using yaml_writer::printable_text;

// Data (the paragraph, the quote, a raw template): double-quoted, exactly.
YAML::Emitter& quoted(YAML::Emitter& e, std::string_view s) { return e << YAML::DoubleQuoted << std::string(s); }

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
                  {}, w.what, from == 0 ? w.pause : 0ms};
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

// What the reference controller (this profile, no faults) answers a step:
// the reply's form, the reply itself and the rule of a NAK.
struct Expectation {
  std::string reply;  // ack, nak, offline, silence, any
  std::optional<Frame> frame;
  std::string rule;
};

// What the reference controller (this profile, no faults) answers each step.
std::vector<Expectation> reference_expectations(const std::vector<FuzzFrame>& steps, const Profile& profile) {
  auto t = make_in_process_transport({profile});
  std::vector<Expectation> out;
  for (const FuzzFrame& s : steps) {
    if (s.pause.count() > 0) t->pause(s.pause);
    t->send(s.chars, s.wrong_parity);
    ReceiverOptions ro = ReceiverOptions::master();
    Receiver rx(ro);
    ReplySink sink;
    std::uint8_t buf[512];
    for (std::size_t n; (n = t->receive(buf, 1ms)) > 0;) rx.feed(ByteView(buf, n), sink);
    rx.finish(sink);
    const auto rules = t->take_nak_rules();
    Expectation e;
    if (sink.garbage || sink.frames.size() > 1) e.reply = "any";
    else if (sink.frames.empty()) e.reply = "silence";
    else if (sink.frames[0].kind == FrameKind::kNak) e.reply = "nak";
    else if (is_offline_reply(sink.frames[0])) e.reply = "offline";
    else e.reply = "ack";
    if (sink.frames.size() == 1) e.frame = sink.frames[0];
    if (e.reply == "nak" && rules && rules->size() == 1) e.rule = rules->front();
    out.push_back(std::move(e));
  }
  return out;
}

// The lockstep oracle's kinds (Lockstep): the vector checks what the model
// knows, the rule of a NAK and the value of the field that differed.
bool from_the_model(FindingKind kind) {
  return kind == FindingKind::kNakRule || kind == FindingKind::kValue || kind == FindingKind::kEffect;
}

// The reference's text of `field` in an ACK reply (matcher_text), or nullopt.
std::optional<std::string> reference_field(const Expectation& e, std::string_view field) {
  if (e.reply != "ack" || !e.frame) return std::nullopt;
  for (const FieldDescription& fd : describe_frame(encode_frame(*e.frame)).fields)
    if (fd.name == field) return matcher_text(fd);
  return std::nullopt;
}

// A position is checked by the vectors' motion matchers, never a literal
// (the linter's rule): the finding's field is not written for one.
bool is_position_field(std::string_view field) {
  return field == "azimuth" || field == "elevation" || field == "polarization" || field == "position" ||
         field == "azimuth count" || field == "elevation count" || field == "az hundredths" || field == "el hundredths";
}

// The last of `steps` that fit in one vector's step list (kMaxSteps,
// vector_loader.hpp; a write that waited takes a wait_ms step too).
std::vector<FuzzFrame> last_that_fit(std::vector<FuzzFrame> steps) {
  std::size_t used = 0, first = steps.size();
  while (first > 0 && used + (steps[first - 1].pause.count() > 0 ? 2 : 1) <= kMaxSteps)
    used += steps[--first].pause.count() > 0 ? 2 : 1;
  steps.erase(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(first));
  return steps;
}

}  // namespace

std::string finding_vector_yaml(const Finding& finding, const Profile& profile, const FindingContext& context) {
  const std::vector<FuzzFrame>& writes = finding.reproducer.empty() ? finding.history : finding.reproducer;
  // Not reproduced: the writes just before the finding, as many as a vector
  // holds (its state before them is the device's, not restored).
  std::vector<FuzzFrame> steps = one_reply_each(writes, profile);
  if (!finding.reproduced) steps = last_that_fit(std::move(steps));
  const std::vector<Expectation> expect = reference_expectations(steps, profile);
  // The step whose reply shows a value or effect finding: the last ACK that
  // has the field.
  std::optional<std::size_t> field_step;
  if (from_the_model(finding.kind) && !finding.field.empty() && !is_position_field(finding.field))
    for (std::size_t i = steps.size(); i-- > 0;)
      if (reference_field(expect[i], finding.field)) {
        field_step = i;
        break;
      }
  bool parity = false, motion = false, destructive = false;
  for (const FuzzFrame& s : steps) {
    parity |= !s.wrong_parity.empty();
    motion |= !is_safe_to_send(s.chars, false, true);
    destructive |= !is_safe_to_send(s.chars, true, false);
  }
  const std::string kind(to_string(finding.kind));
  // The finding's message and the command line hold what a device said and
  // what a person typed: printable_text, in the comments and the vector's
  // comment alike.
  YAML::Emitter y;
  y << YAML::Comment(printable_text(
      "A finding of sabus fuzz (" + kind + "), seed " + std::to_string(context.seed) + ":\n" + "  " + context.command_line +
      "\n" + finding.message + "\n" +
      (finding.reproduced ? "Minimized by delta debugging from " + std::to_string(finding.history.size()) + " writes"
                          : "NOT reproduced on replay; the last " + std::to_string(steps.size()) + " writes are kept") +
      ". Schema: vectors/README.md."));
  y << YAML::BeginMap;
  y << YAML::Key << "paragraph" << YAML::Value << "framing";
  y << YAML::Key << "title" << YAML::Value << YAML::DoubleQuoted
    << "sabus fuzz finding " + std::to_string(context.number) + ": " + kind;
  y << YAML::Key << "vectors" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  y << YAML::Key << "id" << YAML::Value
    << "framing-fuzz-" + std::to_string(context.seed) + "-" + std::to_string(context.number) + "-" + kind;
  y << YAML::Key << "comment" << YAML::Value << YAML::DoubleQuoted
    << printable_text(finding.message + " (§" + std::string(paragraph_of(finding.kind)) + "; found by sabus fuzz, seed " +
                      std::to_string(context.seed) + "; expectations from the reference controller)");
  y << YAML::Key << "spec" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "paragraph" << YAML::Value;
  quoted(y, paragraph_of(finding.kind));
  y << YAML::Key << "quote" << YAML::Value;
  quoted(y, quote_of(finding.kind));
  y << YAML::EndMap;
  y << YAML::Key << "level" << YAML::Value << "must";
  if (motion || destructive || parity) {
    y << YAML::Key << "tags" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    if (motion) y << "motion";
    if (destructive) y << "destructive";
    if (parity) y << "parity";
    y << YAML::EndSeq;
  }
  y << YAML::Key << "steps" << YAML::Value << YAML::BeginSeq;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const FuzzFrame& s = steps[i];
    if (s.pause.count() > 0)  // the time the write waited for (a move running)
      y << YAML::BeginMap << YAML::Key << "wait_ms" << YAML::Value << s.pause.count() << YAML::EndMap;
    y << YAML::BeginMap;
    y << YAML::Key << "send" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "raw" << YAML::Value;
    quoted(y, to_hex(s.chars)) << YAML::EndMap << YAML::Comment(printable_text(s.what));
    if (!s.wrong_parity.empty()) {
      y << YAML::Key << "modify" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "parity_flip"
        << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (std::size_t k : s.wrong_parity) y << k;
      y << YAML::EndSeq << YAML::EndMap;
    }
    if (needs_length_mismatch(s.chars)) y << YAML::Key << "length_mismatch" << YAML::Value << true;
    const Expectation& e = expect[i];
    y << YAML::Key << "expect" << YAML::Value;
    if (field_step == i) {
      y << YAML::Flow << YAML::BeginMap << YAML::Key << "reply" << YAML::Value << e.reply << YAML::Key << "fields"
        << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << finding.field << YAML::Value;
      quoted(y, *reference_field(e, finding.field)) << YAML::EndMap << YAML::EndMap;
    } else if (from_the_model(finding.kind) && !e.rule.empty()) {
      y << YAML::Flow << YAML::BeginMap << YAML::Key << "reply" << YAML::Value << e.reply << YAML::Key << "rule"
        << YAML::Value << e.rule << YAML::EndMap;
    } else {
      y << e.reply;
    }
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap << YAML::EndSeq << YAML::EndMap;
  return yaml_writer::document(y);
}

}  // namespace sabus::harness::live_fuzz
