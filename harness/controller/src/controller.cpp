// The reference controller's state, motion and replies. The command handlers
// are in handlers*.cpp (handlers.hpp); the line side (receivers, multi-drop)
// in bus.cpp.
#include "sabus/harness/controller.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <cstdio>

#include "controller_internal.hpp"
#include "sabus/protocol/enumerations.hpp"

namespace sabus::harness {
namespace {

constexpr double kEpsilon = 1e-6;
// Positions are shown in tenths (§3.2 bytes 14-31), truncated with 0.01 deg
// feedback: a reading is off by less than this.
constexpr double kDisplayResolution = 0.1;
// A step of a ramped axis takes at most a few phases of constant
// acceleration (stop, speed up, cruise, slow down); the bound keeps a
// degenerate one from looping.
constexpr int kMaxPhases = 16;
// §3.7 'A' (ERRATA E-90): the spiral's step, how long it searches before it
// gives up, and the tick its legs (and a DEPLOY's movements) are timed on.
constexpr double kSpiralStepDeg = 1.0;
constexpr std::chrono::seconds kSearchTime{20};
// E-90's other side: a search that gives up within a second.
constexpr std::chrono::milliseconds kShortSearchTime{300};
constexpr std::chrono::milliseconds kSearchTick{100};
// How near its stow position an axis is at it (§3.2 bytes 32-34 bit C).
constexpr double kAtStowDeg = 0.05;
// ERRATA E-99's other side: how far short of its stow position a STOW leaves
// the elevation (well outside any arrival tolerance and the display's 0.1).
constexpr double kStowShortDeg = 1.0;
// ERRATA E-100's other side: the step of TRACK's peaking pattern.
constexpr double kTrackStepDeg = 0.2;

double seconds(Duration d) { return std::chrono::duration<double>(d).count(); }
int sign_of(double x) { return x > 0 ? 1 : x < 0 ? -1 : 0; }

// ---- an axis with an acceleration ramp (ERRATA E-71) ------------------------

struct Kinematics {
  double x;  // degrees
  double v;  // degrees per second
};

void coast(Kinematics& k, double accel, double t) {
  k.x += k.v * t + 0.5 * accel * t * t;
  k.v += accel * t;
}

// Toward velocity `want` at `accel`, for at most `horizon` seconds; returns
// the time taken. A change of direction first stops at zero, so that within
// one phase the axis moves one way only (a limit it passes is seen).
double ramp_toward(Kinematics& k, double want, double accel, double horizon) {
  const double goal = sign_of(k.v) * sign_of(want) < 0 ? 0.0 : want;
  const double dv = goal - k.v;
  if (std::abs(dv) < 1e-12) {
    k.v = goal;
    coast(k, 0, horizon);
    return horizon;
  }
  const double need = std::abs(dv) / accel;
  if (need > horizon) {
    coast(k, sign_of(dv) * accel, horizon);
    return horizon;
  }
  coast(k, sign_of(dv) * accel, need);
  k.v = goal;
  return need;
}

// One phase of an auto move to `aim` (speed up to `vmax`, cruise, slow down
// to stop there); returns the time taken, at most `horizon`; 0 when the
// axis is at rest at `aim`.
double approach(Kinematics& k, double aim, double vmax, double accel, double horizon) {
  const double d = aim - k.x;
  const double dist = std::abs(d);
  if (dist < kEpsilon && std::abs(k.v) < 1e-9) return 0;
  const int toward = d > 0 ? 1 : d < 0 ? -1 : -sign_of(k.v);
  const double u = std::abs(k.v);
  // Moving away, or too close to stop in time: brake (and turn if need be).
  if (k.v * toward < 0 || u * u / (2 * accel) >= dist - 1e-12) return ramp_toward(k, 0, accel, horizon);
  if (u < vmax - 1e-12) {
    // Speed up until vmax, or until braking must begin: where the speed w
    // satisfies w^2/2a (braking) + (w^2 - u^2)/2a (speeding up) = dist.
    const double top = std::min(vmax, std::sqrt(accel * dist + u * u / 2));
    const double phase = (top - u) / accel;
    if (phase > horizon) {
      coast(k, toward * accel, horizon);
      return horizon;
    }
    coast(k, toward * accel, phase);
    k.v = toward * top;
    return phase;
  }
  const double cruise = std::max(0.0, (dist - u * u / (2 * accel)) / u);
  const double t = std::min(cruise, horizon);
  coast(k, 0, t);
  return t;
}

// ERRATA E-71: an auto move stops where a reading of it is within the
// axis's tolerance of the target: up to tolerance_deg less the display's
// resolution short of it. A move to a limit or stow position ends on its
// switch; an axis already that close does not move.
double aim_for(const AxisProfile& p, double from, double target) {
  const double deadband = std::max(0.0, p.tolerance_deg - kDisplayResolution);
  auto at = [&](double x) { return std::abs(target - x) < kEpsilon; };
  if (deadband < kEpsilon || at(p.min_deg) || at(p.max_deg) || (p.has_stow_limit && at(p.stow_deg))) return target;
  if (std::abs(target - from) <= deadband) return from;
  return target > from ? target - deadband : target + deadband;
}

// Whether two STORE entries share a name: each name placed in an open
// addressing table twice the list's size by a hash of its length and its
// first and last two characters (no loop over the name), names compared
// only where those hashes are equal. Comparing every pair was 1,225 string
// comparisons on a full list, and the fuzz target checks after every chunk
// (libFuzzer intercepts each comparison). Not instrumented for coverage under
// clang, nor inlined where it would take its caller's instrumentation: the
// check is the fuzz target's oracle, not code to steer by.
#if defined(__clang__)
__attribute__((no_sanitize("coverage"), noinline))
#endif
bool has_a_name_twice(const std::vector<StoredSatellite>& store) {
  constexpr std::size_t kSlots = 128;  // more than twice Controller::kMaxStored
  if (store.size() > kSlots / 2) return false;  // the list's size is checked apart
  std::array<std::uint32_t, kSlots> hash_in;
  std::array<std::uint8_t, kSlots> entry_in{};  // 1 + the entry's index; 0: empty
  for (std::size_t i = 0; i < store.size(); ++i) {
    const std::string& name = store[i].name;
    const std::size_t n = name.size();
    auto at = [&](std::size_t k) -> std::uint32_t { return k < n ? static_cast<std::uint8_t>(name[k]) : 0u; };
    const std::uint32_t h = (static_cast<std::uint32_t>(n) * 0x9E3779B1u) ^ (at(0) * 0x85EBCA6Bu) ^
                            (at(n - 1) * 0xC2B2AE35u) ^ (at(n - 2) * 0x27D4EB2Fu);
    for (std::size_t s = (h ^ (h >> 16)) % kSlots;; s = (s + 1) % kSlots) {
      if (entry_in[s] == 0) {
        hash_in[s] = h;
        entry_in[s] = static_cast<std::uint8_t>(i + 1);
        break;
      }
      if (hash_in[s] == h && store[entry_in[s] - 1u].name == name) return true;
    }
  }
  return false;
}

}  // namespace

std::uint8_t enum_value(const enums::EnumList* list, std::string_view name) {
  if (list)
    if (auto v = list->value_of(name)) return *v;
  return enums::kFirstValue;
}

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
  // What the controller shows at power-on (§3.2 bytes 3-12, 35 ZZZ, 36-38 'S').
  state_.displayed_sat = profile_.display.satellite;
  state_.pol_code = profile_.display.pol_code;
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol})
    axis(a).fast = axis(a).configured_fast = axis_profile(a).power_on_speed == AxisSpeed::kFast;
  // Power-on: INIT has finished; MANUAL (or TRACK, for profiles that test it).
  state_.mode.last_mode = mode_value("INIT_MODE");
  state_.mode.exit_status = enum_value(enums::exit_list_for_mode(state_.mode.last_mode, enum_reading()),
                                       "INIT_NORMAL_EXIT");
  if (state_.track.active) {
    state_.mode.mode = mode_value("TRACK_MODE");
    set_state(track_submode(state_.track.activity).state);
    track_pattern_ = {state_.az.position, state_.el.position, 0};
    tick_origin_ = last_update_;
    if (track_moves()) next_track_leg();
  } else {
    state_.mode.mode = mode_value("MANUAL_MODE");
    set_state("MANUAL_IDLE");
  }
}

