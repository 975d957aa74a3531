// The handlers of identity, status and the keypad: §3.1 Device Type, §3.17
// Extended Status, §3.7 Miscellaneous (drive reset, TRACK, STOW, DEPLOY,
// search, key), §3.9 Signal Strength, §3.25 Remote Keypress.
#include <algorithm>

#include "handlers.hpp"

namespace sabus::harness {
namespace {


bool valid_key(char k) { return (k >= '0' && k <= '9') || (k >= 'A' && k <= 'G'); }
// §3.25: 3Ah-3Fh are marked "unused" and 40h lies between the table's rows.
bool unused_key(char k) { return k >= 0x3A && k <= 0x40; }

}  // namespace

// ---- §3.1 / §3.2 / §3.8 / §3.16 / §3.17 -------------------------------------
Outcome Handlers::device_type(C& c) {
  // §3.1 "A.BC" version number: the controller's own (the profile's firmware).
  DeviceTypeReply r{"3K", c.faults_.has(Fault::kDeviceTypeFixedVersion) ? std::string("1.59") : c.profile_.firmware};
  if (c.faults_.has(Fault::kDeviceTypeNoDot)) {
    std::string v = r.version;
    std::erase(v, '.');
    auto frame = Frame{FrameKind::kAck, c.profile_.address, 0x30, {'3', 'K'}};
    v.resize(4, ' ');
    frame.data.insert(frame.data.end(), v.begin(), v.end());
    return Outcome{c.finish_reply(frame), std::nullopt, "", false};
  }
  return ack(c, 0x30, r);
}
Outcome Handlers::extended_status(C& c) {
  ExtendedStatusReply x;
  x.status = c.status_block();
  x.mode = c.state_.mode.mode;
  x.state = c.state_.mode.state;
  x.last_mode = c.state_.mode.last_mode;
  x.exit_status = c.state_.mode.exit_status;
  if (c.faults_.has(Fault::kModeEnumOffByOne)) {
    ++x.mode;
    ++x.last_mode;
  }
  x.az_hundredths = c.hundredths_digit(AxisId::kAz);
  x.el_hundredths = c.hundredths_digit(AxisId::kEl);
  if (c.faults_.has(Fault::kExtendedStatusSpeedBit)) x.status.az_status ^= 0x10;  // §3.2 byte 36 'S'
  // §3.17 bytes 3-44 are 31h's: byte 40 SSSS 0000 says "track mode not active".
  if (c.faults_.has(Fault::kExtendedStatusTrackInactive)) x.status.track &= 0x70;
  return ack(c, 0x40, x);
}

// ---- §3.7 Miscellaneous -----------------------------------------------------------
Outcome Handlers::misc(C& c, const Misc& m) {
  // §3.19 byte 29 'C' needs "a LOCATE function ... immediately prior to the
  // Remote Store": an automatic function in between (STOW, DEPLOY, search)
  // ends that LOCATE's claim. Jogs to peak up the satellite do not.
  const bool function = (m.sub == 'S' && c.profile_.stow) || (m.sub == 'D' && c.profile_.deploy) ||
                        (m.sub == 'A' && (m.param == 'E' || m.param == 'F'));
  if (function) c.state_.last_located.reset();
  switch (m.sub) {
    case 'R': return drive_reset(c, m.param);
    case 'T': return track_command(c, m.param);
    case 'S':
      if (!c.profile_.stow && !c.faults_.has(Fault::kStowWithoutCapability)) return nak(c, 0x36, NakRule::kMiscNoStow);
      // READING-NOTES 25: any printable parameter.
      c.start_stow();
      return status(c, 0x36, "stow");
    case 'D':
      if (!c.profile_.deploy && !c.faults_.has(Fault::kStowWithoutCapability))
        return nak(c, 0x36, NakRule::kMiscNoDeploy);
      c.start_deploy();
      return status(c, 0x36, "deploy");
    case 'A':
      if (m.param != 'E' && m.param != 'F') return nak(c, 0x36, NakRule::kMiscSearchParameter);
      c.start_search(m.param);  // moves from the next update on (E-90)
      return status(c, 0x36, m.param == 'E' ? "expanding spiral search" : "flat spiral search");
    case 'K': {
      auto r = keypress(c, m.param, 0x36);
      if (r.nak) return r;
      return status(c, 0x36, r.note);
    }
    default: break;
  }
  return nak(c, 0x36, NakRule::kMalformedData);
}

// The §3.2 byte 39 code of an axis alarm still active (bytes 36-38: 1010
// runaway, 1011 jammed), the azimuth's first; 0 for none with a code.
std::uint8_t Handlers::active_alarm_code(const C& c) {
  struct Code { AxisId axis; std::uint8_t alarm, code; };
  static constexpr Code kCodes[] = {{AxisId::kAz, 0xB, 2},  {AxisId::kAz, 0xA, 3}, {AxisId::kEl, 0xB, 4},
                                    {AxisId::kEl, 0xA, 5},  {AxisId::kPol, 0xB, 22}};
  for (const Code& k : kCodes)
    if (c.axis(k.axis).alarm == k.alarm) return k.code;
  return 0;
}

Outcome Handlers::drive_reset(C& c, char axis) {
  if (axis != 'A' && axis != 'E' && axis != 'P') return nak(c, 0x36, NakRule::kMiscResetAxis);
  if (axis == 'P' && c.profile_.pol_type == PolType::kCircular) return nak(c, 0x36, NakRule::kMiscResetPolNoFeed);
  const AxisId a = axis == 'A' ? AxisId::kAz : axis == 'E' ? AxisId::kEl : AxisId::kPol;
  if (c.faults_.has(Fault::kDriveResetKeepsAlarm)) return status(c, 0x36, std::string("drive reset ") + axis + " (alarm kept: fault)");
  c.axis(a).alarm = 0;
  // The alarm code of byte 39 belongs to the axis reset (§3.2 byte 39 list).
  const std::uint8_t code = c.state_.alarm_code;
  const bool of_axis = (a == AxisId::kAz && (code == 2 || code == 3)) || (a == AxisId::kEl && (code == 4 || code == 5)) ||
                       (a == AxisId::kPol && code == 22);
  // ERRATA E-101's other side: the code of an alarm still active shows next.
  if (of_axis) c.state_.alarm_code = c.reads_other("E-101") ? active_alarm_code(c) : 0;
  return status(c, 0x36, std::string("drive reset ") + axis);
}

Outcome Handlers::track_command(C& c, char param) {
  if (param != 'R' && param != 'C' && param != 'K') return nak(c, 0x36, NakRule::kMiscTrackParameter);
  if (!c.state_.track.active) return nak(c, 0x36, NakRule::kMiscTrackNotActive);
  if (param == 'R') {
    // "the controller will react as if TRACK mode was activated via RECALL mode".
    if (is_track_error(c.state_.track.activity)) c.state_.track.activity = TrackActivity::kIdle;
    c.set_state(track_submode(c.state_.track.activity).state);
    return status(c, 0x36, "track error reset");
  }
  // ERRATA E-70: a dual-band satellite is a C/Ku one; 'K' is Ku.
  if (!c.state_.track.dual_band) return nak(c, 0x36, NakRule::kMiscTrackNotDualBand);
  if (!c.pol_moves_allowed()) return nak(c, 0x36, NakRule::kMiscTrackPolNotAllowed);
  c.state_.track.band = param == 'C' ? TrackBand::kC : TrackBand::kKu;
  return status(c, 0x36, std::string("band ") + (param == 'C' ? "C" : "Ku"));
}

// ---- §3.25 / §3.7 'K' keypad -----------------------------------------------------
Outcome Handlers::keypress(C& c, char key, std::uint8_t code) {
  // ERRATA E-43: an unused key is NAKed, or (other side) ACKed and does
  // nothing; a code outside 30h-47h is no key code on either side.
  if (unused_key(key) && c.reads_other("E-43"))
    return ack(c, 0x48, AckReply{}, "unused key " + describe_byte(static_cast<std::uint8_t>(key)));
  if (!valid_key(key)) return nak(c, code, NakRule::kKeyCode, describe_byte(static_cast<std::uint8_t>(key)));
  c.state_.last_key = key;
  // The keys act as on the front panel in MANUAL mode: jog keys move for the
  // remote jog hold time (§2 JOG: 20 x 1/40 s), Stop stops, Speed toggles.
  struct KeyJog { char key; AxisId axis; int dir; };
  static constexpr KeyJog kJogKeys[] = {{'1', AxisId::kPol, -1}, {'2', AxisId::kEl, +1}, {'3', AxisId::kPol, +1},
                                        {'4', AxisId::kAz, -1},  {'6', AxisId::kAz, +1}, {'8', AxisId::kEl, -1}};
  for (const auto& j : kJogKeys) {
    if (j.key != key) continue;
    if (j.axis == AxisId::kPol && c.profile_.pol_type == PolType::kCircular) break;
    // At the speed the axis is configured for (the Speed key's or the last
    // jog's), not an auto move's: E-98, whichever side 'S' shows.
    if (!c.limit(j.axis, j.dir))
      c.start_remote_jog(j.axis, j.dir, c.axis(j.axis).configured_fast,
                         key_jog_hold(c.reads_other("E-56") ? ReadingSide::kOther : ReadingSide::kReference), 0, true);
    break;
  }
  if (key == '0')
    for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) {
      // The speed each side of E-98 shows, toggled: both are kept whichever is taken.
      c.axis(a).fast = !c.axis(a).fast;
      c.axis(a).configured_fast = !c.axis(a).configured_fast;
    }
  // Fault stop-key-ignored-in-remote: the Stop key leaves a remote auto move running.
  const bool ignored =
      (c.faults_.has(Fault::kStopKeyIgnoredInRemote) && c.in_mode("REMOTE_MODE")) || stop_ignored_by_fault(c);
  if (key == 'A' && !ignored) {
    c.stop_all();
    // The Stop key ends a LOCATE, STOW, DEPLOY or search where it is, back in
    // MANUAL mode (E-82, E-89, E-90).
    if (const std::string exit = c.moving_exit(true); !exit.empty()) c.enter_mode("MANUAL_MODE", "MANUAL_IDLE", exit);
    // ERRATA E-88's other side: the Stop key leaves REMOTE as well.
    else if (c.reads_other("E-88") && c.in_mode("REMOTE_MODE")) c.enter_mode("MANUAL_MODE", "MANUAL_IDLE");
  }
  if (key == 'C' && !c.in_mode("MANUAL_MODE")) c.enter_mode("MANUAL_MODE", "MANUAL_IDLE");
  Outcome o = ack(c, 0x48, AckReply{}, "key " + meanings::key_code(key));
  return o;
}

Outcome Handlers::signal_strength(C& c, const SignalStrength& s) {
  const int strength = (s.high & 0x1F) << 5 | (s.low & 0x1F);  // ERRATA E-36
  c.signal_strength_ = strength;
  return ack(c, 0x38, SignalStrengthReply{}, "signal strength " + std::to_string(strength));
}

}  // namespace sabus::harness
