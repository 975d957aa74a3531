// The reference controller's state, motion and replies. The command handlers
// are in handlers*.cpp (handlers.hpp); the line side (receivers, multi-drop)
// in bus.cpp.
#include "sabus/harness/controller.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "controller_internal.hpp"
#include "sabus/protocol/enumerations.hpp"

namespace sabus::harness {
namespace {

constexpr double kEpsilon = 1e-6;

double seconds(Duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

std::uint8_t enum_value(const enums::EnumList* list, std::string_view name) {
  if (list)
    if (auto v = list->value_of(name)) return *v;
  return enums::kFirstValue;
}

std::uint8_t mode_value(std::string_view name) { return enum_value(&enums::mode_names(), name); }

Controller::Controller(const Profile& profile, const Clock& clock, FaultSet faults)
    : profile_(profile), clock_(clock), faults_(faults), last_update_(clock.now()) {
  state_.az.position = profile_.az.initial_deg;
  state_.el.position = profile_.el.initial_deg;
  state_.pol.position = profile_.pol.initial_deg;
  state_.store = profile_.store;
  for (const auto& p : profile_.presets)
    if (p.index >= 1 && p.index <= state_.presets.size()) state_.presets[p.index - 1] = p;
  for (const auto& t : profile_.tles)
    if (t.index >= 1 && t.index <= state_.tles.size()) state_.tles[t.index - 1] = t;
  for (const auto& s : profile_.signposts)
    if (s.index >= 1 && s.index <= state_.signposts.size()) state_.signposts[s.index - 1] = s;
  state_.navigation = profile_.navigation;
  state_.az.alarm = profile_.alarms.az;
  state_.el.alarm = profile_.alarms.el;
  state_.pol.alarm = profile_.alarms.pol;
  state_.alarm_code = profile_.alarms.code;
  state_.track = {profile_.track.active, profile_.track.activity, profile_.track.band, profile_.track.dual_band};
  // Power-on: INIT has finished; MANUAL (or TRACK, for profiles that test it).
  state_.mode.last_mode = mode_value("INIT_MODE");
  state_.mode.exit_status = enum_value(enums::exit_list_for_mode(state_.mode.last_mode, enum_reading()),
                                       "INIT_NORMAL_EXIT");
  if (state_.track.active) {
    state_.mode.mode = mode_value("TRACK_MODE");
    set_state(track_state_name(state_.track.activity));
  } else {
    state_.mode.mode = mode_value("MANUAL_MODE");
    set_state("MANUAL_IDLE");
  }
}

enums::EnumReading Controller::enum_reading() const {
  return enums::EnumReading{profile_.restore_lost_locate_exit};
}

const AxisProfile& Controller::axis_profile(AxisId a) const {
  return a == AxisId::kAz ? profile_.az : a == AxisId::kEl ? profile_.el : profile_.pol;
}
AxisState& Controller::axis(AxisId a) { return a == AxisId::kAz ? state_.az : a == AxisId::kEl ? state_.el : state_.pol; }
const AxisState& Controller::axis(AxisId a) const {
  return a == AxisId::kAz ? state_.az : a == AxisId::kEl ? state_.el : state_.pol;
}

// ---- modes (§3.17 bytes 45-48) ----------------------------------------------

void Controller::set_state(std::string_view state) {
  state_.mode.state = enum_value(enums::state_list_for_mode(state_.mode.mode, enum_reading()), state);
}

void Controller::enter_mode(std::string_view mode, std::string_view state, std::string_view exit_of_old) {
  const std::uint8_t next = mode_value(mode);
  if (next != state_.mode.mode) {
    state_.mode.last_mode = state_.mode.mode;
    const auto* exits = enums::exit_list_for_mode(state_.mode.last_mode, enum_reading());
    state_.mode.exit_status = exits ? enum_value(exits, exit_of_old.empty() ? normal_exit_name(*exits) : exit_of_old)
                                    : enums::kFirstValue;
    state_.mode.mode = next;
    if (mode != "TRACK_MODE") state_.track.active = false;
  }
  set_state(state);
}

bool Controller::in_mode(std::string_view mode) const { return state_.mode.mode == mode_value(mode); }

// ---- motion ------------------------------------------------------------------

bool Controller::limit(AxisId a, int direction) const {
  const AxisProfile& p = axis_profile(a);
  const double pos = axis(a).position;
  return direction > 0 ? pos >= p.max_deg - kEpsilon : pos <= p.min_deg + kEpsilon;
}

bool Controller::stow_limit(AxisId a) const {
  const AxisProfile& p = axis_profile(a);
  return p.has_stow_limit && std::abs(axis(a).position - p.stow_deg) < 0.05;
}

bool Controller::moving() const {
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol})
    if (axis(a).motion != AxisState::Motion::kIdle) return true;
  return false;
}

void Controller::stop_all() {
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) axis(a).motion = AxisState::Motion::kIdle;
}

