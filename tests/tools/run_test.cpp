// `sabus run` end to end: against `sabus sim --pty --emulate-line` through the
// serial transport, against `sabus sim --tcp`, and in-process with a fault.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <nlohmann/json.hpp>
#include <set>
#include <map>
#include <sstream>

#include "process.hpp"
#include "shipped_suite.hpp"
#include "sabus/reports/document.hpp"
#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

using test::Process;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

std::string temp_path(const std::string& name) { return test::temp_path("run", name); }

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return nlohmann::json::parse(ss.str());
}

const std::string kVectors = std::string(SABUS_SOURCE_DIR) + "/vectors/framing.yaml";

TEST(Run, OverAPtyWithAnEmulatedLine) {
  const std::string link = temp_path("pty");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--emulate-line"});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const std::string json = temp_path("pty.json");
  Process run({SABUS_BIN, "run", "--port", link, "--vectors", kVectors, "--pace", "0", "--json", json});
  EXPECT_EQ(run.wait_exit(), 0);
  const auto doc = read_json(json);
  EXPECT_EQ(doc["status"], "complete");
  EXPECT_GT(doc["summary"]["passed"].get<int>(), 0);
  EXPECT_EQ(doc["summary"]["failed"].get<int>(), 0);
  EXPECT_NE(doc["device"].get<std::string>().find("termios"), std::string::npos) << "a pty takes the termios backend";
  EXPECT_EQ(sim.interrupt(), 0);
  fs::remove(json);
}

// A controller whose replies take 300 ms (the profile's turnaround_ms, which
// `sabus sim --emulate-line` applies): the runner waits for them from the
// first command on, and a silence window lasts longer than the turnaround,
// so no reply spills into the next step.
TEST(Run, ASlowControllerWithinItsStatedTurnaround) {
  const std::string profile = temp_path("slow.yaml");
  {
    std::ofstream out(profile);
    out << "name: slow\nturnaround_ms: 300\n";
  }
  const std::string link = temp_path("slow-pty");
  Process sim({SABUS_BIN, "sim", "--pty", "--link", link, "--emulate-line", "--profile", profile});
  ASSERT_EQ(sim.line(5s), "READY " + link);
  const std::string json = temp_path("slow.json");
  Process run({SABUS_BIN, "run", "--port", link, "--profile", profile, "--vectors", kVectors, "--filter",
               "framing-*-silence", "--filter", "framing-check-byte-*", "--pace", "0", "--json", json});
  EXPECT_EQ(run.wait_exit_for(60s), 0);
  const auto doc = read_json(json);
  EXPECT_GT(doc["summary"]["passed"].get<int>(), 3);
  EXPECT_EQ(doc["summary"]["failed"].get<int>(), 0);
  EXPECT_EQ(sim.interrupt(), 0);
  fs::remove(json);
  fs::remove(profile);
}

TEST(Run, OverTcp) {
  Process sim({SABUS_BIN, "sim", "--tcp", "127.0.0.1:0"});
  const std::string ready = sim.line(5s);
  ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
  const std::string port = ready.substr(ready.rfind(':') + 1);
  Process run({SABUS_BIN, "run", "--tcp", "127.0.0.1:" + port, "--vectors", kVectors, "--pace", "0"});
  EXPECT_EQ(run.wait_exit(), 0);
  EXPECT_EQ(sim.interrupt(), 0);
}

TEST(Run, InProcessWithAFaultFailsAndWritesJUnit) {
  const std::string junit = temp_path("junit.xml");
  Process run({SABUS_BIN, "run", "--sim", "--fault", "short-status", "--junit", junit});
  EXPECT_EQ(run.wait_exit(), 1);
  std::ifstream in(junit);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("<testsuite name=\"§"), std::string::npos);
  EXPECT_NE(ss.str().find("<failure message="), std::string::npos);
  fs::remove(junit);
}

TEST(Run, UnreachableDeviceExits3AndUsageExits2) {
  // A device that answers some frames is reachable: its failures exit 1.
  EXPECT_EQ(Process({SABUS_BIN, "run", "--sim", "--fault", "check-byte-stx-restarts"}).wait_exit(), 1);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--port", "/nonexistent/tty"}).wait_exit(), 3);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--level", "sometimes"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--sim", "--fault", "no-such-fault"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--tcp", "127.0.0.1:abc"}).wait_exit(), 2);
  EXPECT_EQ(Process({SABUS_BIN, "run", "--tcp", "127.0.0.1:70000"}).wait_exit(), 2);
}

