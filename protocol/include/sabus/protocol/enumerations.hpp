// The extended status poll enumerations (§3.17, "EXTENDED STATUS REPLY
// ENUMERATION LISTS"): the mode list for bytes 45 and 47, and the per-mode
// state (byte 46) and exit-status (byte 48) lists. Each list is a table of
// names; the name at index i has the value 0x20 + i (values 0-1Fh are the
// spec's placeholders and are never sent).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace sabus::enums {

inline constexpr std::uint8_t kFirstValue = 0x20;

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
};

const EnumList& mode_names();

// The state list (byte 46) and exit-status list (byte 48) that the spec assigns
// to a mode value; nullptr when the spec gives no list for that mode.
const EnumList* state_list_for_mode(std::uint8_t mode, const EnumReading& reading = {});
const EnumList* exit_list_for_mode(std::uint8_t mode, const EnumReading& reading = {});

// Every list, for tests and for `sabus decode` listings.
std::span<const EnumList* const> all_lists(const EnumReading& reading = {});

}  // namespace sabus::enums
