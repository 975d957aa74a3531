// Typed requests and replies of every command 30h-48h. Each message is a
// struct with a `layout` that lists its data fields in wire order, as the
// spec's byte tables do, each as (name, field type, member). Encoding,
// decoding and describing (codec.hpp) walk these layouts, so a field's
// position, width and meaning are written once. The total length of every
// layout is checked against the command catalog in the tests.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/fields.hpp"

namespace sabus {

namespace meanings {
std::string az_limits(std::uint8_t bits);
std::string el_limits(std::uint8_t bits);
std::string pol_limits(std::uint8_t bits);
std::string pol_equipment(std::uint8_t bits);
std::string az_status(std::uint8_t bits);
std::string el_status(std::uint8_t bits);
std::string pol_status(std::uint8_t bits);
std::string alarm_code(std::uint8_t bits);
std::string agc_channel(std::uint8_t bits);
std::string latlon_source(std::uint8_t bits);
std::string heading_source(std::uint8_t bits);
std::string magvar_status(std::uint8_t bits);
std::string signal_low(std::uint8_t bits);
std::string signal_high(std::uint8_t bits);
std::string key_code(char key);
std::string misc_parameter(char sub, char param);
std::string mode_name(std::uint8_t mode);
std::string state_name(std::uint8_t mode, std::uint8_t state);
std::string exit_name(std::uint8_t last_mode, std::uint8_t exit_status);
}  // namespace meanings

namespace layouts {
using namespace fields;
// §3.3 byte 3 and the other documented character sets.
inline constexpr ChoiceItem kFormOnePol[] = {{' ', "polarization not changed"},
                                             {'H', "horizontal polarization of the satellite"},
                                             {'V', "vertical polarization of the satellite"}};
inline constexpr ChoiceItem kCountsPol[] = {{'C', "pulse/resolver counts (form 2B)"}};
inline constexpr ChoiceItem kAxisPol[] = {{'A', "azimuth, 0.01 deg (form 2C)"}, {'E', "elevation, 0.01 deg (form 2C)"}};
inline constexpr ChoiceItem kPolPol[] = {{'P', "go to polarization (form 3)"}};
inline constexpr ChoiceItem kDirections[] = {
    {'E', "azimuth counterclockwise"}, {'W', "azimuth clockwise"},          {'D', "elevation down"},
    {'U', "elevation up"},             {'O', "polarization counterclockwise"}, {'L', "polarization clockwise"},
    {'X', "stop all movement"}};
inline constexpr ChoiceItem kSpeeds[] = {{'F', "fast"}, {'S', "slow"}};
inline constexpr ChoiceItem kHV[] = {{'H', "horizontal"}, {'V', "vertical"}};
inline constexpr ChoiceItem kMiscSubs[] = {{'R', "drive reset"},      {'T', "track reset / band change"},
                                           {'S', "stow"},             {'D', "deploy"},
                                           {'A', "automatic search"}, {'K', "keypad input"}};
inline constexpr ChoiceItem kBands[] = {{'0', "C"}, {'1', "Ku"}, {'2', "C/Ku"}, {'3', "L"},
                                        {'4', "X"}, {'5', "Ka"}, {'6', "S"}};
inline constexpr ChoiceItem kEphemeris[] = {{'0', "none"}, {'1', "TLE"}, {'2', "IESS-412"}};
inline constexpr ChoiceItem kRxPol[] = {{'H', "horizontal"}, {'V', "vertical"}, {'N', "none"}};
inline constexpr ChoiceItem kPositionUpdate[] = {{'A', "determine mount position automatically"},
                                                 {'U', "force an update via GPS and compass"}};
inline constexpr ChoiceItem kStorePol[] = {{'C', "use calculated H,V values"},
                                           {'S', "use the H,V values in bytes 30-39"},
                                           {'H', "current position is horizontal"},
                                           {'V', "current position is vertical"}};
// The seven defined FEC codes (READING-NOTES 32: 4 and 8 are not defined).
inline constexpr ChoiceItem kFec[] = {{'1', "1/2"}, {'2', "2/3"}, {'3', "3/4"}, {'5', "5/6"},
                                      {'6', "6/7"}, {'7', "7/8"}, {'9', "AUTO"}};
// The field's range, "1 - 9" (§3.20 byte 21): whether a controller takes 4
// and 8 is ERRATA E-32's reading, so the codec reads them and the
// controller decides.
inline constexpr ChoiceItem kFecRange[] = {{'1', "1/2"}, {'2', "2/3"}, {'3', "3/4"},  {'4', "not defined (E-32)"},
                                           {'5', "5/6"}, {'6', "6/7"}, {'7', "7/8"},  {'8', "not defined (E-32)"},
                                           {'9', "AUTO"}};
inline constexpr ChoiceItem kSignpostPol[] = {{'H', "horizontal"}, {'V', "vertical"}, {'L', "LHCP"}, {'R', "RHCP"}};
inline constexpr ChoiceItem kJogAxis[] = {{'A', "azimuth"}, {'E', "elevation"}, {'P', "polarization"}};
inline constexpr ChoiceItem kBlink[] = {{'0', "cursor not blinking"}, {'1', "cursor blinking"}};
inline constexpr ChoiceItem kOnline[] = {{'0', "online"}};

inline constexpr Text kName{10};
inline constexpr Digits kIndex{2};
inline constexpr LeftDecimal kLongitude{6, 1};
inline constexpr LeftDecimal kInclination{2, 0};
inline constexpr LeftDecimal kPolOffset{5, 1};
inline constexpr Bits kStatusReserved{0x40, 0x00};
// §3.17 bytes 49-50: one digit '0'-'9', or a blank, "no digit", on a mount
// without 0.01 deg feedback (ERRATA E-30); a letter or a control byte does
// not decode.
inline constexpr RightDecimal kHundredthsDigit{1, 0, true};
}  // namespace layouts

// ---------------------------------------------------------------------------
// Shared blocks
// ---------------------------------------------------------------------------

// §3.2 bytes 3-44, also bytes 3-44 of the extended status (§3.17).
struct StatusBlock {
  std::string sat_name;
  fields::AzimuthReading azimuth;
  std::optional<std::int32_t> elevation;     // tenths; nullopt = '*' field
  std::optional<std::int32_t> polarization;  // tenths; nullopt = no feed or A/D error
  std::uint8_t az_limits = 0, el_limits = 0, pol_limits = 0;  // bits A<<2 | B<<1 | C
  std::uint8_t pol_equipment = 0;                             // XX<<4 | Y<<3 | ZZZ
  std::uint8_t az_status = 0, el_status = 0, pol_status = 0;  // S<<4 | XXXX
  std::uint8_t alarm_code = 0;
  std::uint8_t track = 0x10;  // BBB<<4 | SSSS, BBB never 000
  std::optional<std::int32_t> agc = 0;
  std::uint8_t agc_channel = 0;
  std::string reserved13;
  bool operator==(const StatusBlock&) const = default;

  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("sat name", kName, m.sat_name);                                   // 3-12
    v("reserved", Reserved{1, 0x40}, m.reserved13);                     // 13
    v("azimuth", Azimuth{}, m.azimuth);                                 // 14-19
    v("elevation", Position{}, m.elevation);                            // 20-25
    v("polarization", Position{}, m.polarization);                      // 26-31
    v("az limits", Bits{0x40, 0x07, meanings::az_limits}, m.az_limits);     // 32
    v("el limits", Bits{0x40, 0x07, meanings::el_limits}, m.el_limits);     // 33
    v("pol limits", Bits{0x40, 0x07, meanings::pol_limits}, m.pol_limits);  // 34
    v("pol equipment", Bits{0x40, 0x3F, meanings::pol_equipment}, m.pol_equipment);  // 35
    v("az status", Bits{0x40, 0x1F, meanings::az_status}, m.az_status);     // 36
    v("el status", Bits{0x40, 0x1F, meanings::el_status}, m.el_status);     // 37
    v("pol status", Bits{0x40, 0x1F, meanings::pol_status}, m.pol_status);  // 38
    v("alarm code", Bits{0x40, 0x3F, meanings::alarm_code}, m.alarm_code);  // 39
    v("track", TrackByte{}, m.track);                                   // 40
    v("agc", RightDecimal{3, 0}, m.agc);                                // 41-43
    v("agc channel", Bits{0x40, 0x03, meanings::agc_channel}, m.agc_channel);  // 44
  }
};