enums::EnumReading Controller::enum_reading() const {
  return enums::EnumReading{profile_.restore_lost_locate_exit, reads_other("E-34")};
}

bool Controller::reads_other(std::string_view errata_id) const {
  return side_taken(profile_.readings, errata_id) == ReadingSide::kOther;
}

bool Controller::reads_other_2(std::string_view errata_id) const {
  return side_taken(profile_.readings, errata_id) == ReadingSide::kOther2;
}

std::optional<Duration> Controller::inter_character_timeout() const {
  if (!reads_other("E-67")) return std::nullopt;
  return std::chrono::duration_cast<Duration>(kInterCharacterTimeout);
}

void Controller::set_reading(const std::string& errata_id, ReadingSide side) {
  update();
  // E-34 changes the value of a state, not the state: kept by its name.
  const auto* states_before = enums::state_list_for_mode(state_.mode.mode, enum_reading());
  const auto state_before = states_before ? states_before->name_of(state_.mode.state) : std::nullopt;
  profile_.readings[errata_id] = side;
  if (errata_id == "E-34" && state_before) set_state(*state_before);
  const auto* states = enums::state_list_for_mode(state_.mode.mode, enum_reading());
  const auto state = states ? states->name_of(state_.mode.state) : std::nullopt;
  const auto* exits = enums::exit_list_for_mode(state_.mode.last_mode, enum_reading());
  const auto exit = exits ? exits->name_of(state_.mode.exit_status) : std::nullopt;
  // A search or LOCATE that ended by itself, nothing taken over since: in
  // the mode it went to, with its own exit as the last one.
  auto ended_by_itself = [&](std::string_view mode, std::string_view normal_exit) {
    return meanings::mode_name(state_.mode.last_mode) == mode && exit == normal_exit &&
           (state == "MANUAL_IDLE" || state == "WAITING_FOR_USER_INPUT");
  };
  // E-93: still in the mode a completed LOCATE went to: the mode the side
  // taken goes to, the LOCATE's exit kept as the last one.
  if (errata_id == "E-93" && ended_by_itself("LOCATE_MODE", "LOCATE_FUNCTION_COMPLETED")) {
    const ModeState kept = state_.mode;
    if (side == ReadingSide::kOther) enter_mode("REMOTE_MODE", "WAITING_FOR_USER_INPUT");
    else enter_mode("MANUAL_MODE", "MANUAL_IDLE");
    state_.mode.last_mode = kept.last_mode;
    state_.mode.exit_status = kept.exit_status;
  }
  // E-90: a search still running, or over by itself: again from where and
  // when it began (the other side's is over within a second).
  if (errata_id == "E-90" && (in_mode("SPIRAL_REMOTE_MODE") || ended_by_itself("SPIRAL_REMOTE_MODE", "SPIRAL_NO_PEAK_FOUND"))) {
    state_.mode = search_.mode;
    state_.az = search_.az_from;
    state_.el = search_.el_from;
    last_update_ = tick_origin_ = search_.began;
    chain_pending_ = false;
    search_.legs = 0;
    search_.returning = false;
    set_state("BEGINNING_SPIRAL_SEARCH");
    next_search_leg();
    update();
  }
  // E-94: a LOCATE still moving, or completed: its movements again from
  // where they began.
  const bool locate_moving = in_mode("LOCATE_MODE") && state && state->starts_with("LOCATE_") &&
                             state->ends_with("_MOVEMENT");
  if (errata_id == "E-94" && (locate_moving || ended_by_itself("LOCATE_MODE", "LOCATE_FUNCTION_COMPLETED"))) {
    state_.mode = locate_.mode;
    state_.az = locate_.az_from;
    state_.el = locate_.el_from;
    last_update_ = locate_.began;
    start_locate_movements();
    update();  // to the clock's time again, the side's way
  }
  // E-100: a TRACK that peaks or searches begins its movements now.
  if (errata_id == "E-100" && track_moves() && !moving()) {
    tick_origin_ = last_update_;
    next_track_leg();
  }
  // E-61: the last remote jog, nothing else on its axis since: again from
  // where and when it began, for the duration the side taken gives it.
  if (errata_id == "E-61" && remote_jog_.valid && !remote_jog_.key)
    redo_remote_jog(jog_duration(remote_jog_.ms, side == ReadingSide::kOther));
  // E-56: the last jog key, likewise, held for the side's time.
  if (errata_id == "E-56" && remote_jog_.valid && remote_jog_.key) redo_remote_jog(key_jog_hold(side));
  // E-63: a dual-port feed still on its way to a satellite's one position
  // (32h form 1, 34h): that move again, from where and when it began, to the
  // position the side taken gives it.
  if (errata_id == "E-63" && profile_.pol_type == PolType::kDualPort &&
      state_.pol.motion == AxisState::Motion::kRemoteAutoMove) {
    const DualPortMove m = dual_port_move_;  // a copy: the move starts afresh
    const AxisProfile& p = axis_profile(AxisId::kPol);
    const double was = std::clamp(side == ReadingSide::kOther ? m.sat.h_pol_deg : m.sat.v_pol_deg, p.min_deg, p.max_deg);
    if (std::abs(state_.pol.target - was) < 1e-9) {
      state_.pol = m.pol_from;
      start_dual_port_move(m.sat);
      dual_port_move_ = m;
      step_axis(AxisId::kPol, m.began, last_update_);
    }
  }
}

void Controller::start_remote_jog(AxisId a, int direction, bool fast, Duration duration, std::uint32_t ms, bool key) {
  const AxisState from = axis(a);
  start_jog(a, direction, fast, duration);  // forgets the jog before, on this axis
  remote_jog_ = {true, a, clock_.now(), from, ms, key};
}

