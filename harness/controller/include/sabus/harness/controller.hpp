// The reference controller: an in-process RC3000 that implements the whole
// spec (§1 framing, §3.1-§3.25) with the readings of protocol/ERRATA.md. It is
// given a clock (virtual in tests and the in-process runner, steady in `sabus
// sim`), a device profile, and optionally injected faults.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sabus/harness/clock.hpp"
#include "sabus/harness/faults.hpp"
#include "sabus/harness/line_device.hpp"
#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/profile.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/enumerations.hpp"
#include "sabus/protocol/receiver.hpp"

namespace sabus::harness {

enum class AxisId : std::uint8_t { kAz, kEl, kPol };

// One axis: position, motion and alarm (§3.2 bytes 32-38).
struct AxisState {
  double position = 0;        // degrees
  // kStopping: slowing down its ramp after a stop (ERRATA E-71).
  enum class Motion : std::uint8_t { kIdle, kJog, kAutoMove, kRemoteAutoMove, kStopping } motion = Motion::kIdle;
  int direction = 0;          // -1: ccw/down, +1: cw/up
  double target = 0;          // auto moves: the position asked for
  double aim = 0;             // auto moves: where the drive stops (within the axis's tolerance of target)
  double velocity = 0;        // degrees per second, signed; with an acceleration ramp only
  bool fast = true;           // §3.2 'S': configured for fast speed
  // §3.2 'S' as ERRATA E-98's other side reads it: the speed the axis is
  // configured for (power-on, a jog's speed, the '0' key), which an auto move
  // does not change.
  bool configured_fast = true;
  TimePoint jog_end{};
  std::uint8_t alarm = 0;     // §3.2 XXXX alarm code 8-C, 0 for none
  bool operator==(const AxisState&) const = default;
};

struct ModeState {            // §3.17 bytes 45-48
  std::uint8_t mode = 0x20, state = 0x20, last_mode = 0x20, exit_status = 0x20;
  bool operator==(const ModeState&) const = default;
};

struct TrackState {           // §3.2 byte 40, §3.7 'T'
  bool active = false;
  TrackActivity activity = TrackActivity::kIdle;
  TrackBand band = TrackBand::kC;
  bool dual_band = false;
};

struct ControllerState {
  AxisState az, el, pol;
  std::uint8_t alarm_code = 0;            // §3.2 byte 39
  ModeState mode;
  TrackState track;
  std::string displayed_sat;              // §3.2 bytes 3-12, upper case (E-68)
  char pol_code = 0;                      // §3.2 byte 35 ZZZ: 'H', 'h', 'V', 'v' or 0 (none)
  std::optional<StoredSatellite> last_target;   // §3.5: the last target of an auto move
  std::optional<AxisId> last_jogged;            // ERRATA E-46's other side: 47h 'X' replies it
  std::optional<SatelliteData> last_located;    // §3.19 'C': a LOCATE performed before
  // That LOCATE ended in a range error (E-81): not performed for 'C' on
  // ERRATA E-83's reference side. Kept on both sides, so that a side taken
  // late (the live fuzzer's lockstep) judges the same history.
  bool located_out_of_range = false;
  // Commands taken since that LOCATE, reads aside: E-66's other side wants
  // none ("immediately prior").
  int commands_since_locate = 0;
  std::vector<StoredSatellite> store;     // §3.6, <= 50
  std::array<std::optional<PresetSatellite>, 20> presets;
  std::array<std::optional<TleSet>, 10> tles;
  std::array<std::optional<Signpost>, 20> signposts;
  Navigation navigation;
  char last_key = 0;
};

// What one command frame produced.
struct Outcome {
  std::optional<Bytes> reply;             // 7-bit characters; nullopt: silence
  std::optional<NakRule> nak;             // the rule behind a NAK
  std::string note;                       // what happened, for transcripts
  bool stored_data_changed = false;       // for --state-file
};

// ERRATA E-67's other side: the receiver drops a frame whose next byte
// comes more than this after the one before, and waits for a new STX. 20 ms
// is about 19 character times at 9600 baud (E-2) and more than the 16 ms a
// USB serial adapter may hold bytes back (its latency timer), so a master
// that writes a frame at once is never cut; the vectors' pauses inside a
// frame (50 ms and more) are longer.
inline constexpr std::chrono::milliseconds kInterCharacterTimeout{20};

class Controller {
 public:
  Controller(const Profile& profile, const Clock& clock, FaultSet faults = {});