// §3.10/§3.11 bytes 5-29.
struct SatelliteData {
  std::string name;
  std::optional<std::int32_t> longitude = 0;    // tenths, west negative
  std::optional<std::int32_t> inclination = 0;  // degrees
  char band = '0';
  char ephemeris = '0';
  std::optional<std::int32_t> pol_offset = 0;   // tenths
  bool operator==(const SatelliteData&) const = default;

  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("sat name", kName, m.name);                       // 5-14
    v("longitude", kLongitude, m.longitude);            // 15-20
    v("inclination", kInclination, m.inclination);      // 21-22
    v("band", Choice{kBands}, m.band);                  // 23
    v("ephemeris", Choice{kEphemeris}, m.ephemeris);    // 24
    v("pol offset", kPolOffset, m.pol_offset);          // 25-29
  }
};

// §3.20/§3.21 bytes 5-33.
struct SignpostData {
  std::optional<std::int32_t> longitude = 0;    // tenths
  std::optional<std::int32_t> frequency = 10700;
  std::optional<std::int32_t> symbol_rate = 1000;
  char fec = '9';
  char polarization = 'H';
  std::string id;
  std::uint32_t priority = 0;
  std::string spare;
  bool operator==(const SignpostData&) const = default;

  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("longitude", kLongitude, m.longitude);                  // 5-10
    v("frequency", LeftDecimal{5, 0}, m.frequency);           // 11-15
    v("symbol rate", LeftDecimal{5, 0}, m.symbol_rate);       // 16-20
    v("fec", Choice{kFecRange}, m.fec);                       // 21
    v("polarization", Choice{kSignpostPol}, m.polarization);  // 22
    v("id", Text{6}, m.id);                                   // 23-28
    v("priority", Digits{1}, m.priority);                     // 29
    v("spare", Reserved{4, '0'}, m.spare);                    // 30-33 "pad with zeros"
  }
};

