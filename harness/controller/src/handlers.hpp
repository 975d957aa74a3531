// The command handlers of the reference controller (not part of its API): one
// function per command (§3.1-§3.25), each NAK naming its rule (nak_rules.hpp).
// Handlers is the Controller's friend; its functions are defined by command
// family:
//   handlers.cpp         the front door (Controller::execute, dispatch) and
//                        the replies every handler builds
//   handlers_motion.cpp  §3.3 Auto Move, §3.4 / §3.24 Jog, §3.5 Polarization
//                        preset, §3.18 Remote Locate
//   handlers_stored.cpp  §3.6 Query Name, §3.10-§3.15 preset satellites, TLEs
//                        and IESS, §3.19 Remote Store, §3.20-§3.23 signposts
//                        and navigation data
//   handlers_misc.cpp    §3.1 Device Type, §3.17 Extended Status, §3.7
//                        Miscellaneous, §3.9 Signal Strength, §3.25 keypad
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "controller_internal.hpp"
#include "sabus/harness/controller.hpp"

namespace sabus::harness {

struct Handlers {
  using C = Controller;

  // ---- replies (handlers.cpp) ----------------------------------------------------
  static Outcome ack(C& c, std::uint8_t code, Reply reply, std::string note = {});
  static Outcome status(C& c, std::uint8_t code, std::string note = {});
  static Outcome nak(C& c, std::uint8_t code, NakRule rule, std::string detail = {});
  static Outcome stored(Outcome o);
  // No reply at all (an ignored frame, a side of the spec that answers none).
  static Outcome unanswered(std::string note);
  static void take_remote_control(C& c);
  // A jog or 34h taking control (ERRATA E-52): REMOTE on the reference side.
  static void take_control_to_move(C& c);
  static bool track_busy(const C& c);
  // Faults locate-, stow-, deploy- and search-ignores-stop: a stop ('X' or
  // the Stop key) leaves a LOCATE, STOW, DEPLOY or search running.
  static bool stop_ignored_by_fault(const C& c);
  static bool implemented(const C& c, std::uint8_t code);
  // §3.18/§3.19 byte 3 "B - Tens digit": the other side of ERRATA E-29 takes
  // B as the single bit the diagram draws, so a preset's tens digit of 2 or
  // more is malformed (41h and 42h alike, before any index range).
  static bool tens_malformed(const C& c, const fields::PresetRef& p) {
    return p.preset && p.index >= 20 && c.reads_other("E-29");
  }

  static bool in_range(std::optional<std::int32_t> v, std::int32_t lo, std::int32_t hi) {
    return v && *v >= lo && *v <= hi;
  }
  // A satellite name as the controller holds and shows it: §3.2 "in upper
  // case letters", §3.6 "in capital letters" (ERRATA E-68).
  static std::string capitals(std::string name) {
    for (char& ch : name)
      if (ch >= 'a' && ch <= 'z') ch = static_cast<char>(ch - 'a' + 'A');
    return name;
  }
  // ERRATA E-68's other side: a name with a lower-case letter is an error in
  // the supplied data (41h, 42h).
  static bool lower_case_refused(const C& c, std::string_view name);
  // §3.10 field bounds: longitude -179.9..179.9, inclination 0..19, pol offset -90.0..90.0.
  static bool satellite_fields_ok(const SatelliteData& s) {
    return in_range(s.longitude, -1799, 1799) && in_range(s.inclination, 0, 19) && in_range(s.pol_offset, -900, 900);
  }

  // ---- motion (handlers_motion.cpp) ----------------------------------------------
  static Outcome auto_move(C& c, const Frame& f, const AutoMove& m);
  static std::optional<StoredSatellite> find_stored(const C& c, std::string_view name);
  // A 32h ' ' frame whose bytes 4-13 name a stored satellite (form 1 then,
  // READING-NOTES 31).
  static bool names_stored(const C& c, const Frame& f);
  static std::string form_one_name(const Frame& f);  // bytes 4-13, trailing blanks off
  static bool target_ok(const C& c, AxisId a, double deg);
  static std::optional<double> target_within(const C& c, AxisId a, double deg);
  static Outcome auto_move_form(C& c, const Frame& f, const AutoMoveStored& m);
  static Outcome auto_move_form(C& c, const Frame& f, const AutoMoveAzEl& m);
  static Outcome auto_move_form(C& c, const Frame& f, const AutoMoveCounts& m);
  static Outcome auto_move_form(C& c, const Frame& f, const AutoMoveAxis& m);
  static Outcome auto_move_form(C& c, const Frame& f, const AutoMovePol& m);
  static Outcome move_az_el(C& c, double az, double el, std::string note);
  static Outcome jog(C& c, std::uint8_t code, const JogFields& j);
  static Outcome jog_position(C& c, AxisId a);
  static Outcome pol_preset(C& c, const PolPreset& p);
  static Outcome remote_locate(C& c, const RemoteLocate& l);

  // ---- stored data (handlers_stored.cpp) -----------------------------------------
  static Outcome query_name(C& c, const QueryName& q);
  static Outcome write_iess(C& c, const WriteIess& w);
  static Outcome read_iess(C& c, const ReadIess& r);
  static Outcome write_satellite(C& c, const WriteSatellite& w);
  static Outcome read_satellite(C& c, const ReadSatellite& r);
  static std::optional<std::uint8_t> empty_index(const C& c);
  static Outcome write_tle(C& c, const WriteTle& w);
  static Outcome read_tle(C& c, const ReadTle& r);
  static Outcome remote_store(C& c, const RemoteStore& s);
  static bool dvb(const C& c);
  static std::optional<Outcome> without_dvb(C& c, std::uint8_t code);
  static Outcome write_signpost(C& c, const WriteSignpost& w);
  static Outcome read_signpost(C& c, const ReadSignpost& r);
  static Outcome read_navigation(C& c);
  static Outcome write_navigation(C& c, const WriteNavigation& w);

  // ---- identity, status, miscellaneous, keypad (handlers_misc.cpp) ---------------
  static Outcome device_type(C& c);
  static Outcome extended_status(C& c);
  static Outcome misc(C& c, const Misc& m);
  static Outcome drive_reset(C& c, char axis);
  static std::uint8_t active_alarm_code(const C& c);
  static Outcome track_command(C& c, char param);
  static Outcome keypress(C& c, char key, std::uint8_t code);
  static Outcome signal_strength(C& c, const SignalStrength& s);
};

}  // namespace sabus::harness
