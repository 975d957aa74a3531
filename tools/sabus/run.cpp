// `sabus run`: the conformance suite against the in-process reference
// controller (default), a serial port or a TCP serial server.
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "device.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void on_sigint(int) { g_stop = true; }

struct RunCliOptions {
  DeviceOptions device;
  std::string level = "informative", junit, json, report_dir, known_issues;
  std::vector<std::string> vectors, filters, excludes;
  int repeat = 0;
  long pace_ms = -1;
  std::uint64_t seed = 0;
  bool allow_motion = false, allow_destructive = false;
};

std::optional<Level> parse_level(const std::string& s) {
  if (s == "must") return Level::kMust;
  if (s == "should") return Level::kShould;
  if (s == "informative") return Level::kInformative;
  return std::nullopt;
}

// Known issues: one vector id per line, then its reason ("id: reason" or
// "id  reason"); '#' starts a comment.
std::optional<std::map<std::string, std::string>> read_known_issues(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::map<std::string, std::string> out;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    const auto a = line.find_first_not_of(" \t");
    if (a == std::string::npos) continue;
    const auto b = line.find_first_of(": \t", a);
    const std::string id = line.substr(a, b == std::string::npos ? std::string::npos : b - a);
    std::string reason = b == std::string::npos ? "" : line.substr(b + 1);
    reason.erase(0, reason.find_first_not_of(" \t:"));
    out[id] = reason.empty() ? "listed as a known issue" : reason;
  }
  return out;
}

nlohmann::json result_json(const VectorResult& r) {
  nlohmann::json transcript = nlohmann::json::array();
  for (const auto& t : r.transcript)
    transcript.push_back({{"t_ms", t.t_ms}, {"dir", t.sent ? "tx" : "rx"}, {"hex", to_hex(t.bytes)}, {"note", t.note}});
  return {{"id", r.id},
          {"paragraph", r.paragraph},
          {"file", r.file},
          {"level", std::string(to_string(r.level))},
          {"outcome", std::string(to_string(r.verdict))},
          {"failures", r.failures},
          {"skip_reason", r.skip_reason},
          {"known_issue", r.known_issue_reason},
          {"duration_ms", r.duration_ms},
          {"transcript", transcript}};
}

// Written after every vector (to a temporary file renamed over the target),
// so an interrupted run keeps what it measured.
class JsonReport {
 public:
  JsonReport(std::string path, nlohmann::json header) : path_(std::move(path)), doc_(std::move(header)) {
    doc_["schema"] = "sabus-run";
    doc_["schema_version"] = 1;
    doc_["status"] = "running";
    doc_["vectors"] = nlohmann::json::array();
    write();
  }
  void add(const VectorResult& r) {
    doc_["vectors"].push_back(result_json(r));
    write();
  }
  void finish(const RunResult& run) {
    doc_["status"] = run.aborted ? "aborted" : "complete";
    doc_["abort_reason"] = run.abort_reason;
    doc_["summary"] = {{"passed", run.passed},   {"failed", run.failed},       {"skipped", run.skipped},
                       {"known", run.known},     {"unexpected", run.unexpected}, {"exit_code", run.exit_code()}};
    nlohmann::json live = nlohmann::json::array();
    for (const auto& l : run.liveness) live.push_back({{"when", l.when}, {"alive", l.alive}, {"detail", l.detail}});
    doc_["liveness"] = live;
    doc_["restore"] = run.restore_notes;
    doc_["traffic"] = {{"bytes_sent", run.bytes_sent},
                       {"bytes_received", run.bytes_received},
                       {"silence_windows", run.silence_windows},
                       {"silence_listened_ms", run.silence_listened.count() / 1000.0},
                       {"measured_turnaround_ms", run.measured_turnaround.count() / 1000.0}};
    write();
  }

 private:
  void write() {
    if (path_.empty()) return;
    const std::string tmp = path_ + ".tmp";
    {
      std::ofstream out(tmp, std::ios::trunc);
      out << doc_.dump(2) << "\n";
    }
    std::error_code ec;
    fs::rename(tmp, path_, ec);
  }
  std::string path_;
  nlohmann::json doc_;
};

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') out += fmt::format("&#x{:x};", static_cast<int>(c));
        else out += c;
    }
  }
  return out;
}

