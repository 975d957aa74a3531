// `sabus vectors sweep` as a process: the profiles it writes, a failing one
// under a comment of its failures (which hold what the vectors and the
// controller said), load back equal to the random profiles they came from;
// each is a new file, and one that cannot be written is said to be.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "process.hpp"
#include "sabus/harness/profile_generator.hpp"
#include "sabus/harness/profile_loader.hpp"
#include "temp_dir.hpp"
#include "yaml_text.hpp"

namespace sabus::harness {
namespace {

namespace fs = std::filesystem;

class SweepFiles : public test::TempDirTest {
 protected:
  SweepFiles() : TempDirTest("sabus-sweep-test") {}

  // A vector that fails on every profile, its failure text holding what a
  // strict YAML reader must never see as it is: the expected satellite name
  // has line breaks, YAML, control characters, DEL, NEL, a line separator,
  // a byte order mark.
  fs::path hostile_vector() {
    const fs::path file = dir_ / "hostile.yaml";
    std::ofstream(file) << "paragraph: \"3.2\"\n"
                           "title: A vector whose failure says anything\n"
                           "vectors:\n"
                           "  - id: 3.2-hostile-failure-text\n"
                           "    comment: Its expected satellite name is text no controller sends.\n"
                           "    spec: {paragraph: \"3.2\", quote: \"31 Device Status Poll\"}\n"
                           "    level: must\n"
                           "    steps:\n"
                           "      - send: {command: status}\n"
                           "        expect: {reply: ack, fields: {\"sat name\": {eq: \"x\\ny: 1\\r\\\"q\\\" \\\\ "
                           "\\x01\\x7f\\u0085\\u2028\\ufeff \\u00e9 # z\"}}}\n";
    return file;
  }

  test::ShellResult sweep(const std::string& options) {
    return test::shell("'" SABUS_BIN "' vectors sweep --jobs 1 " + options + " 2>&1");
  }
};

// The profile in `file` is random_profile(seed), and the file is text a
// strict YAML reader takes.
void expect_the_profile_of(const fs::path& file, std::uint64_t seed) {
  const std::string text = test::slurp(file);
  EXPECT_EQ(test::yaml_text_problem(text), "") << text;
  const ProfileResult r = load_profile_file(file.string());
  ASSERT_TRUE(r) << r.error->text() << "\n" << text;
  Profile loaded = *r.profile, expected = random_profile(seed);
  loaded.source = expected.source;
  EXPECT_TRUE(loaded == expected) << text;
}

TEST_F(SweepFiles, AFailingProfileLoadsBackEqualUnderAnyFailureText) {
  const auto r = sweep("--vectors '" + hostile_vector().string() + "' --profile-seed 5 --out '" + (dir_ / "out").string() + "'");
  EXPECT_EQ(r.status, 1) << r.out;
  const fs::path file = dir_ / "out" / "sweep-0000000000000005.yaml";
  EXPECT_NE(r.out.find("profile written to " + file.string()), std::string::npos) << r.out;
  expect_the_profile_of(file, 5);
  const std::string text = test::slurp(file);
  EXPECT_EQ(text.rfind("# A random legal profile (random_profile seed 0x0000000000000005) on which vectors failed:\n"
                       "#   3.2-hostile-failure-text: bytes 3-12 sat name: expected x\n"
                       "# y: 1\\x0d\"q\" \\ \\x01\\x7f\\xc2\\x85\\xe2\\x80\\xa8\\xef\\xbb\\xbf \xc3\xa9 # z, got ",
                       0),
            0u)
      << text;
  EXPECT_NE(text.find("\n# Reproduce: sabus vectors sweep --profile-seed 5\nname: \"random-5\"\n"), std::string::npos) << text;

  // A second sweep of that seed writes a new file beside it.
  const std::string first = text;
  const auto again = sweep("--vectors '" + (dir_ / "hostile.yaml").string() + "' --profile-seed 5 --out '" + (dir_ / "out").string() + "'");
  EXPECT_EQ(again.status, 1) << again.out;
  EXPECT_EQ(test::slurp(file), first);
  expect_the_profile_of(dir_ / "out" / "sweep-0000000000000005-2.yaml", 5);
}

TEST_F(SweepFiles, EveryProfileWrittenWithWriteProfilesLoadsBackEqual) {
  const auto r = sweep("--vectors '" SABUS_SOURCE_DIR "/vectors/3.1-device-type.yaml' --profiles 4 --seed 2 --write-profiles '" +
                       (dir_ / "all").string() + "' --out '" + (dir_ / "failed").string() + "'");
  EXPECT_EQ(r.status, 0) << r.out;
  const std::regex seed_line("profile \\d+ seed (\\d+):");
  std::size_t n = 0;
  for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), seed_line); it != std::sregex_iterator(); ++it, ++n) {
    const std::uint64_t seed = std::stoull((*it)[1].str());
    char name[40];
    std::snprintf(name, sizeof name, "sweep-%016llx.yaml", static_cast<unsigned long long>(seed));
    expect_the_profile_of(dir_ / "all" / name, seed);
  }
  EXPECT_EQ(n, 4u) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "failed"));
}

