// `sabus run --resume` as a process. The failing paths first: a missing or
// malformed file, a run that ran to its end, options the stopped run's own
// would replace, another device (controller type or firmware), no device;
// each refused with a message naming why, and no file written. Then a run
// stopped part-way by SIGINT, and one by a lost device (the simulator
// killed; resumed against a new one on another port), each resumed: the
// same verdicts, reports and console summary as an uninterrupted run, and
// the same stored data once it has restored it, from the backup taken
// before the stop. A run killed outright is resumed from its journal, after
// a destructive vector too (the journal's backup record names the backup);
// refused when the record is missing or malformed, or its file is gone.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "process.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/reports/checks.hpp"
#include "sabus/reports/document.hpp"
#include "temp_dir.hpp"

namespace sabus::reports {
namespace {

using test::Process;
using test::shell;
using test::slurp;
using namespace std::chrono_literals;
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kSabus = SABUS_BIN;

// §3.1 (identity) and §3.10 (preset writes, destructive): 23 vectors, some
// seconds over TCP at this pace, time enough to stop it part-way.
const std::vector<std::string> kSelection = {"--paragraph", "3.1", "--paragraph", "3.10", "--allow-destructive",
                                             "--pace", "50"};

// `sabus sim --tcp` on a free port.
struct Sim {
  std::unique_ptr<Process> process;
  std::string address;  // 127.0.0.1:PORT
  Sim() : process(std::make_unique<Process>(std::vector<std::string>{kSabus, "sim", "--tcp", "127.0.0.1:0"})) {
    const std::string ready = process->line(5s);
    if (ready.rfind("READY tcp ", 0) == 0) address = ready.substr(std::string("READY tcp ").size());
  }
};

// The vector records in a journal so far.
std::size_t journaled_vectors(const fs::path& journal) {
  std::ifstream in(journal);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) {
    const auto r = json::parse(line, nullptr, false);
    n += r.is_object() && !r.contains("record");
  }
  return n;
}

// A report with what differs from run to run made the same: times,
// durations, the simulator's port, and how many exchanges the line carried
// (a resumed run asks the device's identity and liveness once more).
std::string timeless(const std::string& text) {
  static const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)"), decimal(R"(\d+\.\d+)"), port(R"(127\.0\.0\.1:\d+)"),
      git(R"(\(git [^)]*\))"), exchanges(R"( in [0-9,]+ exchanges)");
  std::string out = std::regex_replace(text, port, "PORT");
  out = std::regex_replace(out, exchanges, " in N exchanges");
  out = std::regex_replace(out, iso, "TIME");
  out = std::regex_replace(out, git, "(git)");
  return std::regex_replace(out, decimal, "N");
}

// What a run found, vector by vector: id, outcome, failures, in run order.
json verdicts(const json& doc) {
  json out = json::array();
  for (const auto& v : doc["vectors"])
    out.push_back({v["id"], v["outcome"], v["failures"], v["skip_reason"], v["inconclusive_reason"]});
  return out;
}

// The summaries of a resumed run and an uninterrupted one: the same counts
// and exit code; the line figures the same faults (0), their exchanges not
// (a resumed run asks the device's identity and liveness once more, and a
// killed run's journal has no run-wide figures).
void expect_same_summary(json res, json ref) {
  EXPECT_EQ(res["summary"]["line"]["faults"], ref["summary"]["line"]["faults"]);
  EXPECT_GT(res["summary"]["line"]["exchanges"].get<long>(), 0);
  res["summary"].erase("line");
  ref["summary"].erase("line");
  EXPECT_EQ(res["summary"], ref["summary"]);
}

std::string last_line(const std::string& out) {
  const std::size_t end = out.find_last_not_of('\n');
  if (end == std::string::npos) return "";
  const std::size_t start = out.rfind('\n', end);
  return out.substr(start == std::string::npos ? 0 : start + 1, end - (start == std::string::npos ? 0 : start + 1) + 1);
}

class Resume : public test::TempDirTest {
 protected:
  Resume() : TempDirTest("sabus-resume-cli-test") {}