void Controller::start_jog(AxisId a, int direction, bool fast, Duration duration) {
  AxisState& s = axis(a);
  s.motion = AxisState::Motion::kJog;
  s.direction = direction;
  s.fast = fast;
  s.jog_end = clock_.now() + duration;
}

void Controller::start_move(AxisId a, double target, bool remote) {
  AxisState& s = axis(a);
  const AxisProfile& p = axis_profile(a);
  s.target = std::clamp(target, p.min_deg, p.max_deg);
  s.direction = s.target >= s.position ? 1 : -1;
  if (faults_.has(Fault::kMoveStopsShort) && std::abs(s.target - s.position) > 1.0) s.target -= s.direction * 1.0;
  s.motion = std::abs(s.target - s.position) < kEpsilon ? AxisState::Motion::kIdle
             : remote                                  ? AxisState::Motion::kRemoteAutoMove
                                                       : AxisState::Motion::kAutoMove;
  s.fast = true;
}

void Controller::step_axis(AxisId a, TimePoint from, TimePoint to) {
  AxisState& s = axis(a);
  const AxisProfile& p = axis_profile(a);
  if (s.motion == AxisState::Motion::kIdle) return;
  if (s.motion == AxisState::Motion::kJog) {
    const bool timed = !faults_.has(Fault::kJogIgnoresDuration);
    const TimePoint end = timed ? std::min(to, s.jog_end) : to;
    if (end > from) s.position += s.direction * (s.fast ? p.fast_dps : p.slow_dps) * seconds(end - from);
    if (timed && to >= s.jog_end) s.motion = AxisState::Motion::kIdle;
  } else {
    const double step = p.fast_dps * seconds(to - from);
    if (std::abs(s.target - s.position) <= step) {
      s.position = s.target;
      s.motion = AxisState::Motion::kIdle;
    } else {
      s.position += s.direction * step;
    }
  }
  // A limit stops the axis there (§3.2 bytes 32-34).
  if (s.position >= p.max_deg || s.position <= p.min_deg) {
    s.position = std::clamp(s.position, p.min_deg, p.max_deg);
    s.motion = AxisState::Motion::kIdle;
  }
}

void Controller::update() {
  const TimePoint now = clock_.now();
  if (now <= last_update_) return;
  const bool was_moving = moving();
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) step_axis(a, last_update_, now);
  last_update_ = now;
  if (was_moving && !moving()) on_motion_done();
  if (in_mode("SPIRAL_REMOTE_MODE") && now >= search_end_) {
    enter_mode("MANUAL_MODE", "MANUAL_IDLE", "SPIRAL_NO_PEAK_FOUND");
  }
}

// A mode that drives the antenna ends when the antenna arrives.
void Controller::on_motion_done() {
  if (in_mode("LOCATE_MODE")) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "LOCATE_FUNCTION_COMPLETED");
  else if (in_mode("STOW_MODE")) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "STOW_FINISHED_NORMALLY");
  else if (in_mode("DEPLOY_MODE")) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "DEPLOY_FINISHED_NORMALLY");
  else if (in_mode("RECALL_MODE")) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "RECALL_NORMAL_EXIT");
}

// ---- readings ------------------------------------------------------------------

// Tenths of a degree as the status reply shows them; with 0.01 deg feedback
// the tenths are truncated and the hundredths digit goes to §3.17 byte 49/50
// (READING-NOTES 30: the digit extends the magnitude).
std::int32_t Controller::tenths(AxisId a) const {
  const double pos = axis(a).position;
  if (!profile_.hundredths) return static_cast<std::int32_t>(std::lround(pos * 10));
  return static_cast<std::int32_t>(std::lround(pos * 100) / 10);
}

std::uint32_t Controller::hundredths_digit(AxisId a) const {
  if (!profile_.hundredths) return 0;
  return static_cast<std::uint32_t>(std::labs(std::lround(axis(a).position * 100)) % 10);
}

std::uint32_t Controller::counts(AxisId a) const {
  const double c = profile_.count_offset + axis(a).position * profile_.counts_per_degree;
  return static_cast<std::uint32_t>(std::clamp(std::lround(c), 0L, 99999L));
}