  // Executes one complete command frame that passed the receiver, at the
  // clock's time (§1 State 5). Frames for other addresses are not passed here.
  Outcome execute(const Frame& command);
  // Brings motion up to the clock's time.
  void update();

  const ControllerState& state() const { return state_; }
  // TRACK is active and peaking or searching (§3.2 byte 35 'Y', §3.4; which
  // submodes those are: ERRATA E-69).
  bool track_peaks_or_searches() const;
  // How many times a mode was entered since power-on (§3.17 byte 45): a
  // mode entered and left again within one write shows only here when it
  // was left as the one before it was.
  std::uint32_t modes_entered() const { return modes_entered_; }
  ControllerState& mutable_state() { return state_; }
  const Profile& profile() const { return profile_; }
  // Takes a side of an open point of the spec from now on (readings.hpp):
  // the live fuzzer's model, once a device has shown its side.
  // What the side decides and has already happened is redone its way: a
  // completed LOCATE's mode (E-93), a LOCATE's movements so far (E-94).
  void set_reading(const std::string& errata_id, ReadingSide side);
  const FaultSet& faults() const { return faults_; }
  // ERRATA E-67: the longest pause between two bytes of one frame that the
  // receiver waits out (kInterCharacterTimeout on the other side); nullopt:
  // none, the reference side. The bus asks it at every byte it feeds.
  std::optional<Duration> inter_character_timeout() const;
  TimePoint now() const { return clock_.now(); }

  // Replies as the codecs build them from the state (also used by tests).
  StatusBlock status_block() const;
  DisplayReply display() const;
  std::uint32_t counts(AxisId axis) const;
  bool limit(AxisId axis, int direction) const;
  // Where a STOW drives the elevation: its stow limit, else its lower limit (E-99).
  double stow_elevation() const;
  double stow_elevation_target() const;
  bool elevation_at_stow() const;

  // The model's invariants (positions within limits, STORE <= 50, ...): empty
  // when they hold, else what is broken.
  std::string check_invariants() const;

  static constexpr std::size_t kMaxStored = 50;  // §3.6: the STORE list's capacity

 private:
  friend struct Handlers;
  static constexpr std::size_t kExtendedStatus52DataBytes = 47;  // fault extended-status-52

  const AxisProfile& axis_profile(AxisId a) const;
  AxisState& axis(AxisId a);
  const AxisState& axis(AxisId a) const;
  enums::EnumReading enum_reading() const;
  // A position in display units (per_degree 10 or 100), as ERRATA E-76's side taken reads it.
  long in_units(double deg, int per_degree) const;
  // Whether this controller takes the other side of an open point of the
  // spec (readings.hpp; the profile's `readings:` pins, sabus sim --reading).
  bool reads_other(std::string_view errata_id) const;
  // Whether it takes that point's third side (ERRATA's other-2).
  bool reads_other_2(std::string_view errata_id) const;
  // §3.17: enter `mode` in `state`; the old mode becomes the last exited mode
  // with `exit_of_old` (default: its normal exit) as its exit status.
  void enter_mode(enums::Mode mode, std::string_view state, std::string_view exit_of_old = {});
  void set_state(std::string_view state);
  bool in_mode(enums::Mode mode) const;
  // The §3.17 locate_exit_conditions entry of a LOCATE left before it
  // completes, by a stop (`stop_key`) or by another mode (ERRATA E-82).
  std::string locate_exit(bool stop_key) const;
  // The exit of a LOCATE, STOW, DEPLOY or search left while it moves (E-82, E-89, E-90):
  // stopped (a stop or the Stop key) or taken over by another mode; "" in
  // any other mode or state.
  std::string moving_exit(bool stopped) const;

