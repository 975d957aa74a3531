// `sabus fuzz`: the live fuzzer against the in-process reference controller
// (default), a serial port or a TCP serial server. The engine is
// sabus::harness::live_fuzz (harness/live_fuzz/include/sabus/harness/live_fuzz.hpp).
#include <fmt/format.h>

#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <random>
#include <mutex>
#include <set>
#include <thread>

#include "commands.hpp"
#include "device.hpp"
#include "new_file.hpp"
#include "sabus/harness/line.hpp"
#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;
using namespace sabus::harness::live_fuzz;
namespace fs = std::filesystem;

// The signal that stopped the session (0: none).
std::atomic<int> g_stop_signal{0};
extern "C" void on_fuzz_stop_signal(int signal) { g_stop_signal = signal; }

struct FuzzCliOptions {
  DeviceOptions device;
  std::optional<std::uint64_t> seed;
  std::size_t max_frames = 0, liveness_every = 50, max_findings = 8;
  double max_time = 0;
  long pace_ms = -1;
  std::string findings = "fuzz-findings";
  bool allow_motion = false, allow_destructive = false;
  bool fresh_device = false;
};

// Progress while the fuzzer runs, whatever it is doing (a write, a silence
// window, minimizing a finding): a thread prints the latest count at least
// every 10 s, or on a terminal one line rewritten every second. Every other
// line goes through line(), so none is cut by the progress line.
class FuzzProgress {
 public:
  explicit FuzzProgress(bool enabled) : tty_(::isatty(STDOUT_FILENO) == 1), t0_(std::chrono::steady_clock::now()) {
    if (enabled) thread_ = std::thread([this] { loop(); });
  }
  ~FuzzProgress() {
    {
      std::lock_guard lock(m_);
      stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (tty_ && drawn_) std::cout << "\r\033[K" << std::flush;
  }
  void update(std::size_t writes, std::size_t findings, std::string doing = {}) {
    std::lock_guard lock(m_);
    writes_ = writes;
    findings_ = findings;
    doing_ = std::move(doing);
  }
  void line(const std::string& text) {
    std::lock_guard lock(m_);
    if (tty_ && drawn_) std::cout << "\r\033[K";
    drawn_ = false;
    std::cout << text << std::endl;
  }

 private:
  void loop() {
    const auto every = tty_ ? std::chrono::seconds(1) : std::chrono::seconds(10);
    std::unique_lock lock(m_);
    while (!cv_.wait_for(lock, every, [this] { return stop_; })) {
      const auto elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0_);
      const std::string text = fmt::format("fuzz: {} writes, {} finding(s), {} elapsed{}", writes_, findings_,
                                           reports::clock_text(elapsed), doing_.empty() ? "" : ", " + doing_);
      if (tty_) std::cout << "\r\033[K" << text << std::flush;
      else std::cout << text << std::endl;
      drawn_ = tty_;
    }
  }
  const bool tty_;
  const std::chrono::steady_clock::time_point t0_;
  std::mutex m_;
  std::condition_variable cv_;
  bool stop_ = false, drawn_ = false;
  std::size_t writes_ = 0, findings_ = 0;
  std::string doing_;
  std::thread thread_;
};

// How the run can be repeated: the options that change what is sent.
std::string command_line(const FuzzCliOptions& o, std::uint64_t seed) {
  std::string s = "sabus fuzz";
  if (!o.device.port.empty()) s += " --port " + o.device.port;
  else if (!o.device.tcp.empty()) s += " --tcp " + o.device.tcp;
  else s += " --sim";
  for (const auto& f : o.device.faults) s += " --fault " + f;
  if (!o.device.profile.empty()) s += " --profile " + o.device.profile;
  if (!o.device.address.empty()) s += " --address " + o.device.address;
  s += " --seed " + std::to_string(seed);
  if (o.max_frames) s += " --max-frames " + std::to_string(o.max_frames);
  if (o.liveness_every != 50) s += " --liveness-every " + std::to_string(o.liveness_every);
  if (o.allow_motion) s += " --allow-motion";
  if (o.allow_destructive) s += " --allow-destructive";
  if (o.fresh_device) s += " --fresh-device";
  return s;
}

