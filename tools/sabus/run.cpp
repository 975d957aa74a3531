// `sabus run`: the conformance suite against the in-process reference
// controller (default), a serial port or a TCP serial server.
#include <fmt/format.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "device.hpp"
#include "resume.hpp"
#include "selection.hpp"
#include "version.hpp"
#include "sabus/harness/controller.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/harness/selection.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/reports/document.hpp"
#include "sabus/reports/journal.hpp"
#include "sabus/reports/resume.hpp"
#include "sabus/reports/writers.hpp"

namespace sabus::cli {
namespace {

using namespace sabus::harness;
namespace fs = std::filesystem;

// The signal that asked the run to stop (0: none): the runner stops after
// the current step, the reports say which signal, and the exit status is
// kExitStopped.
std::atomic<int> g_stop_signal{0};
extern "C" void on_run_stop_signal(int signal) { g_stop_signal = signal; }
std::string_view stop_signal() {
  switch (g_stop_signal.load()) {
    case 0: return "";
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
  }
  return "a signal";
}

struct RunCliOptions {
  DeviceOptions device;
  SelectionOptions selection;
  std::string level = "informative", junit, json, html, md, report_dir, known_issues;
  std::string resume;  // --resume: the stopped run's JSON or journal
  std::vector<std::string> vectors;
  int repeat = 0;
  long pace_ms = -1;
  std::uint64_t seed = 0;
  int retries = -1;  // -1: 1 on a line, 0 in-process
  double max_line_fault_rate = 0.1;
  bool allow_motion = false, allow_destructive = false, strict = false, exit_first = false, strict_line = false;
  bool fresh_device = false;
};

std::optional<Level> parse_level(const std::string& s) {
  if (s == "must") return Level::kMust;
  if (s == "should") return Level::kShould;
  if (s == "informative") return Level::kInformative;
  return std::nullopt;
}

struct ReportPaths {
  std::string json, junit, html, md;
  bool to_stdout() const { return json == "-" || junit == "-" || html == "-" || md == "-"; }
};

// The report paths, each checked before the device is touched, so an hour's
// run never ends in "cannot write": one report at most on standard output
// ("-"), no two on the same file, no directory, device, pipe or link to one
// (reports::output_path_problem), and no journal of an earlier run that did
// not end beside the JSON (it holds that run's results), unless `resuming`
// that run (it is read, and kept in the new journal). An error names the
// option; nullopt then.
std::optional<ReportPaths> report_paths(const RunCliOptions& o, bool resuming = false) {
  ReportPaths r{o.json, o.junit, o.html, o.md};
  auto fail = [](const std::string& why) -> std::optional<ReportPaths> {
    std::cerr << "sabus run: " << why << "\n";
    return std::nullopt;
  };
  if (!o.report_dir.empty()) {
    if (o.report_dir == "-")
      return fail("--report-dir -: give a folder; one report goes to standard output with --json -, --junit -, --html - or --md -");
    std::error_code ec;
    fs::create_directories(o.report_dir, ec);
    if (ec) return fail("--report-dir " + o.report_dir + ": " + ec.message());
    auto in_dir = [&](std::string& path, const char* name) {
      if (path.empty()) path = (fs::path(o.report_dir) / name).string();
    };
    in_dir(r.json, "run.json");
    in_dir(r.junit, "junit.xml");
    in_dir(r.html, "report.html");
    in_dir(r.md, "summary.md");
  }
  if (const std::string why = reports::report_paths_problem({{"--json", r.json}, {"--junit", r.junit}, {"--html", r.html}, {"--md", r.md}});
      !why.empty())
    return fail(why);
  if (!r.json.empty() && r.json != "-" && !resuming) {
    const std::string journal = reports::journal_path_for(r.json);
    if (fs::exists(fs::symlink_status(journal)))
      return fail(fmt::format("{} exists: the journal of a run that did not end, with its results; make its JSON with "
                              "`sabus report {} --json FILE`, or remove it",
                              journal, journal));
  }
  return r;
}

// A private folder for the journal of a run whose JSON goes to standard
// output; removed with what is in it.
struct TempFolder {
  fs::path path;
  TempFolder() {
    std::string name = (fs::temp_directory_path() / "sabus-run-XXXXXX").string();
    if (::mkdtemp(name.data()) != nullptr) path = name;
  }
  ~TempFolder() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

// What the console says while the run goes on: on a terminal a progress line
// and the failures (every vector with -v); elsewhere, as in CI, one line per
// vector as it finishes, flushed at once; with -q only the failures.
class Console {
 public:
  Console(std::ostream& out, int fd, std::size_t total) : out_(out), tty_(::isatty(fd) == 1), colour_(use_colour(fd)) {
    progress_.total = total;
    t0_ = std::chrono::steady_clock::now();
  }
  void vector_done(const reports::VectorRecord& v) {
    ++progress_.done;
    progress_.passed += v.outcome == "pass";
    progress_.failed += v.is_failure();
    progress_.skipped += v.is_skip();
    progress_.current = v.id;
    progress_.elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0_);
    const bool every = verbose() || (!tty_ && !quiet());
    // An inconclusive vector's reason is shown as a failure's is: the bench
    // learns which test purposes this device did not reach; and a vector in
    // error's, which exchange the line left unjudged.
    if (v.is_failure() || v.is_inconclusive() || v.is_error() || every) line(reports::verdict_line(v, colour_));
    if (tty_ && !quiet()) {
      out_ << "\r\033[K" << reports::progress_line(progress_) << std::flush;
      drawn_ = true;
    }
  }
  // A line of its own (the progress line, if any, is redrawn by the next vector).
  void line(const std::string& text) {
    end();
    out_ << text << std::endl;
  }
  // Clears the progress line.
  void end() {
    if (drawn_) out_ << "\r\033[K" << std::flush;
    drawn_ = false;
  }
  bool colour() const { return colour_; }