// ---- a run that checked nothing is not a success ---------------------------------

using test::shell;
const std::string kSabus = SABUS_BIN;

// The mistyped filter of the issue: nothing selected, said before the device
// is touched, exit 5.
TEST(Run, AFilterThatMatchesNothingExits5AndSaysWhy) {
  const auto r = shell(kSabus + " run --filter '3.2-stauts*' 2>&1");
  EXPECT_EQ(r.status, 5) << r.out;
  EXPECT_NE(r.out.find("--filter '3.2-stauts*' matches no vector id"), std::string::npos) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(NOTHING RAN: no vector matches --filter '3\.2-stauts\*' \([1-9][0-9]* vectors loaded;)")))
      << r.out;
  EXPECT_EQ(r.out.find("0 passed"), std::string::npos) << "no run, no summary line: " << r.out;
  EXPECT_EQ(shell(kSabus + " run --paragraph 9.9 2>&1").status, 5);
  EXPECT_EQ(shell(kSabus + " run --filter '3.1-*' --exclude '3.1-*' 2>&1").status, 5);
}

// §3.4's vectors all move the antenna (or need another profile): without
// --allow-motion every one is skipped, so nothing ran.
TEST(Run, EverythingSkippedExits5WithTheSkipsByCause) {
  const auto r = shell(kSabus + " run --filter '3.4-*' --json " + temp_path("skipped.json") + " 2>&1");
  EXPECT_EQ(r.status, 5) << r.out;
  EXPECT_NE(r.out.find("\n0 passed, 0 failed, 36 skipped (4 need another profile, 32 need --allow-motion)\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\nNOTHING RAN: all 36 vectors selected were skipped (4 need another profile, 32 need "
                       "--allow-motion); a run that checked nothing is not a success (exit 5)\n"),
            std::string::npos)
      << r.out;
  const auto doc = read_json(temp_path("skipped.json"));
  EXPECT_EQ(doc["summary"]["exit_code"], 5);
  EXPECT_EQ(doc["summary"]["skipped_by_cause"], nlohmann::json({{"motion", 32}, {"profile", 4}}));
  EXPECT_EQ(doc["vectors"][0]["skip_cause"], "motion");
  fs::remove(temp_path("skipped.json"));
  // With motion allowed the same selection runs, and passes.
  EXPECT_EQ(shell(kSabus + " run --filter '3.4-*' --allow-motion >/dev/null 2>&1").status, 0);
  // A vector above --level is skipped for that cause.
  const auto level = shell(kSabus + " run --filter '3.12-*' --level must -q");
  EXPECT_EQ(level.status, 5);
  EXPECT_NE(level.out.find(" skipped (2 above --level, "), std::string::npos) << level.out;
}

// A plain run skips vectors for three causes: the summary line and
// summary.md say why, with the counts.
TEST(Run, TheSummaryLineAndSummaryMdCountTheSkipsByCause) {
  const std::string md = temp_path("summary.md");
  const auto r = shell(kSabus + " run -q --md " + md);
  EXPECT_EQ(r.status, 0) << r.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_match(r.out, m,
                               std::regex(R"(([1-9][0-9]* passed, 0 failed, [1-9][0-9]* skipped \([1-9][0-9]* need another )"
                                          R"(profile, [1-9][0-9]* need --allow-motion, [1-9][0-9]* need --allow-destructive\)))"
                                          "\n")))
      << r.out;
  const std::string line = m[1];
  std::ifstream in(md);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("\n" + line + "\n"), std::string::npos) << ss.str();
  fs::remove(md);
}

TEST(Run, AnUnknownIdInKnownIssuesIsAnError) {
  const std::string known = temp_path("known.txt");
  std::ofstream(known) << "# reasons\n3.2-status-track-byte: vendor ticket 1234\n3.2-status-trak-byte: a typo\n";
  const auto r = shell(kSabus + " run --filter '3.1-*' --known-issues " + known + " 2>&1");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find(known + ":3: no vector has the id \"3.2-status-trak-byte\""), std::string::npos) << r.out;
  std::ofstream(known) << "3.2-status-track-byte: vendor ticket 1234\n";
  EXPECT_EQ(shell(kSabus + " run --filter '3.1-*' --known-issues " + known + " >/dev/null 2>&1").status, 0)
      << "a known id outside the selection is fine";
  EXPECT_EQ(shell(kSabus + " run --known-issues /no/such/file 2>&1").status, 2);
  fs::remove(known);
}