void Controller::redo_remote_jog(Duration duration) {
  const RemoteJog j = remote_jog_;
  AxisState& s = axis(j.axis);
  const AxisState now = s;
  s = j.from;
  s.motion = AxisState::Motion::kJog;
  s.direction = now.direction;
  s.fast = s.configured_fast = now.fast;
  s.jog_end = j.began + duration;
  step_axis(j.axis, j.began, last_update_);
}

// §3.5: a dual-port feed has one polarization position per satellite, for
// 'H' and 'V' alike: its horizontal one, or on ERRATA E-63's other side its
// vertical one.
void Controller::start_dual_port_move(const StoredSatellite& sat) {
  dual_port_move_ = DualPortMove{last_update_, state_.pol, sat};
  start_move(AxisId::kPol, reads_other("E-63") ? sat.v_pol_deg : sat.h_pol_deg, true);
}

void Controller::start_locate_movements() {
  if (reads_other("E-94")) {
    // ERRATA E-94's other side: the movements of §3.17 locate_states one
    // after the other, elevation first (on_motion_done chains them).
    // The LOCATE has the antenna: what moved the azimuth before stops.
    tick_origin_ = last_update_;
    chain_pending_ = false;
    set_state("LOCATE_FIRST_ELEV_MOVEMENT");
    if (state_.az.motion != AxisState::Motion::kIdle) stop_axis(AxisId::kAz);
    start_move(AxisId::kEl, locate_.el_to, false);
  } else {
    set_state("LOCATE_AZIM_MOVEMENT");
    start_move(AxisId::kAz, locate_.az_to, false);
    start_move(AxisId::kEl, locate_.el_to, false);
  }
  if (!moving()) on_motion_done();
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

void Controller::enter_mode(enums::Mode mode, std::string_view state, std::string_view exit_of_old) {
  ++modes_entered_;
  if (mode.value != state_.mode.mode) {
    // A LOCATE, STOW or DEPLOY that another mode takes over has not
    // completed (ERRATA E-82, E-89).
    const std::string locate_changed = exit_of_old.empty() ? moving_exit(false) : std::string(exit_of_old);
    state_.mode.last_mode = state_.mode.mode;
    const auto* exits = enums::exit_list_for_mode(state_.mode.last_mode, enum_reading());
    // Fault locate-stop-exit-stale: a stopped LOCATE leaves byte 48 as it was (§3.17).
    const bool stale = faults_.has(Fault::kLocateStopExitStale) && state_.mode.last_mode == enums::Mode("LOCATE_MODE").value &&
                       locate_changed.ends_with("_STOP_KEY");
    if (!stale)
      state_.mode.exit_status =
          exits ? enum_value(exits, locate_changed.empty() ? normal_exit_name(*exits) : std::string_view(locate_changed))
                : enums::kFirstValue;
    // E-100's other side: a TRACK that moved the antenna hands it over at
    // rest, the new mode's movements starting from there.
    if (track_moves()) stop_all();
    state_.mode.mode = mode.value;
    chain_pending_ = false;
    if (mode != enums::Mode("TRACK_MODE")) state_.track.active = false;
  }
  set_state(state);
}

bool Controller::in_mode(enums::Mode mode) const { return state_.mode.mode == mode.value; }

// ERRATA E-89: stow_exit_conditions and deploy_exit_conditions pair a
// MOVE_STOPPED and a MODE_CHANGED (once spelled MODE_CHANGE) entry with each
// moving state: the one of the state the STOW or DEPLOY is in; a search, a
// STOP_KEY and a MODE_CHANGED entry in locate_exit_conditions (E-90).
std::string Controller::moving_exit(bool stopped) const {
  if (in_mode("LOCATE_MODE")) return locate_exit(stopped);
  const bool search = in_mode("SPIRAL_REMOTE_MODE");
  if (!search && !in_mode("STOW_MODE") && !in_mode("DEPLOY_MODE")) return "";
  if (stopped && in_mode("STOW_MODE") && faults_.has(Fault::kStowStopExitFinished)) return "STOW_FINISHED_NORMALLY";
  if (stopped && in_mode("DEPLOY_MODE") && faults_.has(Fault::kDeployStopExitFinished))
    return "DEPLOY_FINISHED_NORMALLY";
  if (stopped && search && faults_.has(Fault::kSearchStopExitNoPeak)) return "SPIRAL_NO_PEAK_FOUND";
  const auto* states = enums::state_list_for_mode(state_.mode.mode, enum_reading());
  const auto* exits = enums::exit_list_for_mode(state_.mode.mode, enum_reading());
  const auto state = states ? states->name_of(state_.mode.state) : std::nullopt;
  if (!state || !exits) return "";
  // E-90: the spiral's exits drop the state's "SEARCH_"
  // (SPIRAL_SEARCH_STEPPING_UP_IN_ELEVATION -> SPIRAL_STEPPING_UP_IN_ELEVATION_STOP_KEY).
  std::string stem(*state);
  if (search && stem.starts_with("SPIRAL_SEARCH_")) stem.replace(0, 14, "SPIRAL_");
  const std::string_view stop_suffix = search ? "_STOP_KEY" : "_MOVE_STOPPED";
  for (std::string_view suffix : stopped ? std::vector<std::string_view>{stop_suffix}
                                         : std::vector<std::string_view>{"_MODE_CHANGED", "_MODE_CHANGE"}) {
    std::string name = stem + std::string(suffix);
    if (exits->value_of(name)) return name;
  }
  return "";
}

// ERRATA E-82: a LOCATE left before it completes exits with the STOP_KEY or
// MODE_CHANGED entry of the movement it is in (§3.17 locate_exit_conditions
// pair one with each movement state); one left before its first movement
// (waiting for navigation data, or in a range error, E-81) with the entry of
// the movement it was to begin with, the first elevation movement; on the
// other side with another pair: the azimuth movement's, in which the
// reference's own LOCATE moves (E-94).
std::string Controller::locate_exit(bool stop_key) const {
  if (stop_key && faults_.has(Fault::kLocateStopExitCompleted)) return "LOCATE_FUNCTION_COMPLETED";
  std::string movement = reads_other("E-82") ? "LOCATE_AZIM_MOVEMENT" : "LOCATE_FIRST_ELEV_MOVEMENT";
  if (const auto* states = enums::state_list_for_mode(state_.mode.mode, enum_reading()))
    if (const auto name = states->name_of(state_.mode.state))
      for (std::string_view m : {"LOCATE_FIRST_ELEV_MOVEMENT", "LOCATE_POL_MOVEMENT", "LOCATE_AZIM_MOVEMENT",
                                 "LOCATE_SECOND_ELEV_MOVEMENT"})
        if (*name == m) movement = m;
  return movement + (stop_key ? "_STOP_KEY" : "_MODE_CHANGED");
}

// ---- motion ------------------------------------------------------------------

bool Controller::limit(AxisId a, int direction) const {
  const AxisProfile& p = axis_profile(a);
  const double pos = axis(a).position;
  return direction > 0 ? pos >= p.max_deg - kEpsilon : pos <= p.min_deg + kEpsilon;
}

double Controller::stow_elevation() const {
  return profile_.el.has_stow_limit ? profile_.el.stow_deg : profile_.el.min_deg;
}

// ERRATA E-99's other side: the STOW's elevation movement stops a degree
// short of the stow position (an elevation already within that degree is
// not moved), and the STOW ends STOW_FINISHED_WITH_ELEV_NOT_AT_STOW.
double Controller::stow_elevation_target() const {
  const double stow = stow_elevation();
  if (!reads_other("E-99")) return stow;
  const double from = axis(AxisId::kEl).position;
  if (std::abs(from - stow) <= kStowShortDeg) return from;
  return stow + (from > stow ? kStowShortDeg : -kStowShortDeg);
}

bool Controller::elevation_at_stow() const {
  return std::abs(axis(AxisId::kEl).position - stow_elevation()) < kAtStowDeg;
}

bool Controller::stow_limit(AxisId a) const {
  const AxisProfile& p = axis_profile(a);
  return p.has_stow_limit && std::abs(axis(a).position - p.stow_deg) < kAtStowDeg;
}

bool Controller::moving() const {
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol})
    if (axis(a).motion != AxisState::Motion::kIdle) return true;
  return false;
}