  bool stow_limit(AxisId a) const;
  bool moving() const;
  // Stops an axis: at once, or down its deceleration ramp (accel_dps2).
  void stop_axis(AxisId a);
  void stop_all();
  void start_jog(AxisId a, int direction, bool fast, Duration duration);
  void start_move(AxisId a, double target, bool remote);
  void step_axis(AxisId a, TimePoint from, TimePoint to);
  void step_ramped(AxisId a, TimePoint from, TimePoint to);
  void on_motion_done();
  // Motion from the last update to `to`, and what ends with it. A mode that
  // chains movements (search, DEPLOY) chains only at its ticks (`at_tick`):
  // a movement that ends between two waits for the next, so the chain does
  // not depend on how often the clock is read.
  void advance(TimePoint to, bool at_tick = true);
  bool chains_movements() const;
  // §3.7 'A' (ERRATA E-90): a square spiral about the current position, leg
  // by leg; when its time is over, back to where it began.
  void start_search(char pattern);
  // §3.7 'S': the STOW (E-89, E-99).
  void start_stow();
  // When the search gives up with no peak found (E-90: the side taken
  // decides, also of a search already running).
  TimePoint search_end() const;
  void next_search_leg();
  bool track_moves() const;
  void next_track_leg();
  // §3.7 'D' (ERRATA E-90): the elevation, then the azimuth when the profile
  // states a deploy position for it.
  void start_deploy();

  std::int32_t tenths(AxisId a) const;
  // §3.2 bytes 14-31 / §3.24 bytes 4-9: the tenths shown (a heading for a
  // fluxgate azimuth), nullopt for '*': an A/D error or no rotating feed.
  std::optional<std::int32_t> reading(AxisId a) const;
  // §3.17 bytes 49-50; nullopt: a blank (E-30's other side, no 0.01 deg feedback).
  std::optional<std::int32_t> hundredths_digit(AxisId a) const;
  double position_of_counts(std::uint32_t count) const;
  std::uint8_t axis_status_bits(AxisId a) const;
  bool pol_moves_allowed() const;
  std::uint8_t track_byte() const;

  Outcome dispatch(const Frame& command, const Request& request);
  Bytes finish_reply(Frame reply) const;

