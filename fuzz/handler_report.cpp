// Which command handlers a corpus of the whole-controller target reaches:
//   fuzz_handler_report CORPUS_DIR...
// Replays every input as fuzz_controller does (same profile, chunks and
// virtual time), but with the controller's own receiver and Controller::execute
// instead of the Bus, so each executed frame's outcome is known; the bytes
// out are checked against the Bus's for every input, so the two runs are the
// same. A handler counts as reached when a frame got past the front door
// (known code, length, online, implemented, decodable fields) into the
// command's handler: an ACK, or a NAK by one of the handler's own rules.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>

#include "fuzz_support.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/protocol/catalog.hpp"

namespace fs = std::filesystem;
using namespace sabus;
using namespace sabus::harness;

namespace {

struct Frames : ReceiverSink {
  std::vector<Frame> frames;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard&) override {}
};

bool front_door(NakRule r) {
  return r == NakRule::kUnknownCommand || r == NakRule::kWrongLength || r == NakRule::kNotImplemented ||
         r == NakRule::kMalformedData;
}

struct Tally {
  std::map<std::uint8_t, std::map<std::string, std::size_t>> acked;       // code -> form -> count
  std::map<std::uint8_t, std::map<std::string, std::size_t>> handler_nak; // code -> rule -> count
  std::map<std::string, std::size_t> front_door_nak, offline;
  std::size_t inputs = 0, frames = 0, mismatches = 0;
};

#define SABUS_COUNT(id, paragraph, text) +1
constexpr std::size_t kNakRuleCount = 0 SABUS_NAK_RULES(SABUS_COUNT);
#undef SABUS_COUNT

std::string rule_name(NakRule r) { return "§" + std::string(paragraph(r)) + " " + std::string(description(r)); }

void replay(const std::vector<std::uint8_t>& data, Tally& t) {
  fuzz::ControllerInput in;
  if (!fuzz::parse_controller_input(data.data(), data.size(), in)) return;
  ++t.inputs;
  VirtualClock clock, bus_clock;
  Controller c(*in.profile, clock);
  Receiver rx(receiver_options(*in.profile, {}, Parity::kEvenBit7));
  Bus bus({*in.profile}, bus_clock);
  Frames sink;
  Bytes out, bus_out;
  for (const auto chunk : in.chunks) {
    rx.feed(chunk, sink);
    for (const Frame& f : sink.frames) {
      ++t.frames;
      const Outcome o = c.execute(f);
      if (o.reply) {
        const Bytes w = add_even_parity(*o.reply);
        out.insert(out.end(), w.begin(), w.end());
      }
      const std::uint8_t code = f.command;
      if (o.nak) {
        if (front_door(*o.nak)) ++t.front_door_nak[rule_name(*o.nak)];
        else ++t.handler_nak[code][rule_name(*o.nak)];
      } else if (o.reply && o.reply->size() == kOfflineReplyLength && (*o.reply)[3] == kOfflineMarker) {
        ++t.offline[describe_byte(code)];
      } else if (o.reply) {
        auto r = decode_request(f);
        ++t.acked[code][r ? std::string(form_of(r.value())) : std::string("?")];
      }
    }
    sink.frames.clear();
    bus.receive(chunk, bus_out);
    clock.advance(in.step);
    bus_clock.advance(in.step);
    c.update();
    bus.tick();
    (void)bus.take_log();
  }
  if (out != bus_out) ++t.mismatches;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: fuzz_handler_report CORPUS_DIR...\n");
    return 2;
  }
  Tally t;
  for (int i = 1; i < argc; ++i) {
    if (!fs::is_directory(argv[i])) continue;
    for (const auto& e : fs::recursive_directory_iterator(argv[i])) {
      if (!e.is_regular_file()) continue;
      std::ifstream in(e.path(), std::ios::binary);
      std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      replay(bytes, t);
    }
  }
  std::printf("inputs %zu, frames executed %zu, replies different from the Bus's: %zu\n", t.inputs, t.frames,
              t.mismatches);
  std::size_t reached = 0;
  std::printf("command handlers (catalog order): reached = ACK, or NAK by the handler's own rule\n");
  for (const auto& info : catalog()) {
    const auto a = t.acked.find(info.code);
    const auto n = t.handler_nak.find(info.code);
    const bool hit = a != t.acked.end() || n != t.handler_nak.end();
    reached += hit;
    std::string forms;
    if (a != t.acked.end())
      for (const auto& [form, count] : a->second)
        forms += (forms.empty() ? "" : ", ") + (form.empty() ? std::string("-") : form) + " x" + std::to_string(count);
    std::string naks;
    if (n != t.handler_nak.end()) naks = std::to_string(n->second.size()) + " handler NAK rule(s)";
    std::printf("  %-3s %02Xh %-28s ACK forms: %-40s %s\n", hit ? "yes" : "NO", info.code,
                std::string(info.name).c_str(), forms.empty() ? "none" : forms.c_str(), naks.c_str());
    // Forms of the catalog that no ACK reached.
    if (info.forms.size() > 1)
      for (const auto& f : info.forms)
        if (a == t.acked.end() || !a->second.count(std::string(f.id)))
          std::printf("        form %s not ACKed\n", std::string(f.id).c_str());
  }
  std::set<std::string> rules;
  for (const auto& [code, m] : t.handler_nak)
    for (const auto& [r, count] : m) rules.insert(r);
  for (const auto& [r, count] : t.front_door_nak) rules.insert(r);
  std::printf("NAK rules fired: %zu of %zu; not fired:\n", rules.size(), kNakRuleCount);
  for (std::size_t i = 0; i < kNakRuleCount; ++i) {
    const std::string r = rule_name(static_cast<NakRule>(i));
    if (!rules.count(r)) std::printf("  %s\n", r.c_str());
  }
  std::printf("offline replies: %zu command code(s)\n", t.offline.size());
  std::printf("handlers reached: %zu of %zu commands\n", reached, catalog().size());
  return t.mismatches == 0 ? 0 : 1;
}
