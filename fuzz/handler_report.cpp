// Which command handlers a corpus of the whole-controller target reaches:
//   fuzz_handler_report [--missing] [--max-len N] CORPUS_DIR...
// Replays every input as fuzz_controller does (same profile, chunks and
// virtual time), but with the controller's own receiver and Controller::execute
// instead of the Bus, so each executed frame's outcome is known; the bytes
// out are checked against the Bus's for every input, so the two runs are the
// same. A handler counts as reached when a frame got past the front door
// (known code, length, online, implemented, decodable fields) into the
// command's handler: an ACK, or a NAK by one of the handler's own rules.
// With --missing it prints one line, what the corpus lacks of every command
// ACKed and every NAK rule fired ("missing: none" when nothing), and exits 3
// when something is missing: tools/fuzz-perf.sh polls a running fuzzer's
// corpus with it. The corpus may change while it is read (libFuzzer adds and
// replaces files): a file that vanished is skipped. With --max-len, every
// input is cut to its first N bytes, as libFuzzer runs the files of a corpus
// with -max_len=N (a seed longer than that is never run whole).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <system_error>
#include <vector>

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
  fuzz::parse_controller_input(data.data(), data.size(), in);
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

// What the corpus lacks of the goal: every command ACKed, every NAK rule fired.
std::vector<std::string> missing(const Tally& t, const std::set<std::string>& rules) {
  std::vector<std::string> m;
  for (const auto& info : catalog())
    if (!t.acked.count(info.code)) {
      char code[8];
      std::snprintf(code, sizeof code, "%02Xh", info.code);
      m.push_back(std::string(code) + " " + std::string(info.name) + " ACK");
    }
  for (std::size_t i = 0; i < kNakRuleCount; ++i) {
    const std::string r = rule_name(static_cast<NakRule>(i));
    if (!rules.count(r)) m.push_back("NAK " + r);
  }
  return m;
}

// Every file under the directories, read as it is now; a file that vanished
// or cannot be read is skipped.
void replay_corpus(const std::vector<std::string>& dirs, std::size_t max_len, Tally& t) {
  for (const auto& dir : dirs) {
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      if (!it->is_regular_file(ec) || ec) continue;
      std::ifstream in(it->path(), std::ios::binary);
      if (!in) continue;
      std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (bytes.size() > max_len) bytes.resize(max_len);
      replay(bytes, t);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  bool only_missing = false;
  std::size_t max_len = SIZE_MAX;
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--missing") {
      only_missing = true;
    } else if (arg == "--max-len" && i + 1 < argc) {
      char* end = nullptr;
      const unsigned long long n = std::strtoull(argv[++i], &end, 10);
      if (*argv[i] == '\0' || *end != '\0' || n == 0) {
        std::fprintf(stderr, "fuzz_handler_report: --max-len needs a positive number of bytes, got '%s'\n", argv[i]);
        return 2;
      }
      max_len = static_cast<std::size_t>(n);
    } else {
      dirs.push_back(arg);
    }
  }
  if (dirs.empty()) {
    std::fprintf(stderr, "usage: fuzz_handler_report [--missing] [--max-len N] CORPUS_DIR...\n");
    return 2;
  }
  for (const auto& dir : dirs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
      std::fprintf(stderr, "fuzz_handler_report: %s: not a directory\n", dir.c_str());
      return 2;
    }
  }
  Tally t;
  replay_corpus(dirs, max_len, t);
  std::set<std::string> rules;
  for (const auto& [code, m] : t.handler_nak)
    for (const auto& [r, count] : m) rules.insert(r);
  for (const auto& [r, count] : t.front_door_nak) rules.insert(r);
  if (only_missing) {
    const auto m = missing(t, rules);
    std::string line;
    for (const auto& item : m) line += (line.empty() ? "" : ", ") + item;
    std::printf("missing: %s\n", m.empty() ? "none" : line.c_str());
    return t.mismatches != 0 ? 1 : m.empty() ? 0 : 3;
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
  std::printf("NAK rules fired: %zu of %zu; not fired:\n", rules.size(), kNakRuleCount);
  for (std::size_t i = 0; i < kNakRuleCount; ++i) {
    const std::string r = rule_name(static_cast<NakRule>(i));
    if (!rules.count(r)) std::printf("  %s\n", r.c_str());
  }
  std::printf("offline replies: %zu command code(s)\n", t.offline.size());
  std::printf("handlers reached: %zu of %zu commands\n", reached, catalog().size());
  return t.mismatches == 0 ? 0 : 1;
}