// ---------------------------------------------------------------------------
// Requests (the command frame's data, bytes 3 .. ETX-1)
// ---------------------------------------------------------------------------

template <std::uint8_t Code>
struct NoData {
  static constexpr std::uint8_t kCode = Code;
  bool operator==(const NoData&) const = default;
  template <class S, class V>
  static void layout(S&, V&&) {}
};
using DeviceTypeQuery = NoData<0x30>;      // §3.1
using StatusPoll = NoData<0x31>;           // §3.2
using ReflectDisplayQuery = NoData<0x37>;  // §3.8
using PulseCountQuery = NoData<0x3F>;      // §3.16
using ExtendedStatusPoll = NoData<0x40>;   // §3.17
using NavigationQuery = NoData<0x45>;      // §3.22

// The polls: the device type query and the status polls, which read the
// controller without changing its mode (§3 NOTE for 30h and 31h; 40h, whose
// bytes 47-48 report how the last mode ended, ERRATA E-52).
constexpr bool is_poll(std::uint8_t code) {
  return code == DeviceTypeQuery::kCode || code == StatusPoll::kCode || code == ExtendedStatusPoll::kCode;
}

// §3.3 Auto Move, one struct per form.
struct AutoMoveStored {  // form 1
  static constexpr std::string_view kForm = "1";
  char pol = ' ';
  std::string name;
  bool operator==(const AutoMoveStored&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("polarization", Choice{kFormOnePol}, m.pol);  // 3
    v("sat name", kName, m.name);                   // 4-13
  }
};
struct AutoMoveAzEl {  // form 2A
  static constexpr std::string_view kForm = "2A";
  std::int32_t az = 0;  // tenths
  std::int32_t el = 0;
  bool operator==(const AutoMoveAzEl&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    fields::Unit u;
    v("polarization", Fill{1, ' '}, u);         // 3
    v("azimuth", SignedDigits{5, 1}, m.az);     // 4-8
    v("elevation", SignedDigits{5, 1}, m.el);   // 9-13
  }
};
struct AutoMoveCounts {  // form 2B
  static constexpr std::string_view kForm = "2B";
  std::uint32_t az = 0;
  std::uint32_t el = 0;
  bool operator==(const AutoMoveCounts&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    fields::Unit u;
    v("polarization", Fill{1, 'C'}, u);        // 3
    v("azimuth count", Digits{5}, m.az);       // 4-8
    v("elevation count", Digits{5}, m.el);     // 9-13
  }
};
struct AutoMoveAxis {  // form 2C
  static constexpr std::string_view kForm = "2C";
  char axis = 'A';
  std::int32_t target = 0;  // hundredths
  bool operator==(const AutoMoveAxis&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    fields::Unit u;
    v("axis", Choice{kAxisPol}, m.axis);               // 3
    v("target", SignedDigits{6, 2}, m.target);         // 4-9
    v("blanks", Fill{4, ' '}, u);                      // 10-13
  }
};
struct AutoMovePol {  // form 3
  static constexpr std::string_view kForm = "3";
  std::int32_t pol = 0;  // tenths
  bool operator==(const AutoMovePol&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    fields::Unit u;
    v("polarization", Fill{1, 'P'}, u);                  // 3
    v("pol target", SignedDigits{5, 1}, m.pol);          // 4-8
    v("zeros", Fill{5, '0'}, u);                         // 9-13
  }
};
struct AutoMove {
  static constexpr std::uint8_t kCode = 0x32;
  std::variant<AutoMoveStored, AutoMoveAzEl, AutoMoveCounts, AutoMoveAxis, AutoMovePol> form;
  bool operator==(const AutoMove&) const = default;
  std::string_view form_id() const;
};