double Controller::position_of_counts(std::uint32_t count) const {
  return (static_cast<double>(count) - profile_.count_offset) / profile_.counts_per_degree;
}

// §3.2 bytes 36-38: S<<4 | XXXX; higher codes have priority.
std::uint8_t Controller::axis_status_bits(AxisId a) const {
  const AxisState& s = axis(a);
  std::uint8_t code = 0;
  switch (s.motion) {
    case AxisState::Motion::kIdle: code = 0x0; break;
    // ERRATA E-53: a remote jog reports "movement in progress" (0100/0101).
    case AxisState::Motion::kJog:
    case AxisState::Motion::kAutoMove: code = s.direction > 0 ? 0x5 : 0x4; break;
    case AxisState::Motion::kRemoteAutoMove: code = 0x7; break;
  }
  if (s.alarm) code = s.alarm;
  return static_cast<std::uint8_t>((s.fast ? 0x10 : 0) | code);
}

bool Controller::pol_moves_allowed() const {
  // §3.2 byte 35 'Y': no polarization movement while TRACK peaks or searches.
  return !(state_.track.active &&
           (state_.track.activity == TrackActivity::kPeaking || state_.track.activity == TrackActivity::kSearching));
}

std::uint8_t Controller::track_byte() const {
  // §3.2 byte 40: BBB<<4 | SSSS; BBB is never 000.
  const std::uint8_t band = state_.track.band == 'K' ? 0b101 : 0b100;
  std::uint8_t sub = 0;
  if (state_.track.active) {
    switch (state_.track.activity) {
      case TrackActivity::kIdle: sub = 0b0011; break;       // step track submode active
      case TrackActivity::kPeaking: sub = 0b0011; break;
      case TrackActivity::kSearching: sub = 0b0100; break;  // auto search submode
      case TrackActivity::kError: sub = 0b1101; break;      // track system error
    }
  }
  return static_cast<std::uint8_t>(band << 4 | sub);
}

StatusBlock Controller::status_block() const {
  StatusBlock b;
  b.sat_name = state_.displayed_sat;
  if (profile_.az_sensor == AzSensor::kFluxgate) {
    // §3.2 NOTE: a heading 0.0-359.9 and 'T' (true) when the compass is primary.
    std::int32_t h = tenths(AxisId::kAz) % 3600;
    if (h < 0) h += 3600;
    b.azimuth = {fields::AzimuthReading::Kind::kHeading, h, 'T'};
  } else {
    b.azimuth = {fields::AzimuthReading::Kind::kPosition, tenths(AxisId::kAz), 0};
  }
  b.elevation = tenths(AxisId::kEl);
  if (profile_.pol_type != PolType::kCircular) b.polarization = tenths(AxisId::kPol);
  else b.polarization = std::nullopt;  // "not equipped with a rotating feed": '******'
  auto limit_bits = [&](AxisId a) {
    return static_cast<std::uint8_t>((limit(a, +1) ? 4 : 0) | (limit(a, -1) ? 2 : 0) | (stow_limit(a) ? 1 : 0));
  };
  b.az_limits = limit_bits(AxisId::kAz);
  b.el_limits = limit_bits(AxisId::kEl);
  b.pol_limits = profile_.pol_type == PolType::kCircular ? 0 : limit_bits(AxisId::kPol);
  const std::uint8_t feed = profile_.pol_type == PolType::kCircular ? 0 : profile_.pol_type == PolType::kSinglePort ? 1 : 2;
  const std::uint8_t code = state_.pol_code == 'H' ? 0 : state_.pol_code == 'h' ? 1 : state_.pol_code == 'V' ? 2
                            : state_.pol_code == 'v' ? 3 : 4;
  b.pol_equipment = static_cast<std::uint8_t>(feed << 4 | (pol_moves_allowed() ? 8 : 0) | code);
  b.az_status = axis_status_bits(AxisId::kAz);
  b.el_status = axis_status_bits(AxisId::kEl);
  b.pol_status = profile_.pol_type == PolType::kCircular ? 0 : axis_status_bits(AxisId::kPol);
  b.alarm_code = state_.alarm_code;
  b.track = track_byte();
  b.agc = profile_.agc;
  b.agc_channel = 1;
  return b;
}