// The totals after the run: writes, replies, traffic, findings.
void print_totals(const Session& session, const Transport& transport, double wall, std::uint64_t seed, bool pty,
                  const std::string& aborted, const std::vector<Finding>& findings,
                  const std::vector<std::string>& written) {
  const Counts& c = session.counts();
  const double wire_s = transport.baud() > 0 ? (c.bytes_sent + c.bytes_received) * 10.0 / transport.baud() : 0.0;
  std::cout << fmt::format("{} writes ({} liveness probes) in {:.1f} s, seed {}\n", c.writes, c.probes, wall, seed);
  std::cout << fmt::format("replies: {} ack, {} nak, {} offline, {} silence, {} garbage; {} refused by the safety gate\n",
                           c.ack, c.nak, c.offline, c.silence, c.garbage, c.refused);
  std::cout << fmt::format("traffic: bytes_sent={} bytes_received={} wall_s={:.3f} baud={}", c.bytes_sent, c.bytes_received,
                           wall, transport.baud());
  if (transport.baud() > 0 && pty) std::cout << fmt::format(" wire_s={:.3f} (at that baud rate; a pseudo-terminal has none, so no line_busy)", wire_s);
  else if (transport.baud() > 0) std::cout << fmt::format(" line_busy={:.1f}%", 100.0 * wire_s / wall);
  std::cout << "\n";
  if (const Lockstep* l = session.lockstep()) {
    // What the lockstep oracle reached: the rules the device NAKed by, of
    // all the reference controller knows, and the reply fields compared.
    const LockstepCoverage& cov = l->coverage();
    std::string rules;
    for (const std::string& r : cov.rules_fired) rules += (rules.empty() ? "" : ", ") + r;
    std::cout << fmt::format("lockstep: {} of {} NAK rules fired on the device{}; {} of {} reply fields compared; {} resync(s)\n",
                             cov.rules_fired.size(), all_nak_rules().size(), rules.empty() ? "" : " (" + rules + ")",
                             cov.fields_compared.size(), comparable_reply_fields(), cov.resyncs);
  }
  if (const Lockstep* l = session.lockstep()) {
    // Differences the other side of an open point of the spec explains
    // (readings.hpp): a legal controller's, noted with the ERRATA entry and
    // what the model would have said, never a finding.
    std::size_t count = 0;
    for (const auto& n : l->notes()) count += n.count;
    std::cout << fmt::format("{} note(s) on the spec's open points{}\n", count, count ? ":" : "");
    for (const auto& n : l->notes())
      std::cout << fmt::format("  {} {} x{}, e.g. {}\n", n.errata, to_string(n.side), n.count, n.example);
  }
  if (!aborted.empty()) std::cout << "ABORTED: " << aborted << "\n";
  std::cout << fmt::format("{} finding(s)\n", findings.size());
  for (std::size_t i = 0; i < findings.size(); ++i)
    std::cout << fmt::format("  {} {}: {}\n", written[i], to_string(findings[i].kind), findings[i].message);
}