// §3.4 / §3.24 Jog (same request layout, different code and reply).
struct JogFields {
  char direction = 'X';
  char speed = 'S';
  std::uint32_t duration_ms = 0;
  bool operator==(const JogFields&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("direction", Choice{kDirections}, m.direction);  // 3
    v("speed", Choice{kSpeeds}, m.speed);              // 4
    v("duration", Digits{4}, m.duration_ms);           // 5-8
  }
};
struct Jog : JogFields {
  static constexpr std::uint8_t kCode = 0x33;
  bool operator==(const Jog&) const = default;
};
struct JogMinimal : JogFields {
  static constexpr std::uint8_t kCode = 0x47;
  bool operator==(const JogMinimal&) const = default;
};

struct PolPreset {  // §3.5
  static constexpr std::uint8_t kCode = 0x34;
  char pol = 'H';
  bool operator==(const PolPreset&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("polarization", fields::Choice{layouts::kHV}, m.pol);  // 3
  }
};

struct IndexQuery {
  std::uint32_t index = 1;
  bool operator==(const IndexQuery&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", layouts::kIndex, m.index);  // 3-4
  }
};
struct QueryName : IndexQuery {  // §3.6
  static constexpr std::uint8_t kCode = 0x35;
  bool operator==(const QueryName&) const = default;
};
struct ReadSatellite : IndexQuery {  // §3.11
  static constexpr std::uint8_t kCode = 0x3A;
  bool operator==(const ReadSatellite&) const = default;
};
struct ReadTle : IndexQuery {  // §3.13
  static constexpr std::uint8_t kCode = 0x3C;
  bool operator==(const ReadTle&) const = default;
};
struct ReadIess : IndexQuery {  // §3.15
  static constexpr std::uint8_t kCode = 0x3E;
  bool operator==(const ReadIess&) const = default;
};
struct ReadSignpost : IndexQuery {  // §3.21
  static constexpr std::uint8_t kCode = 0x44;
  bool operator==(const ReadSignpost&) const = default;
};

struct Misc {  // §3.7
  static constexpr std::uint8_t kCode = 0x36;
  char sub = 'R';
  char param = 'A';
  bool operator==(const Misc&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("sub-command", fields::Choice{layouts::kMiscSubs}, m.sub);  // 3
    v("parameter", fields::AnyChar{}, m.param,                    // 4
      [&m](const char& p) { return meanings::misc_parameter(m.sub, p); });
  }
};