  std::vector<std::string> run_args(const Sim& sim, const std::string& dir) {
    std::vector<std::string> args = {kSabus, "run", "--tcp", sim.address, "--report-dir", path(dir)};
    args.insert(args.end(), kSelection.begin(), kSelection.end());
    return args;
  }
  // The stored data of the device now, as a destructive run's backup reads
  // it before its first write (35h names, 3Ah presets, 3Ch TLEs, 45h
  // navigation): its backup.json.
  std::string stored_data(const Sim& sim, const std::string& dir) {
    const auto r = shell(kSabus + " run -q --tcp " + sim.address + " --filter 3.10-write-satellite-two-slots " +
                         "--allow-destructive --pace 0 --report-dir " + path(dir) + " 2>&1");
    EXPECT_EQ(r.status, 0) << r.out;
    return slurp(dir_ / dir / "backup.json");
  }
  // The run uninterrupted, on a simulator of its own: its output, and the
  // stored data at its end.
  void run_uninterrupted() {
    Sim sim;
    ASSERT_FALSE(sim.address.empty());
    Process run(run_args(sim, "ref"));
    ref_out_ = run.read_all(60s);
    ASSERT_EQ(run.wait_exit_for(30s), 0) << ref_out_;
    ref_stored_ = stored_data(sim, "ref-stored");
  }
  // Waits until the journal in `dir` holds `n` vectors and the backup is
  // taken (the stop comes after the first destructive vector, so the
  // resumed run must reuse it).
  void wait_for(const std::string& dir, std::size_t n) {
    for (int i = 0; i < 600 && (journaled_vectors(dir_ / dir / "run.journal.jsonl") < n || !fs::exists(dir_ / dir / "backup.json"));
         ++i)
      std::this_thread::sleep_for(20ms);
  }
  // The resumed run's files against the uninterrupted run's: the same
  // verdicts and summary, JUnit and Markdown alike but for times, the
  // console's last line the same; the JSON through its schema, noting the
  // stop; the backup taken before the stop reused (no second one); the
  // stored data at the end the same.
  void expect_one_run(const std::string& resumed_out, const std::string& stopped_by, const Sim& sim) {
    const json ref = json::parse(slurp(dir_ / "ref/run.json")), res = json::parse(slurp(dir_ / "res/run.json"));
    EXPECT_EQ(checks::run_json_problems(slurp(dir_ / "res/run.json")), checks::Problems{});
    EXPECT_EQ(res["status"], "complete");
    EXPECT_EQ(verdicts(res), verdicts(ref));
    expect_same_summary(res, ref);
    EXPECT_EQ(res["planned"], ref["planned"]);
    EXPECT_EQ(res["options"], ref["options"]);
    ASSERT_EQ(res["resumptions"].size(), 1u) << res.dump();
    const json& stop = res["resumptions"][0];
    EXPECT_EQ(stop["stopped_by"], stopped_by);
    EXPECT_LE(stop["stopped_at"].get<std::string>(), stop["resumed_at"].get<std::string>());
    EXPECT_LT(stop["kept"].get<std::size_t>(), res["vectors"].size());
    EXPECT_GT(stop["kept"].get<std::size_t>(), 0u);
    EXPECT_EQ(res["backup"], path("res/backup.json")) << "the stopped run's backup";
    EXPECT_FALSE(fs::exists(dir_ / "res/backup-2.json")) << "no second backup: the device may hold the stopped run's writes";
    EXPECT_FALSE(fs::exists(dir_ / "res/run.journal.jsonl"));
    std::string error;
    const auto doc = read_run_file(path("res/run.json"), error);
    ASSERT_TRUE(doc) << error;
    const std::string junit = slurp(dir_ / "res/junit.xml"), md = slurp(dir_ / "res/summary.md");
    EXPECT_EQ(checks::junit_problems(junit, *doc), checks::Problems{});
    EXPECT_EQ(checks::markdown_problems(md, *doc), checks::Problems{});
    EXPECT_EQ(timeless(junit), timeless(slurp(dir_ / "ref/junit.xml")));
    EXPECT_EQ(timeless(md), timeless(slurp(dir_ / "ref/summary.md")));
    EXPECT_EQ(timeless(last_line(resumed_out)), timeless(last_line(ref_out_)));
    EXPECT_EQ(stored_data(sim, "res-stored"), ref_stored_) << "the stored data at the end";
  }

  std::string ref_out_, ref_stored_;
};

// ---- refused --------------------------------------------------------------------

