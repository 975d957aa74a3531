#include "sabus/protocol/catalog.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace sabus {
namespace {

constexpr Effects kNone{};
constexpr Effects kMoves{.moves_antenna = true};
constexpr Effects kStores{.changes_stored_data = true};
constexpr Effects kMovesAgain{.moves_antenna = true, .acts_again = true};

constexpr FormInfo kSingle[] = {{"", "", "the only form", kNone}};
constexpr FormInfo kSingleStores[] = {{"", "", "the only form", kStores}};
// §3.25 Remote Keypress: a key pressed twice is not a key pressed once.
constexpr FormInfo kKeypressForms[] = {{"", "", "the only form", kMovesAgain}};

// §3.3 Auto Move: byte 3 selects the form. ' ' is shared by form 1 (a stored
// name) and form 2A (az/el x10); READING-NOTES 13/31 decide between them.
constexpr FormInfo kAutoMoveForms[] = {
    {"1", " HV", "move to a satellite of the STORE list, pol ' ', 'H' or 'V'", kMoves},
    {"2A", " ", "move to azimuth and elevation x10", kMoves},
    {"2B", "C", "move to azimuth and elevation pulse/resolver counts", kMoves},
    {"2C", "AE", "move one axis to a position x100", kMoves},
    {"3", "P", "move polarization to a position x10", kMoves},
};

// §3.4 / §3.24 Jog: byte 3 is the direction (READING-NOTES 14).
constexpr FormInfo kJogForms[] = {
    {"E", "E", "azimuth counterclockwise", kMovesAgain},
    {"W", "W", "azimuth clockwise", kMovesAgain},
    {"D", "D", "elevation down", kMovesAgain},
    {"U", "U", "elevation up", kMovesAgain},
    {"O", "O", "polarization counterclockwise", kMovesAgain},
    {"L", "L", "polarization clockwise", kMovesAgain},
    {"X", "X", "stop all movement", kMoves},
};

// §3.5 Polarization preset.
constexpr FormInfo kPolPresetForms[] = {
    {"H", "H", "horizontal position of the last auto-move target", kMoves},
    {"V", "V", "vertical position of the last auto-move target", kMoves},
};

// §3.7 Miscellaneous: byte 3 is the sub-command (READING-NOTES 26 for effects).
constexpr FormInfo kMiscForms[] = {
    {"R", "R", "drive reset of axis A, E or P", kNone},
    // ERRATA E-26: re-entering TRACK or changing band re-peaks the antenna.
    {"T", "T", "track error reset (R) or band change (C, K)", kMovesAgain},
    {"S", "S", "stow", kMoves},
    {"D", "D", "deploy", kMoves},
    {"A", "A", "automatic search, expanding (E) or flat (F) spiral", kMovesAgain},
    {"K", "K", "keypad input", kMovesAgain},
};

// §3.18 / §3.19: bit 4 of byte 3 is the preset flag.
constexpr FormInfo kLocateForms[] = {
    {"preset", "", "LOCATE an indexed satellite of the preset list", kMovesAgain},
    {"data", "", "LOCATE a satellite given by name, longitude, inclination and band", kMovesAgain},
};
constexpr FormInfo kStoreForms[] = {
    // §3.19 "If a particular satellite name has already been STOREd, it's
    // data will be overwritten": a second STORE of the same record leaves
    // the list as one does (but pol selection 'C', which needs a LOCATE
    // right before it: the runner's resend_rule).
    {"preset", "", "STORE a satellite of the preset list", kStores},
    {"data", "", "STORE a satellite given by its data", kStores},
};

using RK = ReplyKind;
constexpr std::optional<std::uint8_t> kTbd = std::nullopt;
constexpr std::optional<std::uint8_t> kByte3 = 3;
constexpr std::optional<std::uint8_t> kNoSelector = std::nullopt;

// clang-format off
constexpr std::array<CommandInfo, kCommandCount> kCatalog = {{
 // code  name                              key                    §      req   reply  reply kind          forms            impl   dvb    selector
  {0x30, "Device Type Query",               "device_type",         "3.1",  5,    11,   RK::kDeviceType,     kSingle,         true,  false, kNoSelector},
  {0x31, "Device Status Poll",              "status",              "3.2",  5,    52,   RK::kStatus,         kSingle,         true,  false, kNoSelector},
  {0x32, "Auto Move",                       "auto_move",           "3.3",  16,   52,   RK::kStatus,         kAutoMoveForms,  true,  false, kByte3},
  {0x33, "Azimuth/Elevation/Polarization Jog", "jog",              "3.4",  11,   52,   RK::kStatus,         kJogForms,       true,  false, kByte3},
  {0x34, "Polarization Preset",             "pol_preset",          "3.5",  6,    52,   RK::kStatus,         kPolPresetForms, true,  false, kByte3},
  {0x35, "Query Name",                      "query_name",          "3.6",  7,    19,   RK::kQueryName,      kSingle,         true,  false, kNoSelector},
  {0x36, "Miscellaneous",                   "misc",                "3.7",  7,    52,   RK::kStatus,         kMiscForms,      true,  false, kByte3},
  {0x37, "Reflect Display",                 "reflect_display",     "3.8",  5,    169,  RK::kDisplay,        kSingle,         true,  false, kNoSelector},
  {0x38, "Load Signal Strength",            "signal_strength",     "3.9",  7,    6,    RK::kSignalStrength, kSingle,         false, false, kNoSelector},
  {0x39, "Write Satellite Data",            "write_satellite",     "3.10", 32,   5,    RK::kAckOnly,        kSingleStores,   true,  false, kNoSelector},
  {0x3A, "Read Satellite Data",             "read_satellite",      "3.11", 7,    32,   RK::kSatelliteData,  kSingle,         true,  false, kNoSelector},
  {0x3B, "Write Two Line Element Data",     "write_tle",           "3.12", 145,  5,    RK::kAckOnly,        kSingleStores,   true,  false, kNoSelector},
  {0x3C, "Read Two Line Element Data",      "read_tle",            "3.13", 7,    145,  RK::kTleData,        kSingle,         true,  false, kNoSelector},
  {0x3D, "Write IESS-412 Data",             "write_iess",          "3.14", kTbd, 5,    RK::kAckOnly,        kSingleStores,   false, false, kNoSelector},
  {0x3E, "Read IESS-412 Data",              "read_iess",           "3.15", 7,    kTbd, RK::kIessData,       kSingle,         false, false, kNoSelector},
  {0x3F, "Read Pulse Count",                "pulse_count",         "3.16", 5,    15,   RK::kPulseCount,     kSingle,         true,  false, kNoSelector},
  {0x40, "Extended Device Status Poll",     "extended_status",     "3.17", 5,    58,   RK::kExtendedStatus, kSingle,         true,  false, kNoSelector},
  {0x41, "Remote Locate",                   "remote_locate",       "3.18", 37,   5,    RK::kAckOnly,        kLocateForms,    true,  false, kNoSelector},
  {0x42, "Remote Store",                    "remote_store",        "3.19", 48,   5,    RK::kAckOnly,        kStoreForms,     true,  false, kNoSelector},
  {0x43, "Write Signpost Data",             "write_signpost",      "3.20", 36,   5,    RK::kAckOnly,        kSingleStores,   true,  true,  kNoSelector},
  {0x44, "Read Signpost Data",              "read_signpost",       "3.21", 7,    36,   RK::kSignpostData,   kSingle,         true,  true,  kNoSelector},
  {0x45, "Read Navigation Data",            "read_navigation",     "3.22", 5,    72,   RK::kNavigationData, kSingle,         true,  false, kNoSelector},
  {0x46, "Write Navigation Data",           "write_navigation",    "3.23", 33,   5,    RK::kAckOnly,        kSingleStores,   true,  false, kNoSelector},
  {0x47, "Jog with Minimal Reply",          "jog_minimal",         "3.24", 11,   12,   RK::kJogPosition,    kJogForms,       true,  false, kByte3},
  {0x48, "Remote Keypress",                 "keypress",            "3.25", 6,    5,    RK::kAckOnly,        kKeypressForms,  true,  false, kNoSelector},
}};
// clang-format on

constexpr bool catalog_is_dense() {
  for (std::size_t i = 0; i < kCatalog.size(); ++i)
    if (kCatalog[i].code != kFirstCommand + i) return false;
  return true;
}
static_assert(catalog_is_dense(), "one row per code 30h-48h, in order");

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

std::optional<std::uint8_t> parse_code_text(std::string_view s) {
  int base = 16;
  if (s.size() > 2 && (s.substr(0, 2) == "0x" || s.substr(0, 2) == "0X")) s.remove_prefix(2);
  else if (!s.empty() && (s.back() == 'h' || s.back() == 'H')) s.remove_suffix(1);
  else return std::nullopt;
  unsigned v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, base);
  if (ec != std::errc{} || p != s.data() + s.size() || v > 0xFF) return std::nullopt;
  return static_cast<std::uint8_t>(v);
}

}  // namespace