void Controller::stop_axis(AxisId a) {
  if (remote_jog_.axis == a) remote_jog_.valid = false;
  AxisState& s = axis(a);
  if (!axis_profile(a).accel_dps2 || std::abs(s.velocity) < 1e-9) {
    s.motion = AxisState::Motion::kIdle;
    s.velocity = 0;
    return;
  }
  s.motion = AxisState::Motion::kStopping;  // down its ramp (E-71)
}

void Controller::stop_all() {
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) stop_axis(a);
}

void Controller::start_jog(AxisId a, int direction, bool fast, Duration duration) {
  if (remote_jog_.axis == a) remote_jog_.valid = false;  // a remote jog records itself after
  AxisState& s = axis(a);
  s.motion = AxisState::Motion::kJog;
  s.direction = direction;
  s.fast = s.configured_fast = fast;
  s.jog_end = clock_.now() + duration;
}

void Controller::start_move(AxisId a, double target, bool remote) {
  if (remote_jog_.axis == a) remote_jog_.valid = false;
  AxisState& s = axis(a);
  const AxisProfile& p = axis_profile(a);
  s.target = std::clamp(target, p.min_deg, p.max_deg);
  // Fault move-stops-short: the axis stops 1 degree before its target.
  if (faults_.has(Fault::kMoveStopsShort) && std::abs(s.target - s.position) > 1.0)
    s.target -= (s.target >= s.position ? 1.0 : -1.0);
  s.aim = aim_for(p, s.position, s.target);
  s.fast = true;
  if (std::abs(s.aim - s.position) < kEpsilon && std::abs(s.velocity) < 1e-9) {
    s.motion = AxisState::Motion::kIdle;
    s.velocity = 0;
    return;
  }
  s.direction = s.aim >= s.position ? 1 : -1;
  s.motion = remote ? AxisState::Motion::kRemoteAutoMove : AxisState::Motion::kAutoMove;
  if (a == AxisId::kAz) az_auto_moved_ = true;
}

