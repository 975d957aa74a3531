// Tests for the extended status enumeration lists (§3.17, "EXTENDEND STATUS
// REPLY ENUMERATION LISTS"). Expected values are counted by hand in the spec
// text (placeholders 0-1Fh left out, so the first real name is 0x20).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/protocol/enumerations.hpp"

namespace {

using sabus::enums::EnumList;
using sabus::enums::EnumReading;
using sabus::enums::all_lists;
using sabus::enums::exit_list_for_mode;
using sabus::enums::Mode;
using sabus::enums::mode_names;
using sabus::enums::state_list_for_mode;

constexpr EnumReading kRestored{true};
constexpr EnumReading kPrinted{false};

const EnumList* find_list(std::string_view name, const EnumReading& reading = {}) {
  for (const EnumList* l : all_lists(reading))
    if (l != nullptr && l->name == name) return l;
  return nullptr;
}

std::uint8_t mode(std::string_view name) {
  auto v = mode_names().value_of(name);
  EXPECT_TRUE(v.has_value()) << "no mode named " << name;
  return v.value_or(0);
}

int value(std::string_view list, std::string_view name, const EnumReading& reading = {}) {
  const EnumList* l = find_list(list, reading);
  if (l == nullptr) {
    ADD_FAILURE() << "no list " << list;
    return -1;
  }
  auto v = l->value_of(name);
  if (!v) {
    ADD_FAILURE() << "no name " << name << " in " << list;
    return -1;
  }
  return *v;
}

// enums::Mode: the value of a mode named in code, found at compile time, is
// the list's value for that name (a name not in the list does not compile).
TEST(Enumerations, ModeNamedInCodeHasTheListsValue) {
  static_assert(Mode("MANUAL_MODE").value == 0x20);
  static_assert(Mode("SPIRAL_REMOTE_MODE").value == 0x26);
  static_assert(Mode("REMOTE_MODE") != Mode("SPIRAL_REMOTE_MODE"));
  EXPECT_EQ(Mode("LOCATE_MODE").value, mode("LOCATE_MODE"));
  EXPECT_EQ(Mode("TRACK_MODE").value, mode("TRACK_MODE"));
  EXPECT_EQ(Mode("INIT_MODE").value, mode("INIT_MODE"));
  EXPECT_EQ(mode_names().name_of(Mode("RECALL_MODE").value), "RECALL_MODE");
}

TEST(Enumerations, ModeValues) {
  EXPECT_EQ(mode("MANUAL_MODE"), 0x20);
  EXPECT_EQ(mode("AUTO_MODE"), 0x21);
  EXPECT_EQ(mode("POSITION_MODE"), 0x22);
  EXPECT_EQ(mode("TRUCK_POS_MODE"), 0x23);
  EXPECT_EQ(mode("TRUCK_HDG_MODE"), 0x24);
  EXPECT_EQ(mode("LOCATE_MODE"), 0x25);
  EXPECT_EQ(mode("SPIRAL_REMOTE_MODE"), 0x26);
  EXPECT_EQ(mode("STORE_SAT_MODE"), 0x27);
  EXPECT_EQ(mode("TRACK_MODE"), 0x28);
  EXPECT_EQ(mode("RECALL_MODE"), 0x31);
  EXPECT_EQ(mode("REMOTE_MODE"), 0x32);
  EXPECT_EQ(mode("DEFINE_MODE"), 0x33);
  EXPECT_EQ(mode("DELETE_MODE"), 0x38);
  EXPECT_EQ(mode("CONFIG_MENU_MODE"), 0x39);
  EXPECT_EQ(mode("TLE_2_CONFIG_MODE"), 0x4C);
  EXPECT_EQ(mode("DUMP_FLUXGATE_DATA_MODE"), 0x4D);
  EXPECT_EQ(mode("DIAG_MENU_MODE"), 0x57);
  EXPECT_EQ(mode("UNDEFINED_MODE"), 0x5C);
  EXPECT_EQ(mode_names().name, "mode_names");
  EXPECT_EQ(mode_names().names.size(), 61u);
  // "SPIRAL REMOTE MODE" is one name; the OCR spaces are gone.
  EXPECT_FALSE(mode_names().value_of("SPIRAL_MODE").has_value());
  EXPECT_FALSE(mode_names().value_of("LOCATE MODE").has_value());
}

TEST(Enumerations, LocateExitReadings) {
  // Default reading restores the entry lost at the page break (READING-NOTES 28).
  EXPECT_EQ(value("locate_exit_conditions", "LOCATE_FUNCTION_COMPLETED"), 0x38);
  EXPECT_EQ(value("locate_exit_conditions", "LOCATE_FUNCTION_COMPLETED", kRestored), 0x38);
  EXPECT_EQ(value("locate_exit_conditions", "LOCATE_FUNCTION_COMPLETED", kPrinted), 0x37);

  const EnumList* restored = find_list("locate_exit_conditions", kRestored);
  const EnumList* printed = find_list("locate_exit_conditions", kPrinted);
  ASSERT_NE(restored, nullptr);
  ASSERT_NE(printed, nullptr);
  EXPECT_NE(restored, printed);
  EXPECT_EQ(restored->names.size(), 64u);
  EXPECT_EQ(printed->names.size(), 63u);

  EXPECT_EQ(restored->value_of("LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_STOP_KEY"), 0x2A);
  EXPECT_EQ(printed->value_of("LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_STOP_KEY"), 0x2A);
  EXPECT_EQ(restored->value_of("LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_MODE_CHANGED"), 0x2B);
  EXPECT_FALSE(printed->value_of("LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_MODE_CHANGED"));
  EXPECT_EQ(restored->value_of("LOCATE_ROLL_CALC_AZIM_MOVEMENT_STOP_KEY"), 0x2C);
  EXPECT_EQ(printed->value_of("LOCATE_ROLL_CALC_AZIM_MOVEMENT_STOP_KEY"), 0x2B);
  EXPECT_EQ(restored->value_of("LAST_LOCATE_EXIT_CONDITION"), 0x5F);
  EXPECT_EQ(printed->value_of("LAST_LOCATE_EXIT_CONDITION"), 0x5E);

  // Apart from the lost entry the two readings hold the same names in order.
  std::vector<std::string_view> a(restored->names.begin(), restored->names.end());
  std::erase(a, "LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_MODE_CHANGED");
  std::vector<std::string_view> b(printed->names.begin(), printed->names.end());
  EXPECT_EQ(a, b);

  // The mode mapping follows the reading.
  EXPECT_EQ(exit_list_for_mode(mode("LOCATE_MODE")), restored);
  EXPECT_EQ(exit_list_for_mode(mode("LOCATE_MODE"), kPrinted), printed);
  EXPECT_EQ(state_list_for_mode(mode("LOCATE_MODE"), kPrinted),
            state_list_for_mode(mode("LOCATE_MODE"), kRestored));
}

TEST(Enumerations, NamesAreWellFormedAndUnique) {
  const std::regex ident("^[A-Z0-9_]+$");
  for (const EnumReading& reading : {kRestored, kPrinted}) {
    for (const EnumList* l : all_lists(reading)) {
      ASSERT_NE(l, nullptr);
      EXPECT_FALSE(l->name.empty());
      EXPECT_FALSE(l->names.empty()) << l->name;
      std::set<std::string_view> seen;
      for (std::string_view n : l->names) {
        EXPECT_FALSE(n.empty()) << l->name;
        EXPECT_TRUE(std::regex_match(std::string(n), ident)) << l->name << ": '" << n << "'";
        EXPECT_TRUE(seen.insert(n).second) << l->name << ": duplicate " << n;
      }
    }
  }
}

TEST(Enumerations, EveryValueFitsInAPrintableByte) {
  for (const EnumReading& reading : {kRestored, kPrinted}) {
    for (const EnumList* l : all_lists(reading)) {
      ASSERT_FALSE(l->names.empty());
      EXPECT_LE(0x20u + l->names.size() - 1, 0x7Fu) << l->name;
      for (std::string_view n : l->names) {
        auto v = l->value_of(n);
        ASSERT_TRUE(v.has_value()) << n;
        EXPECT_GE(*v, 0x20) << n;
        EXPECT_LE(*v, 0x7F) << n;
      }
    }
  }
}

TEST(Enumerations, NameOfValueOfRoundTrip) {
  for (const EnumReading& reading : {kRestored, kPrinted}) {
    for (const EnumList* l : all_lists(reading)) {
      for (std::size_t i = 0; i < l->names.size(); ++i) {
        const auto v = static_cast<std::uint8_t>(0x20 + i);
        auto n = l->name_of(v);
        ASSERT_TRUE(n.has_value()) << l->name << " " << i;
        EXPECT_EQ(*n, l->names[i]);
        EXPECT_EQ(l->value_of(*n), v) << l->name << ": " << *n;
      }
      EXPECT_FALSE(l->name_of(0x00).has_value()) << l->name;
      EXPECT_FALSE(l->name_of(0x1F).has_value()) << l->name;
      EXPECT_FALSE(l->name_of(static_cast<std::uint8_t>(0x20 + l->names.size())).has_value())
          << l->name;
      EXPECT_FALSE(l->name_of(0xFF).has_value()) << l->name;
      EXPECT_FALSE(l->value_of("").has_value()) << l->name;
    }
  }
  // Placeholders are not names.
  EXPECT_FALSE(mode_names().value_of("U0").has_value());
  EXPECT_FALSE(mode_names().value_of("U31").has_value());
}

TEST(Enumerations, ListSizesAsCountedInTheSpec) {
  const std::map<std::string_view, std::size_t> expected = {
      {"mode_names", 61},          {"simple_mode_states", 3},
      {"simple_exit_status", 2},   {"locate_states", 63},
      {"locate_exit_conditions", 64}, {"store_states", 9},
      {"store_exit_conditions", 11}, {"track_states", 42},
      {"stow_states", 17},         {"stow_exit_conditions", 21},
      {"deploy_states", 8},        {"deploy_exit_conditions", 8},
      {"menu_states", 2},          {"menu_exit_conditions", 2},
      {"manual_states", 10},       {"pos_confirm_states", 3},
      {"fairing_mode_states", 9},  {"truck_pos_mode_states", 8},
      {"init_mode_states", 11},    {"init_exit_conditions", 6},
      {"setup_pack_mode_states", 7}, {"setup_pack_exit_conditions", 10},
      {"recall_mode_states", 9},   {"recall_exit_conditions", 9},
  };
  auto lists = all_lists();
  ASSERT_EQ(lists.size(), expected.size());
  EXPECT_EQ(lists[0], &mode_names());
  std::set<std::string_view> names;
  for (const EnumList* l : lists) {
    EXPECT_TRUE(names.insert(l->name).second) << "duplicate list " << l->name;
    auto it = expected.find(l->name);
    ASSERT_NE(it, expected.end()) << l->name;
    EXPECT_EQ(l->names.size(), it->second) << l->name;
  }
  EXPECT_EQ(all_lists(kPrinted).size(), expected.size());
  EXPECT_EQ(all_lists(kPrinted)[0], &mode_names());
}

// ERRATA E-34: track_states' last four as printed, or in manual_states'
// order; every other value of the list, and every other list, the same. The
// two readings combine with E-28's.
TEST(Enumerations, TheLastFourTrackStatesFollowE34) {
  const EnumList* printed = state_list_for_mode(Mode("TRACK_MODE").value);
  const EnumList* manual = state_list_for_mode(Mode("TRACK_MODE").value, EnumReading{true, true});
  ASSERT_TRUE(printed && manual);
  EXPECT_EQ(printed->value_of("TRACK_MANUAL_SEARCH_JOG_POL_CCW"), 0x45);
  EXPECT_EQ(printed->value_of("TRACK_MANUAL_SEARCH_JOG_POL_CW"), 0x48);
  const std::vector<std::string_view> order = {"TRACK_MANUAL_SEARCH_JOG_POL_CW", "TRACK_MANUAL_SEARCH_JOG_POL_CCW",
                                               "TRACK_MANUAL_SEARCH_AUTO_POL_MOVE", "TRACK_MANUAL_SEARCH_IDLE"};
  for (std::size_t k = 0; k < order.size(); ++k) EXPECT_EQ(manual->value_of(order[k]), 0x45 + k) << order[k];
  ASSERT_EQ(printed->names.size(), manual->names.size());
  for (std::uint8_t v = 0x20; v < 0x45; ++v) EXPECT_EQ(printed->name_of(v), manual->name_of(v)) << int(v);
  EXPECT_EQ(printed->name_of(0x49), manual->name_of(0x49));
  for (const EnumReading reading : {EnumReading{true, true}, EnumReading{false, true}}) {
    const auto lists = all_lists(reading);
    EXPECT_EQ(lists.size(), all_lists().size());
    EXPECT_NE(std::find(lists.begin(), lists.end(), manual), lists.end());
    EXPECT_EQ(std::find(lists.begin(), lists.end(), printed), lists.end());
    EXPECT_EQ(exit_list_for_mode(Mode("LOCATE_MODE").value, reading),
              exit_list_for_mode(Mode("LOCATE_MODE").value, EnumReading{reading.restore_lost_locate_exit}));
  }
}

TEST(Enumerations, SentinelsArePartOfTheLists) {
  for (const EnumList* l : all_lists()) {
    const std::string_view last = l->names.back();
    if (l == &mode_names())
      EXPECT_EQ(last, "UNDEFINED_MODE");
    else
      EXPECT_TRUE(last.starts_with("LAST_")) << l->name << " ends with " << last;
  }
  EXPECT_EQ(value("locate_states", "LAST_LOCATE_STATE"), 0x5E);
  EXPECT_EQ(value("track_states", "LAST_TRACK_STATE"), 0x49);
}

TEST(Enumerations, FirstEntriesAndCountedValues) {
  EXPECT_EQ(value("simple_mode_states", "INITIALIZING_MODE"), 0x20);
  EXPECT_EQ(value("simple_mode_states", "WAITING_FOR_USER_INPUT"), 0x21);
  EXPECT_EQ(value("simple_exit_status", "MODE_NORMAL_EXIT"), 0x20);
  EXPECT_EQ(value("locate_states", "ENTERING_LOCATE_MODE"), 0x20);
  EXPECT_EQ(value("locate_states", "LOCATE_WAITING_FOR_SAT_DATA"), 0x2C);
  EXPECT_EQ(value("locate_states", "BEGINNING_SPIRAL_SEARCH"), 0x4E);
  EXPECT_EQ(value("locate_exit_conditions", "LOCATE_CANNOT_INITIATE_MOVEMENT_BELOW_DOWN_LIMIT"), 0x20);
  EXPECT_EQ(value("store_states", "STORE_ENTERING_MODE"), 0x20);
  EXPECT_EQ(value("store_exit_conditions", "STORE_INVALID_REGION"), 0x20);
  EXPECT_EQ(value("store_exit_conditions", "STORE_SAT_DATA_STORED_OK"), 0x26);
  EXPECT_EQ(value("track_states", "TRACK_ENTERING_MODE"), 0x20);
  EXPECT_EQ(value("track_states", "TRACK_MANUAL_SEARCH_ACTIVE"), 0x2F);
  // Printed order kept (errata): ..., JOG_POL_CCW, AUTO_POL_MOVE, IDLE, JOG_POL_CW.
  EXPECT_EQ(value("track_states", "TRACK_MANUAL_SEARCH_JOG_POL_CCW"), 0x45);
  EXPECT_EQ(value("track_states", "TRACK_MANUAL_SEARCH_IDLE"), 0x47);
  EXPECT_EQ(value("track_states", "TRACK_MANUAL_SEARCH_JOG_POL_CW"), 0x48);
  EXPECT_EQ(value("stow_states", "STOW_INITIALIZING_MODE"), 0x20);
  EXPECT_EQ(value("stow_exit_conditions", "STOW_FINISHED_NORMALLY"), 0x31);
  EXPECT_EQ(value("deploy_states", "DEPLOY_INITIAIZING_MODE"), 0x20);
  EXPECT_EQ(value("deploy_exit_conditions", "DEPLOY_FINISHED_NORMALLY"), 0x26);
  EXPECT_EQ(value("menu_states", "MENU_WAITING_FOR_SELECTION"), 0x20);
  EXPECT_EQ(value("menu_exit_conditions", "MENU_MODE_NORMAL_EXIT"), 0x20);
  EXPECT_EQ(value("manual_states", "MANUAL_INITIALIZING_MODE"), 0x20);
  EXPECT_EQ(value("manual_states", "MANUAL_JOG_AZIM_CCW"), 0x21);
  EXPECT_EQ(value("manual_states", "MANUAL_IDLE"), 0x28);
  EXPECT_EQ(value("pos_confirm_states", "POS_CONFIRM_INITIALIZING_MODE"), 0x20);
  EXPECT_EQ(value("fairing_mode_states", "FAIRING_WAITING_ELEV_NOT_STOWED"), 0x20);
  EXPECT_EQ(value("truck_pos_mode_states", "TRUCK_POS_INITIALIZING_MODE"), 0x20);
  EXPECT_EQ(value("init_mode_states", "INIT_INITIALIZING_MODE"), 0x20);
  EXPECT_EQ(value("init_exit_conditions", "INIT_NORMAL_EXIT"), 0x24);
  EXPECT_EQ(value("setup_pack_mode_states", "SETUP_PACK_WAITING_FOR_USER_TO_INITATE_MVOEMENT"), 0x20);
  EXPECT_EQ(value("setup_pack_exit_conditions", "SETUP_PACK_NORMAL_EXIT"), 0x28);
  EXPECT_EQ(value("recall_mode_states", "RECALL_ENTERING_MODE"), 0x20);
  EXPECT_EQ(value("recall_exit_conditions", "RECALL_ELEV_MOVE_STOPPED"), 0x20);
  EXPECT_EQ(value("recall_exit_conditions", "RECALL_NORMAL_EXIT"), 0x27);
}

TEST(Enumerations, SpecSpellingIsKept) {
  EXPECT_EQ(value("init_mode_states", "INIT_WAIITNING_FOR_DEPLOY_CONFIRMATION"), 0x21);
  EXPECT_EQ(value("stow_states", "STOW_WAITITNG_CANNOT_FIND_AZ_STOW_SWITCH"), 0x27);
  EXPECT_EQ(value("stow_exit_conditions", "STOW_MOVING_TO_INITIAL_CW_POSITION_MODE_CHANGE"), 0x22);
  EXPECT_EQ(value("locate_exit_conditions", "SPIRAL_ADJUSTING_AZIM_ELEVATION_STEP_MODE_CHANGED"), 0x57);
  const EnumList* init = find_list("init_mode_states");
  ASSERT_NE(init, nullptr);
  EXPECT_FALSE(init->value_of("INIT_WAITING_FOR_DEPLOY_CONFIRMATION").has_value());
}

TEST(Enumerations, ManualModeUsesManualStatesAndSimpleExit) {
  const EnumList* s = state_list_for_mode(0x20);
  const EnumList* e = exit_list_for_mode(0x20);
  ASSERT_NE(s, nullptr);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(s->name, "manual_states");
  EXPECT_EQ(e->name, "simple_exit_status");
  EXPECT_EQ(s, find_list("manual_states"));
  EXPECT_EQ(e, find_list("simple_exit_status"));
}

TEST(Enumerations, ModeToListMapping) {
  struct Row {
    std::string_view mode;
    std::string_view states;  // "" = nullptr
    std::string_view exits;   // "" = nullptr
  };
  const Row rows[] = {
      {"MANUAL_MODE", "manual_states", "simple_exit_status"},
      {"AUTO_MODE", "", ""},
      {"POSITION_MODE", "simple_mode_states", "simple_exit_status"},
      {"TRUCK_POS_MODE", "truck_pos_mode_states", "simple_exit_status"},
      {"TRUCK_HDG_MODE", "simple_mode_states", "simple_exit_status"},
      {"LOCATE_MODE", "locate_states", "locate_exit_conditions"},
      {"SPIRAL_REMOTE_MODE", "locate_states", "locate_exit_conditions"},
      {"STORE_SAT_MODE", "store_states", "store_exit_conditions"},
      {"TRACK_MODE", "track_states", ""},
      {"AUX_MODE", "simple_mode_states", "simple_exit_status"},
      {"FAIRING_MODE", "fairing_mode_states", "simple_exit_status"},
      {"POS_CONFIRM_MODE", "pos_confirm_states", "simple_exit_status"},
      {"DEPLOY_REQUEST_MODE", "", ""},
      {"HEADING_FIX_MODE", "simple_mode_states", "simple_exit_status"},
      {"SETTINGS_MODE", "simple_mode_states", "simple_exit_status"},
      {"STOW_MODE", "stow_states", "stow_exit_conditions"},
      {"DEPLOY_MODE", "deploy_states", "deploy_exit_conditions"},
      {"RECALL_MODE", "recall_mode_states", "recall_exit_conditions"},
      {"REMOTE_MODE", "simple_mode_states", "simple_exit_status"},
      {"DEFINE_MODE", "simple_mode_states", "simple_exit_status"},
      {"INIT_MODE", "init_mode_states", "init_exit_conditions"},
      {"SETUP_MODE", "setup_pack_mode_states", "setup_pack_exit_conditions"},
      {"PACK_MODE", "setup_pack_mode_states", "setup_pack_exit_conditions"},
      {"RESET_MODE", "simple_mode_states", "simple_exit_status"},
      {"DELETE_MODE", "simple_mode_states", "simple_exit_status"},
      {"CONFIG_MENU_MODE", "menu_states", "menu_exit_conditions"},
      {"ANTENNA_CONFIG_MODE", "simple_mode_states", "simple_exit_status"},
      {"PULSE_LIMITS_MODE", "simple_mode_states", "simple_exit_status"},
      {"TLE_2_CONFIG_MODE", "simple_mode_states", "simple_exit_status"},
      {"DUMP_FLUXGATE_DATA_MODE", "", ""},
      {"COMPASS_CAL", "", ""},
      {"DIAG_MENU_MODE", "", ""},
      {"GPSHDG_MODE", "", ""},
      {"UNDEFINED_MODE", "", ""},
  };
  for (const EnumReading& reading : {kRestored, kPrinted}) {
    for (const Row& r : rows) {
      const std::uint8_t m = mode(r.mode);
      const EnumList* s = state_list_for_mode(m, reading);
      const EnumList* e = exit_list_for_mode(m, reading);
      if (r.states.empty()) {
        EXPECT_EQ(s, nullptr) << r.mode;
      } else {
        ASSERT_NE(s, nullptr) << r.mode;
        EXPECT_EQ(s->name, r.states) << r.mode;
        EXPECT_EQ(s, find_list(r.states, reading)) << r.mode;
      }
      if (r.exits.empty()) {
        EXPECT_EQ(e, nullptr) << r.mode;
      } else {
        ASSERT_NE(e, nullptr) << r.mode;
        EXPECT_EQ(e->name, r.exits) << r.mode;
        EXPECT_EQ(e, find_list(r.exits, reading)) << r.mode;
      }
    }
  }
}

TEST(Enumerations, ConfigurationBlockAndMaintenanceBlock) {
  // Every programming mode after CONFIG_MENU_MODE uses the simple lists; no
  // maintenance mode is instrumented.
  const std::uint8_t first_cfg = mode("ANTENNA_CONFIG_MODE");
  const std::uint8_t last_cfg = mode("TLE_2_CONFIG_MODE");
  EXPECT_EQ(last_cfg - first_cfg + 1, 19);
  for (unsigned m = first_cfg; m <= last_cfg; ++m) {
    const EnumList* s = state_list_for_mode(static_cast<std::uint8_t>(m));
    ASSERT_NE(s, nullptr) << *mode_names().name_of(static_cast<std::uint8_t>(m));
    EXPECT_EQ(s->name, "simple_mode_states");
  }
  for (unsigned m = mode("DUMP_FLUXGATE_DATA_MODE"); m <= mode("UNDEFINED_MODE"); ++m) {
    EXPECT_EQ(state_list_for_mode(static_cast<std::uint8_t>(m)), nullptr) << m;
    EXPECT_EQ(exit_list_for_mode(static_cast<std::uint8_t>(m)), nullptr) << m;
  }
}

TEST(Enumerations, ValuesOutsideTheModeListHaveNoList) {
  for (unsigned m : {0x00u, 0x1Fu, 0x5Du, 0x7Fu, 0xFFu}) {
    EXPECT_EQ(state_list_for_mode(static_cast<std::uint8_t>(m)), nullptr) << m;
    EXPECT_EQ(exit_list_for_mode(static_cast<std::uint8_t>(m)), nullptr) << m;
  }
}

TEST(Enumerations, EveryMappedListIsListed) {
  for (const EnumReading& reading : {kRestored, kPrinted}) {
    auto lists = all_lists(reading);
    std::set<const EnumList*> listed(lists.begin(), lists.end());
    for (unsigned m = 0; m < 256; ++m) {
      for (const EnumList* l : {state_list_for_mode(static_cast<std::uint8_t>(m), reading),
                                exit_list_for_mode(static_cast<std::uint8_t>(m), reading)}) {
        if (l != nullptr) {
          EXPECT_TRUE(listed.count(l)) << m << " " << l->name;
        }
      }
    }
  }
}

}  // namespace
