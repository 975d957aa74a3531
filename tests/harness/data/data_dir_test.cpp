// The data directory lookup (data_dir.hpp): --data-dir, $SABUS_DATA_DIR, an
// installation beside the executable, the source tree, in that order.
#include "sabus/harness/data_dir.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

namespace sabus::harness {
namespace {

namespace fs = std::filesystem;

// Four directories: three hold data (a vectors/ folder), one does not.
class DataDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("sabus-data-dir-test-" + std::to_string(getpid()));
    fs::remove_all(root_);
    for (const char* name : {"option", "env", "installed"}) fs::create_directories(root_ / name / "vectors");
    fs::create_directories(root_ / "empty");
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string dir(const char* name) const { return (root_ / name).string(); }
  std::string source_tree() const { return dir("installed"); }  // any directory that holds data

  fs::path root_;
};

TEST_F(DataDirTest, TakesTheFirstPlaceInOrder) {
  DataDirPlaces places{dir("option"), dir("env"), dir("installed"), source_tree()};
  DataDir d = find_data_dir(places);
  ASSERT_TRUE(d.path);
  EXPECT_EQ(*d.path, dir("option"));
  EXPECT_EQ(d.source, DataDirSource::kOption);
  EXPECT_EQ(d.describe(), dir("option") + " (from --data-dir)");

  places.option.clear();
  d = find_data_dir(places);
  EXPECT_EQ(d.path.value_or(""), dir("env"));
  EXPECT_EQ(d.describe(), dir("env") + " (from $SABUS_DATA_DIR)");

  places.environment.clear();
  d = find_data_dir(places);
  EXPECT_EQ(d.path.value_or(""), dir("installed"));
  EXPECT_EQ(d.describe(), dir("installed") + " (installed beside the executable)");
  EXPECT_EQ(d.looked_in, (std::vector<std::string>{"--data-dir: not given", "$SABUS_DATA_DIR: not given"}));
}

TEST_F(DataDirTest, FallsBackToTheSourceTreeWhenNotInstalled) {
  const DataDir d = find_data_dir({"", "", dir("empty"), SABUS_SOURCE_DIR});
  ASSERT_TRUE(d.path) << d.error();
  EXPECT_EQ(d.source, DataDirSource::kSourceTree);
  EXPECT_EQ(d.describe(), fs::path(SABUS_SOURCE_DIR).lexically_normal().string() + " (source tree of this build)");
  EXPECT_EQ(d.looked_in.back(), "installed beside the executable " + dir("empty") + ": no vectors/ directory there");
}

TEST_F(DataDirTest, AWrongExplicitChoiceIsTheErrorWithNoFallThrough) {
  DataDir d = find_data_dir({dir("empty"), dir("env"), dir("installed"), source_tree()});
  EXPECT_FALSE(d.path);
  EXPECT_EQ(d.looked_in, std::vector<std::string>{"--data-dir " + dir("empty") + ": no vectors/ directory there"});

  d = find_data_dir({"", dir("missing"), dir("installed"), source_tree()});
  EXPECT_FALSE(d.path);
  EXPECT_EQ(d.looked_in.back(), "$SABUS_DATA_DIR " + dir("missing") + ": no such directory");
}

TEST_F(DataDirTest, NothingFoundNamesEveryPlaceLookedIn) {
  const DataDir d = find_data_dir({"", "", dir("missing"), dir("empty")});
  ASSERT_FALSE(d.path);
  EXPECT_EQ(d.error(),
            "no sabus data directory (vectors/, vectors/profiles/, protocol/ERRATA.md) found; looked in:\n"
            "  --data-dir: not given\n"
            "  $SABUS_DATA_DIR: not given\n"
            "  installed beside the executable " + dir("missing") + ": no such directory\n"
            "  source tree of this build " + dir("empty") + ": no vectors/ directory there\n"
            "give one with --data-dir DIR or the environment variable SABUS_DATA_DIR");
  EXPECT_EQ(d.describe(), "none found");
}

TEST_F(DataDirTest, PathsAreNormalized) {
  const DataDir d = find_data_dir({dir("empty") + "/../option/", "", "", ""});
  EXPECT_EQ(d.path.value_or(""), dir("option"));
}

// The process: the option set by the CLI takes precedence, and data_path
// throws, naming the places, when it holds no data.
TEST_F(DataDirTest, TheProcessOptionAndDataPath) {
  set_data_dir_option(dir("option"));
  EXPECT_EQ(this_process_places().option, dir("option"));
  EXPECT_EQ(data_path("vectors/profiles"), dir("option") + "/vectors/profiles");
  set_data_dir_option(dir("empty"));
  try {
    data_path("vectors");
    ADD_FAILURE() << "no DataDirNotFound";
  } catch (const DataDirNotFound& e) {
    EXPECT_NE(std::string(e.what()).find("--data-dir " + dir("empty") + ": no vectors/ directory there"),
              std::string::npos)
        << e.what();
  }
  set_data_dir_option("");
  EXPECT_EQ(this_process_places().source_tree, SABUS_SOURCE_DIR);
  EXPECT_EQ(fs::path(this_process_places().installed).filename(), "sabus") << "<exe dir>/../share/sabus";
}

}  // namespace
}  // namespace sabus::harness