void Controller::step_axis(AxisId a, TimePoint from, TimePoint to) {
  AxisState& s = axis(a);
  const AxisProfile& p = axis_profile(a);
  if (s.motion == AxisState::Motion::kIdle) return;
  if (p.accel_dps2) return step_ramped(a, from, to);
  if (s.motion == AxisState::Motion::kStopping) {
    s.motion = AxisState::Motion::kIdle;
  } else if (s.motion == AxisState::Motion::kJog) {
    const bool timed = !faults_.has(Fault::kJogIgnoresDuration);
    const TimePoint end = timed ? std::min(to, s.jog_end) : to;
    if (end > from) s.position += s.direction * (s.fast ? p.fast_dps : p.slow_dps) * seconds(end - from);
    if (timed && to >= s.jog_end) s.motion = AxisState::Motion::kIdle;
  } else {
    const double step = p.fast_dps * seconds(to - from);
    if (std::abs(s.aim - s.position) <= step) {
      s.position = s.aim;
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

// ERRATA E-71: the axis speeds up and slows down at accel_dps2. A jog runs
// its timer at speed (from wherever the ramp has got) and then ramps down,
// so it travels on after the timer; an auto move slows down to stop at its
// aim. Phases of constant acceleration, each computed exactly, so that how
// the time is cut into steps changes nothing.
void Controller::step_ramped(AxisId a, TimePoint from, TimePoint to) {
  using Motion = AxisState::Motion;
  AxisState& s = axis(a);
  const AxisProfile& p = axis_profile(a);
  const double accel = *p.accel_dps2;
  const double total = seconds(to - from);
  Kinematics k{s.position, s.velocity};
  double t = 0;
  for (int phase = 0; phase < kMaxPhases && s.motion != Motion::kIdle && t < total; ++phase) {
    const double left = total - t;
    if (s.motion == Motion::kJog || s.motion == Motion::kStopping) {
      const bool timed = s.motion == Motion::kStopping || !faults_.has(Fault::kJogIgnoresDuration);
      const double until_end = s.motion == Motion::kStopping ? 0.0 : timed ? seconds(s.jog_end - from) - t : left;
      const double want = until_end > 1e-9 ? s.direction * (s.fast ? p.fast_dps : p.slow_dps) : 0.0;
      if (want == 0 && std::abs(k.v) < 1e-9) {
        k.v = 0;
        s.motion = Motion::kIdle;
        break;
      }
      t += ramp_toward(k, want, accel, want != 0 ? std::min(left, until_end) : left);
    } else {
      t += approach(k, s.aim, p.fast_dps, accel, left);
      if (std::abs(s.aim - k.x) < kEpsilon && std::abs(k.v) < 1e-9) {
        k = {s.aim, 0};
        s.motion = Motion::kIdle;
      }
    }
    // A limit stops the axis there (§3.2 bytes 32-34).
    if (k.x >= p.max_deg || k.x <= p.min_deg) {
      k = {std::clamp(k.x, p.min_deg, p.max_deg), 0};
      s.motion = Motion::kIdle;
    }
  }
  s.position = k.x;
  s.velocity = k.v;
  if (s.motion != Motion::kJog && k.v != 0) s.direction = sign_of(k.v);
}

void Controller::advance(TimePoint to, bool at_tick) {
  const bool was_moving = moving();
  for (AxisId a : {AxisId::kAz, AxisId::kEl, AxisId::kPol}) step_axis(a, last_update_, to);
  last_update_ = to;
  // E-90's other side: a search whose time is over gives up where it is
  // (next_search_leg exits once the axes have stopped).
  if (at_tick && in_mode("SPIRAL_REMOTE_MODE") && reads_other("E-90") && !search_.returning && to >= search_end()) {
    search_.returning = true;
    stop_all();
  }
  if (moving() || !(was_moving || chain_pending_)) return;
  if (!at_tick) {
    chain_pending_ = true;
    return;
  }
  chain_pending_ = false;
  on_motion_done();
}

bool Controller::chains_movements() const {
  // E-94's other side: a LOCATE's movements follow each other too.
  return in_mode("SPIRAL_REMOTE_MODE") || in_mode("DEPLOY_MODE") || (in_mode("LOCATE_MODE") && reads_other("E-94")) ||
         (in_mode("STOW_MODE") && reads_other("E-89")) || track_moves();
}

void Controller::update() {
  const TimePoint now = clock_.now();
  // A search or a DEPLOY chains movements on ticks fixed to its start: each
  // begins at the first tick after the one before ended.
  const auto tick = std::chrono::duration_cast<Duration>(kSearchTick);
  while (chains_movements() && last_update_ < now) {
    const TimePoint next = tick_origin_ + ((last_update_ - tick_origin_) / tick + 1) * tick;
    if (next > now) {
      advance(now, false);
      return;
    }
    advance(next);
  }
  if (now > last_update_) advance(now);
}

// ---- TRACK's own movements (ERRATA E-100) -------------------------------------

// E-100: the reference controller's TRACK holds the antenna still (its model
// measures no signal); on the other side a peaking or search operation moves
// it, as a real TRACK may at any moment.
bool Controller::track_moves() const {
  return in_mode("TRACK_MODE") && reads_other("E-100") && track_peaks_or_searches();
}

// The other side's pattern: azimuth out a step and back, elevation out a
// step and back, about where TRACK began, over and over; a step is 0.2 deg,
// or twice the axis's arrival tolerance where that is more, away from a limit
// the axis stands at. A search finds its peak after one round and goes on
// peaking (§3.2 byte 40 SSSS 0100 to 0011, track_states'
// TRACK_STEP_PEAKING), so moves stay refused (§3.4) whichever it shows.
void Controller::next_track_leg() {
  struct Leg {
    AxisId axis;
    bool out;
  };
  static constexpr Leg kLegs[] = {{AxisId::kAz, true}, {AxisId::kAz, false}, {AxisId::kEl, true}, {AxisId::kEl, false}};
  if (track_pattern_.legs == static_cast<int>(std::size(kLegs)) && state_.track.activity == TrackActivity::kSearching) {
    state_.track.activity = TrackActivity::kPeaking;
    set_state(track_submode(state_.track.activity).state);
  }
  for (std::size_t tries = 0; tries < std::size(kLegs); ++tries) {
    const Leg& leg = kLegs[static_cast<std::size_t>(track_pattern_.legs++) % std::size(kLegs)];
    const AxisProfile& p = axis_profile(leg.axis);
    const double center = leg.axis == AxisId::kAz ? track_pattern_.az_center : track_pattern_.el_center;
    const double step = std::max(kTrackStepDeg, 2 * p.tolerance_deg);
    const double target = !leg.out ? center : center + step <= p.max_deg ? center + step : center - step;
    start_move(leg.axis, target, false);
    if (moving()) return;
  }
}

// ---- §3.7 'A': the spiral search, 'D': the deploy (ERRATA E-90) --------------

void Controller::start_search(char pattern) {
  tick_origin_ = last_update_;
  chain_pending_ = false;
  search_ = Search{pattern, 0, clock_.now(), false, state_.az, state_.el, ModeState{}};
  enter_mode("SPIRAL_REMOTE_MODE", "BEGINNING_SPIRAL_SEARCH");
  search_.mode = state_.mode;
  next_search_leg();
}

// ERRATA E-90: how long a search lasts is the controller's; the other side
// gives up within a second.
TimePoint Controller::search_end() const {
  return search_.began + (reads_other("E-90") ? std::chrono::duration_cast<Duration>(kShortSearchTime)
                                              : std::chrono::duration_cast<Duration>(kSearchTime));
}

// Azimuth clockwise, elevation up, azimuth counterclockwise, elevation down,
// each pair a step longer than the last ('E'); a flat spiral keeps its
// elevation legs one step long ('F'). A step is 1 deg, or twice the axis's
// arrival tolerance where that is more. A leg a limit leaves no room for is
// passed over. When the search time is over: back to where it began, and out
// with no peak found (the model measures no signal).
void Controller::next_search_leg() {
  struct Leg {
    AxisId axis;
    int direction;
    std::string_view state;
  };
  static constexpr Leg kLegs[] = {{AxisId::kAz, +1, "SPIRAL_SEARCH_STEPPING_CW_IN_AZIMUTH"},
                                  {AxisId::kEl, +1, "SPIRAL_SEARCH_STEPPING_UP_IN_ELEVATION"},
                                  {AxisId::kAz, -1, "SPIRAL_SEARCH_STEPPING_CCW_IN_AZIMUTH"},
                                  {AxisId::kEl, -1, "SPIRAL_SEARCH_STEPPING_DOWN_IN_ELEVATION"}};
  if (search_.returning) {
    enter_mode("MANUAL_MODE", "MANUAL_IDLE", "SPIRAL_NO_PEAK_FOUND");
    return;
  }
  for (std::size_t tries = 0; tries < std::size(kLegs) && last_update_ < search_end(); ++tries) {
    const Leg& leg = kLegs[static_cast<std::size_t>(search_.legs) % std::size(kLegs)];
    const int size = search_.legs / 2 + 1;
    ++search_.legs;
    // A step the drive could not make (within its arrival tolerance) would
    // not move at all: at least twice that.
    const double step = std::max(kSpiralStepDeg, 2 * axis_profile(leg.axis).tolerance_deg);
    const double length = step * (leg.axis == AxisId::kEl && search_.pattern == 'F' ? 1 : size);
    set_state(leg.state);
    start_move(leg.axis, axis(leg.axis).position + leg.direction * length, false);
    if (moving()) return;
  }
  search_.returning = true;
  set_state("SPIRAL_SEARCH_NO_PEAK_MOVING_TO_AZIMUTH");
  start_move(AxisId::kAz, search_.az_from.position, false);
  start_move(AxisId::kEl, search_.el_from.position, false);
  if (!moving()) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "SPIRAL_NO_PEAK_FOUND");
}

void Controller::start_stow() {
  tick_origin_ = last_update_;
  chain_pending_ = false;
  enter_mode("STOW_MODE", "STOW_MOVING_TO_AZIM_STOW");
  // ERRATA E-99: a STOW drives every axis with a stow limit to it (§3.2
  // bytes 32-34 bit C then shows it); an azimuth without one goes to 0.0
  // and an elevation without one to its lower limit, all at once (E-89; the
  // other side moves the azimuth first and the others after it, in
  // on_motion_done). A circular feed has no polarization drive (§3.5).
  // E-99's other side leaves the elevation short (stow_elevation_target).
  start_move(AxisId::kAz, profile_.az.has_stow_limit ? profile_.az.stow_deg : 0.0, false);
  if (!reads_other("E-89")) {
    start_move(AxisId::kEl, stow_elevation_target(), false);
    if (profile_.pol.has_stow_limit && profile_.pol_type != PolType::kCircular)
      start_move(AxisId::kPol, profile_.pol.stow_deg, false);
  }
  // Already stowed: the STOW finishes at once (as a LOCATE or DEPLOY with
  // nothing to move does), not a STOW_MODE that never ends.
  if (!moving()) on_motion_done();
}

void Controller::start_deploy() {
  tick_origin_ = last_update_;
  chain_pending_ = false;
  enter_mode("DEPLOY_MODE", "DEPLOY_MOVING_ELEVATION");
  start_move(AxisId::kEl, profile_.el.deploy_deg.value_or(profile_.el.initial_deg), false);
  if (!moving()) on_motion_done();
}

// A mode that drives the antenna ends when the antenna arrives.
void Controller::on_motion_done() {
  // A LOCATE completes when its movement arrives: not in a range error or
  // while it waits for data (E-81), where a stop may still be ramping down.
  const auto* states = enums::state_list_for_mode(state_.mode.mode, enum_reading());
  const auto state = states ? states->name_of(state_.mode.state) : std::nullopt;
  if (in_mode("LOCATE_MODE")) {
    // E-94's other side: the movements of locate_states one after the
    // other; the feed has no polarization target (the offset is unused,
    // §3.18 bytes 24-28) and the first elevation movement went all the way.
    if (state == "LOCATE_FIRST_ELEV_MOVEMENT") {
      set_state("LOCATE_POL_MOVEMENT");
      return on_motion_done();
    }
    if (state == "LOCATE_POL_MOVEMENT") {
      set_state("LOCATE_AZIM_MOVEMENT");
      start_move(AxisId::kAz, locate_.az_to, false);
      if (moving()) return;
      return on_motion_done();
    }
    if (state == "LOCATE_AZIM_MOVEMENT" && reads_other("E-94")) set_state("LOCATE_SECOND_ELEV_MOVEMENT");
    // E-93: where a LOCATE that completes goes (E-52: MANUAL_MODE).
    const bool completed = state == "LOCATE_AZIM_MOVEMENT" || state == "LOCATE_SECOND_ELEV_MOVEMENT";
    if (completed && reads_other("E-93")) enter_mode("REMOTE_MODE", "WAITING_FOR_USER_INPUT", "LOCATE_FUNCTION_COMPLETED");
    else if (completed) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "LOCATE_FUNCTION_COMPLETED");
  } else if (track_moves()) {
    next_track_leg();
  } else if (in_mode("STOW_MODE")) {
    // ERRATA E-89's other side: one axis after another, in the order of
    // stow_states (azimuth, polarization, elevation).
    if (reads_other("E-89") && state == "STOW_MOVING_TO_AZIM_STOW") {
      set_state("STOW_MOVING_TO_POL_STOW");
      if (profile_.pol.has_stow_limit && profile_.pol_type != PolType::kCircular)
        start_move(AxisId::kPol, profile_.pol.stow_deg, false);
      if (moving()) return;
      return on_motion_done();
    }
    if (reads_other("E-89") && state == "STOW_MOVING_TO_POL_STOW") {
      set_state("STOW_MOVING_TO_ELEV_STOW");
      start_move(AxisId::kEl, stow_elevation_target(), false);
      if (moving()) return;
    }
    enter_mode("MANUAL_MODE", "MANUAL_IDLE",
               reads_other("E-99") && !elevation_at_stow() ? "STOW_FINISHED_WITH_ELEV_NOT_AT_STOW" : "STOW_FINISHED_NORMALLY");
  }
  else if (in_mode("DEPLOY_MODE")) {
    const auto* states = enums::state_list_for_mode(state_.mode.mode, enum_reading());
    const bool elevation_done = states && states->name_of(state_.mode.state) == "DEPLOY_MOVING_ELEVATION";
    if (elevation_done && profile_.az.deploy_deg) {
      set_state("DEPLOY_MOVING_AZIMUTH");
      start_move(AxisId::kAz, *profile_.az.deploy_deg, false);
      if (moving()) return;
    }
    enter_mode("MANUAL_MODE", "MANUAL_IDLE", "DEPLOY_FINISHED_NORMALLY");
  } else if (in_mode("SPIRAL_REMOTE_MODE")) next_search_leg();
  // A pol jog of a manual search (E-34's states) over: the search again.
  else if (in_mode("TRACK_MODE") && state && state->starts_with("TRACK_MANUAL_SEARCH_JOG_POL"))
    set_state(track_submode(state_.track.activity).state);
  else if (in_mode("RECALL_MODE")) enter_mode("MANUAL_MODE", "MANUAL_IDLE", "RECALL_NORMAL_EXIT");
}

// ---- readings ------------------------------------------------------------------

// Tenths of a degree as the status reply shows them; with 0.01 deg feedback
// the tenths are truncated and the hundredths digit goes to §3.17 byte 49/50
// (READING-NOTES 30: the digit extends the magnitude).
std::int32_t Controller::tenths(AxisId a) const {
  const double pos = axis(a).position;
  if (!profile_.hundredths) return static_cast<std::int32_t>(in_units(pos, 10));
  // ERRATA E-87: the hundredths' tenths truncated toward zero, the digit
  // extending the magnitude; on the other side rounded down, the digit
  // added to them (-123.45 reads -123.5 and '5').
  const long h = in_units(pos, 100);
  if (reads_other("E-87")) return static_cast<std::int32_t>(h >= 0 ? h / 10 : -((-h + 9) / 10));
  return static_cast<std::int32_t>(h / 10);
}

// ERRATA E-76: a position in display units (10 or, with 0.01 deg feedback,
// 100 to the degree): rounded, or on the other side its further digits
// dropped toward zero, on other-2 toward minus infinity. The motion model's
// sums may fall a hair short of a unit (44.9999999 for 45.0): a millionth
// of a unit counts as the unit.
long Controller::in_units(double deg, int per_degree) const {
  const double v = deg * per_degree;
  if (reads_other("E-76")) return static_cast<long>(std::trunc(v + (v < 0 ? -1e-6 : 1e-6)));
  if (reads_other_2("E-76")) return static_cast<long>(std::floor(v + 1e-6));
  return std::lround(v);
}

std::optional<std::int32_t> Controller::reading(AxisId a) const {
  if (axis_profile(a).ad_error) return std::nullopt;  // '*' (§3.2 bytes 14-31, E-42)
  if (a == AxisId::kPol && profile_.pol_type == PolType::kCircular) return std::nullopt;  // no rotating feed
  if (a == AxisId::kAz && profile_.az_sensor == AzSensor::kFluxgate) {
    // §3.2 NOTE: the compass reads a heading 0.0-359.9 (ERRATA E-72). With
    // 0.01 deg feedback the heading's tenths, truncated as its hundredths
    // digit extends them (E-87): -2.63 deg reads 357.3, not 357.4.
    if (profile_.hundredths) {
      const long h100 = ((in_units(axis(a).position, 100) % 36000) + 36000) % 36000;
      return static_cast<std::int32_t>(h100 / 10);
    }
    const std::int32_t h = tenths(a) % 3600;
    return h < 0 ? h + 3600 : h;
  }
  return tenths(a);
}

std::optional<std::int32_t> Controller::hundredths_digit(AxisId a) const {
  // ERRATA E-30: without 0.01 deg feedback '0', or on the other side a blank
  // (the text gives the byte's content only "for mounts with the ability").
  if (!profile_.hundredths) return reads_other("E-30") ? std::nullopt : std::optional<std::int32_t>(0);
  if (axis_profile(a).ad_error || faults_.has(Fault::kHundredthsAlwaysZero)) return 0;
  long h = in_units(axis(a).position, 100);
  // A fluxgate heading's own hundredths: -2.63 deg is heading 357.37, read
  // 357.3 and '7' (§3.2 NOTE, E-72; ERRATA E-87), not the position's '3'.
  if (a == AxisId::kAz && profile_.az_sensor == AzSensor::kFluxgate) h = ((h % 36000) + 36000) % 36000;
  // E-87's other side: the digit added to tenths rounded down (-123.45 is
  // -123.5 and '5'); the reference's extends the magnitude (-123.4 and '5').
  if (reads_other("E-87")) return static_cast<std::int32_t>(((h % 10) + 10) % 10);
  return static_cast<std::int32_t>(std::labs(h) % 10);
}

// §3.16 (ERRATA E-85): the counts of the position, count_offset at 0 deg and
// counts_per_degree more for each degree; five digits.
std::uint32_t Controller::counts(AxisId a) const {
  const double position = faults_.has(Fault::kPulseCountStale) ? axis_profile(a).initial_deg : axis(a).position;
  const double offset = faults_.has(Fault::kPulseCountNoOffset) ? 0.0 : profile_.count_offset;
  const double c = offset + position * profile_.counts_per_degree;
  return static_cast<std::uint32_t>(std::clamp(std::lround(c), 0L, 99999L));
}

double Controller::position_of_counts(std::uint32_t count) const {
  double from_zero = static_cast<double>(count) - profile_.count_offset;
  // Fault form2b-negative-mirrored: a count below the offset taken as as far above it.
  if (faults_.has(Fault::kForm2BMirrored)) from_zero = std::abs(from_zero);
  return from_zero / profile_.counts_per_degree;
}

// §3.2 bytes 36-38: S<<4 | XXXX; higher codes have priority.
std::uint8_t Controller::axis_status_bits(AxisId a) const {
  const AxisState& s = axis(a);
  std::uint8_t code = 0;
  switch (s.motion) {
    case AxisState::Motion::kIdle: code = 0x0; break;
    // ERRATA E-53: a remote jog reports "movement in progress" (0100/0101),
    // or (other side) "jog movement pending" (0010/0011) while its time runs.
    case AxisState::Motion::kJog:
      code = reads_other("E-53") ? (s.direction > 0 ? 0x3 : 0x2) : (s.direction > 0 ? 0x5 : 0x4);
      break;
    case AxisState::Motion::kStopping:
    case AxisState::Motion::kAutoMove: code = s.direction > 0 ? 0x5 : 0x4; break;
    case AxisState::Motion::kRemoteAutoMove: code = 0x7; break;
  }
  // Fault never-shows-rest: the azimuth at rest after an auto move still
  // reads "automatic movement in progress" (§3.2 byte 36 XXXX 0100/0101).
  if (faults_.has(Fault::kNeverShowsRest) && a == AxisId::kAz && s.motion == AxisState::Motion::kIdle && az_auto_moved_)
    code = s.direction > 0 ? 0x5 : 0x4;
  if (s.alarm) code = s.alarm;
  // E-98: 'S' is the speed of the move, or (other side) the configured speed.
  const bool fast = reads_other("E-98") ? s.configured_fast : s.fast;
  return static_cast<std::uint8_t>((fast ? 0x10 : 0) | code);
}

bool Controller::track_peaks_or_searches() const {
  return state_.track.active && track_submode(state_.track.activity).peaking_or_search;
}

// §3.2 byte 35 'Y': no polarization movement while TRACK peaks or searches.
bool Controller::pol_moves_allowed() const { return !track_peaks_or_searches(); }

std::uint8_t Controller::track_byte() const {
  // §3.2 byte 40: BBB<<4 | SSSS; BBB is never 000 (TrackBand's values are the codes).
  const auto band = static_cast<std::uint8_t>(state_.track.band);
  const std::uint8_t sub = state_.track.active ? track_submode(state_.track.activity).ssss : 0;
  return static_cast<std::uint8_t>(band << 4 | sub);
}

StatusBlock Controller::status_block() const {
  StatusBlock b;
  // ERRATA E-74's other side: the name shown after a blank (§3.6: blanks
  // entered before a name), where the field has room for it.
  b.sat_name = reads_other("E-74") && !state_.displayed_sat.empty() && state_.displayed_sat.size() < 10
                   ? " " + state_.displayed_sat
                   : state_.displayed_sat;
  const auto az = reading(AxisId::kAz);
  if (!az) {
    b.azimuth = {fields::AzimuthReading::Kind::kError, 0, 0};
  } else if (profile_.az_sensor == AzSensor::kFluxgate) {
    // §3.2 NOTE: a heading and 'M' or 'T' when the compass is primary.
    b.azimuth = {fields::AzimuthReading::Kind::kHeading, *az, profile_.fluxgate_heading};
  } else {
    b.azimuth = {fields::AzimuthReading::Kind::kPosition, *az, 0};
  }
  b.elevation = reading(AxisId::kEl);
  b.polarization = reading(AxisId::kPol);  // '******' also "not equipped with a rotating feed"
  auto limit_bits = [&](AxisId a) {
    return static_cast<std::uint8_t>((limit(a, +1) ? 4 : 0) | (limit(a, -1) ? 2 : 0) | (stow_limit(a) && !faults_.has(Fault::kStowLimitBitsMissing) ? 1 : 0));
  };
  b.az_limits = faults_.has(Fault::kAzLimitBitsMissing) ? 0 : limit_bits(AxisId::kAz);
  b.el_limits = limit_bits(AxisId::kEl);
  b.pol_limits = profile_.pol_type == PolType::kCircular ? 0 : limit_bits(AxisId::kPol);
  const std::uint8_t feed = profile_.pol_type == PolType::kCircular ? 0 : profile_.pol_type == PolType::kSinglePort ? 1 : 2;
  // E-96's other side: the code in lower case while the feed still moves to it.
  char shown = state_.pol_code;
  if (reads_other("E-96") && state_.pol.motion != AxisState::Motion::kIdle && (shown == 'H' || shown == 'V'))
    shown = static_cast<char>(shown - 'A' + 'a');
  const std::uint8_t code = shown == 'H' ? 0 : shown == 'h' ? 1 : shown == 'V' ? 2 : shown == 'v' ? 3 : 4;
  // §3.2 byte 35 'Y' "only contains meaningful data when TRACK mode is
  // active" (E-95): the other side shows 0 outside TRACK.
  const bool y = pol_moves_allowed() && (state_.track.active || !reads_other("E-95"));
  b.pol_equipment = static_cast<std::uint8_t>(feed << 4 | (y ? 8 : 0) | code);
  b.az_status = axis_status_bits(AxisId::kAz);
  b.el_status = axis_status_bits(AxisId::kEl);
  b.pol_status = profile_.pol_type == PolType::kCircular ? 0 : axis_status_bits(AxisId::kPol);
  b.alarm_code = state_.alarm_code;
  // Fault alarm-code-low-battery: byte 39 never shows "0 No alarm active".
  if (faults_.has(Fault::kAlarmCodeLowBattery) && b.alarm_code == 0) b.alarm_code = 1;
  b.track = track_byte();
  b.agc = profile_.agc;
  b.agc_channel = profile_.agc_channel;
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
  auto pos = [&](AxisId a) {
    const auto r = reading(a);
    return r ? fields::format_scaled(*r, 1) : std::string(a == AxisId::kPol && !axis_profile(a).ad_error ? "----" : "*****");
  };
  std::snprintf(row, sizeof row, "AZ %6s  EL %6s  POL %6s", pos(AxisId::kAz).c_str(), pos(AxisId::kEl).c_str(),
                pos(AxisId::kPol).c_str());
  d.rows[1] = row;
  std::snprintf(row, sizeof row, "STORED %2zu  %s", state_.store.size(), moving() ? "MOVING" : "");
  d.rows[2] = row;
  d.rows[3] = state_.alarm_code ? meanings::alarm_code(state_.alarm_code) : "";
  for (auto& r : d.rows) {
    // The LCD shows 7-bit characters (§3.8 "in ASCII format"): texts from
    // the meanings tables may hold others ('§').
    std::erase_if(r, [](char c) { return static_cast<unsigned char>(c) > 0x7E; });
    for (auto& c : r) c = static_cast<char>(c < 0x20 ? ' ' : std::toupper(static_cast<unsigned char>(c)));
    if (r.size() > 40) r.resize(40);
    while (!r.empty() && r.back() == ' ') r.pop_back();
  }
  // The cursor stays where it was at power-on: the model has no menus to move it.
  d.cursor_row = profile_.display.cursor_row;
  // ERRATA E-20: columns count from 0 (the profile's 0-39); the other side
  // counts them from 1, as the rows (§3.8 byte 163 "1-4").
  d.cursor_column = profile_.display.cursor_column + (reads_other("E-20") ? 1u : 0u);
  d.blinking = profile_.display.cursor_blinking ? '1' : '0';
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
  if (has_a_name_twice(state_.store)) broken += "a name twice in the STORE list; ";
  if (state_.mode.mode < 0x20 || state_.mode.state < 0x20 || state_.mode.last_mode < 0x20 ||
      state_.mode.exit_status < 0x20)
    broken += "an extended status value below 0x20; ";
  return broken;
}

// ---- replies and the faults that bend them ----------------------------------

namespace {

// The bytes first..first+width-1 of a reply (frame byte numbers, §3) with
// their leading blanks moved to the end: "  45.0" -> "45.0  ". A fluxgate
// heading ("123.4T", §3.2 bytes 14-19) keeps its 'M'/'T' in the last byte.
void left_justify(Frame& f, std::size_t first, std::size_t width) {
  const auto at = f.data.begin() + static_cast<std::ptrdiff_t>(first - 3);
  const auto last = at[static_cast<std::ptrdiff_t>(width - 1)];
  if (last == 'M' || last == 'T') return;
  std::string field(at, at + static_cast<std::ptrdiff_t>(width));
  field.erase(0, field.find_first_not_of(' '));
  field.resize(width, ' ');
  std::copy(field.begin(), field.end(), at);
}

// The same bytes with their leading zeros blanked, the units digit kept:
// "00123" -> "  123", "000.5" -> "  0.5". A blank field stays blank.
void blank_pad(Frame& f, std::size_t first, std::size_t width) {
  const auto at = f.data.begin() + static_cast<std::ptrdiff_t>(first - 3);
  for (std::size_t i = 0; i + 1 < width && at[static_cast<std::ptrdiff_t>(i)] == '0'; ++i) {
    const auto next = at[static_cast<std::ptrdiff_t>(i + 1)];
    if (next < '0' || next > '9') break;
    at[static_cast<std::ptrdiff_t>(i)] = ' ';
  }
}

// A six-'*' A/D error field at frame byte `first` as five '*' after a blank.
void five_stars(Frame& f, std::size_t first) {
  const auto at = f.data.begin() + static_cast<std::ptrdiff_t>(first - 3);
  if (std::all_of(at, at + 6, [](std::uint8_t c) { return c == '*'; })) at[0] = ' ';
}

}  // namespace

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
    // ERRATA E-42's other side: the azimuth's A/D error field as §3.2 bytes
    // 14-19 and §3.24 bytes 4-9 print it, five '*' (after a blank).
    if (reads_other("E-42")) {
      if (status) five_stars(f, 14);
      else if (info && !is_offline_reply(f) && info->reply == ReplyKind::kJogPosition && f.data[0] == 'A') five_stars(f, 4);
    }
    // ERRATA E-33's other side: positions left-justified, counts and the 45h
    // heading padded with blanks (§3.2, §3.16, §3.22 give no justification
    // for them). The fault left-justified-position is the same bend on a
    // device whose profile pins the reference side.
    const bool other_justification = reads_other("E-33");
    const bool full_reply = info && !is_offline_reply(f);
    if (other_justification || faults_.has(Fault::kLeftJustifiedPosition)) {
      if (status) {
        for (std::size_t first : {14, 20, 26}) left_justify(f, first, 6);
      } else if (full_reply && info->reply == ReplyKind::kJogPosition) {
        left_justify(f, 4, 6);
      }
    }
    if (other_justification && full_reply && info->reply == ReplyKind::kPulseCount) {
      blank_pad(f, 3, 5);
      blank_pad(f, 8, 5);
    }
    if (other_justification && full_reply && info->reply == ReplyKind::kNavigationData) blank_pad(f, 30, 5);
    // ERRATA E-40's other side: the magnetic variation left-justified (§3.22
    // bytes 36-41 give no justification; six blanks stay six blanks).
    if (reads_other("E-40") && full_reply && info->reply == ReplyKind::kNavigationData) left_justify(f, 36, 6);
    // ERRATA E-18's other side: an empty slot's reply (7Fh 7Fh index, §3.11,
    // §3.13, §3.15, §3.21) holds zeros where the reference has blanks; the
    // text describes only the index bytes and the length.
    const bool indexed_read = info && (info->reply == ReplyKind::kSatelliteData || info->reply == ReplyKind::kTleData ||
                                       info->reply == ReplyKind::kIessData || info->reply == ReplyKind::kSignpostData);
    if (reads_other("E-18") && full_reply && indexed_read && f.data.size() > 2 && f.data[0] == 0x7F && f.data[1] == 0x7F)
      std::replace(f.data.begin() + 2, f.data.end(), std::uint8_t{' '}, std::uint8_t{'0'});
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