std::string_view to_string(ReplyKind kind) {
  switch (kind) {
    case RK::kDeviceType: return "device type";
    case RK::kStatus: return "status";
    case RK::kQueryName: return "query name";
    case RK::kDisplay: return "display";
    case RK::kSignalStrength: return "signal strength";
    case RK::kAckOnly: return "ACK/NAK only";
    case RK::kSatelliteData: return "satellite data";
    case RK::kTleData: return "TLE data";
    case RK::kIessData: return "IESS-412 data";
    case RK::kPulseCount: return "pulse count";
    case RK::kExtendedStatus: return "extended status";
    case RK::kSignpostData: return "signpost data";
    case RK::kNavigationData: return "navigation data";
    case RK::kJogPosition: return "jog position";
  }
  return "?";
}

Effects CommandInfo::effects() const {
  Effects e;
  for (const auto& f : forms) {
    e.moves_antenna |= f.effects.moves_antenna;
    e.changes_stored_data |= f.effects.changes_stored_data;
    e.acts_again |= f.effects.acts_again;
  }
  return e;
}

std::optional<std::size_t> CommandInfo::request_data_length() const {
  if (!request_length) return std::nullopt;
  return *request_length - kFrameOverhead;
}

std::optional<std::size_t> CommandInfo::reply_data_length() const {
  if (!reply_length) return std::nullopt;
  return *reply_length - kFrameOverhead;
}

