// The vector schema table (vector_schema.hpp) is the loader's: at every node
// a key outside the table is rejected naming the file, line, column, key and
// the table's keys, and every key of the table gets past the key check.
// Suite `vectors`, so that `ctest -R vectors` selects these tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "sabus/harness/readings.hpp"
#include "sabus/harness/vector_loader.hpp"
#include "sabus/harness/vector_schema.hpp"

namespace sabus::harness {
namespace {

// One file with every node, each with a marker where a key can be put in
// (@NODE@, at the indentation of that node's keys). Without insertions it
// loads clean.
std::string document() {
  const std::string reading(reading_points().front().id);
  return R"(paragraph: "3.2"
title: t
@kFile@
notes:
  Flag1:
    description: d
    @kNote@
groups:
  - level: must
    @kGroup@
    vectors:
      - id: 3.2-a
        comment: c
        spec:
          paragraph: "3.2"
          quote: q
          @kSpec@
        flags: [Flag1]
        @kVector@
        steps:
          - wait:
              ms: 1
              @kWait@
          - send:
              command: status
              @kSend@
            modify:
              lrc_xor: 1
              @kModify@
            expect: silence
            @kStep@
          - send:
              command: status
            expect:
              reply: ack
              @kExpect@
              fields:
                agc:
                  capture: $agc
                  @kMatcher@
                elevation:
                  near:
                    value: 1
                    @kNear@
                azimuth:
                  jogged:
                    jog: W
                    speed: F
                    from: 0
                    ms: 100
                    @kJogged@
              readings:
                )" + reading + R"(:
                  reply: nak
                  @kReading@
          - poll:
              send:
                command: status
              until:
                "az status": any
              @kPoll@
          - survey:
              send:
                command: status
              count: 10
              @kSurvey@
)";
}

const std::pair<SchemaNode, const char*> kMarkers[] = {
    {SchemaNode::kFile, "@kFile@"},       {SchemaNode::kNote, "@kNote@"},       {SchemaNode::kGroup, "@kGroup@"},
    {SchemaNode::kVector, "@kVector@"},   {SchemaNode::kSpec, "@kSpec@"},       {SchemaNode::kStep, "@kStep@"},
    {SchemaNode::kWait, "@kWait@"},       {SchemaNode::kSend, "@kSend@"},       {SchemaNode::kModify, "@kModify@"},
    {SchemaNode::kPoll, "@kPoll@"},       {SchemaNode::kSurvey, "@kSurvey@"},   {SchemaNode::kExpect, "@kExpect@"},
    {SchemaNode::kReading, "@kReading@"},
    {SchemaNode::kMatcher, "@kMatcher@"}, {SchemaNode::kNear, "@kNear@"},       {SchemaNode::kJogged, "@kJogged@"},
};

// The document with `line` at the node's marker and the other markers blank.
std::string with_line(SchemaNode node, const std::string& line) {
  std::string text = document();
  for (const auto& [n, marker] : kMarkers) {
    const auto at = text.find(marker);
    text.replace(at, std::string(marker).size(), n == node ? line : "");
  }
  return text;
}

std::string errors_of(const LoadResult& r) {
  std::string out;
  for (const auto& e : r.errors) out += "  " + e.text() + "\n";
  return out;
}

std::string listed(std::span<const std::string_view> keys) {
  std::string out;
  for (auto k : keys) out += (out.empty() ? "" : ", ") + std::string(k);
  return out;
}

TEST(vectors, SchemaDocumentLoadsClean) {
  const LoadResult r = load_vector_text(with_line(SchemaNode::kFile, ""), "schema.yaml");
  EXPECT_TRUE(r.ok()) << errors_of(r);
}

TEST(vectors, SchemaRejectsAKeyOutsideTheTableAtEveryNode) {
  for (const auto& [node, marker] : kMarkers) {
    SCOPED_TRACE(marker);
    const std::string text = with_line(node, "zz_unknown: 1");
    const LoadResult r = load_vector_text(text, "schema.yaml");
    ASSERT_EQ(r.errors.size(), 1u) << errors_of(r);
    const LoadError& e = r.errors[0];
    const auto at = text.find("zz_unknown");
    const auto line_start = text.rfind('\n', at) + 1;
    EXPECT_EQ(e.where.file, "schema.yaml");
    EXPECT_EQ(e.where.line, 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    EXPECT_EQ(e.where.column, static_cast<int>(at - line_start) + 1);
    EXPECT_TRUE(e.key.ends_with("zz_unknown")) << e.key;
    EXPECT_EQ(e.message, "unknown key \"zz_unknown\"; allowed keys: " + listed(schema_keys(node)));
  }
}

TEST(vectors, SchemaKeysAreAcceptedAtTheirNode) {
  for (const auto& [node, marker] : kMarkers) {
    for (const auto key : schema_keys(node)) {
      SCOPED_TRACE(std::string(marker) + " " + std::string(key));
      // The value is often wrong for the key: only the key check is under
      // test, and a map's keys are all checked before any value is read.
      const LoadResult r = load_vector_text(with_line(node, std::string(key) + ": 0"), "schema.yaml");
      for (const auto& e : r.errors) EXPECT_EQ(e.message.find("unknown key"), std::string::npos) << e.text();
    }
  }
}

TEST(vectors, SchemaReadingAlternativeHasNoReadings) {
  const auto keys = schema_keys(SchemaNode::kReading);
  EXPECT_EQ(std::find(keys.begin(), keys.end(), "readings"), keys.end());
  const LoadResult r = load_vector_text(with_line(SchemaNode::kReading, "readings: {}"), "schema.yaml");
  ASSERT_EQ(r.errors.size(), 1u) << errors_of(r);
  EXPECT_NE(r.errors[0].message.find("unknown key \"readings\""), std::string::npos) << r.errors[0].text();
}

// `ends` (vectors/README.md): an alternative's, on a send of a vector's
// steps; true or left out.
TEST(vectors, SchemaReadingAlternativeEndsOnlyASendInSteps) {
  EXPECT_TRUE(load_vector_text(with_line(SchemaNode::kReading, "ends: true"), "schema.yaml").ok());
  const LoadResult off = load_vector_text(with_line(SchemaNode::kReading, "ends: false"), "schema.yaml");
  ASSERT_EQ(off.errors.size(), 1u) << errors_of(off);
  EXPECT_NE(off.errors[0].message.find("default"), std::string::npos) << off.errors[0].text();
  const auto keys = schema_keys(SchemaNode::kExpect);
  EXPECT_EQ(std::find(keys.begin(), keys.end(), "ends"), keys.end()) << "the reference side ends nothing";
  // In a setup, and on a poll, it is refused.
  const std::string alt = std::string(reading_points().front().id) + ": {reply: nak, ends: true}";
  const std::string in_setup = with_line(SchemaNode::kVector, "setup: [{send: {command: status}, expect: {reply: ack, readings: {" + alt + "}}}]");
  const LoadResult setup = load_vector_text(in_setup, "schema.yaml");
  ASSERT_EQ(setup.errors.size(), 1u) << errors_of(setup);
  EXPECT_NE(setup.errors[0].message.find("not in a setup or teardown"), std::string::npos) << setup.errors[0].text();
  const std::string on_poll = with_line(SchemaNode::kPoll, "expect: {reply: ack, readings: {" + alt + "}}");
  const LoadResult poll = load_vector_text(on_poll, "schema.yaml");
  ASSERT_EQ(poll.errors.size(), 1u) << errors_of(poll);
  EXPECT_NE(poll.errors[0].message.find("put it on a send"), std::string::npos) << poll.errors[0].text();
}

TEST(vectors, SchemaTableHasEveryNodeOnceWithMeanings) {
  std::set<SchemaNode> seen;
  for (const auto& n : vector_schema()) {
    EXPECT_TRUE(seen.insert(n.node).second) << n.name;
    EXPECT_FALSE(n.where.empty()) << n.name;
    std::set<std::string_view> keys;
    for (const auto& k : n.keys) {
      EXPECT_TRUE(keys.insert(k.key).second) << n.name << ": " << k.key << " twice";
      EXPECT_FALSE(k.meaning.empty()) << n.name << ": " << k.key;
    }
  }
  EXPECT_EQ(seen.size(), std::size(kMarkers));
}

TEST(vectors, SchemaMarkdownHasARowPerKey) {
  const std::string md = schema_markdown();
  for (const auto& n : vector_schema()) {
    EXPECT_NE(md.find("## " + std::string(n.name) + "\n"), std::string::npos) << n.name;
    for (const auto& k : n.keys) EXPECT_NE(md.find("| `" + std::string(k.key) + "` |"), std::string::npos) << k.key;
  }
}

}  // namespace
}  // namespace sabus::harness