 private:
  std::ostream& out_;
  bool tty_, colour_, drawn_ = false;
  reports::Progress progress_;
  std::chrono::steady_clock::time_point t0_;
};

// The suite loaded and linted, or nullopt after printing its errors.
std::optional<std::vector<Vector>> load_suite(const RunCliOptions& o, std::set<std::string>& ids) {
  LoadResult suite = load_vectors(o.vectors.empty() ? std::vector<std::string>{default_vectors_dir()} : o.vectors);
  auto lint_errors = lint(suite.files);
  suite.errors.insert(suite.errors.end(), lint_errors.begin(), lint_errors.end());
  if (!suite.ok()) {
    for (const auto& e : suite.errors) std::cerr << e.text() << "\n";
    std::cerr << "sabus run: " << suite.errors.size() << " vector error(s)\n";
    return std::nullopt;
  }
  std::vector<Vector> all;
  for (const auto& f : suite.files)
    for (const auto& v : f.vectors) {
      all.push_back(v);
      ids.insert(v.id);
    }
  return all;
}

// The runner's options from the command line and the device.
void set_run_options(RunOptions& ro, const RunCliOptions& o, Level level, const Transport& transport,
                     const ReportPaths& paths) {
  ro.allow_motion = o.allow_motion;
  ro.allow_destructive = o.allow_destructive;
  ro.fresh_device = o.fresh_device;
  ro.max_level = level;
  ro.repeat = o.repeat;
  ro.strict = o.strict;
  ro.exit_first = o.exit_first;
  ro.seed = o.seed;
  // A line garbles a byte now and then (§4 "a garbled status reply"); the
  // in-process controller never does, unless --line-faults emulates a line.
  ro.retries = o.retries >= 0 ? o.retries : (transport.in_process() && o.device.line_faults.empty() ? 0 : 1);
  ro.strict_line = o.strict_line;
  ro.max_line_fault_rate = o.max_line_fault_rate;
  // §4: no more than one status request a second, and wait for ACK/NAK.
  ro.pace = std::chrono::milliseconds(o.pace_ms >= 0 ? o.pace_ms : (transport.in_process() ? 0 : 1000));
  ro.stop = stop_signal;
  ro.keep_transcripts = false;  // the run document and its journal have them
  // The stored-data backup (taken before the first destructive vector) is
  // for a device that outlives the run: the in-process controller is gone
  // at exit, so there is nothing to back up or restore.
  ro.backup_stored_data = !transport.in_process();
  const bool json_file = !paths.json.empty() && paths.json != "-";
  ro.backup_path = !ro.backup_stored_data ? ""
                   : !o.report_dir.empty() ? (fs::path(o.report_dir) / "backup.json").string()
                   : json_file             ? paths.json + ".backup.json"
                                           : "sabus-backup.json";
}

// The run document before the first vector: who, what and how.
reports::RunDocument start_document(const RunCliOptions& o, const RunOptions& ro, const OpenedDevice& device,
                                    std::size_t planned) {
  reports::RunDocument doc;
  doc.generator = "sabus " + full_version();
  doc.started_at = reports::utc_now();
  doc.device = device.transport->describe();
  doc.profile = device.profile.name;
  doc.address = device.profile.address;
  doc.faults = o.device.faults;
  doc.options = {{"allow_motion", o.allow_motion}, {"allow_destructive", o.allow_destructive},
                 {"fresh_device", o.fresh_device},
                 {"level", o.level},               {"seed", o.seed},
                 {"repeat", o.repeat},             {"pace_ms", ro.pace.count()},
                 {"strict", o.strict},             {"retries", ro.retries},
                 {"strict_line", o.strict_line},   {"max_line_fault_rate", o.max_line_fault_rate},
                 {"line_faults", o.device.line_faults},
                 {"filters", o.selection.filters}, {"excludes", o.selection.excludes},
                 {"paragraphs", o.selection.paragraphs},
                 {"shard", o.selection.shard},       {"last_failed", o.selection.last_failed},
                 {"failed_first", o.selection.failed_first}, {"exit_first", o.exit_first},
                 {"known_issues", o.known_issues}, {"vectors", o.vectors}};
  doc.invocation = reports::Invocation{.profile = o.device.profile,
                                       .port = o.device.port,
                                       .tcp = o.device.tcp,
                                       .line = o.device.line,
                                       .serial_backend = o.device.serial_backend,
                                       .reading = o.device.reading,
                                       .baud = o.device.baud,
                                       .json = o.json,
                                       .junit = o.junit,
                                       .html = o.html,
                                       .md = o.md,
                                       .report_dir = o.report_dir};
  doc.planned = planned;
  return doc;
}

// --resume: the command line of the stopped run, read back from what
// start_document recorded (its `options`, `faults`, `address` and
// `invocation`). Where the device is now may be given (`given`'s --port,
// --tcp, --sim, --serial-backend): an adapter that came back as another
// port. The reports are the stopped run's, where it wrote them, when the JSON
// it recorded is the file resumed (the command runs in the folder the
// stopped run was started in); the file resumed alone otherwise.
RunCliOptions options_of_stopped_run(const RunCliOptions& given, const reports::StoppedRun& stopped) {
  const reports::RunDocument& d = stopped.doc;
  const nlohmann::json& op = d.options;
  const reports::Invocation& inv = *d.invocation;
  RunCliOptions o;
  o.resume = given.resume;
  o.level = op.value("level", o.level);
  o.allow_motion = op.value("allow_motion", false);
  o.allow_destructive = op.value("allow_destructive", false);
  o.fresh_device = op.value("fresh_device", false);
  o.seed = op.value("seed", std::uint64_t{0});
  o.repeat = op.value("repeat", 0);
  o.pace_ms = op.value("pace_ms", -1L);
  o.strict = op.value("strict", false);
  o.exit_first = op.value("exit_first", false);
  o.retries = op.value("retries", -1);
  o.strict_line = op.value("strict_line", false);
  o.max_line_fault_rate = op.value("max_line_fault_rate", 0.1);
  o.device.line_faults = op.value("line_faults", "");
  o.known_issues = op.value("known_issues", "");
  o.vectors = op.value("vectors", std::vector<std::string>{});
  o.selection.filters = op.value("filters", std::vector<std::string>{});
  o.selection.excludes = op.value("excludes", std::vector<std::string>{});
  o.selection.paragraphs = op.value("paragraphs", std::vector<std::string>{});
  o.selection.shard = op.value("shard", "");
  o.selection.last_failed = op.value("last_failed", "");
  o.selection.failed_first = op.value("failed_first", "");
  o.device.faults = d.faults;
  o.device.address = std::to_string(d.address);
  o.device.profile = inv.profile;
  o.device.baud = inv.baud;
  o.device.line = inv.line.empty() ? o.device.line : inv.line;
  o.device.reading = inv.reading;
  o.device.serial_backend = given.device.serial_backend != "auto" || inv.serial_backend.empty() ? given.device.serial_backend
                                                                                                  : inv.serial_backend;
  const bool moved = given.device.sim || !given.device.port.empty() || !given.device.tcp.empty();
  o.device.sim = moved && given.device.sim;
  o.device.port = moved ? given.device.port : inv.port;
  o.device.tcp = moved ? given.device.tcp : inv.tcp;
  const std::string recorded_json =
      !inv.json.empty() || inv.report_dir.empty() ? inv.json : (fs::path(inv.report_dir) / "run.json").string();
  std::error_code ec;
  if (recorded_json != "-" && !recorded_json.empty() && fs::equivalent(recorded_json, stopped.json, ec)) {
    o.json = inv.json;
    o.junit = inv.junit;
    o.html = inv.html;
    o.md = inv.md;
    o.report_dir = inv.report_dir;
  } else {
    o.json = stopped.json;
    if (!quiet() && (!inv.junit.empty() || !inv.html.empty() || !inv.md.empty() || !inv.report_dir.empty()))
      std::cerr << "sabus run: --resume " << stopped.json << ": only the run JSON is written: the stopped run wrote its "
                << "other reports from another folder (`sabus report " << stopped.json << "` makes them)\n";
  }
  return o;
}

// The journal takes each vector as it finishes (reports/journal.hpp); the
// JSON is written at the start, saying the run goes on and where its vectors
// are, and once more at the end (also after SIGINT or a lost device). For a
// JSON on standard output the journal is a private temporary file, and the
// JSON is written once, at the end.
struct RunJournal {
  reports::JournalWriter writer;
  std::optional<TempFolder> folder;