// A fresh seed each run, printed first, and the same profiles again from
// the printed seed (issue 22: a gate that keeps exploring); a seed that is
// neither a number nor "fresh" is refused.
TEST_F(SweepFiles, AFreshSeedIsPrintedAndReproducesItsProfiles) {
  const std::string file = "--vectors '" SABUS_SOURCE_DIR "/vectors/3.1-device-type.yaml' --profiles 3 --out '" +
                           (dir_ / "failed").string() + "' ";
  const auto r = sweep(file + "--seed fresh");
  ASSERT_EQ(r.status, 0) << r.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("^sweep seed (\\d+) \\(fresh\\): 3 profiles"))) << r.out;
  const auto again = sweep(file + "--seed " + m[1].str());
  ASSERT_EQ(again.status, 0) << again.out;
  const std::regex seed_line("profile \\d+ seed \\d+");
  auto seeds = [&](const std::string& out) {
    std::multiset<std::string> s;
    for (auto it = std::sregex_iterator(out.begin(), out.end(), seed_line); it != std::sregex_iterator(); ++it)
      s.insert(it->str());
    return s;
  };
  EXPECT_EQ(seeds(r.out).size(), 3u) << r.out;
  EXPECT_EQ(seeds(r.out), seeds(again.out)) << r.out << again.out;
  const auto bad = sweep(file + "--seed banana");
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_NE(bad.out.find("--seed banana: a whole number below 2^64, or fresh"), std::string::npos) << bad.out;
}

// A skip's cause ends at the first ':' outside parentheses: the TLE slot's
// reason keeps its closing parenthesis in the per-profile and summary lines.
TEST_F(SweepFiles, ASkipCauseKeepsItsParenthesisClosed) {
  const auto r = sweep("--vectors '" SABUS_SOURCE_DIR "/vectors/3.12-write-tle.yaml' --profiles 30 --seed 3 --out '" +
                       (dir_ / "failed").string() + "'");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("filled in the profile (a write there could not be undone: a slot cannot be emptied)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("could not be undone;"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("could not be undone\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sweep skips by cause (vector runs): "), std::string::npos) << r.out;
}

TEST_F(SweepFiles, AProfileThatCannotBeWrittenIsSaidToBe) {
  std::ofstream(dir_ / "a-file") << "x";
  const auto r = sweep("--vectors '" + hostile_vector().string() + "' --profile-seed 5 --out '" + (dir_ / "a-file" / "out").string() + "'");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("sabus vectors sweep: the profile of seed 5 is not written: cannot create the folder"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("profile written to"), std::string::npos) << r.out;
}

// --shard K/N slices the profiles of one --seed and --profiles by seed: the
// shards over every K run each profile exactly once; a bad value is a usage
// error naming the option.
TEST_F(SweepFiles, TheShardsOfASweepRunEachProfileOnce) {
  const std::string common = "--vectors '" SABUS_SOURCE_DIR "/vectors/3.1-device-type.yaml' --profiles 9 --seed 4";
  auto seeds = [](const std::string& out) {
    std::multiset<std::string> found;
    const std::regex line(R"(^profile \d+ seed (\d+):)");
    std::istringstream in(out);
    for (std::string l; std::getline(in, l);)
      if (std::smatch m; std::regex_search(l, m, line)) found.insert(m[1]);
    return found;
  };
  const auto whole = sweep(common);
  ASSERT_EQ(whole.status, 0) << whole.out;
  const auto all = seeds(whole.out);
  ASSERT_EQ(all.size(), 9u) << whole.out;
  std::multiset<std::string> sharded;
  for (int k = 1; k <= 3; ++k) {
    const auto part = sweep(common + " --shard " + std::to_string(k) + "/3");
    ASSERT_EQ(part.status, 0) << part.out;
    EXPECT_NE(part.out.find("of 9, shard " + std::to_string(k) + "/3"), std::string::npos) << part.out;
    for (const auto& seed : seeds(part.out)) sharded.insert(seed);
  }
  EXPECT_EQ(sharded, all);
  const auto bad = sweep(common + " --shard 0/3");
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_NE(bad.out.find("sabus vectors sweep: --shard 0/3: K must be between 1 and N (3)"), std::string::npos) << bad.out;
}

}  // namespace
}  // namespace sabus::harness
