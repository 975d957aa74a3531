// Fuzz target: the record of a run whose device answers anything. A scripted
// transport answers each command the runner sends for a short selection of
// the suite's vectors (record_support.hpp) with bytes from the input:
// silence, a reply cut short, a bad LRC, wrong parity, another address, a NAK
// without its command, garbage, many frames, 8-bit bytes; or the port is
// lost. The run is recorded as `sabus run --json --junit --html --md`
// records it (the journal line by line, the run JSON from the journal, the
// reports from the document), and then read back as `sabus report` and a CI
// server read it.
// Oracle: checks::run_record_problems (reports/checks.hpp) finds nothing:
//  - the journal: every line JSON, each record valid against
//    reports/run.schema.json; the run JSON made from it valid too;
//  - JUnit valid against reports/junit.xsd; the HTML parsed by an HTML5
//    parser without error, with no markup but the writer's, each string from
//    the device shown as text; the Markdown parsed with no raw HTML, its
//    counts and failures the document's;
//  - `sabus report` reads the run JSON back and rebuilds the same JUnit, HTML
//    and Markdown, byte for byte, and the journal read back (a killed run's
//    record) gives the same run JSON;
//  - the Markdown diff of the run against the same run on the reference
//    controller (`sabus diff --md`) parses, each changed vector a row.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <sstream>
#include <string>

#include "record_support.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transport.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/protocol/lrc.hpp"
#include "sabus/reports/checks.hpp"
#include "sabus/reports/document.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace {

using namespace sabus;
namespace checks = reports::checks;

// A device on a virtual clock that answers the n-th command with the n-th
// reply of the script, and then nothing.
class ScriptedTransport final : public harness::Transport {
 public:
  explicit ScriptedTransport(fuzz::record::Script script) : script_(std::move(script)) {}
  void send(ByteView, std::span<const std::size_t>) override {
    if (script_.lost_at && next_ >= *script_.lost_at) throw harness::TransportLost("the scripted device is lost");
    if (next_ < script_.replies.size()) {
      const Bytes& reply = script_.replies[next_++];
      pending_.insert(pending_.end(), reply.begin(), reply.end());
    }
  }
  std::size_t receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override {
    if (pending_.empty()) {
      clock_.advance(timeout);
      return 0;
    }
    std::size_t n = 0;
    for (; n < buf.size() && !pending_.empty(); ++n) {
      buf[n] = uart(pending_.front());
      pending_.pop_front();
    }
    return n;
  }
  void pause(std::chrono::milliseconds d) override { clock_.advance(d); }
  harness::TimePoint now() const override { return clock_.now(); }
  bool in_process() const override { return true; }  // its clock is virtual
  bool can_send_parity_errors() const override { return !script_.true_7e1; }
  bool parity_in_bit7() const override { return !script_.true_7e1; }
  int baud() const override { return 0; }
  std::string describe() const override { return "scripted replies (fuzz_record)"; }

 private:
  // A true 7E1 port's UART: the 7-bit character, bit 7 set when its parity
  // was wrong (transport.hpp); otherwise the wire byte as it came.
  std::uint8_t uart(std::uint8_t wire) const {
    if (!script_.true_7e1) return wire;
    return static_cast<std::uint8_t>((wire & 0x7F) | (has_even_parity(wire) ? 0 : 0x80));
  }
  fuzz::record::Script script_;
  std::size_t next_ = 0;
  std::deque<std::uint8_t> pending_;
  harness::VirtualClock clock_;
};

// The run recorded as `sabus run` records it (tools/sabus/run.cpp).
reports::MemoryRecord record_run(harness::Transport& transport) {
  const harness::Profile& profile = fuzz::record::profile();
  reports::MemoryRecord record;
  reports::RunDocument& doc = record.doc;
  doc.generator = "sabus fuzz_record";
  doc.started_at = "2026-01-01T00:00:00Z";
  doc.device = transport.describe();
  doc.profile = profile.name;
  doc.address = profile.address;
  doc.options = {{"allow_motion", false}, {"allow_destructive", false}, {"level", "informative"}, {"seed", 0}, {"repeat", 1}};
  doc.planned = fuzz::record::vectors().size();
  doc.identity = reports::query_identity(transport, profile.address);
  record.start();
  harness::RunOptions options = fuzz::record::run_options();
  options.on_result = record.on_result(1.0);
  record.end(harness::Runner(transport, profile, options).run(fuzz::record::vectors()), "2026-01-01T00:01:00Z");
  return record;
}

// The same run against the reference controller: what each run is diffed
// against (`sabus diff CLEAN RUN --md`), read back from its journal.
const reports::RunDocument& clean_run() {
  static const reports::RunDocument clean = [] {
    auto device = harness::make_in_process_transport(harness::bus_of(fuzz::record::profile()));
    const reports::MemoryRecord record = record_run(*device);
    std::istringstream journal(record.journal);
    reports::JournalNotes notes;
    std::string error;
    auto doc = reports::read_journal(journal, "clean run", notes, error);
    if (!doc) throw std::logic_error("fuzz_record: the clean run's journal does not read: " + error);
    return *doc;
  }();
  return clean;
}

[[noreturn]] void fail(const std::string& why, const std::string& detail) {
  std::fprintf(stderr, "fuzz_record: %s\n%s\n", why.c_str(), detail.substr(0, 4000).c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ScriptedTransport transport(fuzz::record::parse_script(data, size));
  const reports::MemoryRecord record = record_run(transport);
  const checks::Problems problems = checks::run_record_problems(record.doc, record.journal, &clean_run());
  if (!problems.empty()) {
    std::string all;
    for (const auto& p : problems) all += p + "\n";
    fail("the record of the run does not read back:\n" + all, record.journal);
  }
  return 0;
}
