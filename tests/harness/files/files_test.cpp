// Files written whole or not at all (files.hpp): the refusals first, then
// what is written where; on every path the folder holds no temporary after.
#include "sabus/harness/files.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

namespace fs = std::filesystem;
using test::slurp;

class Files : public test::TempDirTest {
 protected:
  Files() : TempDirTest("sabus-files-test") {}
  void put(const std::string& name, const std::string& text) { std::ofstream(path(name)) << text; }
  // The folder's names: a temporary left behind shows here.
  std::set<std::string> names() const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.insert(e.path().filename().string());
    return out;
  }
};

// ---- replace_file ------------------------------------------------------------

TEST_F(Files, ReplaceRefusesAFolderAndLeavesItAlone) {
  fs::create_directory(path("d"));
  std::string error;
  EXPECT_FALSE(replace_file(path("d"), "x", error));
  EXPECT_EQ(error, path("d") + " is a directory, not a regular file; not replaced");
  EXPECT_TRUE(fs::is_directory(path("d")));
  EXPECT_EQ(names(), std::set<std::string>{"d"});
}

TEST_F(Files, ReplaceRefusesALinkToNothing) {
  fs::create_symlink(path("nowhere"), path("link"));
  std::string error;
  EXPECT_FALSE(replace_file(path("link"), "x", error));
  EXPECT_NE(error.find("a symbolic link to a file that does not exist"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(path("nowhere")));
  EXPECT_EQ(names(), std::set<std::string>{"link"});
}

TEST_F(Files, ReplaceInAMissingFolderIsAnErrorNamingIt) {
  std::string error;
  EXPECT_FALSE(replace_file(path("no/such/file"), "x", error));
  EXPECT_NE(error.find(path("no/such/file")), std::string::npos) << error;
  EXPECT_TRUE(names().empty());
}

TEST_F(Files, ReplaceWritesANewFileAndReplacesAnOldOneWhole) {
  std::string error;
  ASSERT_TRUE(replace_file(path("f"), "first\n", error)) << error;
  EXPECT_EQ(slurp(path("f")), "first\n");
  ASSERT_TRUE(replace_file(path("f"), "second", error)) << error;
  EXPECT_EQ(slurp(path("f")), "second");
  EXPECT_EQ(names(), std::set<std::string>{"f"});
  // The mode of any new file, not mkstemp's 0600.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(static_cast<unsigned>(fs::status(path("f")).permissions()), 0666u & ~mask);
}

TEST_F(Files, ReplaceWritesThroughALinkAndKeepsTheLink) {
  put("target", "old");
  fs::create_symlink(path("target"), path("link"));
  std::string error;
  ASSERT_TRUE(replace_file(path("link"), "new", error)) << error;
  EXPECT_TRUE(fs::is_symlink(path("link")));
  EXPECT_EQ(slurp(path("target")), "new");
  EXPECT_EQ(names(), (std::set<std::string>{"link", "target"}));
}

TEST_F(Files, ReplaceLeavesAFileNamedLikeItsTemporaryAlone) {
  // The temporary's name is made unique (mkstemp): a file "f.tmp" is not it.
  put("f.tmp", "someone else's");
  std::string error;
  ASSERT_TRUE(replace_file(path("f"), "mine", error)) << error;
  EXPECT_EQ(slurp(path("f.tmp")), "someone else's");
  EXPECT_EQ(names(), (std::set<std::string>{"f", "f.tmp"}));
}

// ---- write_new_file ----------------------------------------------------------

TEST_F(Files, NewFileInAMissingFolderIsAnErrorAndLeavesNothing) {
  std::string error;
  EXPECT_FALSE(write_new_file(path("no/such/backup.json"), "x", error));
  EXPECT_NE(error.find(path("no/such/backup.json")), std::string::npos) << error;
  EXPECT_TRUE(names().empty());
}

TEST_F(Files, NewFileNeverReplacesAndTakesTheNextFreeName) {
  put("backup.json", "the first run's");
  put("backup-2.json", "the second run's");
  std::string error;
  const auto written = write_new_file(path("backup.json"), "the third run's", error);
  ASSERT_TRUE(written) << error;
  EXPECT_EQ(*written, path("backup-3.json"));
  EXPECT_EQ(slurp(path("backup.json")), "the first run's");
  EXPECT_EQ(slurp(path("backup-2.json")), "the second run's");
  EXPECT_EQ(slurp(path("backup-3.json")), "the third run's");
  EXPECT_EQ(names(), (std::set<std::string>{"backup.json", "backup-2.json", "backup-3.json"}));
}

TEST_F(Files, NewFileTakesTheNameItWasGivenWhenFree) {
  std::string error;
  const auto written = write_new_file(path("run.json.backup.json"), "{}\n", error);
  ASSERT_TRUE(written) << error;
  EXPECT_EQ(*written, path("run.json.backup.json"));
  EXPECT_EQ(slurp(*written), "{}\n");
  EXPECT_EQ(names(), std::set<std::string>{"run.json.backup.json"});
  // A link counts as taken, even one to nothing: it is not written through.
  fs::create_symlink(path("nowhere"), path("x.json"));
  const auto beside = write_new_file(path("x.json"), "y", error);
  ASSERT_TRUE(beside) << error;
  EXPECT_EQ(*beside, path("x-2.json"));
  EXPECT_FALSE(fs::exists(path("nowhere")));
}

TEST_F(Files, NewFileGivesUpWhenEveryNameIsTaken) {
  put("b.json", "");
  for (int i = 2; i <= kNewFileTries; ++i) put("b-" + std::to_string(i) + ".json", "");
  std::string error;
  EXPECT_FALSE(write_new_file(path("b.json"), "x", error));
  EXPECT_NE(error.find("are taken; nothing replaced"), std::string::npos) << error;
  EXPECT_EQ(names().size(), static_cast<std::size_t>(kNewFileTries)) << "no temporary left";
}

}  // namespace
}  // namespace sabus::harness