TEST_F(Resume, AMissingOrMalformedFileIsAnErrorNamingIt) {
  auto r = shell(kSabus + " run --resume " + path("none/run.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --resume " + path("none/run.json") +
                       ": no such file (give the run.json of a stopped `sabus run`, or its journal)\n");
  std::ofstream(path("bad.json")) << "{\"schema\": \"sabus-run\", ";
  r = shell(kSabus + " run --resume " + path("bad.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out.rfind("sabus run: --resume " + path("bad.json") + ": not JSON", 0), 0u) << r.out;
  EXPECT_EQ(slurp(path("bad.json")), "{\"schema\": \"sabus-run\", ") << "left as it was";
}

TEST_F(Resume, ARunThatRanToItsEndIsRefusedAndLeftAsItWas) {
  ASSERT_EQ(shell(kSabus + " run --paragraph 3.1 --report-dir " + path("done") + " >/dev/null 2>&1").status, 0);
  const std::string before = slurp(dir_ / "done/run.json");
  const auto r = shell(kSabus + " run --resume " + path("done") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --resume " + path("done/run.json") +
                       ": the run ran to its end (exit 0): there is nothing to resume (`sabus run --last-failed " +
                       path("done/run.json") + "` runs its failures again)\n");
  EXPECT_EQ(slurp(dir_ / "done/run.json"), before);
}

// A run stopped by SIGINT on a simulator, to resume in the tests below.
class AStoppedRun : public Resume {
 protected:
  void SetUp() override {
    Resume::SetUp();
    sim_ = std::make_unique<Sim>();
    ASSERT_FALSE(sim_->address.empty());
    Process run(run_args(*sim_, "res"));
    wait_for("res", 8);
    ASSERT_EQ(run.interrupt(), harness::kStoppedExitCode);
    stopped_json_ = slurp(dir_ / "res/run.json");
  }
  std::unique_ptr<Sim> sim_;
  std::string stopped_json_;
};

TEST_F(AStoppedRun, OtherOptionsWithResumeAreRefused) {
  const auto r = shell(kSabus + " run --resume " + path("res/run.json") + " --filter '3.1*' --json " + path("x.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --resume continues the stopped run with its own options and reports; --filter, --json cannot "
                   "be given with it (only --port, --tcp, --sim and --serial-backend, to reach the device where it is now)\n");
  EXPECT_EQ(slurp(dir_ / "res/run.json"), stopped_json_);
  EXPECT_FALSE(fs::exists(path("x.json")));
}

// The stopped run's firmware edited: the device answering now is another
// one, and the run is not resumed on it (exit 2: the file does not fit the
// device); no file is written.
TEST_F(AStoppedRun, AnotherFirmwareIsRefusedBeforeAFileIsWritten) {
  json doc = json::parse(stopped_json_);
  doc["identity"]["firmware_version"] = "1.58";
  std::ofstream(path("res/run.json")) << doc.dump();
  const std::string before = slurp(dir_ / "res/run.json"), junit = slurp(dir_ / "res/junit.xml");
  const auto r = shell(kSabus + " run --resume " + path("res/run.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("sabus run: --resume " + path("res/run.json") +
                       ": the run stopped on controller 3K, firmware 1.58; this device answers controller 3K, firmware 1.59 "
                       "(30h, §3.1): a resumed run is one run on one device"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(slurp(dir_ / "res/run.json"), before);
  EXPECT_EQ(slurp(dir_ / "res/junit.xml"), junit);
  EXPECT_FALSE(fs::exists(dir_ / "res/run.journal.jsonl"));
}

// No device where the stopped run's was: exit 3, nothing written.
TEST_F(AStoppedRun, NoDeviceIsUnreachable) {
  const std::string address = sim_->address;
  ASSERT_EQ(sim_->process->interrupt(), 0);
  sim_.reset();
  const auto r = shell(kSabus + " run --resume " + path("res/run.json") + " --tcp " + address + " 2>&1");
  EXPECT_EQ(r.status, 3) << r.out;
  EXPECT_EQ(slurp(dir_ / "res/run.json"), stopped_json_);
}

// ---- resumed --------------------------------------------------------------------

// Ctrl-C part-way, then --resume: one run, as if never stopped.
TEST_F(AStoppedRun, ResumedAfterSigintItIsTheUninterruptedRun) {
  EXPECT_EQ(json::parse(stopped_json_)["stopped_by"], "SIGINT");
  Process resumed({kSabus, "run", "--resume", path("res/run.json")});
  const std::string out = resumed.read_all(60s);
  ASSERT_EQ(resumed.wait_exit_for(30s), 0) << out;
  EXPECT_NE(out.find("resuming " + path("res/run.json") + ", stopped by SIGINT at "), std::string::npos) << out;
  run_uninterrupted();
  expect_one_run(out, "SIGINT", *sim_);
}

// The device lost part-way (the simulator killed), then resumed on a new
// one at another address (--tcp): the vector it was lost in runs again, and
// the restore at the end writes back the backup taken on the first.
TEST_F(Resume, ResumedAfterALostDeviceItIsTheUninterruptedRun) {
  {
    Sim first;
    ASSERT_FALSE(first.address.empty());
    Process run(run_args(first, "res"));
    wait_for("res", 12);
    first.process.reset();  // SIGKILL: the socket closes
    ASSERT_EQ(run.wait_exit_for(30s), harness::kStoppedExitCode);
  }
  const json stopped = json::parse(slurp(dir_ / "res/run.json"));
  ASSERT_EQ(stopped["stopped_by"], "lost device") << stopped["abort_reason"];
  Sim second;
  Process resumed({kSabus, "run", "--resume", path("res/run.json"), "--tcp", second.address});
  const std::string out = resumed.read_all(60s);
  ASSERT_EQ(resumed.wait_exit_for(30s), 0) << out;
  run_uninterrupted();
  expect_one_run(out, "lost device", second);
  // The vector the device was lost in ran again (its verdict is the
  // uninterrupted run's, above); the others were kept.
  std::size_t finished = 0;
  for (const auto& v : stopped["vectors"])
    finished += v["failures"].empty() || v["failures"][0].get<std::string>().rfind(harness::kDeviceLostFailure, 0) != 0;
  EXPECT_LT(finished, stopped["vectors"].size()) << "the device was lost in a vector";
  EXPECT_EQ(json::parse(slurp(dir_ / "res/run.json"))["resumptions"][0]["kept"], finished);
}

// A run killed outright (SIGKILL: no end record, its JSON still says
// "running") is resumed from its journal, which the resumed run replaces
// with one holding the kept vectors first: the uninterrupted run's verdicts.
TEST_F(Resume, AKilledRunIsResumedFromItsJournal) {
  const std::vector<std::string> reads = {"--paragraph", "3.1", "--paragraph", "3.11", "--pace", "50"};
  Sim sim;
  ASSERT_FALSE(sim.address.empty());
  auto args = [&](const std::string& dir) {
    std::vector<std::string> a = {kSabus, "run", "--tcp", sim.address, "--report-dir", path(dir)};
    a.insert(a.end(), reads.begin(), reads.end());
    return a;
  };
  {
    Process run(args("res"));
    for (int i = 0; i < 600 && journaled_vectors(dir_ / "res/run.journal.jsonl") < 4; ++i) std::this_thread::sleep_for(20ms);
  }  // SIGKILL
  ASSERT_EQ(json::parse(slurp(dir_ / "res/run.json"))["status"], "running");
  const std::size_t journaled = journaled_vectors(dir_ / "res/run.journal.jsonl");
  ASSERT_GE(journaled, 4u);
  const auto resumed = shell(kSabus + " run --resume " + path("res/run.journal.jsonl") + " 2>&1");
  ASSERT_EQ(resumed.status, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("resuming " + path("res/run.json") + ", killed at "), std::string::npos) << resumed.out;
  Process ref(args("ref"));
  ASSERT_EQ(ref.wait_exit_for(60s), 0);
  const json res = json::parse(slurp(dir_ / "res/run.json")), uninterrupted = json::parse(slurp(dir_ / "ref/run.json"));
  EXPECT_EQ(checks::run_json_problems(slurp(dir_ / "res/run.json")), checks::Problems{});
  EXPECT_EQ(verdicts(res), verdicts(uninterrupted));
  expect_same_summary(res, uninterrupted);
  EXPECT_EQ(res["resumptions"][0]["stopped_by"], "killed");
  EXPECT_EQ(res["resumptions"][0]["kept"], journaled);
  EXPECT_FALSE(fs::exists(dir_ / "res/run.journal.jsonl"));
}

// A run killed outright (SIGKILL) after a destructive vector ran, to resume
// in the tests below: its journal has no end record, and names the backup
// taken before the first destructive vector in its backup record.
class AKilledDestructiveRun : public Resume {
 protected:
  void SetUp() override {
    Resume::SetUp();
    sim_ = std::make_unique<Sim>();
    ASSERT_FALSE(sim_->address.empty());
    {
      Process run(run_args(*sim_, "res"));
      wait_for("res", 9);
    }  // SIGKILL
    ASSERT_EQ(json::parse(slurp(dir_ / "res/run.json"))["status"], "running");
    journal_ = slurp(dir_ / "res/run.journal.jsonl");
    const std::string line = std::string("\n").append(backup_record()).append("\n");
    ASSERT_NE(journal_.find(line), std::string::npos) << "no backup record " << backup_record();
    ASSERT_NE(journal_.find("{\"id\":\"3.10-"), std::string::npos) << "no destructive vector ran";
  }
  std::string backup_record() const {
    return nlohmann::ordered_json{{"record", "backup"}, {"file", path("res/backup.json")}}.dump();
  }
  // The journal with its backup record replaced by `line` ("": left out).
  void replace_backup_record(const std::string& line) {
    std::string text = journal_;
    const std::string record = backup_record() + "\n";
    text.replace(text.find(record), record.size(), line.empty() ? "" : line + "\n");
    std::ofstream(path("res/run.journal.jsonl"), std::ios::binary | std::ios::trunc) << text;
    journal_ = text;
  }
  std::unique_ptr<Sim> sim_;
  std::string journal_;
};

// A journal without the backup record (as an earlier sabus wrote it) does
// not say where the backup taken before the destructive vector is: the
// restore at the end could not be complete; refused, the journal left as it
// was.
TEST_F(AKilledDestructiveRun, WithoutABackupRecordItIsRefused) {
  replace_backup_record("");
  const auto r = shell(kSabus + " run --resume " + path("res/run.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("the run was killed after a destructive vector (3.10-"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("its journal does not name the stored-data backup it took before it (no backup record)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(slurp(dir_ / "res/run.journal.jsonl"), journal_);
}

// A backup record without its file names the journal's line.
TEST_F(AKilledDestructiveRun, AMalformedBackupRecordIsRefusedNamingItsLine) {
  std::size_t line = 1;
  for (std::size_t i = 0; i < journal_.find(backup_record()); ++i) line += journal_[i] == '\n';
  replace_backup_record("{\"record\":\"backup\",\"file\":\"\"}");
  const auto r = shell(kSabus + " run --resume " + path("res/run.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --resume " + path("res/run.journal.jsonl") + ":" + std::to_string(line) +
                       ": a backup record without its file (\"file\": the stored-data backup file, a string)\n");
  EXPECT_EQ(slurp(dir_ / "res/run.journal.jsonl"), journal_);
}

// The backup file the record names is gone: the restore could not be
// complete without it.
TEST_F(AKilledDestructiveRun, ABackupFileThatCannotBeReadIsRefused) {
  fs::rename(dir_ / "res/backup.json", dir_ / "elsewhere.json");
  const auto r = shell(kSabus + " run --resume " + path("res/run.json") + " 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --resume " + path("res/backup.json") +
                       ": cannot read the stopped run's stored-data backup (the restore at the end needs it)\n");
  EXPECT_EQ(slurp(dir_ / "res/run.journal.jsonl"), journal_);
}

// Killed after a destructive vector, resumed from its journal: one run, as
// if never stopped; the restore at the end writes back the backup the
// journal names, taken before the kill, and no second one is taken.
TEST_F(AKilledDestructiveRun, ResumedItIsTheUninterruptedRun) {
  EXPECT_EQ(checks::journal_problems(journal_), checks::Problems{});
  const std::size_t journaled = journaled_vectors(dir_ / "res/run.journal.jsonl");
  Process resumed({kSabus, "run", "--resume", path("res/run.journal.jsonl")});
  const std::string out = resumed.read_all(60s);
  ASSERT_EQ(resumed.wait_exit_for(30s), 0) << out;
  EXPECT_NE(out.find("resuming " + path("res/run.json") + ", killed at "), std::string::npos) << out;
  run_uninterrupted();
  expect_one_run(out, "killed", *sim_);
  EXPECT_EQ(json::parse(slurp(dir_ / "res/run.json"))["resumptions"][0]["kept"], journaled);
}

}  // namespace
}  // namespace sabus::reports
