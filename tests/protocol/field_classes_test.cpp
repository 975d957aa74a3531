// The field classes (field_classes.hpp) against the reply layouts: every
// field of every reply has exactly one class, and the table names no field
// a reply does not have.
#include "sabus/protocol/field_classes.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <variant>

#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/frame.hpp"

namespace sabus {
namespace {

const std::set<std::string> kFraming = {"start", "address", "command", "ETX", "check byte"};

// The fields describe_frame names in a reply of each kind (its codec's
// default reply to the first command that answers with it).
template <std::size_t... I>
std::map<ReplyKind, std::set<std::string>> layouts(std::index_sequence<I...>) {
  std::map<ReplyKind, std::set<std::string>> out;
  auto one = [&]<class T>(std::type_identity<T>) {
    if constexpr (requires { T::kKind; }) {
      for (const auto& info : catalog()) {
        if (info.reply != T::kKind) continue;
        const auto frame = reply_frame(Reply{T{}}, '2', info.code);
        if (!frame) continue;
        for (const auto& f : describe_frame(encode_frame(frame.value())).fields)
          if (!kFraming.count(f.name)) out[T::kKind].insert(f.name);
        break;
      }
    }
  };
  (one(std::type_identity<std::variant_alternative_t<I, Reply>>{}), ...);
  return out;
}

TEST(FieldClasses, EveryFieldOfEveryReplyHasOneClassAndNoOther) {
  const auto fields = layouts(std::make_index_sequence<std::variant_size_v<Reply>>{});
  ASSERT_GE(fields.size(), 13u) << "a reply of each kind with fields";
  for (const auto& [kind, names] : fields)
    for (const auto& name : names) {
      const ReplyFieldClass* c = field_class(kind, name);
      EXPECT_NE(c, nullptr) << to_string(kind) << " \"" << name << "\" has no class";
      if (c) {
        EXPECT_FALSE(c->paragraph.empty() || c->rests_on.empty()) << name;
      }
    }
  std::set<std::pair<ReplyKind, std::string>> seen;
  for (const auto& c : reply_field_classes()) {
    const auto it = fields.find(c.reply);
    EXPECT_TRUE(it != fields.end() && it->second.count(std::string(c.field)))
        << to_string(c.reply) << " has no field \"" << c.field << "\"";
    EXPECT_TRUE(seen.insert({c.reply, std::string(c.field)}).second) << c.field << " twice";
  }
}

TEST(FieldClasses, FramingAndUnknownFieldsHaveNone) {
  EXPECT_EQ(field_class(ReplyKind::kStatus, "check byte"), nullptr);
  EXPECT_EQ(field_class(ReplyKind::kStatus, "no such field"), nullptr);
  EXPECT_EQ(field_class(ReplyKind::kStatus, "azimuth")->cls, FieldClass::kMotion);
  EXPECT_EQ(field_class(ReplyKind::kExtendedStatus, "exit status")->cls, FieldClass::kState);
  EXPECT_FALSE(value_required(FieldClass::kDevice));
  EXPECT_TRUE(value_required(FieldClass::kFixed));
}

}  // namespace
}  // namespace sabus
