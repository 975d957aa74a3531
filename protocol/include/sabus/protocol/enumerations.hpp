// The extended status poll enumerations (§3.17, "EXTENDED STATUS REPLY
// ENUMERATION LISTS"): the mode list for bytes 45 and 47, and the per-mode
// state (byte 46) and exit-status (byte 48) lists. Each list is a table of
// names; the name at index i has the value 0x20 + i (values 0-1Fh are the
// spec's placeholders and are never sent).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace sabus::enums {

inline constexpr std::uint8_t kFirstValue = 0x20;

// Values for byte 45 (current mode) and byte 47 (last exited mode), as the
// spec prints them (transcription rules: enumerations.cpp). Here rather than
// with the other lists because code names modes: enums::Mode.
inline constexpr std::string_view kModeNames[] = {
    "MANUAL_MODE",          // 0x20
    "AUTO_MODE",            // 0x21
    "POSITION_MODE",
    "TRUCK_POS_MODE",
    "TRUCK_HDG_MODE",
    "LOCATE_MODE",          // printed "LOCATE MODE"
    // Printed "SPIRAL REMOTE MODE": one name (READING-NOTES 27). REMOTE_MODE
    // appears again below and a C enum cannot hold a name twice.
    "SPIRAL_REMOTE_MODE",   // 0x26
    "STORE_SAT_MODE",       // 0x27
    "TRACK_MODE",
    "AUX_MODE",             // printed "AUX MODE"
    "FAIRING_MODE",
    "POS_CONFIRM_MODE",
    "DEPLOY_REQUEST_MODE",
    "HEADING_FIX_MODE",
    "SETTINGS_MODE",
    "STOW_MODE",
    "DEPLOY_MODE",
    "RECALL_MODE",          // printed "RECALL MODE"
    "REMOTE_MODE",          // 0x32
    "DEFINE_MODE",
    "INIT_MODE",
    "SETUP_MODE",
    "PACK_MODE",
    "RESET_MODE",
    "DELETE_MODE",          // printed "DELETE MODE"
    /* START OF PROGRAMMING MODES */
    "CONFIG_MENU_MODE",
    "ANTENNA_CONFIG_MODE",
    "AUTOPOL_CONFIG_MODE",
    "SAT_PRESET_CONFIG_MODE",
    "TRUCK_PRESET_CONFIG_MODE",
    "EXPERT_CONFIG_MODE",
    "RESET_DEFAULTS_CONFIG_MODE",
    "AZIM_CAL_CONFIG_MODE",
    "SYS_COMP_CONFIG_MODE",
    "AZIM_POT_DRIVE_CONFIG_MODE",
    "ELEV_POT_DRIVE_CONFIG_MODE",
    "AZIM_PULSE_CAL_CONFIG_MODE",
    "ELEV_PULSE_CAL_CONFIG_MODE",
    "POL_POT_DRIVE_CONFIG_MODE",
    "PULSE_LIMITS_MODE",
    "TRACK_CONFIG_MODE",
    "AGC_CONFIG_MODE",
    "LIMITS_CONFIG_MODE",
    "TLE_1_CONFIG_MODE",
    "TLE_2_CONFIG_MODE",
    // Maintenance / diagnostic modes.
    "DUMP_FLUXGATE_DATA_MODE",
    "DUMP_GPS1_NMEA_DATA_MODE",
    "DUMP_GPS1_RAW_DATA_MODE",
    "DUMP_GPS2_RAW_DATA_MODE",
    "DUMP_GPS3_RAW_DATA_MODE",
    "COMPASS_CAL",
    "GPS_DIAG_MODE",
    "AD_DIAG_MODE",
    "LIMITS_DIAG_MODE",
    "AGC_OFFSET_MODE",
    "DIAG_MENU_MODE",
    "TIMEDATE_DIAG_MODE",
    "SHAKE_MODE",
    "AZEL_MODE",
    "GPSHDG_MODE",
    "UNDEFINED_MODE",
};

// The index and the value of `name` in a list of names, for names written in
// code: a name not in the list is not a constant expression, so in a constant
// context (static_assert, consteval) a typo fails to compile.
constexpr std::size_t index_in(std::span<const std::string_view> names, std::string_view name) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return i;
  throw "name not in list";
}
constexpr std::size_t value_in(std::span<const std::string_view> names, std::string_view name) {
  return kFirstValue + index_in(names, name);
}

// A mode named in code, e.g. Mode("LOCATE_MODE"): its value found at compile
// time, so that a name not in kModeNames fails to compile (it used to read as
// 0x20, MANUAL_MODE).
struct Mode {
  std::uint8_t value;
  consteval Mode(std::string_view name) : value(static_cast<std::uint8_t>(value_in(kModeNames, name))) {}
  consteval Mode(const char* name) : Mode(std::string_view(name)) {}
  friend constexpr bool operator==(Mode, Mode) = default;
};

struct EnumList {
  std::string_view name;                      // the C enum name, e.g. "locate_exit_conditions"
  std::span<const std::string_view> names;    // names[i] has value 0x20 + i
  std::optional<std::string_view> name_of(std::uint8_t value) const;
  std::optional<std::uint8_t> value_of(std::string_view name) const;
};

// Readings of the garbled lists that a device profile can switch
// (protocol/ERRATA.md E-28).
struct EnumReading {
  // READING-NOTES 28: restore LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_MODE_CHANGED,
  // lost at a page break, so LOCATE_FUNCTION_COMPLETED is 0x38 (printed list: 0x37).
  bool restore_lost_locate_exit = true;
  // ERRATA E-34: track_states' last four as printed (JOG_POL_CCW 0x45 ...
  // JOG_POL_CW 0x48), or in the order of manual_states (JOG_POL_CW 0x45,
  // JOG_POL_CCW, AUTO_POL_MOVE, IDLE 0x48).
  bool track_pol_states_as_manual_states = false;
};

const EnumList& mode_names();

// The state list (byte 46) and exit-status list (byte 48) that the spec assigns
// to a mode value; nullptr when the spec gives no list for that mode.
const EnumList* state_list_for_mode(std::uint8_t mode, const EnumReading& reading = {});
const EnumList* exit_list_for_mode(std::uint8_t mode, const EnumReading& reading = {});

// Every list, for tests and for `sabus decode` listings.
std::span<const EnumList* const> all_lists(const EnumReading& reading = {});

}  // namespace sabus::enums
