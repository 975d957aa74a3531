// Where `sabus run` and `sabus report` write their reports: "-" is standard
// output (and the console moves to standard error); special files, links to
// them, this process's own standard output, two reports on one file, and the
// journal an unfinished run left are refused before the device is touched,
// and left as they were.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "process.hpp"
#include "temp_dir.hpp"

namespace sabus::test {
namespace {

namespace fs = std::filesystem;

const std::string kSabus = SABUS_BIN;

class ReportPaths : public TempDirTest {
 protected:
  ReportPaths() : TempDirTest("sabus-report-paths-test") {}
  // A command line run in the test's folder.
  ShellResult in_dir(const std::string& command) const { return shell("cd " + dir_.string() + " && " + command); }
};

TEST_F(ReportPaths, DashWritesTheJsonToStandardOutputAndTheConsoleToStandardError) {
  const auto r = in_dir(kSabus + " run --filter '3.1-*' --json - 2>console.txt");
  EXPECT_EQ(r.status, 0);
  const auto doc = nlohmann::json::parse(r.out);  // nothing else on standard output
  EXPECT_EQ(doc["status"], "complete");
  EXPECT_FALSE(doc.contains("journal"));
  ASSERT_EQ(doc["vectors"].size(), 6u);
  EXPECT_FALSE(doc["vectors"][0]["transcript"][0]["fields"].empty()) << "every field, from the run's journal";
  const std::string console = slurp(dir_ / "console.txt");
  EXPECT_NE(console.find("PASS 3.1-device-type-reply-length §3.1 must\n"), std::string::npos) << console;
  EXPECT_NE(console.find("5 passed, 0 failed, 1 skipped (1 need --allow-motion)\n"), std::string::npos) << console;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir_)) files.push_back(e.path().filename().string());
  EXPECT_EQ(files, std::vector<std::string>{"console.txt"}) << "no file named -, no journal left behind";

  const auto md = in_dir(kSabus + " run --filter '3.1-*' --md - --json run.json 2>/dev/null");
  EXPECT_EQ(md.out.rfind("### SAbus conformance: **PASS**\n", 0), 0u) << md.out;
  // `sabus report` too: the verdict line goes to standard error then.
  const auto report = in_dir(kSabus + " report run.json --junit - 2>verdict.txt");
  EXPECT_EQ(report.status, 0);
  EXPECT_EQ(report.out.rfind("<?xml", 0), 0u) << report.out;
  EXPECT_EQ(slurp(dir_ / "verdict.txt"), "PASS: 5 passed, 0 failed, 1 skipped (1 need --allow-motion) (complete)\n");
}

TEST_F(ReportPaths, TwoReportsOnStandardOutputOrOnOneFileAreRefused) {
  auto r = in_dir(kSabus + " run --json - --md - 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --json - and --md -: only one report can go to standard output\n");
  r = in_dir(kSabus + " run --json out.json --report-dir . --html out.json 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: --json and --html both name out.json\n");
  r = in_dir(kSabus + " report none.json --md - --html - 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus report: --html - and --md -: only one report can go to standard output\n");
  r = in_dir(kSabus + " run --report-dir - 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(ReportPaths, SpecialFilesAndLinksToThemAreRefusedBeforeTheRunAndLeftAlone) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  fs::create_symlink(path("fifo"), path("to-fifo.json"));
  fs::create_directory(path("folder"));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--json to-fifo.json", "--json to-fifo.json is a FIFO (named pipe) through the symbolic link to " + path("fifo")},
      {"--junit fifo", "--junit fifo is a FIFO (named pipe): reports are written to regular files only (- for standard output)"},
      {"--html folder", "--html folder is a directory"},
      {"--md /dev/null", "--md /dev/null is a character device"},
      {"--json missing/run.json", "--json missing/run.json: cannot write: no such directory missing"},
  };
  for (const auto& [option, why] : cases) {
    const auto r = in_dir(kSabus + " run --filter '3.1-*' " + option + " 2>&1");
    EXPECT_EQ(r.status, 2) << option;
    EXPECT_EQ(r.out.rfind("sabus run: " + why, 0), 0u) << r.out;
    EXPECT_EQ(r.out.find("device: controller"), std::string::npos) << "refused before the run: " << r.out;
  }
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("to-fifo.json"))));
  EXPECT_EQ(fs::read_symlink(path("to-fifo.json")), path("fifo"));
}

// `--json /dev/stdout > out.json` replaced /dev/stdout (as root). Here a link
// of the test's own stands for /dev/stdout: it names this process's standard
// output through /proc.
TEST_F(ReportPaths, ThisProcesssOwnStandardOutputByAnotherNameIsRefused) {
  fs::create_symlink("/proc/self/fd/1", path("stdout-link"));
  const auto r = in_dir(kSabus + " run --filter '3.1-*' --json stdout-link >out.txt 2>err.txt");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(slurp(dir_ / "err.txt"),
            "sabus run: --json stdout-link is this process's own standard output or error through the symbolic link "
            "to /proc/self/fd/1: give - for standard output\n");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("stdout-link"))));
  EXPECT_EQ(slurp(dir_ / "out.txt"), "");
}

// A link to a regular file is written through: the file gets the report,
// the link stays.
TEST_F(ReportPaths, ALinkToARegularFileIsWrittenThrough) {
  fs::create_directory(path("archive"));
  std::ofstream(path("archive/run-1.json")) << "old";
  fs::create_symlink(path("archive/run-1.json"), path("latest.json"));
  const auto r = in_dir(kSabus + " run --filter '3.1-*' -q --json latest.json");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("latest.json"))));
  EXPECT_EQ(nlohmann::json::parse(slurp(path("archive/run-1.json")))["status"], "complete");
}

// The journal of a run that did not end holds its results: a new run with
// the same JSON path is refused instead of truncating it.
TEST_F(ReportPaths, TheJournalOfAnUnfinishedRunIsNotOverwritten) {
  fs::create_directory(path("out"));
  std::ofstream(path("out/run.journal.jsonl")) << "{\"record\":\"header\",\"run\":{}}\n";
  const auto r = in_dir(kSabus + " run --filter '3.1-*' --report-dir out 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "sabus run: out/run.journal.jsonl exists: the journal of a run that did not end, with its results; "
                   "make its JSON with `sabus report out/run.journal.jsonl --json FILE`, or remove it\n");
  EXPECT_EQ(slurp(path("out/run.journal.jsonl")), "{\"record\":\"header\",\"run\":{}}\n");
  EXPECT_FALSE(fs::exists(path("out/run.json")));
}

}  // namespace
}  // namespace sabus::test
