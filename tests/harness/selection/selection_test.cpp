// The selection library: which vectors a run takes and in which order.
// Failing paths first: bad --shard values, a known-issues file that does
// not read or names an unknown id, ids of an earlier run gone from the suite.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>

#include "sabus/harness/selection.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "temp_dir.hpp"

namespace sabus::harness {
namespace {

Vector vector(std::string id, std::string paragraph = "3.2") {
  Vector v;
  v.id = std::move(id);
  v.paragraph = std::move(paragraph);
  return v;
}

std::vector<std::string> ids(const Selection& s) {
  std::vector<std::string> out;
  for (const auto& v : s.vectors) out.push_back(v.id);
  return out;
}

std::vector<Vector> shipped() {
  std::vector<Vector> out;
  for (auto& f : load_vectors({default_vectors_dir()}).files)
    for (auto& v : f.vectors) out.push_back(std::move(v));
  return out;
}

TEST(Shard, ABadValueIsAnErrorNamingTheOptionAndTheValue) {
  const std::map<std::string, std::string> bad = {
      {"3", "--shard 3: give K/N"},          {"a/b", "--shard a/b: give K/N"},
      {"1/", "--shard 1/: give K/N"},        {"-1/4", "--shard -1/4: give K/N"},
      {"1/0", "--shard 1/0: N must be between 1 and 10000"},
      {"0/4", "--shard 0/4: K must be between 1 and N (4)"},
      {"5/4", "--shard 5/4: K must be between 1 and N (4)"},
      {"1/4x", "--shard 1/4x: give K/N"}};
  for (const auto& [text, want] : bad) {
    std::string error;
    EXPECT_FALSE(parse_shard(text, error)) << text;
    EXPECT_EQ(error.rfind(want, 0), 0u) << text << ": " << error;
  }
  std::string error;
  const auto s = parse_shard("2/4", error);
  ASSERT_TRUE(s) << error;
  EXPECT_EQ(s->index, 2u);
  EXPECT_EQ(s->count, 4u);
}

// The N shards of the shipped suite's selection hold each vector exactly
// once, whatever N; with a filter too.
TEST(Shard, TheShardsOfASelectionCoverItExactlyOnce) {
  const std::vector<Vector> all = shipped();
  ASSERT_GT(all.size(), 100u);
  for (const std::vector<std::string>& filters : {std::vector<std::string>{}, std::vector<std::string>{"3.4-*"}}) {
    SelectionOptions o;
    o.filters = filters;
    const std::vector<std::string> whole = ids(select_vectors(all, o));
    ASSERT_FALSE(whole.empty());
    for (std::uint32_t n : {1u, 2u, 3u, 7u, 16u}) {
      std::map<std::string, int> seen;
      for (std::uint32_t k = 1; k <= n; ++k) {
        o.shard = Shard{k, n};
        for (const auto& id : ids(select_vectors(all, o))) ++seen[id];
      }
      EXPECT_EQ(seen.size(), whole.size()) << n << " shards";
      for (const auto& id : whole) EXPECT_EQ(seen[id], 1) << id << " in " << n << " shards";
    }
  }
}

// A vector's shard is its id's: the same with or without other vectors
// selected, so a CI matrix cell keeps its vectors as the suite grows.
TEST(Shard, AVectorKeepsItsShardWhateverElseIsSelected) {
  const std::vector<Vector> all = shipped();
  SelectionOptions whole, part;
  whole.shard = part.shard = Shard{2, 3};
  part.filters = {"3.3-*"};
  const auto in_whole = ids(select_vectors(all, whole));
  const auto in_part = ids(select_vectors(all, part));
  ASSERT_FALSE(in_part.empty());
  for (const auto& id : in_part) EXPECT_NE(std::find(in_whole.begin(), in_whole.end(), id), in_whole.end()) << id;
  // Every slice of the suite holds some vectors: the hash spreads them.
  for (std::uint32_t k = 1; k <= 4; ++k) {
    SelectionOptions o;
    o.shard = Shard{k, 4};
    EXPECT_GT(select_vectors(all, o).vectors.size(), all.size() / 8) << k;
  }
}

TEST(Selection, LastFailedTakesOnlyThoseAndNotesTheOnesGoneFromTheSuite) {
  const std::vector<Vector> all = {vector("a"), vector("b"), vector("c"), vector("d", "3.3")};
  SelectionOptions o;
  o.only = std::set<std::string>{"c", "a", "renamed"};
  o.only_from = "out/run.json";
  Selection s = select_vectors(all, o);
  EXPECT_EQ(ids(s), (std::vector<std::string>{"a", "c"}));
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_EQ(s.notes[0], "--last-failed out/run.json: 1 vector(s) that failed there are not in the suite: renamed");
  // With the other options: only the failures they select.
  o.paragraphs = {"3.3"};
  EXPECT_TRUE(select_vectors(all, o).vectors.empty());
  EXPECT_EQ(empty_selection_reason(o), "no vector matches --paragraph '3.3' and --last-failed out/run.json (3 failed there)");
  // A run with no failure selects nothing, and says why.
  o = {};
  o.only = std::set<std::string>{};
  o.only_from = "out/run.json";
  EXPECT_TRUE(select_vectors(all, o).vectors.empty());
  EXPECT_EQ(empty_selection_reason(o), "no vector matches --last-failed out/run.json (no vector failed in that run)");
}

TEST(Selection, FailedFirstRunsThemFirstThenTheRestEachInSuiteOrder) {
  const std::vector<Vector> all = {vector("a"), vector("b"), vector("c"), vector("d"), vector("e")};
  SelectionOptions o;
  o.first = {"d", "b", "gone"};
  EXPECT_EQ(ids(select_vectors(all, o)), (std::vector<std::string>{"b", "d", "a", "c", "e"}));
  o.excludes = {"d"};
  EXPECT_EQ(ids(select_vectors(all, o)), (std::vector<std::string>{"b", "a", "c", "e"}));
}

TEST(Selection, GlobsAndParagraphsWithTheirNotes) {
  const std::vector<Vector> all = {vector("3.2-a"), vector("3.2-b"), vector("3.20-a", "3.20"), vector("3.3-a", "3.3")};
  SelectionOptions o;
  o.filters = {"3.2*", "3.9-*"};
  o.excludes = {"3.2-b", "nothing*"};
  Selection s = select_vectors(all, o);
  EXPECT_EQ(ids(s), (std::vector<std::string>{"3.2-a", "3.20-a"}));
  EXPECT_EQ(s.notes, (std::vector<std::string>{
                         "--filter '3.2*' matches vectors of 2 paragraphs (§3.2, §3.20); --paragraph 3.2 selects §3.2 alone",
                         "--filter '3.9-*' matches no vector id", "--exclude 'nothing*' matches no vector id"}));
  o = {};
  o.paragraphs = {"§3.2", "3.9"};
  s = select_vectors(all, o);
  EXPECT_EQ(ids(s), (std::vector<std::string>{"3.2-a", "3.2-b"}));
  EXPECT_EQ(s.notes, (std::vector<std::string>{"--paragraph 3.9: no vector of §3.9"}));
  EXPECT_EQ(empty_selection_reason(SelectionOptions{}), "no vector was given");
}

class KnownIssuesFile : public test::TempDirTest {
 protected:
  KnownIssuesFile() : TempDirTest("sabus-selection-test") {}
};

TEST_F(KnownIssuesFile, AMissingFileOrAnUnknownIdIsAnErrorNamingFileAndLine) {
  KnownIssues k = read_known_issues(path("none.txt"), {"a"});
  EXPECT_EQ(k.errors, (std::vector<std::string>{path("none.txt") + ": cannot read"}));
  std::ofstream(path("known.txt")) << "# comment\n\na: drive firmware 1.2\nb  wrong id\nc\n";
  k = read_known_issues(path("known.txt"), {"a", "c"});
  EXPECT_EQ(k.errors, (std::vector<std::string>{path("known.txt") + ":4: no vector has the id \"b\""}));
  EXPECT_EQ(k.reasons, (std::map<std::string, std::string>{{"a", "drive firmware 1.2"}, {"c", "listed as a known issue"}}));
}

}  // namespace
}  // namespace sabus::harness