struct SignalStrength {  // §3.9 (ERRATA E-36)
  static constexpr std::uint8_t kCode = 0x38;
  std::uint8_t low = 0;   // k<<5 | s4..s0
  std::uint8_t high = 0;  // s9..s5
  bool operator==(const SignalStrength&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("signal low", fields::Bits{0x40, 0x3F, meanings::signal_low}, m.low);     // 3
    v("signal high", fields::Bits{0x40, 0x1F, meanings::signal_high}, m.high);  // 4
  }
};

struct WriteSatellite {  // §3.10
  static constexpr std::uint8_t kCode = 0x39;
  std::uint32_t index = 1;
  SatelliteData sat;
  bool operator==(const WriteSatellite&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", layouts::kIndex, m.index);  // 3-4
    SatelliteData::layout(m.sat, v);       // 5-29
  }
};

struct WriteTle {  // §3.12
  static constexpr std::uint8_t kCode = 0x3B;
  std::uint32_t index = 1;
  std::string line1, line2;
  bool operator==(const WriteTle&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", layouts::kIndex, m.index);           // 3-4
    v("tle line 1", fields::Text{69}, m.line1);     // 5-73
    v("tle line 2", fields::Text{69}, m.line2);     // 74-142
  }
};

struct WriteIess {  // §3.14, layout TBD (ERRATA E-37)
  static constexpr std::uint8_t kCode = 0x3D;
  std::uint32_t index = 1;
  std::string payload;
  bool operator==(const WriteIess&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", layouts::kIndex, m.index);       // 3-4
    v("iess data", fields::Opaque{}, m.payload);  // 5-TBD
  }
};

struct RemoteLocate {  // §3.18
  static constexpr std::uint8_t kCode = 0x41;
  fields::PresetRef preset;
  SatelliteData sat;   // ephemeris is not part of 41h; pol offset at 24-28
  std::string blank_data;  // bytes 5-28 when A=1 ("may be left blank")
  char rx_pol = 'N';
  char position_update = 'A';
  std::string spare;
  bool operator==(const RemoteLocate&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("preset flag/index", PresetIndex{}, m.preset);  // 3-4
    if (m.preset.preset) {
      v("satellite data (unused with A=1)", Text{24}, m.blank_data);  // 5-28
    } else {
      v("sat name", kName, m.sat.name);                   // 5-14
      v("longitude", kLongitude, m.sat.longitude);        // 15-20
      v("inclination", kInclination, m.sat.inclination);  // 21-22
      v("band", Choice{kBands}, m.sat.band);              // 23
      v("pol offset", kPolOffset, m.sat.pol_offset);      // 24-28
    }
    v("receive polarization", Choice{kRxPol}, m.rx_pol);          // 29
    v("position update", Choice{kPositionUpdate}, m.position_update);  // 30
    v("spare", Reserved{4, ' '}, m.spare);                        // 31-34
  }
};

struct RemoteStore {  // §3.19
  static constexpr std::uint8_t kCode = 0x42;
  fields::PresetRef preset;
  SatelliteData sat;
  std::string blank_data;  // bytes 5-28 when A=1
  char pol_selection = 'C';
  std::optional<std::int32_t> h_pos, v_pos;  // tenths; blank unless selection 'S'
  char track_pol = 'H';
  std::string spare;
  bool operator==(const RemoteStore&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace layouts;
    v("preset flag/index", PresetIndex{}, m.preset);  // 3-4
    if (m.preset.preset) {
      v("satellite data (unused with A=1)", Text{24}, m.blank_data);  // 5-28
    } else {
      v("sat name", kName, m.sat.name);                   // 5-14
      v("longitude", kLongitude, m.sat.longitude);        // 15-20
      v("inclination", kInclination, m.sat.inclination);  // 21-22
      v("band", Choice{kBands}, m.sat.band);              // 23
      v("pol offset", kPolOffset, m.sat.pol_offset);      // 24-28
    }
    v("pol selection", Choice{kStorePol}, m.pol_selection);            // 29
    v("horizontal pol", LeftDecimal{5, 1, true}, m.h_pos);             // 30-34
    v("vertical pol", LeftDecimal{5, 1, true}, m.v_pos);               // 35-39
    v("track pol", Choice{kHV}, m.track_pol);                          // 40
    v("spare", Reserved{5, ' '}, m.spare);                             // 41-45
  }
};