// The 4x40 LCD (§3.8), derived from the state so that 37h is meaningful.
DisplayReply Controller::display() const {
  DisplayReply d;
  auto mode = enums::mode_names().name_of(state_.mode.mode).value_or("UNDEFINED_MODE");
  std::string m(mode.substr(0, mode.rfind("_MODE")));
  char row[64];
  std::snprintf(row, sizeof row, "%-14s %s", m.c_str(), state_.displayed_sat.c_str());
  d.rows[0] = row;
  auto pos = [&](AxisId a) { return fields::format_scaled(tenths(a), 1); };
  std::snprintf(row, sizeof row, "AZ %6s  EL %6s  POL %6s", pos(AxisId::kAz).c_str(), pos(AxisId::kEl).c_str(),
                profile_.pol_type == PolType::kCircular ? "  ----" : pos(AxisId::kPol).c_str());
  d.rows[1] = row;
  std::snprintf(row, sizeof row, "STORED %2zu  %s", state_.store.size(), moving() ? "MOVING" : "");
  d.rows[2] = row;
  d.rows[3] = state_.alarm_code ? meanings::alarm_code(state_.alarm_code) : "";
  for (auto& r : d.rows) {
    for (auto& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (r.size() > 40) r.resize(40);
    while (!r.empty() && r.back() == ' ') r.pop_back();
  }
  d.cursor_row = 1;
  d.cursor_column = 0;
  d.blinking = '0';
  return d;
}

std::string Controller::check_invariants() const {
  std::string broken;
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) {
    const AxisProfile& p = axis_profile(a);
    if (axis(a).position < p.min_deg - kEpsilon || axis(a).position > p.max_deg + kEpsilon)
      broken += "axis outside its limits; ";
  }
  if (state_.store.size() > kMaxStored) broken += "STORE list over 50; ";
  for (std::size_t i = 0; i < state_.store.size(); ++i)
    for (std::size_t j = i + 1; j < state_.store.size(); ++j)
      if (state_.store[i].name == state_.store[j].name) broken += "a name twice in the STORE list; ";
  if (state_.mode.mode < 0x20 || state_.mode.state < 0x20 || state_.mode.last_mode < 0x20 ||
      state_.mode.exit_status < 0x20)
    broken += "an extended status value below 0x20; ";
  return broken;
}

// ---- replies and the faults that bend them ----------------------------------

Bytes Controller::finish_reply(Frame f) const {
  if (faults_.has(Fault::kReplyAddressZero)) f.address = '0';
  if (f.kind == FrameKind::kAck && !f.data.empty()) {
    const CommandInfo* info = find_command(f.command);
    const bool status = info && (info->reply == ReplyKind::kStatus || info->reply == ReplyKind::kExtendedStatus) &&
                        !is_offline_reply(f);
    if (status && faults_.has(Fault::kWrongNibbleBase)) {
      // Frame bytes 32-39 and 44 are 0x40 | bits.
      for (std::size_t byte : {32, 33, 34, 35, 36, 37, 38, 39, 44}) f.data[byte - 3] -= 0x10;
    }
    if (faults_.has(Fault::kLeftJustifiedPosition)) {
      auto left = [&](std::size_t first) {
        std::string field(f.data.begin() + static_cast<std::ptrdiff_t>(first - 3),
                          f.data.begin() + static_cast<std::ptrdiff_t>(first + 3));
        field.erase(0, field.find_first_not_of(' '));
        field.resize(6, ' ');
        std::copy(field.begin(), field.end(), f.data.begin() + static_cast<std::ptrdiff_t>(first - 3));
      };
      if (status) {
        left(14);
        left(20);
        left(26);
      } else if (info && info->reply == ReplyKind::kJogPosition) {
        left(4);
      }
    }
    if (status && info->reply == ReplyKind::kStatus && faults_.has(Fault::kShortStatus)) f.data.pop_back();
    if (info && info->reply == ReplyKind::kExtendedStatus && faults_.has(Fault::kExtendedStatus52))
      f.data.resize(kExtendedStatus52DataBytes);
    if (faults_.has(Fault::kDropsReplyByte)) f.data.pop_back();
  }
  if (is_offline_reply(f) && faults_.has(Fault::kOfflineWithoutF)) f.data.clear();
  if (f.kind == FrameKind::kNak && faults_.has(Fault::kNakWithoutCommand)) {
    Bytes b = {NAK, f.address, ETX};
    b.push_back(lrc(b, faults_.has(Fault::kLrcSkipsByte0) ? LrcRule::kFromAddress : LrcRule::kFromByte0));
    return b;
  }
  return encode_frame(f, faults_.has(Fault::kLrcSkipsByte0) ? LrcRule::kFromAddress : LrcRule::kFromByte0);
}

}  // namespace sabus::harness
