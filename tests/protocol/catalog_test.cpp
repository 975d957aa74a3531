// The command catalog (§3 Command Set) and its agreement with the layouts.
#include <gtest/gtest.h>

#include <set>

#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"

namespace sabus {
namespace {

TEST(Catalog, HasOneRowPerCode30hTo48hInOrder) {
  auto rows = catalog();
  ASSERT_EQ(rows.size(), 25u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].code, 0x30 + i);
    EXPECT_EQ(find_command(static_cast<std::uint8_t>(0x30 + i)), &rows[i]);
  }
  EXPECT_EQ(find_command(std::uint8_t{0x2F}), nullptr);
  EXPECT_EQ(find_command(std::uint8_t{0x49}), nullptr);
}

TEST(Catalog, ParagraphsFollowTheCommandTable) {
  // §3: 30h is paragraph 3.1, ... 48h is 3.25.
  for (const auto& c : catalog()) EXPECT_EQ(c.paragraph, "3." + std::to_string(c.code - 0x30 + 1)) << c.name;
}

TEST(Catalog, LengthsFromTheSpec) {
  // Spot checks against the spec text (whole frames, STX..check byte).
  EXPECT_EQ(find_command(std::uint8_t{0x30})->reply_length, 11);   // §3.1
  EXPECT_EQ(find_command(std::uint8_t{0x31})->reply_length, 52);   // §3.2
  EXPECT_EQ(find_command(std::uint8_t{0x32})->request_length, 16); // §3.3
  EXPECT_EQ(find_command(std::uint8_t{0x33})->request_length, 11); // §3.4
  EXPECT_EQ(find_command(std::uint8_t{0x37})->reply_length, 169);  // §3.8
  EXPECT_EQ(find_command(std::uint8_t{0x3B})->request_length, 145);// §3.12
  EXPECT_EQ(find_command(std::uint8_t{0x40})->reply_length, 58);   // §3.17, ERRATA E-21
  EXPECT_EQ(find_command(std::uint8_t{0x45})->reply_length, 72);   // §3.22
  EXPECT_EQ(find_command(std::uint8_t{0x47})->reply_length, 12);   // §3.24
  EXPECT_FALSE(find_command(std::uint8_t{0x3D})->request_length.has_value());  // §3.14 TBD
  EXPECT_FALSE(find_command(std::uint8_t{0x3E})->reply_length.has_value());    // §3.15 TBD
  EXPECT_EQ(max_request_length(), 145u);  // READING-NOTES 8
  EXPECT_EQ(max_reply_length(), 169u);
}

TEST(Catalog, NotImplementedOnTheRc3000) {
  std::set<std::uint8_t> not_implemented;
  for (const auto& c : catalog())
    if (!c.implemented) not_implemented.insert(c.code);
  EXPECT_EQ(not_implemented, (std::set<std::uint8_t>{0x38, 0x3D, 0x3E}));
}

TEST(Catalog, EffectsFollowReadingNotes26) {
  std::set<std::uint8_t> moves, stores;
  for (const auto& c : catalog()) {
    if (c.effects().moves_antenna) moves.insert(c.code);
    if (c.effects().changes_stored_data) stores.insert(c.code);
  }
  EXPECT_EQ(moves, (std::set<std::uint8_t>{0x32, 0x33, 0x34, 0x36, 0x41, 0x47, 0x48}));
  EXPECT_EQ(stores, (std::set<std::uint8_t>{0x39, 0x3B, 0x3D, 0x42, 0x43, 0x46}));
  // Per form: misc 'R' (drive reset) does not move; 'S' (stow) does.
  const auto* misc = find_command(std::uint8_t{0x36});
  EXPECT_FALSE(misc->form_for_selector('R')->effects.moves_antenna);
  EXPECT_TRUE(misc->form_for_selector('S')->effects.moves_antenna);
}

TEST(Catalog, FormsAndSelectors) {
  const auto* am = find_command(std::uint8_t{0x32});
  ASSERT_EQ(am->forms.size(), 5u);
  EXPECT_EQ(am->form_for_selector('C')->id, "2B");
  EXPECT_EQ(am->form_for_selector('E')->id, "2C");
  EXPECT_EQ(am->form_for_selector('P')->id, "3");
  EXPECT_EQ(am->form_for_selector('Z'), nullptr);
  EXPECT_EQ(find_command(std::uint8_t{0x33})->forms.size(), 7u);  // E W D U O L X
  EXPECT_EQ(find_command(std::uint8_t{0x47})->forms.size(), 7u);
}

TEST(Catalog, FindByKeyNameOrCode) {
  EXPECT_EQ(find_command("auto_move")->code, 0x32);
  EXPECT_EQ(find_command("Device Status Poll")->code, 0x31);
  EXPECT_EQ(find_command("device status poll")->code, 0x31);
  EXPECT_EQ(find_command("40h")->code, 0x40);
  EXPECT_EQ(find_command("0x48")->code, 0x48);
  EXPECT_EQ(find_command("nonsense"), nullptr);
  EXPECT_EQ(find_command("4Zh"), nullptr);
}

// Every request layout fills exactly the catalog's length.
TEST(Catalog, EveryRequestLayoutMatchesTheCatalogLength) {
  std::set<std::uint8_t> seen;
  auto check = [&]<class T>(std::type_identity<T>) {
    Request r = T{};
    const CommandInfo* info = find_command(command_code(r));
    ASSERT_NE(info, nullptr);
    seen.insert(info->code);
    Bytes frame = encode_request(r, '2');
    if (info->request_length) {
      EXPECT_EQ(frame.size(), *info->request_length) << info->name;
    } else {
      EXPECT_EQ(frame.size(), 7u) << info->name << ": index only when the payload is empty";
    }
  };
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (check(std::type_identity<std::variant_alternative_t<I, Request>>{}), ...);
  }(std::make_index_sequence<std::variant_size_v<Request>>{});
  EXPECT_EQ(seen.size(), 25u) << "one request type per command code";
}

// Every command's reply layout fills exactly the catalog's reply length.
TEST(Catalog, EveryReplyLayoutMatchesTheCatalogLength) {
  for (const auto& info : catalog()) {
    bool found = false;
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      auto try_one = [&]<class T>(std::type_identity<T>) {
        if constexpr (requires { T::kKind; }) {
          if (T::kKind != info.reply) return;
          found = true;
          auto bytes = encode_reply(Reply{T{}}, '2', info.code);
          ASSERT_TRUE(bytes.ok()) << info.name;
          if (info.reply_length) {
            EXPECT_EQ(bytes.value().size(), *info.reply_length) << info.name;
          }
        }
      };
      (try_one(std::type_identity<std::variant_alternative_t<I, Reply>>{}), ...);
    }(std::make_index_sequence<std::variant_size_v<Reply>>{});
    EXPECT_TRUE(found) << info.name << " has a reply type";
  }
}

}  // namespace
}  // namespace sabus
