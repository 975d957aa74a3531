// Helpers shared by the controller's source files (not part of its API).
#pragma once

#include <string_view>

#include "sabus/harness/controller.hpp"
#include "sabus/protocol/enumerations.hpp"

namespace sabus::harness {

// Values of the §3.17 enumerations by name, so no value is written twice.
std::uint8_t enum_value(const enums::EnumList* list, std::string_view name);
std::uint8_t mode_value(std::string_view name);

// The track_states entry that stands for an activity of the profile.
constexpr std::string_view track_state_name(TrackActivity a) {
  switch (a) {
    case TrackActivity::kIdle: return "TRACK_STEP_IDLE";
    case TrackActivity::kPeaking: return "TRACK_STEP_PEAKING";
    case TrackActivity::kSearching: return "TRACK_SEARCH_PERFORMING_SEARCH_PATTERN";
    case TrackActivity::kError: return "TRACK_ERROR_TRACK_SYSTEM";
  }
  return "TRACK_STEP_IDLE";
}

// The entry of an exit list that means "finished as intended".
inline std::string_view normal_exit_name(const enums::EnumList& exits) {
  for (std::string_view key : {"NORMAL_EXIT", "FINISHED_NORMALLY", "FUNCTION_COMPLETED", "STORED_OK"})
    for (auto name : exits.names)
      if (name.find(key) != std::string_view::npos) return name;
  return exits.names.empty() ? std::string_view{} : exits.names.front();
}

}  // namespace sabus::harness