  // `earlier`: a resumed run's kept vectors, in the journal before the first
  // vector it runs (JournalWriter::open with them), and `backup` the stopped
  // run's stored-data backup, which it restores from.
  void open(const ReportPaths& paths, reports::RunDocument& doc, const std::vector<reports::VectorRecord>* earlier = nullptr,
            const std::string& backup = "") {
    if (paths.json.empty()) return;
    const bool json_file = paths.json != "-";
    std::string journal_path, error;
    if (json_file) {
      journal_path = reports::journal_path_for(paths.json);
      doc.journal = fs::path(journal_path).filename().string();
    } else {
      folder.emplace();
      journal_path = (folder->path / "run.journal.jsonl").string();
    }
    if (!(earlier ? writer.open(journal_path, doc, *earlier, backup) : writer.open(journal_path, doc)))
      std::cerr << "sabus run: " << writer.error() << "\n";
    else if (json_file && !reports::write_run_json(paths.json, doc, error)) std::cerr << "sabus run: " << error << "\n";
  }

  // The end record and fsync, then the JSON from the journal, written once.
  void close(const ReportPaths& paths, reports::RunDocument& doc) {
    doc.journal.clear();
    if (!writer.is_open()) {
      if (!paths.json.empty())
        std::cerr << "sabus run: " << paths.json << " not written: the journal could not be written\n";
      return;
    }
    const std::string journal_path = writer.path();
    std::string error;
    if (!writer.close(doc)) std::cerr << "sabus run: " << writer.error() << "\n";
    std::error_code ec;
    if (reports::write_run_json(paths.json, doc, journal_path, error))
      fs::remove(journal_path, ec);  // the JSON holds every vector now
    else if (paths.json != "-")
      std::cerr << "sabus run: " << error << "; the journal keeps every vector: sabus report " << journal_path
                << " --json " << paths.json << "\n";
    else
      std::cerr << "sabus run: " << error << "\n";
  }
};

// Each report is made only when asked for.
void write_reports(const ReportPaths& paths, const reports::RunDocument& doc) {
  std::string error;
  auto write = [&](const std::string& path, std::string (*make)(const reports::RunDocument&)) {
    if (!path.empty() && !reports::write_file(path, make(doc), error)) std::cerr << "sabus run: " << error << "\n";
  };
  write(paths.junit, reports::junit_xml);
  write(paths.html, reports::html_report);
  write(paths.md, reports::markdown_summary);
}

// The lines after the last vector: liveness, backup, restore, abort, summary;
// the exit status.
// `on_a_line`: the device is reached over a line, a real one or one emulated
// with --line-faults; the in-process controller's own exchanges never fault,
// so its figures would only push the summary off the last line.
int finish_console(Console& console, const RunResult& run, const reports::RunDocument& doc, bool on_a_line) {
  console.end();
  for (const auto& l : run.liveness)
    if (!l.alive) console.line(fmt::format("LIVENESS {}: {}", l.when, l.detail));
  if (!run.backup.file.empty() && !quiet()) console.line("stored data backed up to " + run.backup.file);
  for (const auto& n : run.restore_notes) console.line("RESTORE " + n);
  if (run.aborted) console.line((run.stopped_by.empty() ? "ABORTED: " : "STOPPED: ") + run.abort_reason);
  console.line(reports::summary_line(*doc.summary));
  // The line figures over a line: a bench engineer reads a clean line's
  // zero as much as a noisy line's count.
  if (const std::string line = reports::line_text(*doc.summary); !line.empty() && (on_a_line || run.line.faults > 0))
    console.line(line);
  if (const std::string warning = reports::line_warning(*doc.summary); !warning.empty())
    console.line(std::string(console.colour() ? "\033[33mWARNING\033[0m: " : "WARNING: ") + warning);
  const int status = run.exit_code();
  if (status == kExitLineError)
    console.line(std::string(console.colour() ? "\033[1;34mLINE ERRORS\033[0m: " : "LINE ERRORS: ") +
                 reports::line_error_text(*doc.summary) + "; the firmware is neither accepted nor rejected (exit 6)");
  if (status == kExitNothingRan)
    console.line(std::string(console.colour() ? "\033[33mNOTHING RAN\033[0m: " : "NOTHING RAN: ") +
                 reports::nothing_ran_reason(*doc.summary) + "; a run that checked nothing is not a success (exit 5)");
  return status;
}

int run_run(RunCliOptions o, const CLI::App& sub) {
  // --resume: the stopped run read first, its options the command's.
  std::optional<Resume> resume;
  if (!o.resume.empty()) {
    if (!(resume = read_resume(o.resume, sub))) return kExitUsage;
    o = options_of_stopped_run(o, resume->stopped);
  }
  const auto level = parse_level(o.level);
  std::set<std::string> ids;
  const auto all = load_suite(o, ids);
  if (!all) return kExitUsage;

  RunOptions ro;
  const auto choice = selection_options(o.selection, "sabus run");
  if (!choice) return kExitUsage;
  const harness::Selection selection = harness::select_vectors(*all, *choice);
  if (!quiet())
    for (const auto& note : selection.notes) std::cerr << "sabus run: " << note << "\n";
  if (selection.vectors.empty()) {
    // Said before the device is touched: there is nothing to ask it.
    std::cerr << "sabus run: NOTHING RAN: " << harness::empty_selection_reason(*choice) << " (" << all->size()
              << " vectors loaded; `sabus vectors list --filter GLOB` previews a selection)\n";
    return kExitNothingRan;
  }
  std::optional<std::vector<Vector>> left;  // --resume: the vectors the stopped run did not finish
  if (resume && !(left = vectors_left(selection.vectors, *resume))) return kExitUsage;
  const std::vector<Vector>& to_run = left ? *left : selection.vectors;
  if (!o.known_issues.empty()) {
    auto known = harness::read_known_issues(o.known_issues, ids);
    for (const auto& e : known.errors) std::cerr << "sabus run: --known-issues " << e << "\n";
    if (!known.errors.empty()) return kExitUsage;
    ro.known_issues = std::move(known.reasons);
  }
  const auto paths = report_paths(o, resume.has_value());
  if (!paths) return kExitUsage;

  o.device.line_fault_seed = o.seed;
  OpenedDevice device = open_device("run", o.device);
  if (device.exit_code != kExitOk) return device.exit_code;
  Transport& transport = *device.transport;
  set_run_options(ro, o, *level, transport, *paths);

  // A report on standard output keeps it to itself: the console goes to
  // standard error then.
  std::ostream& out = paths->to_stdout() ? std::cerr : std::cout;
  Console console(out, paths->to_stdout() ? STDERR_FILENO : STDOUT_FILENO, to_run.size());

  reports::RunDocument doc = start_document(o, ro, device, selection.vectors.size());
  // §3.1: who answers, asked once before the first vector.
  doc.identity = reports::query_identity(transport, device.profile.address);
  if (!doc.identity.ok) std::cerr << "sabus run: device identity: " << doc.identity.error << "\n";
  else if (!quiet())
    console.line("device: controller " + doc.identity.controller_type + ", firmware " + doc.identity.firmware_version);
  // --resume: the same device, checked before a file is written.
  if (resume)
    if (const int status = check_same_device(*resume, doc.identity); status != kExitOk) return status;
  if (ro.pace.count() > 0) transport.pause(ro.pace);  // §4 pacing before the runner's first command

  // --resume: one run, whose journal starts with the vectors it kept.
  if (resume) resume_document(doc, *resume);
  RunJournal journal;
  journal.open(*paths, doc, resume ? &resume->stopped.doc.vectors : nullptr, resume ? resume->stopped.doc.backup : "");
  if (resume) {
    keep_vectors(doc, ro, *resume);
    if (!quiet()) console.line(resume_line(*resume, to_run.size()));
  }
  auto last_result = std::chrono::steady_clock::now();
  ro.on_result = [&](const VectorResult& r) {
    reports::VectorRecord record = reports::vector_record(r);
    // Wall clock since the previous result (the start of the run for the
    // first): the vector and whatever the runner did before it.
    record.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - last_result).count();
    if (journal.writer.is_open() && !journal.writer.append(record))
      std::cerr << "sabus run: " << journal.writer.error() << "\n";
    reports::compact_for_reports(record);  // the journal has the fields; the reports need them for failures only
    doc.vectors.push_back(std::move(record));
    console.vector_done(doc.vectors.back());
    last_result = std::chrono::steady_clock::now();  // writing this one is not the next one's time
  };
  // A run killed from here on has no end record to name the backup file:
  // the journal names it before the destructive vector runs, so that
  // --resume restores the device from it.
  ro.on_backup = [&](const StoredDataBackup& backup) {
    if (!backup.file.empty() && journal.writer.is_open() && !journal.writer.backup(backup.file))
      std::cerr << "sabus run: " << journal.writer.error() << "\n";
  };
  std::signal(SIGINT, on_run_stop_signal);
  std::signal(SIGTERM, on_run_stop_signal);

