// The handlers of the commands that move the antenna: §3.3 Auto Move (all
// five forms), §3.4 / §3.24 Jog, §3.5 Polarization preset, §3.18 Remote
// Locate.
#include <algorithm>
#include <cmath>

#include "handlers.hpp"
#include "sabus/harness/look_angles.hpp"

namespace sabus::harness {
namespace {

// The navigation data a LOCATE computes with, bent by the LOCATE faults
// (faults.hpp): each a realistic misreading of §3.22/§3.23.
Navigation locate_navigation(Navigation n, const FaultSet& faults) {
  if (faults.has(Fault::kLocateIgnoresHeading) && n.heading_tenths) n.heading_tenths = 0;
  if (faults.has(Fault::kLocateNorthernLatitude) && n.latitude_min) n.latitude_min = std::abs(*n.latitude_min);
  if (faults.has(Fault::kLocateEasternLongitude) && n.longitude_min) n.longitude_min = std::abs(*n.longitude_min);
  return n;
}

}  // namespace

bool Handlers::stop_ignored_by_fault(const C& c) {
  return (c.faults_.has(Fault::kLocateIgnoresStop) && c.in_mode("LOCATE_MODE")) ||
         (c.faults_.has(Fault::kStowIgnoresStop) && c.in_mode("STOW_MODE")) ||
         (c.faults_.has(Fault::kDeployIgnoresStop) && c.in_mode("DEPLOY_MODE")) ||
         (c.faults_.has(Fault::kSearchIgnoresStop) && c.in_mode("SPIRAL_REMOTE_MODE"));
}

// ---- §3.3 Auto Move -----------------------------------------------------------
Outcome Handlers::auto_move(C& c, const Frame& f, const AutoMove& m) {
  return std::visit([&](const auto& form) { return auto_move_form(c, f, form); }, m.form);
}

std::optional<StoredSatellite> Handlers::find_stored(const C& c, std::string_view name) {
  for (const auto& s : c.state_.store)
    if (s.name == name) return s;
  return std::nullopt;
}

bool Handlers::target_ok(const C& c, AxisId a, double deg) {
  const AxisProfile& p = c.axis_profile(a);
  return deg >= p.min_deg - 1e-9 && deg <= p.max_deg + 1e-9;
}

// §3.3 "not specified properly": a well-formed target outside the axis's
// limits is NAKed (nullopt), or on ERRATA E-54's other side driven to the
// limit it lies beyond.
std::optional<double> Handlers::target_within(const C& c, AxisId a, double deg) {
  if (target_ok(c, a, deg)) return deg;
  if (!c.reads_other("E-54")) return std::nullopt;
  const AxisProfile& p = c.axis_profile(a);
  return std::clamp(deg, p.min_deg, p.max_deg);
}

bool Handlers::lower_case_refused(const C& c, std::string_view name) {
  return c.reads_other("E-68") && std::any_of(name.begin(), name.end(), [](char ch) { return ch >= 'a' && ch <= 'z'; });
}

Outcome Handlers::auto_move_form(C& c, const Frame&, const AutoMoveStored& m) {
  const auto sat = find_stored(c, m.name);
  if (!sat) return nak(c, 0x32, NakRule::kUnknownSatellite, "\"" + m.name + "\"");
  if (m.pol != ' ' && c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
    return nak(c, 0x32, NakRule::kPolWithCircularFeed);
  take_remote_control(c);
  c.start_move(AxisId::kAz, sat->az_deg, true);
  c.start_move(AxisId::kEl, sat->el_deg, true);
  if (m.pol != ' ' && c.profile_.pol_type != PolType::kCircular) {
    // §3.5: a dual-port feed has one position per satellite (ERRATA E-63).
    const bool dual = c.profile_.pol_type == PolType::kDualPort;
    if (dual) c.start_dual_port_move(*sat);
    else c.start_move(AxisId::kPol, m.pol == 'H' ? sat->h_pol_deg : sat->v_pol_deg, true);
    c.state_.pol_code = m.pol;
  }
  c.state_.displayed_sat = sat->name;
  c.state_.last_target = sat;
  return status(c, 0x32, "auto move (form 1) to " + sat->name);
}

std::string Handlers::form_one_name(const Frame& f) {
  std::string name(f.data.begin() + 1, f.data.end());
  while (!name.empty() && name.back() == ' ') name.pop_back();
  return name;
}

// ERRATA E-31: a field that names a stored satellite is form 1 even when it
// parses as a 2A pair; on the other side a valid 2A pair is form 2A whatever
// is stored (the codec's own reading).
bool Handlers::names_stored(const C& c, const Frame& f) {
  return !c.reads_other("E-31") && f.command == AutoMove::kCode && !f.data.empty() && f.data[0] == ' ' && find_stored(c, form_one_name(f));
}

Outcome Handlers::auto_move_form(C& c, const Frame& f, const AutoMoveAzEl& m) {
  // READING-NOTES 31, ERRATA E-31: a field that names a stored satellite is form 1.
  if (names_stored(c, f)) return auto_move_form(c, f, AutoMoveStored{' ', form_one_name(f)});
  return move_az_el(c, m.az / 10.0, m.el / 10.0, "auto move (form 2A)");
}

// Forms 2A and 2B: both axes to a target, or NAK when it is outside the limits.
Outcome Handlers::move_az_el(C& c, double az, double el, std::string note) {
  const auto az_to = target_within(c, AxisId::kAz, az), el_to = target_within(c, AxisId::kEl, el);
  if (!az_to || !el_to) return nak(c, 0x32, NakRule::kTargetOutOfRange);
  take_remote_control(c);
  c.start_move(AxisId::kAz, *az_to, true);
  c.start_move(AxisId::kEl, *el_to, true);
  c.state_.displayed_sat.clear();
  return status(c, 0x32, std::move(note));
}

// Forms 2B and 2C need their sensors (§3.3); ERRATA E-50's other side takes
// them anyway, as well as the mount can.
Outcome Handlers::auto_move_form(C& c, const Frame&, const AutoMoveCounts& m) {
  if (c.profile_.az_sensor != AzSensor::kPulse && c.profile_.az_sensor != AzSensor::kResolver && !c.reads_other("E-50"))
    return nak(c, 0x32, NakRule::kNoCountSensors);
  return move_az_el(c, c.position_of_counts(m.az), c.position_of_counts(m.el), "auto move (form 2B)");
}

Outcome Handlers::auto_move_form(C& c, const Frame&, const AutoMoveAxis& m) {
  if (!c.profile_.hundredths && !c.reads_other("E-50")) return nak(c, 0x32, NakRule::kNoHundredths);
  const AxisId a = m.axis == 'A' ? AxisId::kAz : AxisId::kEl;
  // Fault form2c-sign-dropped: the digits without their '-'.
  double target = (c.faults_.has(Fault::kForm2CSignDropped) ? std::abs(m.target) : m.target) / 100.0;
  if (!c.profile_.hundredths) target = std::round(target * 10) / 10;  // E-50: the mount's 0.1 deg
  const auto to = target_within(c, a, target);
  if (!to) return nak(c, 0x32, NakRule::kTargetOutOfRange);
  take_remote_control(c);
  c.start_move(a, *to, true);
  return status(c, 0x32, "auto move (form 2C)");
}

Outcome Handlers::auto_move_form(C& c, const Frame&, const AutoMovePol& m) {
  if (c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
    return nak(c, 0x32, NakRule::kPolWithCircularFeed);
  const double target = m.pol / 10.0;
  const auto to = target_within(c, AxisId::kPol, target);
  if (!to) return nak(c, 0x32, NakRule::kTargetOutOfRange);
  take_remote_control(c);
  if (c.profile_.pol_type != PolType::kCircular) c.start_move(AxisId::kPol, *to, true);
  return status(c, 0x32, "auto move (form 3)");
}

// ---- §3.4 / §3.24 Jog ---------------------------------------------------------
Outcome Handlers::jog(C& c, std::uint8_t code, const JogFields& j) {
  const bool pol = j.direction == 'O' || j.direction == 'L';
  if (j.direction != 'X') {
    if (pol && c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
      return nak(c, code, NakRule::kJogPolCircular);
    if (track_busy(c)) return nak(c, code, NakRule::kTrackPeaking);
    const AxisId a = j.direction == 'E' || j.direction == 'W' ? AxisId::kAz
                     : j.direction == 'D' || j.direction == 'U' ? AxisId::kEl
                                                                : AxisId::kPol;
    const int dir = j.direction == 'W' || j.direction == 'U' || j.direction == 'L' ? +1 : -1;
    if (c.limit(a, dir) && !c.faults_.has(Fault::kJogIntoLimitAcked)) return nak(c, code, NakRule::kJogIntoLimit);
    // §3.4: in TRACK, X/E/W/D/U hand control to REMOTE; pol jogs do not.
    // Outside TRACK, ERRATA E-52 says what a jog does to the mode.
    if (!c.state_.track.active) take_control_to_move(c);
    else if (!pol) take_remote_control(c);
    // A pol jog in a manual search keeps TRACK: §3.17 track_states name it
    // (their order is ERRATA E-34).
    if (pol && c.state_.track.active && c.state_.track.activity == TrackActivity::kManualSearch)
      c.set_state(dir > 0 ? "TRACK_MANUAL_SEARCH_JOG_POL_CW" : "TRACK_MANUAL_SEARCH_JOG_POL_CCW");
    // §3.4: "the controller can only support a remote jog about a single axis".
    if (!c.faults_.has(Fault::kSecondAxisJogKeepsFirst))
      for (AxisId other : {AxisId::kAz, AxisId::kEl, AxisId::kPol})
        if (other != a && c.axis(other).motion == AxisState::Motion::kJog)
          c.stop_axis(other);
    c.start_remote_jog(a, dir, j.speed == 'F', jog_duration(j.duration_ms, c.reads_other("E-61")), j.duration_ms, false);
    c.state_.last_jogged = a;
    if (code == 0x47) return jog_position(c, a);
    return status(c, code, "jog " + std::string(1, j.direction));
  }
  // 'X': stop all movement (speed and duration are still required, READING-NOTES 14).
  if (track_busy(c)) return nak(c, code, NakRule::kTrackPeaking);
  // Fault x-reenters-remote: REMOTE mode is entered again (ERRATA E-88).
  if (c.faults_.has(Fault::kXReentersRemote) && c.in_mode("REMOTE_MODE")) c.set_state("INITIALIZING_MODE");
  if (stop_ignored_by_fault(c)) return status(c, code, "stop ignored (fault)");
  // A LOCATE, STOW, DEPLOY or search stopped before it completes exits as by the
  // Stop key (E-82, E-89).
  // ERRATA E-52's other side leaves it for MANUAL_MODE, and stays in the
  // mode it is in otherwise (§3.4: in TRACK, 'X' hands control to REMOTE).
  const bool to_manual = c.reads_other("E-52");
  // ERRATA E-82 (a LOCATE) and E-89 (a STOW or DEPLOY): the reference exits
  // with the entry of the movement stopped, the other sides with its
  // MODE_CHANGED entry (REMOTE took control).
  const bool x_changes_mode = (c.in_mode("LOCATE_MODE") && c.reads_other("E-82")) ||
                              ((c.in_mode("STOW_MODE") || c.in_mode("DEPLOY_MODE")) && c.reads_other("E-89"));
  const std::string exit = c.moving_exit(!x_changes_mode);
  if (!exit.empty() && to_manual) c.enter_mode("MANUAL_MODE", "MANUAL_IDLE", exit);
  else if (!exit.empty()) c.enter_mode("REMOTE_MODE", "WAITING_FOR_USER_INPUT", exit);
  if (c.state_.track.active || !to_manual) take_remote_control(c);
  c.stop_all();  // from the next update on
  // ERRATA E-46: 'X' names no axis: the reference replies the azimuth, the
  // other side the axis last jogged (the azimuth before any jog).
  if (code == 0x47) return jog_position(c, c.reads_other("E-46") ? c.state_.last_jogged.value_or(AxisId::kAz) : AxisId::kAz);
  return status(c, code, "stop all movement");
}

// §3.24: "the position (at the time the command is received) of the axis",
// as the status reply shows it (E-42 '*', E-72 a fluxgate heading).
Outcome Handlers::jog_position(C& c, AxisId a) {
  JogPositionReply r;
  r.axis = a == AxisId::kAz ? 'A' : a == AxisId::kEl ? 'E' : 'P';
  r.position = c.reading(a);
  return ack(c, 0x47, r);
}

// ---- §3.5 Polarization preset ---------------------------------------------------
Outcome Handlers::pol_preset(C& c, const PolPreset& p) {
  if (c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
    return nak(c, 0x34, NakRule::kPolPresetCircular);
  // §3.5: during TRACK peaking or search the move waits, and the reply is an
  // ACK. With no satellite in memory the reference NAKs at once, TRACK busy
  // or not; the other side defers first and checks when it runs (ERRATA E-64).
  // With no auto move since power-on the reference takes the first STORE
  // entry; ERRATA E-57's other side has no "last target" and NAKs.
  auto no_satellite = [&]() -> std::optional<Outcome> {
    if (c.state_.store.empty()) return nak(c, 0x34, NakRule::kPolPresetNoSatellites);
    if (c.reads_other("E-57") && !c.state_.last_target)
      return nak(c, 0x34, NakRule::kPolPresetNoSatellites, "no auto move since power-on (E-57)");
    return std::nullopt;
  };
  if (!c.reads_other("E-64"))
    if (auto refused = no_satellite()) return *refused;
  if (track_busy(c)) return status(c, 0x34, "pol preset deferred until peaking ends");
  if (auto refused = no_satellite()) return *refused;
  const StoredSatellite sat = c.state_.last_target.value_or(c.state_.store.front());
  const bool dual = c.profile_.pol_type == PolType::kDualPort;
  take_control_to_move(c);  // ERRATA E-52
  if (c.profile_.pol_type != PolType::kCircular) {
    if (dual) c.start_dual_port_move(sat);
    else c.start_move(AxisId::kPol, p.pol == 'H' ? sat.h_pol_deg : sat.v_pol_deg, true);
    c.state_.pol_code = p.pol;
  }
  return status(c, 0x34, std::string("pol preset ") + p.pol);
}

// ---- §3.18 Remote Locate ------------------------------------------------------------
Outcome Handlers::remote_locate(C& c, const RemoteLocate& l) {
  SatelliteData sat;
  if (l.preset.preset) {
    if (tens_malformed(c, l.preset)) return nak(c, 0x41, NakRule::kMalformedData, "tens digit 2 (E-29)");
    if (l.preset.index < c.profile_.locate_index_min || l.preset.index > c.profile_.locate_index_max)
      return nak(c, 0x41, NakRule::kLocateIndex, "index " + std::to_string(l.preset.index));
    const auto& p = l.preset.index >= 1 && l.preset.index <= 20 ? c.state_.presets[l.preset.index - 1] : std::nullopt;
    if (!p) return nak(c, 0x41, NakRule::kLocateEmptyPreset);
    // A preset with no name or a blank or out-of-range field cannot be
    // located either (the data form's rule).
    if (!satellite_fields_ok(p->data) || p->data.name.empty())
      return nak(c, 0x41, NakRule::kLocateField, "preset " + std::to_string(l.preset.index));
    sat = p->data;
  } else {
    // §3.18 asks for a "10 character satellite name"; whether a blank one is
    // an error in the supplied data is ERRATA E-92 (the other side ACKs).
    if (!satellite_fields_ok(l.sat) || (l.sat.name.empty() && !c.reads_other("E-92")))
      return nak(c, 0x41, NakRule::kLocateField);
    // ERRATA E-68: a lower-case name is accepted and shown in capitals, or
    // (other side) an error in the supplied data.
    if (lower_case_refused(c, l.sat.name)) return nak(c, 0x41, NakRule::kLocateField, "a lower-case name (E-68)");
    sat = l.sat;
  }
  c.enter_mode("LOCATE_MODE", "INITIALIZING_LOCATE_MODE");
  c.state_.displayed_sat = capitals(sat.name);  // §3.2 bytes 3-12, ERRATA E-68
  c.state_.last_located = sat;
  c.state_.located_out_of_range = false;
  c.state_.commands_since_locate = 0;
  // ERRATA E-59, E-80: the site and how a true azimuth becomes the mount's.
  const look::SiteOf site =
      look::site_of(locate_navigation(c.state_.navigation, c.faults_), c.profile_.az_sensor, c.profile_.fluxgate_heading);
  if (!site.site) {
    // Fault locate-without-site-completes: no waiting; the LOCATE "completes" where it is.
    if (c.faults_.has(Fault::kLocateWithoutSiteCompletes)) {
      c.enter_mode("MANUAL_MODE", "MANUAL_IDLE", "LOCATE_FUNCTION_COMPLETED");
      return ack(c, 0x41, AckReply{}, "locate " + sat.name + ": completed without a site (fault)");
    }
    c.set_state(look::waiting_state(site.missing));
    return ack(c, 0x41, AckReply{}, "locate " + sat.name + ": waiting for " + look::describe(site.missing));
  }
  look::Pointing to = look::pointing(*site.site, *sat.longitude / 10.0);
  if (c.faults_.has(Fault::kLocateAzimuthCounterclockwise)) to.azimuth_deg = -to.azimuth_deg;
  const auto az = look::azimuth_position(c.profile_.az, to.azimuth_deg, c.state_.az.position);
  // ERRATA E-81: a satellite the mount cannot reach (below the horizon,
  // where the earth is in the way whatever the elevation axis allows, or
  // outside a range) is a range error the remote must act on (§3.17
  // locate_states: "if commanded remotely, action required"): the
  // antenna does not move, and what an earlier command moved stops.
  const bool el_ok = to.elevation_deg >= 0 && target_ok(c, AxisId::kEl, to.elevation_deg);
  const std::string_view error = !az      ? "LOCATE_AZIMUTH_RANGE_ERROR"
                                 : !el_ok ? "LOCATE_ELEVATION_RANGE_ERROR"
                                          : "";
  if (!error.empty() && !c.faults_.has(Fault::kLocateMovesOutOfRange)) {
    c.stop_all();
    c.set_state(error);
    // ERRATA E-83: no LOCATE performed for 42h 'C' (the other side counts
    // it, and 'C' calculates for its satellite).
    c.state_.located_out_of_range = true;
    return ack(c, 0x41, AckReply{}, "locate " + sat.name + ": " + std::string(error));
  }
  // Clamped at the limits under the fault locate-moves-out-of-range.
  c.locate_ = {c.last_update_, c.state_.az, c.state_.el, az.value_or(to.azimuth_deg), to.elevation_deg, c.state_.mode};
  c.start_locate_movements();
  return ack(c, 0x41, AckReply{}, "locate " + sat.name);
}

}  // namespace sabus::harness