// One testsuite per spec paragraph, one testcase per vector.
void write_junit(const std::string& path, const RunResult& run) {
  std::map<std::string, std::vector<const VectorResult*>> by_paragraph;
  for (const auto& r : run.vectors) by_paragraph[r.paragraph].push_back(&r);
  std::ofstream out(path);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"sabus\">\n";
  for (const auto& [paragraph, results] : by_paragraph) {
    std::size_t failures = 0, skipped = 0;
    for (const auto* r : results) {
      failures += r->verdict == Verdict::kFail || r->verdict == Verdict::kUnexpectedPass;
      skipped += r->verdict == Verdict::kSkip || r->verdict == Verdict::kKnownFailure;
    }
    out << fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" skipped=\"{}\">\n",
                       xml_escape("§" + paragraph), results.size(), failures, skipped);
    for (const auto* r : results) {
      out << fmt::format("    <testcase name=\"{}\" classname=\"sabus.{}\" time=\"{:.3f}\">", xml_escape(r->id),
                         xml_escape(paragraph), r->duration_ms / 1000.0);
      if (r->verdict == Verdict::kFail || r->verdict == Verdict::kUnexpectedPass) {
        std::string text;
        for (const auto& f : r->failures) text += f + "\n";
        for (const auto& t : r->transcript) text += (t.sent ? "tx " : "rx ") + to_hex(t.bytes) + "  " + t.note + "\n";
        out << fmt::format("<failure message=\"{}\">{}</failure>",
                           xml_escape(r->failures.empty() ? "unexpected pass" : r->failures.front()), xml_escape(text));
      } else if (r->verdict == Verdict::kSkip || r->verdict == Verdict::kKnownFailure) {
        out << fmt::format("<skipped message=\"{}\"/>",
                           xml_escape(r->verdict == Verdict::kSkip ? r->skip_reason : "known issue: " + r->known_issue_reason));
      }
      out << "</testcase>\n";
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

int run_run(RunCliOptions o) {
  const auto level = parse_level(o.level);
  if (!level) {
    std::cerr << "sabus run: --level must be must, should or informative\n";
    return kExitUsage;
  }
  LoadResult suite = load_vectors(o.vectors.empty() ? std::vector<std::string>{default_vectors_dir()} : o.vectors);
  auto lint_errors = lint(suite.files);
  suite.errors.insert(suite.errors.end(), lint_errors.begin(), lint_errors.end());
  if (!suite.ok()) {
    for (const auto& e : suite.errors) std::cerr << e.text() << "\n";
    std::cerr << "sabus run: " << suite.errors.size() << " vector error(s)\n";
    return kExitUsage;
  }
  std::vector<Vector> vectors;
  for (const auto& f : suite.files) vectors.insert(vectors.end(), f.vectors.begin(), f.vectors.end());

  OpenedDevice device = open_device("run", o.device);
  if (device.exit_code != kExitOk) return device.exit_code;
  const Profile& profile = device.profile;
  std::unique_ptr<Transport>& transport = device.transport;

  RunOptions ro;
  ro.allow_motion = o.allow_motion;
  ro.allow_destructive = o.allow_destructive;
  ro.max_level = *level;
  ro.filters = o.filters;
  ro.excludes = o.excludes;
  ro.repeat = o.repeat;
  ro.seed = o.seed;
  // §4: no more than one status request a second, and wait for ACK/NAK.
  ro.pace = std::chrono::milliseconds(o.pace_ms >= 0 ? o.pace_ms : (transport->in_process() ? 0 : 1000));
  if (!o.known_issues.empty()) {
    auto known = read_known_issues(o.known_issues);
    if (!known) {
      std::cerr << "sabus run: cannot read " << o.known_issues << "\n";
      return kExitUsage;
    }
    ro.known_issues = *known;
  }
  ro.stop = [] { return g_stop.load(); };

  std::string json_path = o.json, junit_path = o.junit;
  if (!o.report_dir.empty()) {
    fs::create_directories(o.report_dir);
    if (json_path.empty()) json_path = (fs::path(o.report_dir) / "run.json").string();
    if (junit_path.empty()) junit_path = (fs::path(o.report_dir) / "junit.xml").string();
  }
  // The stored-data backup (taken before the first destructive vector).
  ro.backup_path = !o.report_dir.empty() ? (fs::path(o.report_dir) / "backup.json").string()
                   : !json_path.empty()  ? json_path + ".backup.json"
                                         : "sabus-backup.json";
  JsonReport json(json_path, {{"device", transport->describe()},
                              {"profile", profile.name},
                              {"address", profile.address},
                              {"faults", o.device.faults},
                              {"options", {{"allow_motion", o.allow_motion}, {"allow_destructive", o.allow_destructive},
                                           {"level", o.level}, {"seed", o.seed}, {"repeat", o.repeat}}}});
  const bool tty = isatty(1);
  std::size_t done = 0;
  const std::size_t total = vectors.size();
  ro.on_result = [&](const VectorResult& r) {
    ++done;
    json.add(r);
    if (r.verdict == Verdict::kFail || r.verdict == Verdict::kUnexpectedPass) {
      const std::string why = r.failures.empty() ? "passed but is listed as a known issue" : r.failures.front();
      std::cout << (tty ? "\r\033[K" : "")
                << fmt::format("FAIL {} §{} {}: {}\n", r.id, r.paragraph, to_string(r.level), why);
    }
    if (tty) std::cout << fmt::format("\r[{}/{}] {}", done, total, r.id) << std::flush;
  };
  std::signal(SIGINT, on_sigint);

  Runner runner(*transport, profile, ro);
  RunResult run = runner.run(vectors);
  json.finish(run);
  if (!junit_path.empty()) write_junit(junit_path, run);
  if (tty) std::cout << "\r\033[K";
  for (const auto& l : run.liveness)
    if (!l.alive) std::cout << fmt::format("LIVENESS {}: {}\n", l.when, l.detail);
  if (run.backup.taken) std::cout << "stored data backed up to " << ro.backup_path << "\n";
  for (const auto& n : run.restore_notes) std::cout << "RESTORE " << n << "\n";
  if (run.aborted) std::cout << "ABORTED: " << run.abort_reason << "\n";
  std::cout << fmt::format("{} passed, {} failed, {} skipped", run.passed, run.failed + run.unexpected, run.skipped);
  if (run.known) std::cout << fmt::format(", {} known failures", run.known);
  std::cout << "\n";
  return run.exit_code();
}

}  // namespace

Command add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunCliOptions>();
  CLI::App* sub = app.add_subcommand("run", "Run the conformance vectors against a controller");
  add_device_options(sub, o->device);
  sub->add_option("--vectors", o->vectors, "Vector files or folders (default vectors/)");
  sub->add_option("--filter", o->filters, "Run only vectors whose id matches this glob (repeatable)");
  sub->add_option("--exclude", o->excludes, "Skip vectors whose id matches this glob (repeatable)");
  sub->add_option("--level", o->level, "Run vectors up to this level: must, should, informative");
  sub->add_flag("--allow-motion", o->allow_motion, "Run vectors that move the antenna");
  sub->add_flag("--allow-destructive", o->allow_destructive, "Run vectors that change stored data");
  sub->add_option("--known-issues", o->known_issues, "Vector ids expected to fail, with reasons");
  sub->add_option("--repeat", o->repeat, "Re-run each failing vector N times");
  sub->add_option("--seed", o->seed, "Seed for every random choice");
  sub->add_option("--pace", o->pace_ms, "Milliseconds between commands (default 1000 on a line, 0 in-process)");
  sub->add_option("--junit", o->junit, "Write JUnit XML");
  sub->add_option("--json", o->json, "Write the JSON result (written after every vector)");
  sub->add_option("--report-dir", o->report_dir, "Write run.json and junit.xml into DIR");
  return {sub, [o] { return run_run(*o); }};
}

}  // namespace sabus::cli
