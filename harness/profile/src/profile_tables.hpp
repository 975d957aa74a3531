// The names a profile file spells its enumerations with (not part of the
// profile library's API): one table per fact, read by the loader
// (profile_loader.cpp) and written by the writer (profile_writer.cpp), so
// what to_yaml writes is what the loader reads.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "sabus/harness/profile.hpp"

namespace sabus::harness::profile_internal {

template <class T>
struct Named {
  std::string_view name;
  T value;
};

inline constexpr Named<PolType> kPolTypes[] = {
    {"circular", PolType::kCircular}, {"single_port", PolType::kSinglePort}, {"dual_port", PolType::kDualPort}};
inline constexpr Named<AzSensor> kAzSensors[] = {{"pot", AzSensor::kPot},
                                          {"pulse", AzSensor::kPulse},
                                          {"resolver", AzSensor::kResolver},
                                          {"fluxgate", AzSensor::kFluxgate}};
inline constexpr Named<OfflineUnknown> kOfflineUnknown[] = {{"nak", OfflineUnknown::kNak},
                                                     {"offline", OfflineUnknown::kOffline}};
// §3.2 byte 40 SSSS. The first name of a value is the one the writer
// writes; "error" is kept for the track system error.
inline constexpr Named<TrackActivity> kTrackActivities[] = {
    {"setup", TrackActivity::kSetup},
    {"auto_entry", TrackActivity::kAutoEntry},
    {"idle", TrackActivity::kIdle},
    {"peaking", TrackActivity::kPeaking},
    {"searching", TrackActivity::kSearching},
    {"program_track", TrackActivity::kProgramTrack},
    {"manual_search", TrackActivity::kManualSearch},
    {"jammed_error", TrackActivity::kJammedError},
    {"limit_error", TrackActivity::kLimitError},
    {"drive_error", TrackActivity::kDriveError},
    {"peak_limit_error", TrackActivity::kPeakLimitError},
    {"geo_position_error", TrackActivity::kGeoPositionError},
    {"system_error", TrackActivity::kError},
    {"error", TrackActivity::kError},
    {"checksum_error", TrackActivity::kChecksumError}};
// §3.2 byte 40 BBB; "K" (the 'T' parameter of §3.7) is Ku.
inline constexpr Named<TrackBand> kTrackBands[] = {{"X", TrackBand::kX},   {"Ka", TrackBand::kKa},
                                                   {"S", TrackBand::kS},   {"C", TrackBand::kC},
                                                   {"Ku", TrackBand::kKu}, {"K", TrackBand::kKu},
                                                   {"L", TrackBand::kL},   {"none", TrackBand::kNone}};
// §3.2 byte 35 ZZZ: the polarization code displayed.
inline constexpr Named<char> kPolCodes[] = {{"H", 'H'}, {"h", 'h'}, {"V", 'V'}, {"v", 'v'}, {"none", 0}};
// §3.2 byte 44 CC (00 is not defined).
inline constexpr Named<std::uint8_t> kAgcChannels[] = {{"SS1", 1}, {"SS2", 2}, {"not_applicable", 3}};
// §3.2 byte 19 with a fluxgate compass: magnetic or true heading.
inline constexpr Named<char> kHeadingReferences[] = {{"T", 'T'}, {"M", 'M'}};
// §3.2 bytes 36-38 'S'.
inline constexpr Named<AxisSpeed> kAxisSpeeds[] = {{"fast", AxisSpeed::kFast}, {"slow", AxisSpeed::kSlow}};
// §3.22 byte 3 'XXX' (110 is not defined for lat/lon).
inline constexpr Named<std::uint8_t> kLatLonSources[] = {{"none", 1},   {"gps", 2},   {"manual", 3},
                                                  {"preset", 4}, {"saved", 5}, {"remote", 7}};
// §3.22 byte 29 'XXX'.
inline constexpr Named<std::uint8_t> kHeadingSources[] = {{"none", 1},     {"fluxgate_auto", 2}, {"fluxgate_manual", 3},
                                                   {"manual", 4},   {"user_fix", 5},      {"dvb_receiver", 6},
                                                   {"remote", 7}};
// §3.2 bytes 36-38 'XXXX': the alarm codes 1000-1100.
inline constexpr Named<std::uint8_t> kAxisAlarms[] = {{"none", 0},     {"off_axis", 8}, {"sensor_direction", 9},
                                               {"runaway", 10}, {"jammed", 11},  {"drive", 12}};
// ERRATA E-2: CONFIG items 1-6.
inline constexpr int kBauds[] = {300, 600, 1200, 2400, 4800, 9600};

// The first name of `value` (the one the writer writes); empty when the
// table has none (a raw source code 1-7).
template <class T, std::size_t N>
std::string_view name_of(const Named<T> (&table)[N], T value) {
  for (const auto& n : table)
    if (n.value == value) return n.name;
  return {};
}

template <class T, std::size_t N>
std::string names_of(const Named<T> (&table)[N]) {
  std::string out;
  for (const auto& n : table) out += (out.empty() ? "" : ", ") + std::string(n.name);
  return out;
}

}  // namespace sabus::harness::profile_internal
