// The command handlers of the reference controller: one function per command
// (§3.1-§3.25), each NAK naming its rule (nak_rules.hpp).
#include <algorithm>
#include <cmath>

#include "controller_internal.hpp"
#include "sabus/harness/controller.hpp"

namespace sabus::harness {
namespace {

constexpr std::chrono::milliseconds kJogTick{50};        // §3.4: timer resolution ~50 ms
constexpr std::chrono::milliseconds kKeyJogHold{500};    // §2 REMOTE JOG HOLD 20 x 1/40 s
constexpr std::chrono::seconds kSpiralSearchTime{20};

// §3.4: "any move will be for a time interval equal to a multiple of approx.
// 50 milliseconds": a duration is rounded up to the timer's resolution.
Duration jog_duration(std::uint32_t ms) {
  const auto ticks = (ms + kJogTick.count() - 1) / kJogTick.count();
  return std::chrono::duration_cast<Duration>(kJogTick * ticks);
}

bool in_range(std::optional<std::int32_t> v, std::int32_t lo, std::int32_t hi) { return v && *v >= lo && *v <= hi; }

// §3.10 field bounds: longitude -179.9..179.9, inclination 0..19, pol offset -90.0..90.0.
bool satellite_fields_ok(const SatelliteData& s) {
  return in_range(s.longitude, -1799, 1799) && in_range(s.inclination, 0, 19) && in_range(s.pol_offset, -900, 900);
}

// A TLE line's own checksum (READING-NOTES 19): the last digit is the sum of
// the other digits, with '-' counting 1, modulo 10.
bool tle_checksum_ok(const std::string& line) {
  if (line.size() != 69 || line.back() < '0' || line.back() > '9') return false;
  int sum = 0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    if (line[i] >= '0' && line[i] <= '9') sum += line[i] - '0';
    else if (line[i] == '-') sum += 1;
  }
  return sum % 10 == line.back() - '0';
}

// Geostationary look angles from the mount's position, for LOCATE (§3.18).
std::pair<double, double> look_angles(double site_lat_deg, double site_lon_deg, double sat_lon_deg) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kRatio = 0.1513;  // earth radius / geostationary orbit radius
  const double lat = site_lat_deg * kPi / 180, dlon = (sat_lon_deg - site_lon_deg) * kPi / 180;
  const double c = std::cos(lat) * std::cos(dlon);
  const double el = std::atan2(c - kRatio, std::sqrt(std::max(0.0, 1 - c * c))) * 180 / kPi;
  double az = std::atan2(std::tan(dlon), std::sin(lat)) * 180 / kPi;  // from south
  return {std::clamp(az, -180.0, 180.0), el};
}

}  // namespace

struct Handlers {
  using C = Controller;

  static Outcome ack(C& c, std::uint8_t code, Reply reply, std::string note = {}) {
    auto frame = reply_frame(reply, c.profile_.address, code);
    return Outcome{c.finish_reply(frame.value()), std::nullopt, std::move(note), false};
  }
  static Outcome status(C& c, std::uint8_t code, std::string note = {}) {
    return ack(c, code, StatusReply{c.status_block(), ""}, std::move(note));
  }
  static Outcome nak(C& c, std::uint8_t code, NakRule rule, std::string detail = {}) {
    std::string note = "NAK §" + std::string(paragraph(rule)) + ": " + std::string(description(rule));
    if (!detail.empty()) note += " (" + detail + ")";
    return Outcome{c.finish_reply(nak_reply(c.profile_.address, code)), rule, std::move(note), false};
  }
  static Outcome stored(Outcome o) {
    o.stored_data_changed = true;
    return o;
  }

  // Commands that move the antenna hand control to REMOTE mode (§3 Online/Offline
  // Reply NOTE: "A few commands ... cause the RC3000 to enter the REMOTE mode";
  // ERRATA E-52).
  static void take_remote_control(C& c) {
    if (!c.in_mode("REMOTE_MODE")) c.enter_mode("REMOTE_MODE", "WAITING_FOR_USER_INPUT");
  }
  static bool track_busy(const C& c) { return !c.pol_moves_allowed(); }

