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
#include "version.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/reports/document.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void on_sigint(int) { g_stop = true; }

struct RunCliOptions {
  DeviceOptions device;
  std::string level = "informative", junit, json, html, md, report_dir, known_issues;
  std::vector<std::string> vectors, filters, excludes;
  int repeat = 0;
  long pace_ms = -1;
  std::uint64_t seed = 0;
  bool allow_motion = false, allow_destructive = false, strict = false;
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
  ro.strict = o.strict;
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
  ro.keep_transcripts = false;  // the run document and its journal have them

  std::string json_path = o.json, junit_path = o.junit, html_path = o.html, md_path = o.md;
  if (!o.report_dir.empty()) {
    std::error_code ec;
    fs::create_directories(o.report_dir, ec);
    if (ec) {
      std::cerr << "sabus run: --report-dir " << o.report_dir << ": " << ec.message() << "\n";
      return kExitUsage;
    }
    auto in_dir = [&](std::string& path, const char* name) {
      if (path.empty()) path = (fs::path(o.report_dir) / name).string();
    };
    in_dir(json_path, "run.json");
    in_dir(junit_path, "junit.xml");
    in_dir(html_path, "report.html");
    in_dir(md_path, "summary.md");
  }
  // The stored-data backup (taken before the first destructive vector).
  // In-process, the device is gone at exit: a backup file is written only
  // next to a report there.
  ro.backup_path = !o.report_dir.empty() ? (fs::path(o.report_dir) / "backup.json").string()
                   : !json_path.empty()  ? json_path + ".backup.json"
                   : transport->in_process() ? ""
                                             : "sabus-backup.json";

  reports::RunDocument doc;
  doc.generator = "sabus " + full_version();
  doc.started_at = reports::utc_now();
  doc.device = transport->describe();
  doc.profile = profile.name;
  doc.address = profile.address;
  doc.faults = o.device.faults;
  doc.options = {{"allow_motion", o.allow_motion}, {"allow_destructive", o.allow_destructive},
                 {"level", o.level},               {"seed", o.seed},
                 {"repeat", o.repeat},             {"pace_ms", ro.pace.count()},
                 {"strict", o.strict},
                 {"filters", o.filters},           {"excludes", o.excludes},
                 {"known_issues", o.known_issues}, {"vectors", o.vectors}};
  for (const auto& v : vectors) doc.planned += is_selected(ro, v.id);
  // §3.1: who answers, asked once before the first vector.
  doc.identity = reports::query_identity(*transport, profile.address);
  if (!doc.identity.ok) std::cerr << "sabus run: device identity: " << doc.identity.error << "\n";
  if (ro.pace.count() > 0) transport->pause(ro.pace);  // §4 pacing before the runner's first command

  // The journal takes each vector as it finishes (reports/journal.hpp); the
  // JSON is written now, saying the run goes on and where its vectors are,
  // and once more at the end (also after SIGINT or a lost device).
  reports::JournalWriter journal;
  std::string error;
  if (!json_path.empty()) {
    const std::string journal_path = reports::journal_path_for(json_path);
    doc.journal = fs::path(journal_path).filename().string();
    if (!journal.open(journal_path, doc)) std::cerr << "sabus run: " << journal.error() << "\n";
    else if (!reports::write_run_json(json_path, doc, error)) std::cerr << "sabus run: " << error << "\n";
  }

  const bool tty = isatty(1);
  reports::Progress progress;
  progress.total = doc.planned;
  const auto t0 = std::chrono::steady_clock::now();
  auto last_result = std::chrono::steady_clock::now();
  ro.on_result = [&](const VectorResult& r) {
    reports::VectorRecord record = reports::vector_record(r);
    // Wall clock since the previous result (the start of the run for the
    // first): the vector and whatever the runner did before it.
    record.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - last_result).count();
    if (journal.is_open() && !journal.append(record)) std::cerr << "sabus run: " << journal.error() << "\n";
    reports::compact_for_reports(record);  // the journal has the fields; the reports need them for failures only
    doc.vectors.push_back(std::move(record));
    const reports::VectorRecord& v = doc.vectors.back();
    ++progress.done;
    progress.passed += v.outcome == "pass";
    progress.failed += v.is_failure();
    progress.skipped += v.is_skip();
    progress.current = v.id;
    progress.elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0);
    if (v.is_failure()) std::cout << (tty ? "\r\033[K" : "") << reports::failure_line(v) << "\n";
    if (tty) std::cout << "\r\033[K" << reports::progress_line(progress) << std::flush;
    last_result = std::chrono::steady_clock::now();  // writing this one is not the next one's time
  };
  std::signal(SIGINT, on_sigint);

  Runner runner(*transport, profile, ro);
  last_result = std::chrono::steady_clock::now();
  RunResult run = runner.run(vectors);
  reports::finish(doc, run, reports::utc_now());
  doc.journal.clear();
  if (journal.is_open()) {
    // The end record and fsync, then the JSON from the journal, written once.
    const std::string journal_path = journal.path();
    if (!journal.close(doc)) std::cerr << "sabus run: " << journal.error() << "\n";
    std::error_code ec;
    if (reports::write_run_json(json_path, doc, journal_path, error))
      fs::remove(journal_path, ec);  // the JSON holds every vector now
    else
      std::cerr << "sabus run: " << error << "; the journal keeps every vector: sabus report " << journal_path << " --json "
                << json_path << "\n";
  } else if (!json_path.empty()) {
    std::cerr << "sabus run: " << json_path << " not written: the journal could not be written\n";
  }
  // Each report is made only when asked for.
  auto write = [&](const std::string& path, std::string (*make)(const reports::RunDocument&)) {
    if (!path.empty() && !reports::write_file(path, make(doc), error)) std::cerr << "sabus run: " << error << "\n";
  };
  write(junit_path, reports::junit_xml);
  write(html_path, reports::html_report);
  write(md_path, reports::markdown_summary);
  if (tty) std::cout << "\r\033[K";
  if (doc.identity.ok)
    std::cout << "device: controller " << doc.identity.controller_type << ", firmware " << doc.identity.firmware_version << "\n";
  for (const auto& l : run.liveness)
    if (!l.alive) std::cout << fmt::format("LIVENESS {}: {}\n", l.when, l.detail);
  if (run.backup.taken && !ro.backup_path.empty()) std::cout << "stored data backed up to " << ro.backup_path << "\n";
  for (const auto& n : run.restore_notes) std::cout << "RESTORE " << n << "\n";
  if (run.aborted) std::cout << "ABORTED: " << run.abort_reason << "\n";
  std::cout << reports::summary_line(*doc.summary) << "\n";
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
  sub->add_flag("--strict", o->strict, "A should-level failure fails the run too (exit 1)");
  sub->add_option("--seed", o->seed, "Seed for every random choice");
  sub->add_option("--pace", o->pace_ms, "Milliseconds between commands (default 1000 on a line, 0 in-process)");
  sub->add_option("--junit", o->junit, "Write JUnit XML");
  sub->add_option("--json", o->json, "Write the JSON result (each vector journaled as it finishes, the JSON at the end)");
  sub->add_option("--html", o->html, "Write the HTML report");
  sub->add_option("--md", o->md, "Write the Markdown summary");
  sub->add_option("--report-dir", o->report_dir, "Write run.json, junit.xml, report.html and summary.md into DIR");
  return {sub, [o] { return run_run(*o); }};
}

}  // namespace sabus::cli
