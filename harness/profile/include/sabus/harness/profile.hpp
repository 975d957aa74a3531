// A device profile: the controller under test as the reference controller and
// the runner see it (vectors/profiles/*.yaml). Every *profile* point of
// protocol/ERRATA.md is a field here, with the errata's decision as default.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/readings.hpp"
#include "sabus/protocol/bytes.hpp"
#include "sabus/protocol/messages.hpp"

namespace sabus::harness {

// §3.2 byte 35 XX; §3.3/§3.4/§3.5 "Polarization Type".
enum class PolType : std::uint8_t { kCircular, kSinglePort, kDualPort };
// The primary azimuth sensor (§3.2 NOTE on the fluxgate compass; §3.3 form 2B).
enum class AzSensor : std::uint8_t { kPot, kPulse, kResolver, kFluxgate };
// E-10: what a disabled controller answers to an unknown command code.
enum class OfflineUnknown : std::uint8_t { kNak, kOffline };
// §3.2 bytes 36-38 'S': the speed an axis is configured for.
enum class AxisSpeed : std::uint8_t { kFast, kSlow };

struct AxisProfile {
  double fast_dps = 2.0;     // degrees per second at fast speed
  double slow_dps = 0.5;     // degrees per second at slow speed
  double min_deg = -180.0;   // limit positions: reaching one asserts its limit bit
  double max_deg = 180.0;
  double initial_deg = 0.0;
  bool has_stow_limit = false;
  double stow_deg = 0.0;
  // How close an auto move stops to its target, the display's 0.1 deg
  // resolution included: vectors check arrivals within it.
  double tolerance_deg = 0.1;
  // Acceleration and deceleration, degrees per second squared; none: the
  // axis reaches its speed at once. Vectors widen motion windows for it.
  std::optional<double> accel_dps2;
  // §3.2 bytes 36-38 'S': the speed the axis is configured for at power-on.
  AxisSpeed power_on_speed = AxisSpeed::kFast;
  // §3.2 bytes 14-31, §3.24 bytes 4-9: the A/D converter reports an error on
  // this axis's sensor, so its position field holds '*' (E-42).
  bool ad_error = false;
  // §3.7 'D': where a DEPLOY drives this axis, when the profile states it
  // (the spec does not; ERRATA E-90). Vectors that stop a DEPLOY need it.
  std::optional<double> deploy_deg;
  bool operator==(const AxisProfile&) const = default;
};

// An entry of the STORE list (§3.6: up to 50, read by 35h, recalled by 32h form 1).
struct StoredSatellite {
  std::string name;          // up to 10 characters
  double az_deg = 0, el_deg = 0;
  double h_pol_deg = 0, v_pol_deg = 0;
  bool operator==(const StoredSatellite&) const = default;
};

struct PresetSatellite {     // §3.10 preset list, index 1-20
  std::uint8_t index = 1;
  SatelliteData data;
  bool dual_band = false;    // §3.7 'T' band change needs a dual band satellite
  bool operator==(const PresetSatellite&) const = default;
};

struct TleSet {              // §3.12, index 1-10
  std::uint8_t index = 1;
  std::string line1, line2;
  bool operator==(const TleSet&) const = default;
};

struct Signpost {            // §3.20, index 1-20, DVB option only
  std::uint8_t index = 1;
  SignpostData data;
  bool operator==(const Signpost&) const = default;
};

struct Navigation {          // §3.22 / §3.23
  std::uint8_t latlon_source = 1;             // 001: no lat/lon data
  std::optional<std::int32_t> latitude_min;   // signed minutes, south negative
  std::optional<std::int32_t> longitude_min;  // signed minutes, west negative
  std::uint8_t heading_source = 1;            // 001: no true heading data
  std::optional<std::int32_t> heading_tenths;
  std::optional<std::int32_t> magvar_tenths;  // nullopt: magvar not ready
  bool operator==(const Navigation&) const = default;
};

// TRACK mode at power-on, for profiles that test the TRACK rules (§3.4, §3.5,
// §3.7 'T'): the submode or error of §3.2 byte 40 SSSS. Step track is idle
// or peaking (one SSSS, told apart by byte 35 'Y'); which submodes count as
// "a peaking or search operation" is ERRATA E-69.
enum class TrackActivity : std::uint8_t {
  kSetup,             // 0001 track setup submode
  kAutoEntry,         // 0010 track auto mode entry
  kIdle,              // 0011 step track, not peaking
  kPeaking,           // 0011 step track, peaking
  kSearching,         // 0100 track auto search
  kProgramTrack,      // 0101 program track
  kManualSearch,      // 0110 track manual search
  kJammedError,       // 1000
  kLimitError,        // 1001
  kDriveError,        // 1010
  kPeakLimitError,    // 1011
  kGeoPositionError,  // 1100
  kError,             // 1101 track system error
  kChecksumError,     // 1110
};
// §3.2 byte 40 BBB, by its wire code (000 is not used).
enum class TrackBand : std::uint8_t { kX = 1, kKa = 2, kS = 3, kC = 4, kKu = 5, kNone = 6, kL = 7 };
struct TrackProfile {
  bool active = false;
  TrackActivity activity = TrackActivity::kIdle;
  TrackBand band = TrackBand::kC;
  // The satellite tracked was set up as dual band: a C/Ku satellite (E-70).
  bool dual_band = false;
  bool operator==(const TrackProfile&) const = default;
};

// What the controller shows at power-on (§3.2 bytes 3-12 and 35 ZZZ, §3.8).
struct DisplayProfile {
  std::string satellite;     // §3.2 bytes 3-12: upper case (E-68); empty: blanks
  char pol_code = 0;         // §3.2 byte 35 ZZZ: 'H', 'h', 'V', 'v'; 0: none displayed
  std::uint8_t cursor_row = 1;     // §3.8 byte 163, 1-4
  std::uint8_t cursor_column = 0;  // §3.8 bytes 164-165, 0-39
  bool cursor_blinking = false;    // §3.8 byte 166
  bool operator==(const DisplayProfile&) const = default;
};

// Alarms active at power-on: for the drive reset sequence (§3.7 'R').
struct AlarmProfile {
  // §3.2 bytes 36-38 XXXX per axis: 0 none, 8 off axis, 9 sensor direction,
  // 10 runaway, 11 jammed, 12 drive.
  std::uint8_t az = 0, el = 0, pol = 0;
  std::uint8_t code = 0;  // §3.2 byte 39 A5..A0, 0-63 (2 Azimuth Jammed, ...)
  bool operator==(const AlarmProfile&) const = default;
};

struct Profile {
  std::string name = "rc3000-1.59";
  std::string source;                       // the file it was read from, if any