  Profile profile_;
  const Clock& clock_;
  FaultSet faults_;
  ControllerState state_;
  TimePoint last_update_;
  std::uint32_t modes_entered_ = 0;
  // The tick grid of a mode that chains movements: its start, and whether a
  // movement ended since the last tick (the next leg begins at the next one).
  TimePoint tick_origin_{};
  bool chain_pending_ = false;
  // Fault never-shows-rest: the azimuth has made an auto move, and its
  // status shows one in progress from then on.
  bool az_auto_moved_ = false;
  // §3.7 'A' (ERRATA E-90): the spiral search in progress.
  struct Search {
    char pattern = 'E';        // 'E' expanding, 'F' flat
    int legs = 0;              // legs begun
    TimePoint began{};         // how long it lasts is E-90's (search_end())
    bool returning = false;    // moving back to where it began (az_from, el_from)
    AxisState az_from, el_from;  // as they were when it began: the nominal position it returns to
    ModeState mode;              // as it began (SPIRAL_REMOTE_MODE)
  } search_;
  // ERRATA E-100's other side: TRACK's peaking or search pattern about
  // where it began, and how many of its legs have begun.
  struct TrackPattern {
    double az_center = 0, el_center = 0;
    int legs = 0;
  } track_pattern_;
  // §3.18: the movements of the LOCATE in progress, from where and when
  // they began (E-94 decides their order; set_reading redoes them).
  struct LocatePlan {
    TimePoint began{};
    AxisState az_from, el_from;  // as they were when it began
    double az_to = 0, el_to = 0;
    ModeState mode;              // as it began (LOCATE_MODE)
  } locate_;
  // Begins the LOCATE's movements to `locate_` as the side of E-94 taken
  // orders them (ERRATA E-94, §3.17 locate_states).
  void start_locate_movements();
  // §3.5 on a dual-port feed: the move to a satellite's one polarization
  // position, from where and when it began (E-63 decides which position;
  // set_reading redoes it).
  struct DualPortMove {
    TimePoint began{};
    AxisState pol_from;
    StoredSatellite sat;
  } dual_port_move_;
  // Starts that move (32h form 1, 34h).
  void start_dual_port_move(const StoredSatellite& sat);
  // §3.4 / §3.24 / §3.25: the last remote jog or jog key, from where and
  // when it began, while nothing else has moved or stopped its axis (E-61
  // decides a jog's duration, E-56 how long a key is held; set_reading
  // redoes it).
  struct RemoteJog {
    bool valid = false;
    AxisId axis = AxisId::kAz;
    TimePoint began{};
    AxisState from;
    std::uint32_t ms = 0;  // the duration a jog asked for
    bool key = false;      // a jog key (36h 'K', 48h): held for E-56's time
  } remote_jog_;
  // Starts a remote jog (`ms` asked for) or jog key (`key`) and records it.
  void start_remote_jog(AxisId a, int direction, bool fast, Duration duration, std::uint32_t ms, bool key);
  // Redoes that jog from where and when it began, for `duration`.
  void redo_remote_jog(Duration duration);
  int signal_strength_ = 0;  // §3.9, when a profile implements 38h
  std::array<std::optional<std::string>, 10> iess_;  // §3.14, when a profile implements 3Dh/3Eh
};

// Controllers on one line: each with its own receiver (§1: "A remote station
// only sends a response following a command containing its unique address").
// Bytes in, bytes out, with parity in bit 7 unless `parity` is kNone.
class Bus : public LineDevice {
 public:
  Bus(std::vector<Profile> profiles, const Clock& clock, FaultSet faults = {}, Parity parity = Parity::kEvenBit7);
  // A copy of every controller and receiver as they are (on the same clock):
  // cheaper than building a bus from its profiles again.
  Bus(const Bus& other);
  Bus& operator=(const Bus&) = delete;
  ~Bus() override;
  void receive(ByteView wire, Bytes& out) override;
  void tick() override;
  std::string take_log() override;
  // Whether receive() writes the transcript that take_log() returns (on by
  // default). Besides each frame and each ignored run, the transcript has one
  // hint line, once, when most bytes of a stretch of the line fail the
  // parity check (a master that is not set to 7E1). Off, a frame costs no text formatting (describe_frame): for
  // callers that never read the log, such as the whole-controller fuzz target.
  void set_transcript(bool on) { transcript_ = on; }
  // The names of the NAK rules applied since the last call, oldest first.
  std::vector<std::string> take_nak_rules();

  std::size_t size() const { return units_.size(); }
  Controller& controller(std::size_t i);
  // Called after a command changed stored data (for --state-file).
  void on_stored_data_change(std::function<void(const Controller&)> f) { on_change_ = std::move(f); }

 private:
  struct Unit;
  void trim_log();
  void watch_parity(ByteView wire);
  void time_out_frame(Unit& u, ByteView wire);
  // Appends a reply's bytes as the line carries them (even parity in bit 7
  // unless the line has none).
  void append_to_line(Bytes& out, ByteView reply) const;
  std::vector<std::unique_ptr<Unit>> units_;
  Parity parity_;
  bool transcript_ = true;
  // The line's bytes counted for the parity hint of the transcript.
  std::size_t window_bytes_ = 0, window_bad_ = 0;
  bool parity_hint_given_ = false;
  std::string log_;
  std::vector<NakRule> nak_rules_;  // names made only when taken
  std::function<void(const Controller&)> on_change_;
};

// The receiver options of a controller with this profile and these faults.
ReceiverOptions receiver_options(const Profile& profile, const FaultSet& faults, Parity parity);

}  // namespace sabus::harness