  Runner runner(transport, device.profile, ro);
  last_result = std::chrono::steady_clock::now();
  RunResult run = runner.run(to_run);
  if (device.injected_faults && !quiet())
    console.line("emulated line (--line-faults): " + harness::describe(device.injected_faults()));
  reports::finish(doc, run, reports::utc_now());
  if (resume) reports::add_stopped_run(doc, resume->stopped.doc);
  journal.close(*paths, doc);
  write_reports(*paths, doc);
  return finish_console(console, run, doc, !transport.in_process() || device.injected_faults != nullptr);
}

static_assert(kExitNothingRan == harness::kNothingRanExitCode);
static_assert(kExitStopped == harness::kStoppedExitCode);
static_assert(kExitLineError == harness::kLineErrorExitCode);

constexpr const char* kRunExitStatus = R"(Exit status:
  0  every must-level vector that ran passed (with --strict every should-level one too), and at least one ran
  1  a must-level vector failed (with --strict a should-level one too), a listed known issue passed, a
     liveness check failed, or the device stopped answering during the run
  2  usage: a bad option or value, a profile, vector or known-issues file that does not load, an unknown id
     in --known-issues, a report path that cannot be written; with --resume, a run that is not a stopped one
     (it ran to its end) or a device that is not the one it stopped on (another type or firmware in 30h)
  3  the device could not be reached: the port or socket does not open, or nothing answers
  4  the run was stopped before its end by SIGINT, SIGTERM or a lost device (the port or socket went away):
     the reports hold every vector finished before it, the JSON is marked aborted and the JUnit has an error
     naming why; failures before the stop do not change the code: the run has no verdict
  5  nothing ran: no vector matches the selection, or every selected vector was skipped (the summary says
     why, by cause) or ended inconclusive (a precondition step did not hold, so its test purpose was not
     reached); a run that checked nothing is not a success, and 5 is pytest's code for it too.
     An inconclusive vector never makes the code 1
  6  no vector failed, but some ended in error: the line (not the firmware) left them unjudged (a garbled
     exchange whose repeats, --retries, got no clean reply); see the line figures. The firmware is neither
     accepted nor rejected: run those vectors again on a sound line (--last-failed takes them)
)";

}  // namespace

