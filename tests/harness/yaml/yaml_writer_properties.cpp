// Any text at all, as a comment before a document (yaml_writer.hpp
// printable_text): the document reads back unchanged, its text is what a
// strict YAML reader takes, and printable text is kept as it is.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "sabus/harness/yaml_writer.hpp"
#include "yaml_text.hpp"

namespace sabus::harness::yaml_writer {
namespace {

// Any bytes, each value as likely.
rc::Gen<std::string> any_bytes() {
  return rc::gen::container<std::string>(rc::gen::map(rc::gen::inRange(0, 256), [](int b) { return static_cast<char>(b); }));
}

RC_GTEST_PROP(PrintableText, AnyCommentLeavesTheDocumentAsItWas, ()) {
  const std::string comment = *any_bytes();
  YAML::Emitter e;
  e << YAML::Comment(printable_text(comment)) << YAML::BeginMap << YAML::Key << "key" << YAML::Value
    << YAML::DoubleQuoted << comment << YAML::EndMap;
  const std::string doc = document(e);
  const YAML::Node n = YAML::Load(doc);
  RC_ASSERT(n.IsMap());
  RC_ASSERT(n.size() == 1u);
  RC_ASSERT(test::yaml_text_problem(printable_text(comment)).empty());
  RC_ASSERT(test::yaml_text_problem(comment_lines(comment)).empty());
  RC_ASSERT(YAML::Load(comment_lines(comment) + "key: value\n")["key"].Scalar() == "value");
}

RC_GTEST_PROP(PrintableText, PrintableTextIsKept, ()) {
  // Printable ASCII and a few printable non-ASCII characters, and line breaks.
  const std::string alphabet = "\n !\"#$%&'()*+,-./09:;<=>?@AZ[\\]^_`az{|}~";
  const auto pieces = *rc::gen::container<std::vector<std::string>>(rc::gen::oneOf(
      rc::gen::map(rc::gen::elementOf(alphabet), [](char c) { return std::string(1, c); }),
      rc::gen::element<std::string>("\xc2\xa7", "\xc3\xa9", "\xe6\x97\xa5", "\xf0\x9f\x98\x80", "\xc2\xa0")));
  std::string text;
  for (const auto& p : pieces) text += p;
  RC_ASSERT(printable_text(text) == text);
}

}  // namespace
}  // namespace sabus::harness::yaml_writer