// Out-of-range values are usage errors naming the option (CLI11 validators).
TEST(Run, NegativeAndOutOfRangeValuesAreUsageErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"run --pace -5", "--pace: Value -5 not in range 0 to 60000"},
      {"run --pace 60001", "--pace: Value 60001 not in range 0 to 60000"},
      {"run --repeat -1", "--repeat: Value -1 not in range 0 to 100"},
      {"run --seed -1", "--seed: Value -1 is not a number 0 or more"},
      {"run --baud 0", "--baud: Value 0 not in range 300 to 115200"},
      {"run --level sometimes", "--level: sometimes not in {must,should,informative}"},
      {"fuzz --pace -1", "--pace: Value -1 not in range 0 to 60000"},
      {"fuzz --max-frames -1", "--max-frames: Value -1 is not a number 0 or more"},
      {"fuzz --max-time -0.5", "--max-time: Value -0.5 is not a number 0 or more"},
      {"fuzz --max-findings 0", "--max-findings: Value 0 not in range 1 to 1000"},
      {"fuzz --liveness-every -3", "--liveness-every: Value -3 is not a number 0 or more"},
      {"sim --tcp 127.0.0.1:0 --turnaround -2", "--turnaround: Value -2 not in range"},
      {"sim --tcp 127.0.0.1:0 --baud 100", "--baud: Value 100 not in range 300 to 115200"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = shell(kSabus + " " + args + " 2>&1");
    EXPECT_EQ(r.status, 2) << args << ": " << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << ": " << r.out;
  }
  EXPECT_EQ(shell(kSabus + " run --filter '3.1-*' --pace 0 --repeat 0 --seed 0 >/dev/null 2>&1").status, 0) << "0 is fine";
}


// '3.2*' also matches §3.20-§3.25; --paragraph takes §3.2 exactly.
TEST(Run, ParagraphSelectsOneParagraphAndAGlobOverSeveralIsNoted) {
  const auto glob = shell(kSabus + " run --filter '3.2*' 2>&1");
  EXPECT_NE(glob.out.find("--filter '3.2*' matches vectors of 7 paragraphs (§3.2, §3.20, §3.21, §3.22, §3.23, §3.24, "
                          "§3.25); --paragraph 3.2 selects §3.2 alone"),
            std::string::npos)
      << glob.out;
  const std::string json = temp_path("paragraph.json");
  const auto exact = shell(kSabus + " run --paragraph 3.2 --json " + json + " 2>&1");
  EXPECT_EQ(exact.status, 0) << exact.out;
  EXPECT_EQ(exact.out.find("matches vectors of"), std::string::npos) << exact.out;
  const auto doc = read_json(json);
  EXPECT_EQ(doc["planned"], test::shipped_vectors_in(SABUS_SOURCE_DIR, "3.2-status.yaml", "3.2-"));
  for (const auto& v : doc["vectors"]) EXPECT_EQ(v["paragraph"], "3.2") << v["id"];
  EXPECT_EQ(doc["options"]["paragraphs"], nlohmann::json::array({"3.2"}));
  fs::remove(json);
  // With a glob: both hold (counted here from the plain list).
  const auto list = shell(kSabus + " vectors list");
  int agc_of_3_2 = 0;
  std::istringstream lines(list.out);
  for (std::string l; std::getline(lines, l);) agc_of_3_2 += l.find("-agc-") != std::string::npos && l.find(" §3.2 ") != std::string::npos;
  ASSERT_GT(agc_of_3_2, 0);
  const auto both = shell(kSabus + " run --paragraph §3.2 --filter '*-agc-*' -q --json " + json);
  EXPECT_EQ(read_json(json)["planned"].get<int>(), agc_of_3_2) << both.out;
  fs::remove(json);
}