Command add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunCliOptions>();
  CLI::App* sub = app.add_subcommand("run", "Run the conformance vectors against a controller");
  sub->footer(kRunExitStatus);
  add_device_options(sub, o->device);
  sub->add_option("--vectors", o->vectors, "Vector files or folders (default vectors/)");
  add_selection_options(sub, o->selection);
  sub->add_option("--level", o->level, "Run vectors up to this level: must, should, informative")
      ->check(CLI::IsMember({"must", "should", "informative"}));
  sub->add_flag("--allow-motion", o->allow_motion, "Run vectors that move the antenna");
  sub->add_flag("--allow-destructive", o->allow_destructive, "Run vectors that change stored data");
  sub->add_flag("--fresh-device", o->fresh_device,
                "The device stands as its profile powers on (just powered on in that state): run the power-on vectors, "
                "which compare the status with the profile's positions, alarms and name (always run with --sim)");
  sub->add_option("--known-issues", o->known_issues, "Vector ids expected to fail, with reasons");
  sub->add_option("--repeat", o->repeat, "Re-run each failing vector N times (0-100)")->check(CLI::Range(0, 100));
  sub->add_flag("--strict", o->strict, "A should-level failure fails the run too (exit 1)");
  sub->add_flag("-x,--exitfirst", o->exit_first,
                "Stop after the first vector that fails the run (exit 1); the reports name the vectors that did not run");
  sub->add_option("--seed", o->seed, "Seed for every random choice")->check(kNonNegative);
  sub->add_option("--pace", o->pace_ms, "Milliseconds between commands, 0-60000 (default 1000 on a line, 0 in-process)")
      ->check(kPaceRange);
  sub->add_option("--retries", o->retries,
                  "Send an exchange again after a line fault, up to N times, 0-10 (default 1 on a line, 0 in-process); "
                  "0 judges a garbled reply as the device's")
      ->check(CLI::Range(0, 10));
  sub->add_flag("--strict-line", o->strict_line, "Any line fault fails the vector it happened in, even one a repeat recovered");
  sub->add_option("--max-line-fault-rate", o->max_line_fault_rate,
                  "The share of garbled replies the line survey accepts before it fails the device, 0-1 (default 0.1)")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--line-faults", o->device.line_faults,
                  "With --sim: emulate a noisy line, RATE[,KIND...]: a byte error rate (1e-3) and flip, drop, insert, "
                  "outage (default all), seeded by --seed");
  sub->add_option("--junit", o->junit, "Write JUnit XML (- : standard output)");
  sub->add_option("--json", o->json,
                  "Write the JSON result (each vector journaled as it finishes, the JSON at the end; - : standard output)");
  sub->add_option("--html", o->html, "Write the HTML report (- : standard output)");
  sub->add_option("--md", o->md, "Write the Markdown summary (- : standard output)");
  sub->add_option("--report-dir", o->report_dir, "Write run.json, junit.xml, report.html and summary.md into DIR");
  sub->add_option("--resume", o->resume,
                  "Continue a run stopped by SIGINT, SIGTERM or a lost device (exit 4), or killed: its run.json, its "
                  "journal or its report folder. The same options and selection; the vectors it finished are kept, the "
                  "rest run on the same device (its 30h identity is checked first); its backup is restored at the end. It "
                  "rewrites that run's JSON and reports, where they were written, as one run; only --port, --tcp, --sim "
                  "and --serial-backend may be given with it")
      ->type_name("RUN.json");
  return {sub, [o, sub] { return run_run(*o, *sub); }};
}

}  // namespace sabus::cli
