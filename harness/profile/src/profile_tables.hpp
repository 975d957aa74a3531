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
inline constexpr Named<TrackActivity> kTrackActivities[] = {{"idle", TrackActivity::kIdle},
                                                     {"peaking", TrackActivity::kPeaking},
                                                     {"searching", TrackActivity::kSearching},
                                                     {"error", TrackActivity::kError}};
inline constexpr Named<char> kTrackBands[] = {{"C", 'C'}, {"K", 'K'}};  // §3.2 byte 40 / §3.7 'T'
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

template <class T, std::size_t N>
std::string names_of(const Named<T> (&table)[N]) {
  std::string out;
  for (const auto& n : table) out += (out.empty() ? "" : ", ") + std::string(n.name);
  return out;
}

}  // namespace sabus::harness::profile_internal
