// Human meanings of the binary and coded fields, from the spec's tables.
#include <cstdio>
#include <string>

#include "sabus/protocol/enumerations.hpp"
#include "sabus/protocol/messages.hpp"

namespace sabus::meanings {
namespace {

std::string limits(std::uint8_t bits, const char* a, const char* b, const char* c) {
  std::string s;
  auto add = [&](const char* name) { s += s.empty() ? name : std::string(", ") + name; };
  if (bits & 4) add(a);
  if (bits & 2) add(b);
  if (bits & 1) add(c);
  return s.empty() ? "no limit" : s + " limit";
}

// §3.2 bytes 36-38: S<<4 | XXXX. Codes 0000-0111 name the axis' movement.
std::string axis_status(std::uint8_t bits, const char* pend_lo, const char* pend_hi, const char* move_lo,
                        const char* move_hi, const char* auto_move) {
  std::string speed = (bits & 0x10) ? "fast, " : "slow, ";
  switch (bits & 0x0F) {
    case 0x0: return speed + "no alarms or movement";
    case 0x2: return speed + pend_lo;
    case 0x3: return speed + pend_hi;
    case 0x4: return speed + move_lo;
    case 0x5: return speed + move_hi;
    case 0x7: return speed + auto_move;
    case 0x8: return speed + "off axis alarm active";
    case 0x9: return speed + "sensor direction alarm active";
    case 0xA: return speed + "runaway alarm active";
    case 0xB: return speed + "jammed alarm active";
    case 0xC: return speed + "drive alarm active";
    default: break;
  }
  char buf[48];
  std::snprintf(buf, sizeof buf, "code %X not defined by §3.2", bits & 0x0F);
  return speed + buf;
}

}  // namespace

std::string az_limits(std::uint8_t bits) { return limits(bits, "azimuth cw", "azimuth ccw", "azimuth stow"); }
std::string el_limits(std::uint8_t bits) { return limits(bits, "elevation up", "elevation down", "elevation stow"); }
std::string pol_limits(std::uint8_t bits) { return limits(bits, "pol cw", "pol ccw", "pol stow"); }

std::string pol_equipment(std::uint8_t bits) {
  static constexpr const char* kFeed[] = {"no rotating feed", "single port rotating feed", "dual port rotating feed",
                                          "feed code 11 not defined"};
  static constexpr const char* kCode[] = {"'H' displayed", "'h' displayed", "'V' displayed", "'v' displayed",
                                          "no polarization code displayed", "code 101 not defined",
                                          "code 110 not defined", "code 111 not defined"};
  return std::string(kFeed[(bits >> 4) & 3]) + ", pol movement " + ((bits & 8) ? "allowed" : "not allowed") + ", " +
         kCode[bits & 7];
}

std::string az_status(std::uint8_t bits) {
  return axis_status(bits, "ccw jog movement pending", "cw jog movement pending", "ccw automatic movement in progress",
                     "cw automatic movement in progress", "remotely commanded auto move in progress");
}
std::string el_status(std::uint8_t bits) {
  return axis_status(bits, "down movement pending", "up movement pending", "down movement in progress",
                     "up movement in progress", "remotely commanded auto move in progress");
}
std::string pol_status(std::uint8_t bits) {
  return axis_status(bits, "ccw movement pending", "cw movement pending", "ccw movement in progress",
                     "cw movement in progress", "auto move in progress");
}

std::string alarm_code(std::uint8_t code) {
  switch (code) {
    case 0: return "no alarm active";
    case 1: return "low battery";
    case 2: return "azimuth jammed";
    case 3: return "azimuth runaway";
    case 4: return "elevation jammed";
    case 5: return "elevation runaway";
    case 14: return "communication port error";
    case 16: return "track configuration error";
    case 18: return "time/date error";
    case 22: return "polarization jammed";
    case 24: return "limits inactive warning";
    default: return "alarm " + std::to_string(code) + " (not listed in §3.2)";
  }
}

std::string agc_channel(std::uint8_t bits) {
  switch (bits & 3) {
    case 1: return "SS1";
    case 2: return "SS2";
    case 3: return "not applicable";
    default: return "code 00 not defined";
  }
}

std::string latlon_source(std::uint8_t bits) {
  static constexpr const char* k[] = {"code 000 not defined", "no lat/lon data", "GPS", "manually entered",
                                      "user preset location list", "saved position", "code 110 not defined",
                                      "remotely entered"};
  return k[bits & 7];
}

std::string heading_source(std::uint8_t bits) {
  static constexpr const char* k[] = {"code 000 not defined", "no true heading data",
                                      "automatically from fluxgate compass", "manually from fluxgate compass",
                                      "manually entered", "fix by user", "fix by DVB receiver", "remotely entered"};
  return k[bits & 7];
}

std::string magvar_status(std::uint8_t bits) { return bits ? "magvar ready (calculated)" : "magvar not ready"; }

std::string signal_low(std::uint8_t bits) {
  return std::string((bits & 0x20) ? "modem locked" : "modem unlocked") + ", s4..s0 = " + std::to_string(bits & 0x1F);
}
std::string signal_high(std::uint8_t bits) { return "s9..s5 = " + std::to_string(bits & 0x1F); }

// §3.7 'K' and §3.25 key table.
std::string key_code(char key) {
  switch (key) {
    case '0': return "0/Speed";
    case '1': return "1/Pol CCW";
    case '2': return "2/N/EL UP";
    case '3': return "3/Pol CW";
    case '4': return "4/E/AZ CCW";
    case '5': return "5";
    case '6': return "6/W/AZ CW";
    case '7': return "7/H";
    case '8': return "8/S/EL DN";
    case '9': return "9/V";
    case 'A': return "Stop/decimal pt.";
    case 'B': return "+/-/BKSP";
    case 'C': return "Mode";
    case 'D': return "Scroll Up/Yes";
    case 'E': return "Scroll Dn/No";
    case 'F': return "Enter";
    case 'G': return "Mode Group Change";
    default: break;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "0x%02x: not a key code (30h-39h, 41h-47h; ERRATA E-43)",
                static_cast<unsigned char>(key));
  return buf;
}

std::string misc_parameter(char sub, char param) {
  switch (sub) {
    case 'R':
      return param == 'A' ? "reset azimuth" : param == 'E' ? "reset elevation" : param == 'P' ? "reset polarization"
                                                                                               : "not A, E or P";
    case 'T':
      return param == 'R' ? "reset track errors" : param == 'C' ? "switch to C band" : param == 'K' ? "switch to K band"
                                                                                                     : "not R, C or K";
    case 'A': return param == 'E' ? "expanding spiral" : param == 'F' ? "flat spiral" : "not E or F";
    case 'K': return key_code(param);
    default: return "parameter " + std::string(1, param);
  }
}

std::string mode_name(std::uint8_t mode) {
  if (auto n = enums::mode_names().name_of(mode)) return std::string(*n);
  return "mode value not in the mode_names list";
}

std::string state_name(std::uint8_t mode, std::uint8_t state) {
  const enums::EnumList* list = enums::state_list_for_mode(mode);
  if (!list) return "no state list for this mode (ERRATA E-39)";
  if (auto n = list->name_of(state)) return std::string(*n);
  return "not in " + std::string(list->name);
}

std::string exit_name(std::uint8_t last_mode, std::uint8_t exit_status) {
  const enums::EnumList* list = enums::exit_list_for_mode(last_mode);
  if (!list) return "no exit list for the last exited mode (ERRATA E-39)";
  if (auto n = list->name_of(exit_status)) return std::string(*n);
  return "not in " + std::string(list->name);
}

}  // namespace sabus::meanings