struct WriteSignpost {  // §3.20
  static constexpr std::uint8_t kCode = 0x43;
  std::uint32_t index = 1;
  SignpostData signpost;
  bool operator==(const WriteSignpost&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", layouts::kIndex, m.index);  // 3-4
    SignpostData::layout(m.signpost, v);   // 5-33
  }
};

struct WriteNavigation {  // §3.23
  static constexpr std::uint8_t kCode = 0x46;
  std::int32_t latitude = 0;   // sddmm as an integer: -1234 = 12 deg 34 min S
  std::int32_t longitude = 0;  // sdddmm
  std::optional<std::int32_t> heading = 0;  // tenths, 000.0-359.9
  std::string reserved;
  bool operator==(const WriteNavigation&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace fields;
    v("latitude", SignedDigits{5, 0, Quantity::kLatitude}, m.latitude);     // 3-7
    v("longitude", SignedDigits{6, 0, Quantity::kLongitude}, m.longitude);  // 8-13
    v("true heading", ZeroPaddedDecimal{5, 1}, m.heading);                  // 14-18
    v("reserved", Reserved{12, ' '}, m.reserved);                           // 19-30
  }
};

struct RemoteKeypress {  // §3.25
  static constexpr std::uint8_t kCode = 0x48;
  char key = '0';
  bool operator==(const RemoteKeypress&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("key code", fields::AnyChar{meanings::key_code}, m.key);  // 3
  }
};

using Request = std::variant<DeviceTypeQuery, StatusPoll, AutoMove, Jog, PolPreset, QueryName, Misc,
                             ReflectDisplayQuery, SignalStrength, WriteSatellite, ReadSatellite, WriteTle, ReadTle,
                             WriteIess, ReadIess, PulseCountQuery, ExtendedStatusPoll, RemoteLocate, RemoteStore,
                             WriteSignpost, ReadSignpost, NavigationQuery, WriteNavigation, JogMinimal,
                             RemoteKeypress>;
std::uint8_t command_code(const Request& r);

// ---------------------------------------------------------------------------
// Replies (the ACK frame's data)
// ---------------------------------------------------------------------------

struct NakReply {  // §3 NAK Reply: NAK A CC ETX LRC
  bool operator==(const NakReply&) const = default;
};
struct OfflineReply {  // §3 Online/Offline Reply: ACK A CC 'F' ETX LRC
  bool operator==(const OfflineReply&) const = default;
};

struct AckReply {  // ACK A CC ETX LRC
  static constexpr ReplyKind kKind = ReplyKind::kAckOnly;
  bool operator==(const AckReply&) const = default;
  template <class S, class V>
  static void layout(S&, V&&) {}
};

struct DeviceTypeReply {  // §3.1
  static constexpr ReplyKind kKind = ReplyKind::kDeviceType;
  std::string controller = "3K";
  std::string version = "1.59";
  bool operator==(const DeviceTypeReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("controller type", fields::Text{2}, m.controller);  // 3-4
    v("version", fields::Version{}, m.version);           // 5-8
  }
};

struct StatusReply {  // §3.2 (also the reply of 32h, 33h, 34h, 36h)
  static constexpr ReplyKind kKind = ReplyKind::kStatus;
  StatusBlock status;
  std::string reserved;
  bool operator==(const StatusReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    StatusBlock::layout(m.status, v);                          // 3-44
    v("reserved", fields::Reserved{5, 0x40}, m.reserved);      // 45-49
  }
};