  // ---- §3.1 / §3.2 / §3.8 / §3.16 / §3.17 -------------------------------------
  static Outcome device_type(C& c) {
    DeviceTypeReply r{"3K", c.profile_.firmware};
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
  static Outcome extended_status(C& c) {
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
    return ack(c, 0x40, x);
  }

  // ---- §3.3 Auto Move -----------------------------------------------------------
  static Outcome auto_move(C& c, const Frame& f, const AutoMove& m) {
    return std::visit([&](const auto& form) { return auto_move_form(c, f, form); }, m.form);
  }

  static std::optional<StoredSatellite> find_stored(const C& c, std::string_view name) {
    for (const auto& s : c.state_.store)
      if (s.name == name) return s;
    return std::nullopt;
  }

  static bool target_ok(const C& c, AxisId a, double deg) {
    const AxisProfile& p = c.axis_profile(a);
    return deg >= p.min_deg - 1e-9 && deg <= p.max_deg + 1e-9;
  }

  static Outcome auto_move_form(C& c, const Frame&, const AutoMoveStored& m) {
    const auto sat = find_stored(c, m.name);
    if (!sat) return nak(c, 0x32, NakRule::kUnknownSatellite, "\"" + m.name + "\"");
    if (m.pol != ' ' && c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
      return nak(c, 0x32, NakRule::kPolWithCircularFeed);
    take_remote_control(c);
    c.start_move(AxisId::kAz, sat->az_deg, true);
    c.start_move(AxisId::kEl, sat->el_deg, true);
    if (m.pol != ' ' && c.profile_.pol_type != PolType::kCircular) {
      // §3.5: a dual-port feed has one position per satellite.
      const bool dual = c.profile_.pol_type == PolType::kDualPort;
      c.start_move(AxisId::kPol, m.pol == 'H' || dual ? sat->h_pol_deg : sat->v_pol_deg, true);
      c.state_.pol_code = m.pol;
    }
    c.state_.displayed_sat = sat->name;
    c.state_.last_target = sat;
    return status(c, 0x32, "auto move (form 1) to " + sat->name);
  }

  static Outcome auto_move_form(C& c, const Frame& f, const AutoMoveAzEl& m) {
    // READING-NOTES 31: a field that names a stored satellite is form 1.
    const std::string field(f.data.begin() + 1, f.data.end());
    std::string name = field;
    while (!name.empty() && name.back() == ' ') name.pop_back();
    if (find_stored(c, name)) return auto_move_form(c, f, AutoMoveStored{' ', name});
    return move_az_el(c, m.az / 10.0, m.el / 10.0, "auto move (form 2A)");
  }

  // Forms 2A and 2B: both axes to a target, or NAK when it is outside the limits.
  static Outcome move_az_el(C& c, double az, double el, std::string note) {
    if (!target_ok(c, AxisId::kAz, az) || !target_ok(c, AxisId::kEl, el))
      return nak(c, 0x32, NakRule::kTargetOutOfRange);
    take_remote_control(c);
    c.start_move(AxisId::kAz, az, true);
    c.start_move(AxisId::kEl, el, true);
    c.state_.displayed_sat.clear();
    return status(c, 0x32, std::move(note));
  }

  static Outcome auto_move_form(C& c, const Frame&, const AutoMoveCounts& m) {
    if (c.profile_.az_sensor != AzSensor::kPulse && c.profile_.az_sensor != AzSensor::kResolver)
      return nak(c, 0x32, NakRule::kNoCountSensors);
    return move_az_el(c, c.position_of_counts(m.az), c.position_of_counts(m.el), "auto move (form 2B)");
  }

  static Outcome auto_move_form(C& c, const Frame&, const AutoMoveAxis& m) {
    if (!c.profile_.hundredths) return nak(c, 0x32, NakRule::kNoHundredths);
    const AxisId a = m.axis == 'A' ? AxisId::kAz : AxisId::kEl;
    const double target = m.target / 100.0;
    if (!target_ok(c, a, target)) return nak(c, 0x32, NakRule::kTargetOutOfRange);
    take_remote_control(c);
    c.start_move(a, target, true);
    return status(c, 0x32, "auto move (form 2C)");
  }

  static Outcome auto_move_form(C& c, const Frame&, const AutoMovePol& m) {
    if (c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
      return nak(c, 0x32, NakRule::kPolWithCircularFeed);
    const double target = m.pol / 10.0;
    if (!target_ok(c, AxisId::kPol, target)) return nak(c, 0x32, NakRule::kTargetOutOfRange);
    take_remote_control(c);
    if (c.profile_.pol_type != PolType::kCircular) c.start_move(AxisId::kPol, target, true);
    return status(c, 0x32, "auto move (form 3)");
  }

  // ---- §3.4 / §3.24 Jog ---------------------------------------------------------
  static Outcome jog(C& c, std::uint8_t code, const JogFields& j) {
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
      if (!pol || !c.state_.track.active) take_remote_control(c);
      // §3.4: "the controller can only support a remote jog about a single axis".
      if (!c.faults_.has(Fault::kSecondAxisJogKeepsFirst))
        for (AxisId other : {AxisId::kAz, AxisId::kEl, AxisId::kPol})
          if (other != a && c.axis(other).motion == AxisState::Motion::kJog)
            c.axis(other).motion = AxisState::Motion::kIdle;
      const double before = c.axis(a).position;
      c.start_jog(a, dir, j.speed == 'F', jog_duration(j.duration_ms));
      if (code == 0x47) return jog_position(c, a, before);
      return status(c, code, "jog " + std::string(1, j.direction));
    }
    // 'X': stop all movement (speed and duration are still required, READING-NOTES 14).
    if (track_busy(c)) return nak(c, code, NakRule::kTrackPeaking);
    take_remote_control(c);
    const double az = c.state_.az.position;
    c.stop_all();
    if (code == 0x47) return jog_position(c, AxisId::kAz, az);  // ERRATA E-46
    return status(c, code, "stop all movement");
  }

  // §3.24: "the position (at the time the command is received) of the axis".
  static Outcome jog_position(C& c, AxisId a, double position) {
    JogPositionReply r;
    r.axis = a == AxisId::kAz ? 'A' : a == AxisId::kEl ? 'E' : 'P';
    const bool no_feed = a == AxisId::kPol && c.profile_.pol_type == PolType::kCircular;
    r.position = no_feed ? std::nullopt : std::optional<std::int32_t>(static_cast<std::int32_t>(std::lround(position * 10)));
    return ack(c, 0x47, r);
  }

  // ---- §3.5 Polarization preset ---------------------------------------------------
  static Outcome pol_preset(C& c, const PolPreset& p) {
    if (c.profile_.pol_type == PolType::kCircular && !c.faults_.has(Fault::kCircularPolAcked))
      return nak(c, 0x34, NakRule::kPolPresetCircular);
    if (c.state_.store.empty()) return nak(c, 0x34, NakRule::kPolPresetNoSatellites);
    // §3.5: during TRACK peaking or search the move waits, and the reply is an ACK.
    if (track_busy(c)) return status(c, 0x34, "pol preset deferred until peaking ends");
    const StoredSatellite sat = c.state_.last_target.value_or(c.state_.store.front());
    const bool dual = c.profile_.pol_type == PolType::kDualPort;
    take_remote_control(c);
    if (c.profile_.pol_type != PolType::kCircular) {
      c.start_move(AxisId::kPol, p.pol == 'H' || dual ? sat.h_pol_deg : sat.v_pol_deg, true);
      c.state_.pol_code = p.pol;
    }
    return status(c, 0x34, std::string("pol preset ") + p.pol);
  }

  // ---- §3.6 Query Name --------------------------------------------------------------
  static Outcome query_name(C& c, const QueryName& q) {
    const bool zero_based = c.faults_.has(Fault::kQueryNameZeroBased);
    const std::size_t first = zero_based ? 0 : 1;
    if (q.index < first || q.index - first >= c.state_.store.size())
      return nak(c, 0x35, NakRule::kQueryNameIndex, "index " + std::to_string(q.index));
    QueryNameReply r;
    r.index = q.index;
    r.total = static_cast<std::uint32_t>(c.state_.store.size()) + (c.faults_.has(Fault::kStoreCountOffByOne) ? 1 : 0);
    r.name = c.state_.store[q.index - first].name;
    return ack(c, 0x35, r);
  }

  // ---- §3.7 Miscellaneous -----------------------------------------------------------
  static Outcome misc(C& c, const Misc& m) {
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
        c.enter_mode("STOW_MODE", "STOW_MOVING_TO_AZIM_STOW");
        c.start_move(AxisId::kAz, 0.0, false);
        c.start_move(AxisId::kEl, c.profile_.el.has_stow_limit ? c.profile_.el.stow_deg : c.profile_.el.min_deg, false);
        return status(c, 0x36, "stow");
      case 'D':
        if (!c.profile_.deploy && !c.faults_.has(Fault::kStowWithoutCapability))
          return nak(c, 0x36, NakRule::kMiscNoDeploy);
        c.enter_mode("DEPLOY_MODE", "DEPLOY_MOVING_ELEVATION");
        c.start_move(AxisId::kEl, c.profile_.el.initial_deg, false);
        return status(c, 0x36, "deploy");
      case 'A':
        if (m.param != 'E' && m.param != 'F') return nak(c, 0x36, NakRule::kMiscSearchParameter);
        c.enter_mode("SPIRAL_REMOTE_MODE", "BEGINNING_SPIRAL_SEARCH");
        c.search_end_ = c.clock_.now() + kSpiralSearchTime;
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

  static Outcome drive_reset(C& c, char axis) {
    if (axis != 'A' && axis != 'E' && axis != 'P') return nak(c, 0x36, NakRule::kMiscResetAxis);
    if (axis == 'P' && c.profile_.pol_type == PolType::kCircular) return nak(c, 0x36, NakRule::kMiscResetPolNoFeed);
    const AxisId a = axis == 'A' ? AxisId::kAz : axis == 'E' ? AxisId::kEl : AxisId::kPol;
    if (c.faults_.has(Fault::kDriveResetKeepsAlarm)) return status(c, 0x36, std::string("drive reset ") + axis + " (alarm kept: fault)");
    c.axis(a).alarm = 0;
    // The alarm code of byte 39 belongs to the axis reset (§3.2 byte 39 list).
    const std::uint8_t code = c.state_.alarm_code;
    const bool of_axis = (a == AxisId::kAz && (code == 2 || code == 3)) || (a == AxisId::kEl && (code == 4 || code == 5)) ||
                         (a == AxisId::kPol && code == 22);
    if (of_axis) c.state_.alarm_code = 0;
    return status(c, 0x36, std::string("drive reset ") + axis);
  }

  static Outcome track_command(C& c, char param) {
    if (param != 'R' && param != 'C' && param != 'K') return nak(c, 0x36, NakRule::kMiscTrackParameter);
    if (!c.state_.track.active) return nak(c, 0x36, NakRule::kMiscTrackNotActive);
    if (param == 'R') {
      // "the controller will react as if TRACK mode was activated via RECALL mode".
      if (c.state_.track.activity == TrackActivity::kError) c.state_.track.activity = TrackActivity::kIdle;
      c.set_state(track_state_name(c.state_.track.activity));
      return status(c, 0x36, "track error reset");
    }
    if (!c.state_.track.dual_band) return nak(c, 0x36, NakRule::kMiscTrackNotDualBand);
    if (!c.pol_moves_allowed()) return nak(c, 0x36, NakRule::kMiscTrackPolNotAllowed);
    c.state_.track.band = param;
    return status(c, 0x36, std::string("band ") + param);
  }

  // ---- §3.25 / §3.7 'K' keypad -----------------------------------------------------
  static bool valid_key(char k) { return (k >= '0' && k <= '9') || (k >= 'A' && k <= 'G'); }

  static Outcome keypress(C& c, char key, std::uint8_t code) {
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
      if (!c.limit(j.axis, j.dir)) c.start_jog(j.axis, j.dir, c.axis(j.axis).fast, kKeyJogHold);
      break;
    }
    if (key == '0')
      for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) c.axis(a).fast = !c.axis(a).fast;
    if (key == 'A') c.stop_all();
    if (key == 'C' && !c.in_mode("MANUAL_MODE")) c.enter_mode("MANUAL_MODE", "MANUAL_IDLE");
    Outcome o = ack(c, 0x48, AckReply{}, "key " + meanings::key_code(key));
    return o;
  }

  // ---- §3.9 / §3.14 / §3.15 (not implemented on software 1.59) ---------------------
  static bool implemented(const C& c, std::uint8_t code) {
    if (c.faults_.has(Fault::kUnimplementedAcked)) return true;
    if (code == 0x38) return c.profile_.implements_signal_strength;
    if (code == 0x3D || code == 0x3E) return c.profile_.implements_iess;
    return find_command(code)->implemented;
  }
  static Outcome signal_strength(C& c, const SignalStrength& s) {
    const int strength = (s.high & 0x1F) << 5 | (s.low & 0x1F);  // ERRATA E-36
    c.signal_strength_ = strength;
    return ack(c, 0x38, SignalStrengthReply{}, "signal strength " + std::to_string(strength));
  }
  static Outcome write_iess(C& c, const WriteIess& w) {
    if (w.index < 1 || w.index > c.iess_.size()) return nak(c, 0x3D, NakRule::kIessIndex);
    c.iess_[w.index - 1] = w.payload;
    return stored(ack(c, 0x3D, AckReply{}));
  }
  static Outcome read_iess(C& c, const ReadIess& r) {
    if (r.index < 1 || r.index > c.iess_.size()) return nak(c, 0x3E, NakRule::kIessIndex);
    IessDataReply reply;
    const auto& slot = c.iess_[r.index - 1];
    if (slot) {
      reply.index = static_cast<std::uint8_t>(r.index);
      reply.payload = *slot;
    } else {
      reply.index = std::nullopt;
    }
    return ack(c, 0x3E, reply);
  }

  // ---- §3.10-§3.13 preset satellites and TLEs ---------------------------------------
  static Outcome write_satellite(C& c, const WriteSatellite& w) {
    if (w.index < 1 || w.index > 20) return nak(c, 0x39, NakRule::kSatelliteIndex, "index " + std::to_string(w.index));
    if (!satellite_fields_ok(w.sat)) return nak(c, 0x39, NakRule::kSatelliteField);
    if (w.sat.ephemeris != '0' && w.index > 10) return nak(c, 0x39, NakRule::kEphemerisIndex);
    PresetSatellite p{static_cast<std::uint8_t>(w.index), w.sat, false};
    if (const auto& old = c.state_.presets[w.index - 1]) p.dual_band = old->dual_band;
    c.state_.presets[w.index - 1] = p;
    return stored(ack(c, 0x39, AckReply{}, "preset " + std::to_string(w.index) + " written"));
  }
  static Outcome read_satellite(C& c, const ReadSatellite& r) {
    if (r.index < 1 || r.index > 20) return nak(c, 0x3A, NakRule::kSatelliteIndex, "index " + std::to_string(r.index));
    SatelliteDataReply reply;
    if (const auto& p = c.state_.presets[r.index - 1]) {
      reply.index = p->index;
      reply.sat = p->data;
    } else {
      reply.index = empty_index(c);
    }
    return ack(c, 0x3A, reply);
  }
  static std::optional<std::uint8_t> empty_index(const C& c) {
    // READING-NOTES 18: 7Fh in both index bytes.
    return c.faults_.has(Fault::kEmptySlotZeros) ? std::optional<std::uint8_t>(0) : std::nullopt;
  }
  static Outcome write_tle(C& c, const WriteTle& w) {
    const std::uint32_t max = c.faults_.has(Fault::kTleIndexTo20) ? 20 : 10;
    if (w.index < 1 || w.index > max) return nak(c, 0x3B, NakRule::kTleIndex, "index " + std::to_string(w.index));
    if (c.profile_.nak_bad_tle_checksum && (!tle_checksum_ok(w.line1) || !tle_checksum_ok(w.line2)))
      return nak(c, 0x3B, NakRule::kTleChecksum);
    if (w.index <= c.state_.tles.size())
      c.state_.tles[w.index - 1] = TleSet{static_cast<std::uint8_t>(w.index), w.line1, w.line2};
    return stored(ack(c, 0x3B, AckReply{}, "TLE " + std::to_string(w.index) + " written"));
  }
  static Outcome read_tle(C& c, const ReadTle& r) {
    if (r.index < 1 || r.index > 10) return nak(c, 0x3C, NakRule::kTleIndex, "index " + std::to_string(r.index));
    TleDataReply reply;
    if (const auto& t = c.state_.tles[r.index - 1]) {
      reply.index = t->index;
      reply.line1 = t->line1;
      reply.line2 = t->line2;
    } else {
      reply.index = empty_index(c);
    }
    return ack(c, 0x3C, reply);
  }

  // ---- §3.18 Remote Locate ------------------------------------------------------------
  static Outcome remote_locate(C& c, const RemoteLocate& l) {
    SatelliteData sat;
    if (l.preset.preset) {
      if (l.preset.index < c.profile_.locate_index_min || l.preset.index > c.profile_.locate_index_max)
        return nak(c, 0x41, NakRule::kLocateIndex, "index " + std::to_string(l.preset.index));
      const auto& p = l.preset.index >= 1 && l.preset.index <= 20 ? c.state_.presets[l.preset.index - 1] : std::nullopt;
      if (!p) return nak(c, 0x41, NakRule::kLocateEmptyPreset);
      sat = p->data;
    } else {
      if (!satellite_fields_ok(l.sat) || l.sat.name.empty()) return nak(c, 0x41, NakRule::kLocateField);
      sat = l.sat;
    }
    c.enter_mode("LOCATE_MODE", "INITIALIZING_LOCATE_MODE");
    c.state_.displayed_sat = sat.name;
    c.state_.last_located = sat;
    const Navigation& nav = c.state_.navigation;
    if (!nav.latitude_min || !nav.longitude_min) {
      c.set_state("LOCATE_WAITING_FOR_LAT_LON");
      return ack(c, 0x41, AckReply{}, "locate " + sat.name + ": waiting for lat/lon");
    }
    const auto [az, el] = look_angles(*nav.latitude_min / 60.0, *nav.longitude_min / 60.0, *sat.longitude / 10.0);
    c.set_state("LOCATE_AZIM_MOVEMENT");
    c.start_move(AxisId::kAz, az, false);
    c.start_move(AxisId::kEl, el, false);
    if (!c.moving()) c.on_motion_done();
    return ack(c, 0x41, AckReply{}, "locate " + sat.name);
  }

  // ---- §3.19 Remote Store ----------------------------------------------------------------
  static double wrap_pol(double deg) { return deg > 90 ? deg - 180 : deg < -90 ? deg + 180 : deg; }

  static Outcome remote_store(C& c, const RemoteStore& s) {
    SatelliteData sat;
    if (s.preset.preset) {
      if (s.preset.index < 1 || s.preset.index > 20) return nak(c, 0x42, NakRule::kStoreIndex);
      const auto& p = c.state_.presets[s.preset.index - 1];
      if (!p) return nak(c, 0x42, NakRule::kStoreEmptyPreset);
      sat = p->data;
    } else {
      if (!satellite_fields_ok(s.sat) || s.sat.name.empty()) return nak(c, 0x42, NakRule::kStoreField);
      sat = s.sat;
    }
    StoredSatellite entry{sat.name, c.state_.az.position, c.state_.el.position, 0, 0};
    if (c.profile_.pol_type != PolType::kCircular) {  // "not applicable if feed type is circular"
      const double pol = c.state_.pol.position;
      switch (s.pol_selection) {
        case 'C':
          if (!c.state_.last_located) return nak(c, 0x42, NakRule::kStoreNeedsLocate);
          entry.h_pol_deg = *c.state_.last_located->pol_offset / 10.0;
          entry.v_pol_deg = wrap_pol(entry.h_pol_deg + 90);
          break;
        case 'S':
          if (!in_range(s.h_pos, -900, 900) || !in_range(s.v_pos, -900, 900)) return nak(c, 0x42, NakRule::kStoreField);
          entry.h_pol_deg = *s.h_pos / 10.0;
          entry.v_pol_deg = *s.v_pos / 10.0;
          break;
        case 'H':
          entry.h_pol_deg = pol;
          entry.v_pol_deg = wrap_pol(pol + 90);
          break;
        default:  // 'V'
          entry.v_pol_deg = pol;
          entry.h_pol_deg = wrap_pol(pol - 90);
          break;
      }
    }
    auto it = std::find_if(c.state_.store.begin(), c.state_.store.end(),
                           [&](const StoredSatellite& x) { return x.name == entry.name; });
    if (it == c.state_.store.end() && c.state_.store.size() >= C::kMaxStored)
      return nak(c, 0x42, NakRule::kStoreListFull);
    // "If a particular satellite name has already been STOREd, its data will be overwritten."
    if (it != c.state_.store.end()) *it = entry;
    else c.state_.store.push_back(entry);
    c.enter_mode("STORE_SAT_MODE", "STORE_ENTERING_MODE");
    c.enter_mode("MANUAL_MODE", "MANUAL_IDLE", "STORE_SAT_DATA_STORED_OK");
    return stored(ack(c, 0x42, AckReply{}, "stored " + entry.name));
  }

  // ---- §3.20 / §3.21 Signposts -----------------------------------------------------------
  static bool dvb(const C& c) { return c.profile_.dvb_receiver || c.faults_.has(Fault::kSignpostsWithoutDvb); }

  static Outcome write_signpost(C& c, const WriteSignpost& w) {
    if (!dvb(c)) return nak(c, 0x43, NakRule::kNoDvbOption);
    if (w.index < 1 || w.index > 20) return nak(c, 0x43, NakRule::kSignpostIndex);
    const SignpostData& d = w.signpost;
    if (!in_range(d.longitude, -1799, 1800) || !in_range(d.frequency, 10700, 12750) ||
        !in_range(d.symbol_rate, 1000, 30000))
      return nak(c, 0x43, NakRule::kSignpostField);
    c.state_.signposts[w.index - 1] = Signpost{static_cast<std::uint8_t>(w.index), d};
    return stored(ack(c, 0x43, AckReply{}, "signpost " + std::to_string(w.index) + " written"));
  }
  static Outcome read_signpost(C& c, const ReadSignpost& r) {
    if (!dvb(c)) return nak(c, 0x44, NakRule::kNoDvbOption);
    if (r.index < 1 || r.index > 20) return nak(c, 0x44, NakRule::kSignpostIndex);
    SignpostDataReply reply;
    if (const auto& s = c.state_.signposts[r.index - 1]) {
      reply.index = s->index;
      reply.signpost = s->data;
    } else {
      reply.index = empty_index(c);
    }
    return ack(c, 0x44, reply);
  }

  // ---- §3.22 / §3.23 Navigation data ---------------------------------------------------
  static Outcome read_navigation(C& c) {
    const Navigation& n = c.state_.navigation;
    NavigationDataReply r;
    r.latlon_source = n.latlon_source;
    r.latitude = n.latitude_min;
    r.longitude = n.longitude_min;
    r.heading_source = n.heading_source;
    r.heading = n.heading_tenths;
    r.magvar_status = n.magvar_tenths ? 1 : 0;
    r.magvar = n.magvar_tenths;
    return ack(c, 0x45, r);
  }
  static Outcome write_navigation(C& c, const WriteNavigation& w) {
    // sddmm / sdddmm: degrees and minutes in one integer (§3.23).
    const std::int32_t lat_deg = std::abs(w.latitude) / 100, lat_min = std::abs(w.latitude) % 100;
    const std::int32_t lon_deg = std::abs(w.longitude) / 100, lon_min = std::abs(w.longitude) % 100;
    const bool lat_ok = lat_min < 60 && (lat_deg < 90 || (lat_deg == 90 && lat_min == 0));
    const bool lon_ok = lon_min < 60 && (lon_deg < 180 || (lon_deg == 180 && lon_min == 0));
    const bool heading_ok = in_range(w.heading, 0, 3599);
    if (!lat_ok || !lon_ok || !heading_ok)
      return nak(c, 0x46, NakRule::kNavigationField,
                 !lat_ok ? "latitude" : !lon_ok ? "longitude" : "heading");
    Navigation& n = c.state_.navigation;
    n.latlon_source = 0b111;   // remotely entered
    n.heading_source = 0b111;
    n.latitude_min = (w.latitude < 0 ? -1 : 1) * (lat_deg * 60 + lat_min);
    n.longitude_min = (w.longitude < 0 ? -1 : 1) * (lon_deg * 60 + lon_min);
    n.heading_tenths = w.heading;
    // §3.23 NOTE: "invalidate (DELETE) any STOREd satellites".
    if (!c.faults_.has(Fault::kWriteNavKeepsStore)) c.state_.store.clear();
    return stored(ack(c, 0x46, AckReply{}, "navigation data written, STORE list deleted"));
  }
};

// ---- the front door ------------------------------------------------------------

Outcome Controller::execute(const Frame& f) {
  update();
  const CommandInfo* info = find_command(f.command);
  const bool offline = !profile_.remote_enabled && !faults_.has(Fault::kRemoteDisabledAnswers);
  auto offline_outcome = [&] {
    return Outcome{finish_reply(offline_reply(profile_.address, f.command)), std::nullopt,
                   "offline: remote control disabled", false};
  };
  auto unknown = [&](NakRule rule, std::string detail) -> Outcome {
    // E-10: unknown code (or wrong length) while offline is a profile switch.
    if (offline && profile_.unknown_command_while_offline == OfflineUnknown::kOffline) return offline_outcome();
    if (rule == NakRule::kUnknownCommand && faults_.has(Fault::kSilentUnknownCommand))
      return Outcome{std::nullopt, std::nullopt, "unknown command ignored", false};
    return Handlers::nak(*this, f.command, rule, std::move(detail));
  };
  if (!info) return unknown(NakRule::kUnknownCommand, describe_byte(f.command));

  Frame command = f;
  const std::size_t length = f.data.size() + kFrameOverhead;
  if (info->request_length && length != *info->request_length) {
    if (length > *info->request_length && faults_.has(Fault::kExecutesOverlong))
      command.data.resize(*info->request_length - kFrameOverhead);
    else
      return unknown(NakRule::kWrongLength,
                     std::to_string(length) + " bytes, " + std::to_string(*info->request_length) + " expected");
  }
  // §3 Online/Offline Reply: a valid command while remote control is disabled.
  if (offline) return offline_outcome();
  if (!Handlers::implemented(*this, f.command)) return Handlers::nak(*this, f.command, NakRule::kNotImplemented);

  auto request = decode_request(command);
  if (!request) return Handlers::nak(*this, f.command, NakRule::kMalformedData, request.error().message());
  Outcome o = dispatch(command, request.value());
  if (o.reply && o.note.empty()) o.note = std::string(info->name);
  return o;
}

Outcome Controller::dispatch(const Frame& f, const Request& request) {
  using H = Handlers;
  return std::visit(
      [&](const auto& m) -> Outcome {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, DeviceTypeQuery> || std::is_same_v<T, StatusPoll>) {
          // §3 NOTE: unlike the RC2000, these do not force REMOTE mode.
          if (faults_.has(Fault::kStatusForcesRemote)) H::take_remote_control(*this);
          if constexpr (std::is_same_v<T, DeviceTypeQuery>) return H::device_type(*this);
          else return H::status(*this, 0x31);
        } else if constexpr (std::is_same_v<T, AutoMove>) {
          return H::auto_move(*this, f, m);
        } else if constexpr (std::is_same_v<T, Jog> || std::is_same_v<T, JogMinimal>) {
          return H::jog(*this, T::kCode, m);
        } else if constexpr (std::is_same_v<T, PolPreset>) {
          return H::pol_preset(*this, m);
        } else if constexpr (std::is_same_v<T, QueryName>) {
          return H::query_name(*this, m);
        } else if constexpr (std::is_same_v<T, Misc>) {
          return H::misc(*this, m);
        } else if constexpr (std::is_same_v<T, ReflectDisplayQuery>) {
          return H::ack(*this, 0x37, display());
        } else if constexpr (std::is_same_v<T, SignalStrength>) {
          return H::signal_strength(*this, m);
        } else if constexpr (std::is_same_v<T, WriteSatellite>) {
          return H::write_satellite(*this, m);
        } else if constexpr (std::is_same_v<T, ReadSatellite>) {
          return H::read_satellite(*this, m);
        } else if constexpr (std::is_same_v<T, WriteTle>) {
          return H::write_tle(*this, m);
        } else if constexpr (std::is_same_v<T, ReadTle>) {
          return H::read_tle(*this, m);
        } else if constexpr (std::is_same_v<T, WriteIess>) {
          return H::write_iess(*this, m);
        } else if constexpr (std::is_same_v<T, ReadIess>) {
          return H::read_iess(*this, m);
        } else if constexpr (std::is_same_v<T, PulseCountQuery>) {
          return H::ack(*this, 0x3F, PulseCountReply{counts(AxisId::kAz), counts(AxisId::kEl)});
        } else if constexpr (std::is_same_v<T, ExtendedStatusPoll>) {
          return H::extended_status(*this);
        } else if constexpr (std::is_same_v<T, RemoteLocate>) {
          return H::remote_locate(*this, m);
        } else if constexpr (std::is_same_v<T, RemoteStore>) {
          return H::remote_store(*this, m);
        } else if constexpr (std::is_same_v<T, WriteSignpost>) {
          return H::write_signpost(*this, m);
        } else if constexpr (std::is_same_v<T, ReadSignpost>) {
          return H::read_signpost(*this, m);
        } else if constexpr (std::is_same_v<T, NavigationQuery>) {
          return H::read_navigation(*this);
        } else if constexpr (std::is_same_v<T, WriteNavigation>) {
          return H::write_navigation(*this, m);
        } else {
          static_assert(std::is_same_v<T, RemoteKeypress>);
          return H::keypress(*this, m.key, 0x48);
        }
      },
      request);
}

}  // namespace sabus::harness
