// The coverage matrix of a vector suite (coverage.hpp): which cells a vector
// fills, and which required cells are reported missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "sabus/harness/coverage.hpp"
#include "sabus/harness/vector_loader.hpp"

namespace sabus::harness {
namespace {

// One vector of paragraph 3.2 with the given steps (YAML, indented 6).
std::vector<VectorFile> suite(const std::string& steps) {
  const std::string text = "paragraph: \"3.2\"\ntitle: t\nvectors:\n  - id: 3.2-x\n    comment: c\n"
                           "    spec: {paragraph: \"3.2\", quote: \"status\"}\n    level: must\n    steps:\n" + steps;
  LoadResult r = load_vector_text(text, "coverage.yaml");
  EXPECT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors[0].text());
  return r.files;
}

const CoverageRow& row(const CoverageMatrix& m, std::string_view key, std::string_view form) {
  auto it = std::find_if(m.rows.begin(), m.rows.end(), [&](const CoverageRow& r) {
    return r.command->key == key && (r.form ? r.form->id : std::string_view("?")) == form;
  });
  if (it == m.rows.end()) throw std::runtime_error("no row " + std::string(key) + " " + std::string(form));
  return *it;
}

bool missing(const CoverageMatrix& m, const std::string& line) {
  const auto all = m.missing();
  return std::find(all.begin(), all.end(), line) != all.end();
}

TEST(Coverage, AStepFillsTheCellOfItsCommandFormAndPath) {
  const CoverageMatrix m = coverage(suite(
      "      - send: {command: status}\n        expect: ack\n"
      "      - send: {command: jog, form: W, fields: {speed: F, duration: 50}}\n        expect: ack\n"
      "      - send: {raw: \"02 {addr} 31 03 {lrc}\"}\n        modify: {lrc_xor: 1}\n        expect: silence\n"
      "      - send: {raw: \"02 {addr} 29 03 {lrc}\"}\n        expect: {reply: nak, rule: UnknownCommand}\n"));
  EXPECT_EQ(row(m, "status", "").ids[0], std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(row(m, "status", "").ids[3], std::vector<std::string>{"3.2-x"}) << "a bad LRC is the ignore path";
  EXPECT_EQ(row(m, "jog", "W").ids[0], std::vector<std::string>{"3.2-x"});
  EXPECT_TRUE(row(m, "jog", "E").ids[0].empty());
  EXPECT_EQ(m.unknown_codes, std::vector<std::string>{"3.2-x"});
  EXPECT_EQ(m.nak_rules.at("UnknownCommand"), std::vector<std::string>{"3.2-x"});

  EXPECT_FALSE(missing(m, "31h status: ack"));
  EXPECT_FALSE(missing(m, "31h status: ignore"));
  EXPECT_TRUE(missing(m, "31h status: nak"));
  EXPECT_TRUE(missing(m, "31h status: offline"));
  EXPECT_FALSE(missing(m, "33h jog W: ack"));
  EXPECT_TRUE(missing(m, "33h jog E: ack"));
  EXPECT_FALSE(missing(m, "a code outside 30h-48h: nak"));
  EXPECT_TRUE(missing(m, "NAK rule WrongLength (§3): no vector names it"));
  EXPECT_FALSE(missing(m, "NAK rule UnknownCommand (§3): no vector names it"));
}

TEST(Coverage, ADamagedFrameCountsForItsCommandWhenItsFormCannotBeTold) {
  // 41h with a frame too short to decode: the form (preset flag) is unknown.
  const CoverageMatrix m = coverage(suite("      - send: {raw: \"02 {addr} 41 03 {lrc}\"}\n        length_mismatch: true\n"
                                          "        expect: nak\n"));
  EXPECT_EQ(row(m, "remote_locate", "?").ids[1], std::vector<std::string>{"3.2-x"});
  EXPECT_FALSE(missing(m, "41h remote_locate: nak"));
  EXPECT_TRUE(missing(m, "41h remote_locate preset: ack"));
}

TEST(Coverage, TheShippedSuiteHasNoMissingCell) {
  const LoadResult r = load_vectors({default_vectors_dir()});
  ASSERT_TRUE(r.ok());
  const auto m = coverage(r.files);
  EXPECT_EQ(m.missing(), std::vector<std::string>{});
}

}  // namespace
}  // namespace sabus::harness