struct ExtendedStatusReply {  // §3.17
  static constexpr ReplyKind kKind = ReplyKind::kExtendedStatus;
  StatusBlock status;
  std::uint8_t mode = 0x20, state = 0x20, last_mode = 0x20, exit_status = 0x20;
  // The hundredths digit 0-9; nullopt: a blank, "no digit" (ERRATA E-30's
  // other side, a mount without 0.01 deg feedback).
  std::optional<std::int32_t> az_hundredths = 0, el_hundredths = 0;
  std::string spare;
  bool operator==(const ExtendedStatusReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace fields;
    StatusBlock::layout(m.status, v);  // 3-44
    v("current mode", EnumByte{}, m.mode, [](const std::uint8_t& x) { return meanings::mode_name(x); });  // 45
    v("current state", EnumByte{}, m.state,
      [&m](const std::uint8_t& x) { return meanings::state_name(m.mode, x); });  // 46
    v("last exited mode", EnumByte{}, m.last_mode,
      [](const std::uint8_t& x) { return meanings::mode_name(x); });  // 47
    v("exit status", EnumByte{}, m.exit_status,
      [&m](const std::uint8_t& x) { return meanings::exit_name(m.last_mode, x); });  // 48 (ERRATA E-39)
    v("az hundredths", layouts::kHundredthsDigit, m.az_hundredths);  // 49 (ERRATA E-30)
    v("el hundredths", layouts::kHundredthsDigit, m.el_hundredths);  // 50
    v("spare", Reserved{5, 0x40}, m.spare);                          // 51-55
  }
};

struct QueryNameReply {  // §3.6
  static constexpr ReplyKind kKind = ReplyKind::kQueryName;
  std::uint32_t index = 1;
  std::uint32_t total = 1;
  std::string name;
  bool operator==(const QueryNameReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", layouts::kIndex, m.index);  // 3-4
    v("total", layouts::kIndex, m.total);  // 5-6
    v("sat name", layouts::kName, m.name); // 7-16
  }
};

struct DisplayReply {  // §3.8
  static constexpr ReplyKind kKind = ReplyKind::kDisplay;
  std::array<std::string, 4> rows;
  std::uint32_t cursor_row = 1;
  std::uint32_t cursor_column = 0;
  char blinking = '0';
  bool operator==(const DisplayReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace fields;
    v("row 1", Text{40}, m.rows[0]);                             // 3-42
    v("row 2", Text{40}, m.rows[1]);                             // 43-82
    v("row 3", Text{40}, m.rows[2]);                             // 83-122
    v("row 4", Text{40}, m.rows[3]);                             // 123-162
    v("cursor row", Digits{1}, m.cursor_row);                    // 163
    v("cursor column", Digits{2}, m.cursor_column);              // 164-165
    v("cursor status", Choice{layouts::kBlink}, m.blinking);     // 166
  }
};

struct SignalStrengthReply {  // §3.9, ERRATA E-36
  static constexpr ReplyKind kKind = ReplyKind::kSignalStrength;
  bool operator==(const SignalStrengthReply&) const = default;
  template <class S, class V>
  static void layout(S&, V&& v) {
    fields::Unit u;
    v("online", fields::Fill{1, '0'}, u);  // 3
  }
};

struct SatelliteDataReply {  // §3.11
  static constexpr ReplyKind kKind = ReplyKind::kSatelliteData;
  std::optional<std::uint8_t> index = 1;  // nullopt: empty slot (7Fh 7Fh)
  SatelliteData sat;
  std::string empty_rest;  // the bytes after an empty-slot index (READING-NOTES 18)
  bool operator==(const SatelliteDataReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", fields::SlotIndex{}, m.index);  // 3-4
    if (m.index) SatelliteData::layout(m.sat, v);        // 5-29
    else v("no data", fields::Reserved{25, ' '}, m.empty_rest);
  }
};

struct TleDataReply {  // §3.13
  static constexpr ReplyKind kKind = ReplyKind::kTleData;
  std::optional<std::uint8_t> index = 1;
  std::string line1, line2;
  std::string empty_rest;
  bool operator==(const TleDataReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", fields::SlotIndex{}, m.index);  // 3-4
    if (m.index) {
      v("tle line 1", fields::Text{69}, m.line1);  // 5-73
      v("tle line 2", fields::Text{69}, m.line2);  // 74-142
    } else {
      v("no data", fields::Reserved{138, ' '}, m.empty_rest);
    }
  }
};

struct IessDataReply {  // §3.15, layout TBD (ERRATA E-37)
  static constexpr ReplyKind kKind = ReplyKind::kIessData;
  std::optional<std::uint8_t> index = 1;
  std::string payload;
  bool operator==(const IessDataReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", fields::SlotIndex{}, m.index);     // 3-4
    v("iess data", fields::Opaque{}, m.payload);  // 5-TBD
  }
};

