// An earlier run read back for --last-failed and --failed-first: through the
// run document's readers, its JSON or the journal of a run that did not end;
// a missing or bad file is an error naming it.
#include "sabus/reports/rerun.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "sabus/reports/journal.hpp"
#include "sample_run.hpp"
#include "temp_dir.hpp"

namespace sabus::reports {
namespace {

using test_documents::sample_header;
using test_documents::sample_vector;

class EarlierRunFile : public test::TempDirTest {
 protected:
  EarlierRunFile() : TempDirTest("sabus-rerun-test") {}
  RunDocument document() {
    RunDocument d = sample_header();
    for (const auto& [id, outcome] : std::vector<std::pair<std::string, std::string>>{
             {"a", "pass"}, {"b", "fail"}, {"c", "unexpected pass"}, {"d", "known failure"}, {"e", "inconclusive"}, {"f", "skip"},
             {"g", "error"}})
      d.vectors.push_back(sample_vector(id, outcome));
    d.status = "complete";
    d.finished_at = "2024-01-01T00:00:01Z";
    d.summary = d.counts();
    return d;
  }
};

TEST_F(EarlierRunFile, AMissingOrBadFileIsAnErrorNamingIt) {
  std::string error;
  EXPECT_FALSE(read_earlier_run(path("none.json"), error));
  EXPECT_EQ(error, path("none.json") + ": no such file (give the run.json of an earlier `sabus run --json` or --report-dir)");
  // A folder without a run.json: the file it would hold is named.
  EXPECT_FALSE(read_earlier_run(dir_.string(), error));
  EXPECT_EQ(error.rfind(path("run.json") + ": no such file", 0), 0u) << error;
  std::ofstream(path("bad.json")) << "{\"schema\": ";
  EXPECT_FALSE(read_earlier_run(path("bad.json"), error));
  EXPECT_EQ(error.rfind(path("bad.json") + ": not JSON", 0), 0u) << error;
  std::ofstream(path("other.json")) << "{\"schema\": \"something-else\"}";
  EXPECT_FALSE(read_earlier_run(path("other.json"), error));
  EXPECT_EQ(error.rfind(path("other.json") + ": ", 0), 0u) << error;
}

// The run JSON as `sabus run` writes it, read back: the vectors to run again
// are those that failed the run (fail, unexpected pass) and those the line
// left unjudged (error), not the known failures, inconclusive or skipped
// ones. A folder means its run.json.
TEST_F(EarlierRunFile, TheFailuresOfAWrittenRunAreReadBack) {
  std::string error;
  ASSERT_TRUE(write_run_json(path("run.json"), document(), error)) << error;
  for (const std::string& given : {path("run.json"), dir_.string()}) {
    const auto run = read_earlier_run(given, error);
    ASSERT_TRUE(run) << error;
    EXPECT_EQ(run->file, path("run.json"));
    EXPECT_EQ(run->vectors, 7u);
    EXPECT_EQ(run->failed, (std::set<std::string>{"b", "c", "g"}));
  }
}

// A run that was killed left its journal: its vectors so far are read.
TEST_F(EarlierRunFile, TheJournalOfARunThatDidNotEndIsReadToo) {
  RunDocument d = sample_header();
  JournalWriter w;
  ASSERT_TRUE(w.open(path("run.journal.jsonl"), d)) << w.error();
  ASSERT_TRUE(w.append(sample_vector("a", "fail"))) << w.error();
  ASSERT_TRUE(w.append(sample_vector("b", "pass"))) << w.error();
  ASSERT_TRUE(w.append(sample_vector("c", "error"))) << w.error();
  std::string error;
  const auto run = read_earlier_run(path("run.journal.jsonl"), error);
  ASSERT_TRUE(run) << error;
  EXPECT_EQ(run->failed, (std::set<std::string>{"a", "c"}));
}

}  // namespace
}  // namespace sabus::reports