int run_fuzz(const FuzzCliOptions& o) {
  OpenedDevice device = open_device("fuzz", o.device);
  if (device.exit_code != kExitOk) return device.exit_code;
  Transport& transport = *device.transport;
  const Profile& profile = device.profile;
  const std::uint64_t seed = o.seed ? *o.seed : std::random_device{}();

  SessionOptions so;
  so.allow_motion = o.allow_motion;
  so.allow_destructive = o.allow_destructive;
  so.liveness_every = o.liveness_every;
  // §4: no more than one request a second on a line (READING-NOTES 3, E-3).
  so.pace = std::chrono::milliseconds(o.pace_ms >= 0 ? o.pace_ms : (transport.in_process() ? 0 : 1000));
  Session session(transport, profile, so);
  GeneratorOptions go{profile.address, o.allow_motion, o.allow_destructive, transport.can_send_parity_errors(), {},
                      profile.bus_peers, &profile};
  for (const StoredSatellite& s : profile.store) go.names.push_back(s.name);
  for (const PresetSatellite& p : profile.presets) go.names.push_back(p.data.name);
  Generator generator(go, seed);
  if (const Lockstep* l = session.lockstep()) {
    generator.set_rules_fired(&l->coverage().rules_fired);
    generator.set_model([l] { return Generator::ModelView{&l->model(), l->now(), l->device_led()}; });
  }
  DeviceFactory fresh;
  if (transport.in_process()) {
    const FaultSet faults = device.faults;
    fresh = [controller = device.controller_profile, faults]() -> std::unique_ptr<Transport> {
      return make_in_process_transport({controller}, faults);
    };
  }

  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::cout << fmt::format("sabus fuzz: {}, seed {}\n", transport.describe(), seed) << std::flush;
  // A pseudo-terminal moves bytes at once whatever baud rate it is set to:
  // their wire time says nothing of how busy it was.
  const bool pty = !o.device.port.empty() && is_pseudo_terminal(o.device.port);
  std::optional<live_fuzz::Verdict> first;
  try {
    first = session.probe();
    if (first && first->kind == FindingKind::kDead) {
      std::cerr << "sabus fuzz: the device does not answer: " << first->message << "\n";
      return 3;
    }
  } catch (const TransportLost& e) {
    std::cerr << "sabus fuzz: the device is lost: " << e.what() << "\n";
    return 3;
  }
  std::signal(SIGINT, on_fuzz_stop_signal);
  std::signal(SIGTERM, on_fuzz_stop_signal);

  std::vector<Finding> findings;
  std::vector<std::string> written;
  std::set<FindingKind> seen_kinds;
  std::vector<FuzzFrame> history;
  constexpr std::size_t kHistory = 512;
  std::string aborted;
  bool stopped = false;  // by a signal or a lost device, before a limit ended the session
  std::size_t frames = 0;
  const FuzzFrame status_probe{encode_frame({FrameKind::kCommand, profile.address, 0x31, {}}), {}, "status poll after it"};

  std::optional<FuzzProgress> progress;
  progress.emplace(!quiet());
  auto record = [&](const live_fuzz::Verdict& v) {
    if (seen_kinds.count(v.kind)) return;  // one reproducer a kind
    seen_kinds.insert(v.kind);
    Finding f{v.kind, v.message, history, {}, false, v.field};
    progress->line(fmt::format("FINDING {} after {} writes, {:.1f} s: {}", to_string(v.kind), frames, elapsed(), v.message));
    progress->update(frames, findings.size(), fmt::format("minimizing the {} finding", to_string(v.kind)));
    minimize(f, profile, so, fresh, fresh ? nullptr : &session);
    // A new file: a finding of an earlier run with this seed stays as it is.
    std::string error;
    const auto file = write_new_file(o.findings, fmt::format("fuzz-{}-{}-{}", seed, findings.size() + 1, to_string(v.kind)),
                                     ".yaml", finding_vector_yaml(f, profile, {seed, command_line(o, seed), findings.size() + 1}),
                                     error);
    progress->line(fmt::format("  {} {} write(s) -> {}", f.reproduced ? "minimized to" : "NOT reproduced; kept",
                               f.reproducer.size(), file ? file->string() : "NOT WRITTEN: " + error));
    if (!file) std::cerr << "sabus fuzz: the finding is not written: " << error << "\n";
    written.push_back(file ? file->string() : "(not written)");
    findings.push_back(std::move(f));
    progress->update(frames, findings.size());
  };

  if (first) {  // answered, but wrongly: a finding already
    history.push_back(liveness_probe(profile.address));
    record(*first);
  }
  // The model where the device is (its positions and mode): a device on a
  // bench is no fresh controller. Again after each finding of the model's
  // kinds, whose divergence would otherwise be reported again.
  auto synchronize = [&] {
    std::string taken;
    if (auto s = session.synchronize(&history, &taken)) record(*s);
    if (!taken.empty()) progress->line("lockstep: the model takes from the device: " + taken);
  };
  try {
    if (!o.fresh_device) synchronize();
    while (g_stop_signal == 0 && (o.max_frames == 0 || frames < o.max_frames) && (o.max_time <= 0 || elapsed() < o.max_time) &&
           findings.size() < o.max_findings) {
      FuzzFrame f = generator.next();
      // A frame the device must ignore is followed by a status poll in the
      // same write: the reply sequence shows whether the ignored frame drew
      // an answer, without waiting out a silence window.
      // A second one when the first is lost too (its STX taken as the check
      // byte of a frame left open, E-7).
      for (int k = 0; k < 2 && session.would_be_ignored(f); ++k) {
        f.chars.insert(f.chars.end(), status_probe.chars.begin(), status_probe.chars.end());
        f.what += " + " + status_probe.what;
      }
      history.push_back(f);
      if (history.size() > kHistory) history.erase(history.begin());
      ++frames;
      progress->update(frames, findings.size());
      auto v = session.step(f);
      if (v) record(*v);
      if (v || (so.liveness_every > 0 && frames % so.liveness_every == 0)) {
        // The probe is a write like the others: a replay needs it (it may
        // complete or cut a frame the last write left open).
        history.push_back(liveness_probe(profile.address));
        if (auto p = session.probe()) {
          record(*p);
          if (p->kind == FindingKind::kDead) {
            aborted = "the device stopped answering";
            break;
          }
        }
      }
      if (v && (v->kind == FindingKind::kNakRule || v->kind == FindingKind::kValue || v->kind == FindingKind::kEffect))
        synchronize();
    }
  } catch (const TransportLost& e) {
    aborted = std::string("the device is lost: ") + e.what();
    stopped = true;
  }
  if (g_stop_signal != 0) {
    aborted = g_stop_signal == SIGTERM ? "stopped by SIGTERM" : "stopped by SIGINT";
    stopped = true;
  }
  progress.reset();  // its last line cleared before the totals

  print_totals(session, transport, elapsed(), seed, pty, aborted, findings, written);
  // A finding is the firmware's, whatever stopped the session after it.
  return !findings.empty() ? kExitFailed : stopped ? kExitStopped : kExitOk;
}

}  // namespace

