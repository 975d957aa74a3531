// What the YAML writers do beyond yaml-cpp's Emitter (yaml_writer.hpp):
// text from outside made printable for comments and free text, comment
// lines, the profile writer's double-quoted scalars, and a writer's bug
// caught. Every result is read back by yaml-cpp and checked, without the
// writer's own code, to be text a strict YAML reader takes (yaml_text.hpp).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <utility>

#include "sabus/harness/yaml_writer.hpp"
#include "yaml_text.hpp"

namespace sabus::harness::yaml_writer {
namespace {

using test::yaml_text_problem;

// `comment` before a map of one entry: the document the writers make.
std::string commented_document(std::string_view comment) {
  YAML::Emitter e;
  e << YAML::Comment(printable_text(comment)) << YAML::BeginMap << YAML::Key << "key" << YAML::Value << "value"
    << YAML::EndMap;
  return document(e);
}

// The comment stays a comment: the document reads back as its one entry.
::testing::AssertionResult reads_back_as_the_map(const std::string& doc) {
  try {
    const YAML::Node n = YAML::Load(doc);
    if (!n.IsMap() || n.size() != 1 || n["key"].Scalar() != "value")
      return ::testing::AssertionFailure() << "the comment changed the document:\n" << doc;
  } catch (const YAML::Exception& e) {
    return ::testing::AssertionFailure() << e.what() << "\n" << doc;
  }
  if (const std::string why = yaml_text_problem(doc); !why.empty()) return ::testing::AssertionFailure() << why << "\n" << doc;
  return ::testing::AssertionSuccess();
}

TEST(PrintableText, KeepsPrintableTextAndItsLineBreaks) {
  for (std::string_view s : {"", "ASCII with YAML's own characters: {}[]#&*!|>'\"%@`\\ - ? ~ null",
                             "\xc2\xa7" "3.2 \xc3\xa9 \xe6\x97\xa5\xe6\x9c\xac \xf0\x9f\x98\x80 \xc2\xa0", "two\nlines\n"})
    EXPECT_EQ(printable_text(s), s);
}

TEST(PrintableText, WritesEverythingElseAsItsBytes) {
  const std::pair<std::string_view, std::string_view> cases[] = {
      {"\r", "\\x0d"},                                  // a line break to a YAML reader
      {"a\r\nb", "a\\x0d\nb"},
      {"\t", "\\x09"},
      {std::string_view("\0", 1), "\\x00"},
      {"\x01\x1f", "\\x01\\x1f"},
      {"\x7f", "\\x7f"},                                // DEL
      {"\xc2\x85", "\\xc2\\x85"},                       // NEL, a line break to YAML 1.1
      {"\xc2\x80\xc2\x9f", "\\xc2\\x80\\xc2\\x9f"},     // C1 controls
      {"\xe2\x80\xa8\xe2\x80\xa9", "\\xe2\\x80\\xa8\\xe2\\x80\\xa9"},  // line and paragraph separators
      {"\xef\xbb\xbf", "\\xef\\xbb\\xbf"},              // byte order mark
      {"\xef\xbf\xbe\xef\xb7\x90", "\\xef\\xbf\\xbe\\xef\\xb7\\x90"},  // noncharacters U+FFFE, U+FDD0
      {"\xf4\x8f\xbf\xbf", "\\xf4\\x8f\\xbf\\xbf"},     // U+10FFFF, a noncharacter
      {"\xff", "\\xff"},
      {"\xc0\x80", "\\xc0\\x80"},                       // overlong NUL
      {"\xe0\x80\xaf", "\\xe0\\x80\\xaf"},              // overlong '/'
      {"\xed\xa0\x80", "\\xed\\xa0\\x80"},              // a surrogate
      {"\xf4\x90\x80\x80", "\\xf4\\x90\\x80\\x80"},     // past U+10FFFF
      {"\xe2\x82", "\\xe2\\x82"},                       // cut short at the end
      {"\xe2\x82x", "\\xe2\\x82x"},                     // cut short, then ASCII: kept
      {"\xc3\xa9\xff\xc3\xa9", "\xc3\xa9\\xff\xc3\xa9"},
  };
  for (const auto& [in, out] : cases) EXPECT_EQ(printable_text(in), out) << "input of " << in.size() << " bytes";
}

TEST(PrintableText, AnyByteOrPairOfBytesIsTextAStrictReaderTakes) {
  for (int a = 0; a < 256; ++a) {
    const std::string one(1, static_cast<char>(a));
    ASSERT_TRUE(reads_back_as_the_map(commented_document(one))) << "byte " << a;
    for (int b = 0; b < 256; ++b) {
      const std::string two = one + static_cast<char>(b);
      ASSERT_EQ(yaml_text_problem(printable_text(two)), "") << "bytes " << a << " " << b;
    }
  }
}

TEST(CommentLines, OneCommentLineForEachLine) {
  EXPECT_EQ(comment_lines(""), "");
  EXPECT_EQ(comment_lines("one"), "# one\n");
  EXPECT_EQ(comment_lines("failed:\n  x: expected a\rb\nReproduce"), "# failed:\n#   x: expected a\\x0db\n# Reproduce\n");
  const std::string doc = comment_lines("key: injected\nvectors: [\x01]\r- x") + "key: value\n";
  EXPECT_TRUE(reads_back_as_the_map(doc));
}

TEST(DoubleQuoted, PrintableAsciiReadsBackExactlyAndQuoted) {
  std::string all;
  for (char c = ' '; c <= '~'; ++c) all += c;
  for (const std::string& s : {all, std::string(), std::string("~"), std::string("null"), std::string("true"),
                               std::string("0x32"), std::string(" lead and trail "), std::string("- a: b #c")}) {
    const std::string doc = "key: " + double_quoted(s) + "\n";
    const YAML::Node n = YAML::Load(doc);
    EXPECT_EQ(n["key"].Scalar(), s) << doc;
    EXPECT_EQ(n["key"].Tag(), "!") << "quoted, so never read as a number, a boolean or null: " << doc;
    EXPECT_EQ(yaml_text_problem(doc), "") << doc;
  }
}

TEST(DoubleQuoted, EveryOtherByteIsEscapedAndTheDocumentStaysValid) {
  for (int b = 0; b < 256; ++b) {
    if (b >= 0x20 && b <= 0x7E) continue;
    const std::string doc = "key: " + double_quoted(std::string("a") + static_cast<char>(b) + "z") + "\n";
    EXPECT_EQ(yaml_text_problem(doc), "") << "byte " << b << ": " << doc;
    char escape[8];
    std::snprintf(escape, sizeof escape, "\\x%02x", b);
    EXPECT_EQ(doc, std::string("key: \"a") + escape + "z\"\n");
    // Read back as the code point of the byte's value.
    std::string expected = "a";
    if (b < 0x80) {
      expected += static_cast<char>(b);
    } else {
      expected += static_cast<char>(0xC0 | (b >> 6));
      expected += static_cast<char>(0x80 | (b & 0x3F));
    }
    EXPECT_EQ(YAML::Load(doc)["key"].Scalar(), expected + "z") << "byte " << b;
  }
}

TEST(Document, EndsInANewlineAndAWriterBugThrows) {
  YAML::Emitter good;
  good << YAML::BeginMap << YAML::Key << "a" << YAML::Value << 1 << YAML::EndMap;
  EXPECT_EQ(document(good), "a: 1\n");
  YAML::Emitter bug;
  bug << YAML::BeginMap << YAML::Key << "a" << YAML::Value << YAML::EndSeq;
  EXPECT_THROW(document(bug), std::logic_error);
}

}  // namespace
}  // namespace sabus::harness::yaml_writer