// Against the in-process controller nothing outlives the run: no backup
// file, no RESTORE notes.
TEST(Run, NoBackupOrRestoreAgainstTheInProcessController) {
  const std::string dir = temp_path("destructive");
  const auto r = shell(kSabus + " run --paragraph 3.10 --allow-destructive --report-dir " + dir + " 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("RESTORE"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("backed up"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "backup.json"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "run.json"));
  EXPECT_TRUE(read_json((fs::path(dir) / "run.json").string())["restore"].empty());
  fs::remove_all(dir);
}

// On a line the device outlives the run: its stored data is backed up
// before the first destructive vector and restored after.
TEST(Run, ARealDeviceIsStillBackedUpAndRestored) {
  Process sim({SABUS_BIN, "sim", "--tcp", "127.0.0.1:0"});
  const std::string ready = sim.line(5s);
  ASSERT_EQ(ready.rfind("READY tcp 127.0.0.1:", 0), 0u) << ready;
  const std::string dir = temp_path("backup");
  const auto r = shell(kSabus + " run --tcp 127.0.0.1:" + ready.substr(ready.rfind(':') + 1) +
                       " --paragraph 3.10 --allow-destructive --pace 0 --report-dir " + dir + " 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("stored data backed up to " + dir + "/backup.json"), std::string::npos) << r.out;
  const auto backup = read_json((fs::path(dir) / "backup.json").string());
  EXPECT_EQ(backup["store_names"].size(), 3u) << backup;
  EXPECT_TRUE(backup["presets"].contains("1")) << backup;
  EXPECT_TRUE(backup["tles"].is_object() && backup["signposts"].is_object() && backup["navigation"].is_string()) << backup;
  // Again into the same folder: the first backup may be the only copy of
  // what the device held, and stays; the second goes beside it.
  const std::string first = test::slurp(fs::path(dir) / "backup.json");
  const auto again = shell(kSabus + " run --tcp 127.0.0.1:" + ready.substr(ready.rfind(':') + 1) +
                           " --paragraph 3.10 --allow-destructive --pace 0 --report-dir " + dir + " 2>&1");
  EXPECT_EQ(again.status, 0) << again.out;
  EXPECT_NE(again.out.find("stored data backed up to " + dir + "/backup-2.json"), std::string::npos) << again.out;
  EXPECT_EQ(test::slurp(fs::path(dir) / "backup.json"), first);
  EXPECT_EQ(read_json((fs::path(dir) / "backup-2.json").string())["store_names"], backup["store_names"]);
  EXPECT_EQ(sim.interrupt(), 0);
  fs::remove_all(dir);
}

// ---- re-runs and shards (issue 34): each run JSON read back by the run
// document's reader ------------------------------------------------------

reports::RunDocument read_run(const std::string& path) {
  std::string error;
  auto doc = reports::read_run_file(path, error);
  EXPECT_TRUE(doc) << error;
  return doc.value_or(reports::RunDocument{});
}

std::set<std::string> ids_of(const reports::RunDocument& d) {
  std::set<std::string> out;
  for (const auto& v : d.vectors) out.insert(v.id);
  return out;
}

TEST(Run, LastFailedAndFailedFirstNameABadFileAndExit2) {
  const auto missing = shell(kSabus + " run --last-failed /no/such/run.json 2>&1");
  EXPECT_EQ(missing.status, 2) << missing.out;
  EXPECT_NE(missing.out.find("sabus run: --last-failed: /no/such/run.json: no such file"), std::string::npos) << missing.out;
  const std::string bad = temp_path("bad-run.json");
  std::ofstream(bad) << "{\"schema\": \"sabus-run\", ";
  const auto broken = shell(kSabus + " run --failed-first " + bad + " 2>&1");
  EXPECT_EQ(broken.status, 2) << broken.out;
  EXPECT_NE(broken.out.find("sabus run: --failed-first: " + bad + ": not JSON"), std::string::npos) << broken.out;
  const auto both = shell(kSabus + " run --last-failed " + bad + " --failed-first " + bad + " 2>&1");
  EXPECT_EQ(both.status, 2) << both.out;
  fs::remove(bad);
}

// A run with a fault, then --last-failed on a controller without it: only
// the vectors that failed run, and pass; --failed-first runs them first,
// then the rest.
TEST(Run, LastFailedRunsOnlyTheFailuresOfTheEarlierRunAndFailedFirstRunsThemFirst) {
  const std::string first = temp_path("first.json"), again = temp_path("again.json"), ordered = temp_path("ordered.json");
  // The as-found vectors (3.2-status-power-on-*) run first whatever the
  // order asked for: left out, so the order is --failed-first's alone.
  const std::string selection = " --paragraph 3.2 --exclude '3.2-status-power-on-*'";
  EXPECT_EQ(shell(kSabus + " run -q --fault short-status" + selection + " --json " + first + " >/dev/null 2>&1").status, 1);
  const reports::RunDocument f = read_run(first);
  std::set<std::string> failed;
  for (const auto& v : f.vectors)
    if (v.is_failure()) failed.insert(v.id);
  ASSERT_FALSE(failed.empty());
  ASSERT_LT(failed.size(), f.vectors.size());
  EXPECT_EQ(shell(kSabus + " run -q --last-failed " + first + " --json " + again + " >/dev/null 2>&1").status, 0);
  const reports::RunDocument a = read_run(again);
  EXPECT_EQ(ids_of(a), failed);
  EXPECT_EQ(a.options.value("last_failed", ""), first);
  for (const auto& v : a.vectors) EXPECT_EQ(v.outcome, "pass") << v.id;
  EXPECT_EQ(shell(kSabus + " run -q" + selection + " --failed-first " + first + " --json " + ordered + " >/dev/null 2>&1").status, 0);
  const reports::RunDocument o = read_run(ordered);
  ASSERT_EQ(o.vectors.size(), f.vectors.size());
  for (std::size_t i = 0; i < o.vectors.size(); ++i)
    EXPECT_EQ(failed.count(o.vectors[i].id) > 0, i < failed.size()) << i << " " << o.vectors[i].id;
  for (const auto& p : {first, again, ordered}) fs::remove(p);
}

// -x: the run stops after the first must-level failure, exits 1, and the
// JSON and JUnit say it was aborted and what did not run.
TEST(Run, ExitFirstStopsAtTheFirstFailureAndTheReportsSayWhatDidNotRun) {
  const std::string json = temp_path("x.json"), junit = temp_path("x.xml");
  const auto r = shell(kSabus + " run --fault short-status -x --json " + json + " --junit " + junit + " 2>&1");
  EXPECT_EQ(r.status, 1) << r.out;
  const reports::RunDocument d = read_run(json);
  EXPECT_EQ(d.status, "aborted");
  ASSERT_FALSE(d.vectors.empty());
  EXPECT_TRUE(d.vectors.back().is_failure()) << d.vectors.back().id;
  EXPECT_EQ(std::count_if(d.vectors.begin(), d.vectors.end(), [](const auto& v) { return v.is_failure(); }), 1);
  EXPECT_LT(d.vectors.size(), d.planned);
  const std::string stop = "stopped at the first failure (--exitfirst): " + d.vectors.back().id + " failed; " +
                           std::to_string(d.planned - d.vectors.size()) + " vector(s) did not run: ";
  EXPECT_EQ(d.abort_reason.rfind(stop, 0), 0u) << d.abort_reason;
  EXPECT_TRUE(d.options.value("exit_first", false));
  std::ifstream in(junit);
  std::stringstream xml;
  xml << in.rdbuf();
  EXPECT_NE(xml.str().find("stopped at the first failure (--exitfirst)"), std::string::npos);
  fs::remove(json);
  fs::remove(junit);
}

// --shard K/N over every K runs each vector of the selection exactly once.
TEST(Run, TheShardsOfARunRunEachVectorOnce) {
  const std::string whole = temp_path("whole.json");
  shell(kSabus + " run -q --json " + whole + " >/dev/null 2>&1");
  const std::set<std::string> all = ids_of(read_run(whole));
  ASSERT_GT(all.size(), 100u);
  std::map<std::string, int> seen;
  for (int k = 1; k <= 3; ++k) {
    const std::string part = temp_path("shard-" + std::to_string(k) + ".json");
    shell(kSabus + " run -q --shard " + std::to_string(k) + "/3 --json " + part + " >/dev/null 2>&1");
    const reports::RunDocument d = read_run(part);
    EXPECT_EQ(d.options.value("shard", ""), std::to_string(k) + "/3");
    for (const auto& v : d.vectors) ++seen[v.id];
    fs::remove(part);
  }
  EXPECT_EQ(seen.size(), all.size());
  for (const auto& id : all) EXPECT_EQ(seen[id], 1) << id;
  const auto bad = shell(kSabus + " run --shard 4/3 2>&1");
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_NE(bad.out.find("sabus run: --shard 4/3: K must be between 1 and N (3)"), std::string::npos) << bad.out;
  fs::remove(whole);
}

}  // namespace
}  // namespace sabus::harness