struct PulseCountReply {  // §3.16
  static constexpr ReplyKind kKind = ReplyKind::kPulseCount;
  std::uint32_t az = 0, el = 0;
  bool operator==(const PulseCountReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("azimuth count", fields::Digits{5, true}, m.az);    // 3-7 (E-33: zeros or blanks)
    v("elevation count", fields::Digits{5, true}, m.el);  // 8-12
  }
};

struct SignpostDataReply {  // §3.21
  static constexpr ReplyKind kKind = ReplyKind::kSignpostData;
  std::optional<std::uint8_t> index = 1;
  SignpostData signpost;
  std::string empty_rest;
  bool operator==(const SignpostDataReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("index", fields::SlotIndex{}, m.index);  // 3-4
    if (m.index) SignpostData::layout(m.signpost, v);    // 5-33
    else v("no data", fields::Reserved{29, ' '}, m.empty_rest);
  }
};

struct NavigationDataReply {  // §3.22
  static constexpr ReplyKind kKind = ReplyKind::kNavigationData;
  std::uint8_t latlon_source = 1;
  std::optional<std::int32_t> latitude, longitude;  // signed minutes
  std::uint8_t heading_source = 1;
  std::optional<std::int32_t> heading;              // tenths
  std::uint8_t magvar_status = 0;
  std::optional<std::int32_t> magvar;               // tenths, west negative
  std::string r10, r20, r23, r42, r43, r51, r59, r60, r65;
  bool operator==(const NavigationDataReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    using namespace fields;
    v("lat/lon source", Bits{0x40, 0x07, meanings::latlon_source}, m.latlon_source);     // 3
    v("latitude", NavAngle{6}, m.latitude);                                               // 4-9
    v("reserved (lat seconds)", Reserved{3, ' '}, m.r10);                                 // 10-12
    v("longitude", NavAngle{7}, m.longitude);                                             // 13-19
    v("reserved (lon seconds)", Reserved{3, ' '}, m.r20);                                 // 20-22
    v("reserved (altitude)", Reserved{6, ' '}, m.r23);                                    // 23-28
    v("heading source", Bits{0x40, 0x07, meanings::heading_source}, m.heading_source);   // 29
    v("true heading", ZeroPaddedDecimal{5, 1, true, true}, m.heading);                    // 30-34 (E-33)
    v("magvar status", Bits{0x40, 0x01, meanings::magvar_status}, m.magvar_status);      // 35
    v("magnetic variation", RightDecimal{6, 1, true}, m.magvar);                          // 36-41
    v("reserved (time status)", Reserved{1, ' '}, m.r42);                                 // 42
    v("reserved (time)", Reserved{8, ' '}, m.r43);                                        // 43-50
    v("reserved (date)", Reserved{8, ' '}, m.r51);                                        // 51-58
    v("reserved (pitch/roll status)", Reserved{1, ' '}, m.r59);                           // 59
    v("reserved (pitch)", Reserved{5, ' '}, m.r60);                                       // 60-64
    v("reserved (roll)", Reserved{5, ' '}, m.r65);                                        // 65-69
  }
};

struct JogPositionReply {  // §3.24
  static constexpr ReplyKind kKind = ReplyKind::kJogPosition;
  char axis = 'A';
  std::optional<std::int32_t> position = 0;  // tenths; nullopt = '*' field
  bool operator==(const JogPositionReply&) const = default;
  template <class S, class V>
  static void layout(S& m, V&& v) {
    v("axis", fields::Choice{layouts::kJogAxis}, m.axis);  // 3
    v("position", fields::Position{}, m.position);         // 4-9
  }
};

using Reply = std::variant<NakReply, OfflineReply, AckReply, DeviceTypeReply, StatusReply, QueryNameReply,
                           DisplayReply, SignalStrengthReply, SatelliteDataReply, TleDataReply, IessDataReply,
                           PulseCountReply, ExtendedStatusReply, SignpostDataReply, NavigationDataReply,
                           JogPositionReply>;

}  // namespace sabus
