// Every reason the reference controller answers NAK, one table: id, spec
// paragraph, and the rule in words. A NAK always names its rule, so the
// transcript, the tests and the reports say which rule fired.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace sabus::harness {

#define SABUS_NAK_RULES(X)                                                                                          \
  X(kUnknownCommand, "3", "unknown command code (NAK Reply; ERRATA E-9)")                                           \
  X(kWrongLength, "3", "a length that is not compatible with the command code (NAK Reply; ERRATA E-9)")              \
  X(kNotImplemented, "3", "not yet implemented on the RC3000 (command table '*'; ERRATA E-16)")                     \
  X(kMalformedData, "3", "a data field that does not decode (invalid command or data, §1 Message Protocol)")        \
  X(kUnknownSatellite, "3.3", "form 1: the satellite name is not in the STORE list")                                \
  X(kTargetOutOfRange, "3.3", "the target position is outside the axis limits (not specified properly)")            \
  X(kNoCountSensors, "3.3", "form 2B on a mount without pulse or resolver sensors (ERRATA E-50)")                   \
  X(kNoHundredths, "3.3", "form 2C on a mount without 0.01 deg feedback (ERRATA E-50)")                             \
  X(kPolWithCircularFeed, "3.3", "polarization movement with the Polarization Type set to CIRCULAR")                \
  X(kJogIntoLimit, "3.4", "jog toward a limit that is asserted")                                                     \
  X(kJogPolCircular, "3.4", "polarization jog with Polarization_Type 0 (circular)")                                  \
  X(kTrackPeaking, "3.4", "TRACK mode is peaking or searching")                                                      \
  X(kPolPresetNoSatellites, "3.5", "no satellites available in memory")                                             \
  X(kPolPresetCircular, "3.5", "Polarization Type set to Circular (No Pol Control)")                                \
  X(kQueryNameIndex, "3.6", "entry XX does not exist in the list (or the list has no entries)")                     \
  X(kMiscResetAxis, "3.7", "'R' needs 'A', 'E' or 'P'")                                                              \
  X(kMiscResetPolNoFeed, "3.7", "'R' 'P' needs a one- or two-port polarization feed")                               \
  X(kMiscTrackParameter, "3.7", "'T' needs 'R', 'C' or 'K'")                                                         \
  X(kMiscTrackNotActive, "3.7", "'T' while TRACK mode is not active")                                               \
  X(kMiscTrackNotDualBand, "3.7", "'T' band change for a satellite that is not dual band")                          \
  X(kMiscTrackPolNotAllowed, "3.7", "'T' band change while track polarization movement is not allowed")             \
  X(kMiscNoStow, "3.7", "'S' on a mount with no stow function")                                                      \
  X(kMiscNoDeploy, "3.7", "'D' on a mount with no deploy function")                                                  \
  X(kMiscSearchParameter, "3.7", "'A' needs 'E' or 'F'")                                                             \
  X(kKeyCode, "3.7", "a key code outside 30h-39h and 41h-47h (ERRATA E-43)")                                         \
  X(kSatelliteIndex, "3.10", "satellite data index outside 1-20")                                                   \
  X(kSatelliteField, "3.10", "a satellite data field out of its range")                                             \
  X(kEphemerisIndex, "3.10", "ephemeris data only for the first 10 satellite data sets (ERRATA E-51)")              \
  X(kTleIndex, "3.12", "TLE index outside 1-10")                                                                     \
  X(kTleChecksum, "3.12", "a TLE line whose mod-10 checksum is wrong (ERRATA E-19)")                                \
  X(kIessIndex, "3.14", "IESS-412 data index outside 1-10")                                                        \
  X(kLocateIndex, "3.18", "preset index outside the locate range (ERRATA E-22)")                                    \
  X(kLocateEmptyPreset, "3.18", "the indexed preset satellite is not stored")                                       \
  X(kLocateField, "3.18", "an error in the supplied satellite data")                                                \
  X(kStoreIndex, "3.19", "preset index outside 1-20")                                                               \
  X(kStoreEmptyPreset, "3.19", "the indexed preset satellite is not stored")                                        \
  X(kStoreField, "3.19", "an error in the supplied satellite data")                                                 \
  X(kStoreListFull, "3.19", "the STORE list holds 50 satellites and the name is new")                               \
  X(kStoreNeedsLocate, "3.19", "'C' (calculated H,V) requires a LOCATE immediately before")                         \
  X(kNoDvbOption, "3.20", "signposts need the integrated DVB receiver option (ERRATA E-23)")                          \
  X(kSignpostIndex, "3.20", "signpost index outside 1-20")                                                          \
  X(kSignpostField, "3.20", "a signpost field out of its range")                                                    \
  X(kNavigationField, "3.23", "invalid lat/lon/heading data")

enum class NakRule : std::uint8_t {
#define SABUS_X(id, paragraph, text) id,
  SABUS_NAK_RULES(SABUS_X)
#undef SABUS_X
};

std::string_view paragraph(NakRule rule);
std::string_view description(NakRule rule);
// The rule's name as vectors write it (`expect: {reply: nak, rule: StoreListFull}`):
// its id without the leading 'k'.
std::string_view name(NakRule rule);
std::optional<NakRule> find_nak_rule(std::string_view name);
std::span<const NakRule> all_nak_rules();

}  // namespace sabus::harness
