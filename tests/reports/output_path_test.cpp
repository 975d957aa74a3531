// Where reports may be written: regular files and links to them, "-" for
// standard output; never a directory, a device, a pipe, a link to one, or
// this process's own standard output. The temporary-file-and-rename of the
// run JSON never replaces anything but a regular file.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "sabus/reports/journal.hpp"
#include "sabus/reports/writers.hpp"
#include "temp_dir.hpp"

namespace sabus::reports {
namespace {

namespace fs = std::filesystem;
using test::slurp;

class OutputPath : public test::TempDirTest {
 protected:
  OutputPath() : TempDirTest("sabus-output-path-test") {}
  static RunDocument doc() {
    RunDocument d;
    d.status = "complete";
    return d;
  }
  // The files in the test's folder, for "nothing else was created".
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

TEST_F(OutputPath, RegularFilesNewNamesAndLinksToRegularFilesAreWritten) {
  EXPECT_EQ(output_path_problem(path("new.json")), "");
  std::ofstream(path("old.json")) << "old";
  EXPECT_EQ(output_path_problem(path("old.json")), "");
  std::string error;
  ASSERT_TRUE(write_run_json(path("old.json"), doc(), error)) << error;
  EXPECT_NE(slurp(path("old.json")).find("\"sabus-run\""), std::string::npos);

  // Through a link: the file it names is replaced, the link stays a link.
  std::ofstream(path("target.json")) << "old";
  fs::create_symlink(path("target.json"), path("link.json"));
  ASSERT_TRUE(write_run_json(path("link.json"), doc(), error)) << error;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("link.json"))));
  EXPECT_NE(slurp(path("target.json")).find("\"sabus-run\""), std::string::npos);
  ASSERT_TRUE(write_file(path("link.json"), "text", error)) << error;
  EXPECT_EQ(slurp(path("target.json")), "text");
  EXPECT_EQ(entries(), (std::vector<std::string>{"link.json", "old.json", "target.json"})) << "no temporary file left";
  // A new file gets the mode any new file gets, not mkstemp's 0600.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(fs::status(path("old.json")).permissions(), static_cast<fs::perms>(0666 & ~mask));
}

TEST_F(OutputPath, DevicesDirectoriesPipesAndLinksToThemAreRefusedAndLeftAlone) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  fs::create_directory(path("folder"));
  fs::create_symlink("/dev/null", path("to-null"));
  fs::create_symlink(path("missing"), path("dangling"));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/dev/null", "/dev/null is a character device: reports are written to regular files only (- for standard output)"},
      {path("fifo"), path("fifo") + " is a FIFO (named pipe): reports are written to regular files only"},
      {path("folder"), path("folder") + " is a directory: reports are written to regular files only"},
      {path("to-null"), path("to-null") + " is a character device through the symbolic link to /dev/null"},
      {path("dangling"), path("dangling") + " is a symbolic link to " + path("missing") + ", which does not exist"},
      {path("no/such/dir.json"), path("no/such/dir.json") + ": cannot write: no such directory"},
  };
  for (const auto& [where, why] : cases) {
    EXPECT_EQ(output_path_problem(where).rfind(why, 0), 0u) << output_path_problem(where);
    std::string error;
    EXPECT_FALSE(write_run_json(where, doc(), error)) << where;
    EXPECT_EQ(error, output_path_problem(where));
    EXPECT_FALSE(write_file(where, "text", error)) << where;
    EXPECT_EQ(error, output_path_problem(where));
  }
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("to-null"))));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(path("dangling"))));
  EXPECT_FALSE(fs::exists(path("missing")));
  EXPECT_EQ(entries(), (std::vector<std::string>{"dangling", "fifo", "folder", "to-null"})) << "no temporary file left";
}

TEST_F(OutputPath, ThisProcesssOwnStandardOutputIsRefusedByName) {
  // `--json /dev/stdout > out.json`: the rename would replace the shell's file.
  const int saved = ::dup(STDOUT_FILENO);
  ASSERT_GE(saved, 0);
  {
    std::ofstream(path("stdout.txt")) << "";
    FILE* f = std::fopen(path("stdout.txt").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fflush(stdout);
    ::dup2(::fileno(f), STDOUT_FILENO);
    std::fclose(f);
    const std::string why = output_path_problem("/dev/stdout");
    std::fflush(stdout);
    ::dup2(saved, STDOUT_FILENO);
    ::close(saved);
    EXPECT_NE(why.find("/dev/stdout is this process's own standard output or error"), std::string::npos) << why;
    EXPECT_NE(why.find("give - for standard output"), std::string::npos) << why;
  }
  EXPECT_EQ(output_path_problem(path("stdout.txt")), "") << "the same file is fine once it is not standard output";
}

TEST_F(OutputPath, TwoReportsOnStandardOutputOrOnOneFileAreRefused) {
  EXPECT_EQ(report_paths_problem({{"--json", "-"}, {"--md", ""}, {"--html", path("r.html")}}), "");
  EXPECT_EQ(report_paths_problem({{"--json", "-"}, {"--md", "-"}}), "--json - and --md -: only one report can go to standard output");
  EXPECT_EQ(report_paths_problem({{"--html", path("x")}, {"--md", path("./x")}}), "--html and --md both name " + path("./x"));
  EXPECT_EQ(report_paths_problem({{"--junit", "/dev/null"}}).rfind("--junit /dev/null is a character device", 0), 0u);
}

TEST_F(OutputPath, ARenameNeverReplacesWhatBecameAnotherKindOfFile) {
  // The path is checked before the JSON is written and again just before
  // the rename. The journal here is a FIFO, so the writer waits in the middle
  // of its write until this test has put a FIFO where the report was.
  std::ofstream(path("run.json")) << "old";
  ASSERT_EQ(::mkfifo(path("run.journal.jsonl").c_str(), 0600), 0);
  std::thread swap([&] {
    std::ofstream journal(path("run.journal.jsonl"));  // opens once the writer reads it
    fs::remove(path("run.json"));
    ASSERT_EQ(::mkfifo(path("run.json").c_str(), 0600), 0);
    journal << "{\"record\":\"header\",\"run\":{}}\n";
  });
  std::string error;
  const bool written = write_run_json(path("run.json"), doc(), path("run.journal.jsonl"), error);
  swap.join();
  EXPECT_FALSE(written);
  EXPECT_EQ(error, path("run.json") + " is a FIFO (named pipe), not a regular file; not replaced (what was written is lost)");
  EXPECT_TRUE(fs::is_fifo(path("run.json")));
  EXPECT_EQ(entries(), (std::vector<std::string>{"run.journal.jsonl", "run.json"})) << "no temporary file left";
}

TEST(OutputPathStdout, DashWritesToStandardOutput) {
  testing::internal::CaptureStdout();
  std::string error;
  RunDocument d;
  d.status = "complete";
  const bool json_ok = write_run_json("-", d, error);
  const bool text_ok = write_file("-", "# summary\n", error);
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_TRUE(json_ok && text_ok) << error;
  EXPECT_EQ(out.rfind("{\n  \"schema\": \"sabus-run\"", 0), 0u) << out;
  EXPECT_NE(out.find("}\n# summary\n"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists("-"));
}

}  // namespace
}  // namespace sabus::reports