const FormInfo* CommandInfo::form_for_selector(std::uint8_t selector) const {
  for (const auto& f : forms)
    if (f.selectors.find(static_cast<char>(selector)) != std::string_view::npos) return &f;
  return nullptr;
}

const FormInfo* CommandInfo::form_by_id(std::string_view id) const {
  for (const auto& f : forms)
    if (iequals(f.id, id)) return &f;
  return nullptr;
}

std::span<const CommandInfo> catalog() { return kCatalog; }

const CommandInfo* find_command(std::uint8_t code) {
  if (code < kFirstCommand || code > kLastCommand) return nullptr;
  return &kCatalog[code - kFirstCommand];
}

const CommandInfo* find_command(std::string_view text) {
  for (const auto& c : kCatalog)
    if (iequals(c.key, text) || iequals(c.name, text)) return &c;
  if (auto code = parse_code_text(text)) return find_command(*code);
  return nullptr;
}

std::size_t max_request_length() {
  std::size_t m = 0;
  for (const auto& c : kCatalog)
    if (c.request_length) m = std::max<std::size_t>(m, *c.request_length);
  return m;
}

std::size_t max_reply_length() {
  std::size_t m = 0;
  for (const auto& c : kCatalog)
    if (c.reply_length) m = std::max<std::size_t>(m, *c.reply_length);
  return m;
}

}  // namespace sabus
