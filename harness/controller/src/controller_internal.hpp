// Helpers shared by the controller's source files (not part of its API).
#pragma once

#include <chrono>
#include <cstdint>
#include <string_view>

#include "sabus/harness/controller.hpp"
#include "sabus/protocol/enumerations.hpp"

namespace sabus::harness {

// Values of the §3.17 enumerations by name, so no value is written twice;
// a mode's at compile time (enums::Mode).
std::uint8_t enum_value(const enums::EnumList* list, std::string_view name);
consteval std::uint8_t mode_value(std::string_view name) { return enums::Mode(name).value; }

// §3.4: "any move will be for a time interval equal to a multiple of approx.
// 50 milliseconds": a duration is rounded up to the timer's resolution, or
// on ERRATA E-61's other side to the nearest multiple (under 25 ms: no move).
inline constexpr std::chrono::milliseconds kJogTick{50};
inline Duration jog_duration(std::uint32_t ms, bool nearest) {
  const auto tick = static_cast<std::uint32_t>(kJogTick.count());
  const auto ticks = nearest ? (ms + tick / 2) / tick : (ms + tick - 1) / tick;
  return std::chrono::duration_cast<Duration>(kJogTick * ticks);
}

// §2 REMOTE JOG HOLD: a jog key sent remotely moves its axis for 20 x 1/40 s
// (the example's value); ERRATA E-56's other side for the hold time the
// device is configured with (1-40 x 1/40 s), here the longest, 40 x 1/40 s.
inline Duration key_jog_hold(ReadingSide side) {
  return std::chrono::duration_cast<Duration>(std::chrono::milliseconds(side == ReadingSide::kOther ? 1000 : 500));
}

// One row per TRACK submode of the profile: §3.2 byte 40 SSSS, the §3.17
// track_states entry that stands for it, and whether it is "a peaking or
// search operation" (§3.2 byte 35 'Y', §3.4, §3.5, §3.7 'T'; ERRATA E-69).
struct TrackSubmode {
  TrackActivity activity;
  std::uint8_t ssss;
  std::string_view state;
  bool peaking_or_search;
};
inline constexpr TrackSubmode kTrackSubmodes[] = {
    {TrackActivity::kSetup, 0b0001, "TRACK_INITIALIZING_PARAMETERS", false},
    {TrackActivity::kAutoEntry, 0b0010, "TRACK_ENTERING_MODE", false},
    {TrackActivity::kIdle, 0b0011, "TRACK_STEP_IDLE", false},
    {TrackActivity::kPeaking, 0b0011, "TRACK_STEP_PEAKING", true},
    {TrackActivity::kSearching, 0b0100, "TRACK_SEARCH_PERFORMING_SEARCH_PATTERN", true},
    {TrackActivity::kProgramTrack, 0b0101, "TRACK_TLE_IDLE", false},
    // The operator searches by hand: its states include pol jogs (E-69).
    {TrackActivity::kManualSearch, 0b0110, "TRACK_MANUAL_SEARCH_ACTIVE", false},
    {TrackActivity::kJammedError, 0b1000, "TRACK_ERROR_CREEP_JAMMED", false},
    {TrackActivity::kLimitError, 0b1001, "TRACK_ERROR_CREEP_LIMIT", false},
    {TrackActivity::kDriveError, 0b1010, "TRACK_ERROR_CREEP_DRIVE", false},
    {TrackActivity::kPeakLimitError, 0b1011, "TRACK_ERROR_PEAK_LIMIT", false},
    {TrackActivity::kGeoPositionError, 0b1100, "TRACK_ERROR_TRACK_GEO", false},
    {TrackActivity::kError, 0b1101, "TRACK_ERROR_TRACK_SYSTEM", false},
    {TrackActivity::kChecksumError, 0b1110, "TRACK_ERROR_TRACK_CHECKSUM", false},
};

constexpr const TrackSubmode& track_submode(TrackActivity a) {
  for (const auto& s : kTrackSubmodes)
    if (s.activity == a) return s;
  return kTrackSubmodes[2];  // not reached: every activity has a row
}
// §3.2 byte 40: the error submodes are 1000-1110.
constexpr bool is_track_error(TrackActivity a) { return track_submode(a).ssss >= 0b1000; }

// The entry of an exit list that means "finished as intended".
inline std::string_view normal_exit_name(const enums::EnumList& exits) {
  for (std::string_view key : {"NORMAL_EXIT", "FINISHED_NORMALLY", "FUNCTION_COMPLETED", "STORED_OK"})
    for (auto name : exits.names)
      if (name.find(key) != std::string_view::npos) return name;
  return exits.names.empty() ? std::string_view{} : exits.names.front();
}

}  // namespace sabus::harness