  // CONFIG-REMOTE (§2 Communications Parameters).
  std::uint8_t address = '2';               // 49-111 (0x31-0x6f)
  // Other controllers on the same RS-422 line (§1 multi-drop), each a copy
  // of this profile at its own address; bus_of() makes the whole bus.
  std::vector<std::uint8_t> bus_peers;
  bool remote_enabled = true;
  int baud = 9600;                          // 300 ... 9600 (READING-NOTES 2)

  // The mount and its options.
  std::string firmware = "1.59";            // §3.1 "A.BC"
  PolType pol_type = PolType::kSinglePort;
  AzSensor az_sensor = AzSensor::kPot;
  // §3.2 byte 19 with a fluxgate compass as the azimuth sensor: 'T' (true)
  // or 'M' (magnetic) heading.
  char fluxgate_heading = 'T';
  bool hundredths = false;                  // 0.01 deg feedback (§3.3 form 2C, §3.17 bytes 49-50)
  bool stow = true;                         // §3.7 'S'
  bool deploy = true;                       // §3.7 'D'
  bool dvb_receiver = false;                // §3.20 / §3.21 (E-23)
  double counts_per_degree = 100.0;         // pulse/resolver sensors (§3.16)
  std::int32_t count_offset = 10000;        // counts at 0 deg
  AxisProfile az{2.0, 0.5, -180.0, 180.0, 0.0, false, 0.0, 0.1, std::nullopt, AxisSpeed::kFast, false, std::nullopt};
  AxisProfile el{1.0, 0.25, -5.0, 90.0, 45.0, true, -5.0, 0.1, std::nullopt, AxisSpeed::kFast, false, std::nullopt};
  AxisProfile pol{5.0, 1.0, -90.0, 90.0, 0.0, false, 0.0, 0.1, std::nullopt, AxisSpeed::kFast, false, std::nullopt};
  // The device's reply turnaround: the longest it takes from the end of a
  // request to the first byte of its reply (sabus sim --emulate-line waits
  // this long; the runner allows for it).
  double turnaround_ms = 2.0;
  std::uint16_t agc = 512;                  // §3.2 bytes 41-43
  std::uint8_t agc_channel = 1;             // §3.2 byte 44 CC: 1 SS1, 2 SS2, 3 not applicable
  DisplayProfile display;

  // Stored data at power-on.
  std::vector<StoredSatellite> store;       // STORE list, <= 50
  std::vector<PresetSatellite> presets;     // 1-20
  std::vector<TleSet> tles;                 // 1-10
  std::vector<Signpost> signposts;          // 1-20
  Navigation navigation;
  TrackProfile track;
  AlarmProfile alarms;

  // Errata switches (protocol/ERRATA.md), defaults = the errata's decisions.
  bool stx_restarts_in_data = true;                        // E-7
  OfflineUnknown unknown_command_while_offline = OfflineUnknown::kNak;  // E-10
  bool implements_signal_strength = false;                 // E-16 (38h)
  bool implements_iess = false;                            // E-16 (3Dh, 3Eh)
  bool nak_bad_tle_checksum = false;                       // E-19
  std::uint8_t locate_index_min = 1;                       // E-22
  std::uint8_t locate_index_max = 20;
  bool restore_lost_locate_exit = true;                    // E-28
  // The side of each open point of the spec this device is known to take
  // (readings.hpp): the reference controller acts on it, and the vectors
  // hold a pinned device to its side; a point not pinned is open.
  ReadingPins readings;

  // Every field, `source` (where it was read from) included.
  bool operator==(const Profile&) const = default;
};

// The 45h reply of a controller holding this navigation data (§3.22): magvar
// ready when it has a value.
NavigationDataReply navigation_reply(const Navigation& n);

// The 3Ah, 3Ch and 44h replies of a controller holding this slot; for an
// empty slot (nullptr) the index is empty: 7Fh 7Fh (READING-NOTES 18).
SatelliteDataReply satellite_reply(const PresetSatellite* slot);
TleDataReply tle_reply(const TleSet* slot);
SignpostDataReply signpost_reply(const Signpost* slot);

// Controllers on one RS-422 bus (sabus sim --address 50,51,60): one profile
// per address, the rest shared.
std::vector<Profile> multi_drop(const Profile& base, const std::vector<std::uint8_t>& addresses);
// The controllers of a profile's line: the profile itself, then one per
// bus_peers address (multi_drop); just the profile when it has no peers.
std::vector<Profile> bus_of(const Profile& profile);

}  // namespace sabus::harness