Command add_fuzz_command(CLI::App& app) {
  auto o = std::make_shared<FuzzCliOptions>();
  CLI::App* sub = app.add_subcommand("fuzz", "Fuzz a controller live: damaged frames, an oracle from the spec, minimized findings");
  add_device_options(sub, o->device);
  sub->add_option("--seed", o->seed, "Seed of the generator (default: random, printed)")->check(kNonNegative);
  sub->add_option("--max-frames", o->max_frames, "Stop after N writes (default: no limit)")->check(kNonNegative);
  sub->add_option("--max-time", o->max_time, "Stop after S seconds (default: no limit)")->check(kNonNegative);
  sub->add_option("--max-findings", o->max_findings, "Stop after N findings, 1-1000 (default 8; one per kind)")
      ->check(CLI::Range(1, 1000));
  sub->add_option("--findings", o->findings, "Write each finding as a vector file into DIR (default fuzz-findings)");
  sub->add_option("--liveness-every", o->liveness_every, "A device type query every N writes (default 50; 0: only after findings)")
      ->check(kNonNegative);
  sub->add_option("--pace", o->pace_ms, "Milliseconds between writes, 0-60000 (default 1000 on a line, §4; 0 in-process)")
      ->check(kPaceRange);
  sub->add_flag("--allow-motion", o->allow_motion, "Also send commands that move the antenna");
  sub->add_flag("--allow-destructive", o->allow_destructive, "Also send commands that change stored data");
  sub->add_flag("--fresh-device", o->fresh_device,
                "The device is as its profile powers on (just powered on, or sabus sim): the lockstep model takes "
                "nothing from it at the start, so a wrong mode it starts in is a finding");
  return {sub, [o] { return run_fuzz(*o); }};
}

}  // namespace sabus::cli
