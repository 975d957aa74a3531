// The live fuzzer's lockstep oracle (issue 24): a reference controller kept in
// step with the device, every reply compared with the model's by the class of
// each field (field_classes.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/transports.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/field_classes.hpp"
#include "sabus/protocol/messages.hpp"

namespace sabus::harness::live_fuzz {

struct ReplyField {
  std::string name, raw;
};

namespace {

// A binary reply byte as describe_frame shows it ("0x5c").
unsigned long hex_byte(const std::string& raw) { return std::strtoul(raw.c_str(), nullptr, 16); }

struct ReplySink : ReceiverSink {
  std::vector<Frame> frames;
  void on_frame(const FrameView& f) override { frames.push_back(f.to_frame()); }
  void on_discard(const Discard&) override {}
};

enum class ReplyForm : std::uint8_t { kAck, kNak, kOffline };
ReplyForm form_of_reply(const Frame& f) {
  return f.kind == FrameKind::kNak ? ReplyForm::kNak : is_offline_reply(f) ? ReplyForm::kOffline : ReplyForm::kAck;
}

// The axis (0 az, 1 el, 2 pol) a motion field of a reply is about; §3.24's
// `position` is the axis the reply echoes.
std::optional<std::size_t> axis_of(std::string_view field, const Frame& reply) {
  if (field == "azimuth" || field == "az limits" || field == "az status" || field == "azimuth count" ||
      field == "az hundredths")
    return 0;
  if (field == "elevation" || field == "el limits" || field == "el status" || field == "elevation count" ||
      field == "el hundredths")
    return 1;
  if (field == "polarization" || field == "pol limits" || field == "pol status") return 2;
  if (field == "position" && !reply.data.empty()) {
    if (reply.data[0] == 'A') return 0;
    if (reply.data[0] == 'E') return 1;
    if (reply.data[0] == 'P') return 2;
  }
  return std::nullopt;
}

bool is_position(std::string_view field) {
  return field == "azimuth" || field == "elevation" || field == "polarization" || field == "position";
}
// The same position in a finer unit: compared only at rest and in step.
bool is_fine_position(std::string_view field) {
  return field == "azimuth count" || field == "elevation count" || field == "az hundredths" || field == "el hundredths";
}

// A position field's value in degrees (a fluxgate azimuth: its heading), as
// the codecs decode the reply; nullopt for '*' or another reply.
std::optional<double> position_value(const Frame& reply, std::string_view field, bool* heading = nullptr) {
  const auto decoded = decode_reply(reply);
  if (!decoded) return std::nullopt;
  const StatusBlock* status = nullptr;
  if (const auto* s = std::get_if<StatusReply>(&decoded.value())) status = &s->status;
  if (const auto* s = std::get_if<ExtendedStatusReply>(&decoded.value())) status = &s->status;
  auto deg = [](const std::optional<std::int32_t>& t) -> std::optional<double> {
    if (!t) return std::nullopt;
    return *t / 10.0;
  };
  if (status) {
    if (field == "azimuth") {
      if (status->azimuth.kind == fields::AzimuthReading::Kind::kError) return std::nullopt;
      if (heading) *heading = status->azimuth.kind == fields::AzimuthReading::Kind::kHeading;
      return status->azimuth.tenths / 10.0;
    }
    if (field == "elevation") return deg(status->elevation);
    if (field == "polarization") return deg(status->polarization);
  }
  if (const auto* j = std::get_if<JogPositionReply>(&decoded.value()); j && field == "position") return deg(j->position);
  return std::nullopt;
}

// A difference of two readings; headings the short way round (a fluxgate's
// 359.9 and 0.0 are 0.1 apart).
double difference(double a, double b, bool heading) {
  double d = a - b;
  if (heading) d = std::remainder(d, 360.0);
  return d;
}

using Field = ReplyField;

// The value fields of a reply (framing fields and "no data" left out), as
// describe_frame reads them.
std::vector<Field> value_fields(const Frame& reply) {
  std::vector<Field> out;
  const CommandInfo* info = find_command(reply.command);
  if (!info) return out;
  for (const FieldDescription& fd : describe_frame(encode_frame(reply)).fields)
    if (field_class(info->reply, fd.name)) out.push_back({fd.name, fd.raw});
  return out;
}

// The raw text of the `occurrence`-th field called `name`, or nullptr.
const std::string* find_field(const std::vector<Field>& fields, std::string_view name, std::size_t occurrence) {
  for (const Field& f : fields)
    if (f.name == name && occurrence-- == 0) return &f.raw;
  return nullptr;
}

std::string fields_text(const std::vector<Field>& fields) {
  std::string s;
  for (const Field& f : fields) {
    s += (s.empty() ? "" : ", ") + f.name + "=" + f.raw;
  }
  return s;
}

std::string summary(const Frame& f) { return describe_frame(encode_frame(f)).summary; }

// A reply field as the coverage counts it: "0x31 azimuth".
std::string field_key(std::uint8_t command, std::string_view field) {
  return describe_byte(command).substr(0, 4) + " " + std::string(field);
}

AxisState::Motion motion_of(const Controller& c, std::size_t axis) {
  const ControllerState& s = c.state();
  return by_axis(s, axis).motion;
}

// The status block of a 31h or 40h reply (§3.2, §3.17), if it is one.
std::optional<StatusBlock> status_block(const Frame& reply) {
  const auto decoded = decode_reply(reply);
  if (!decoded) return std::nullopt;
  if (const auto* s = std::get_if<StatusReply>(&decoded.value())) return s->status;
  if (const auto* s = std::get_if<ExtendedStatusReply>(&decoded.value())) return s->status;
  return std::nullopt;
}

// The status byte of an axis (§3.2 bytes 36-38): its speed bit (0x10) and
// its motion or alarm code (the low nibble).
std::uint8_t axis_status(const StatusBlock& b, std::size_t axis) {
  return axis == 0 ? b.az_status : axis == 1 ? b.el_status : b.pol_status;
}

// Whether a status reply shows the axis moving (§3.2 bytes 36-38: jog
// pending, movement or auto move in progress); a reply without the byte:
// as if it does (no resync from it).
// §3.2 bytes 36-38 XXXX: a movement in progress (0100, 0101, 0111), not one
// pending (0010, 0011).
bool movement_in_progress(std::uint8_t status) {
  const std::uint8_t code = status & 0x0F;
  return code == 0x4 || code == 0x5 || code == 0x7;
}

bool device_moving(const Frame& reply, std::size_t axis) {
  const auto status = status_block(reply);
  if (!status) return true;
  const std::uint8_t code = axis_status(*status, axis) & 0x0F;
  return code == 0x2 || code == 0x3 || movement_in_progress(code);
}

// Whether a reply's status block shows any axis moving; nullopt for a reply
// without one.
std::optional<bool> shows_moving(const Frame& reply) {
  if (!status_block(reply)) return std::nullopt;
  return device_moving(reply, 0) || device_moving(reply, 1) || device_moving(reply, 2);
}

// An exit status's name in the list the profile reads (E-28: where
// LOCATE_FUNCTION_COMPLETED is 0x38 or, as printed, 0x37).
std::string exit_named(std::uint8_t mode, std::uint8_t exit_status, const enums::EnumReading& reading) {
  const enums::EnumList* list = enums::exit_list_for_mode(mode, reading);
  const auto name = list ? list->name_of(exit_status) : std::nullopt;
  return name ? std::string(*name) : meanings::exit_name(mode, exit_status);
}

// An exit status by which a stop ends a mode (§3.17 exit lists): the
// movement's STOP_KEY or MOVE_STOPPED entry, or MODE_CHANGED.
bool is_stop_exit(std::uint8_t mode, std::uint8_t exit_status, const enums::EnumReading& reading) {
  const std::string exit = exit_named(mode, exit_status, reading);
  return exit.ends_with("_STOP_KEY") || exit.ends_with("_MOVE_STOPPED") || exit.find("_MODE_CHANGE") != std::string::npos;
}

// A 40h reply's fields, if it is one.
std::optional<ExtendedStatusReply> extended_status(const Frame& reply) {
  const auto decoded = decode_reply(reply);
  if (!decoded) return std::nullopt;
  if (const auto* x = std::get_if<ExtendedStatusReply>(&decoded.value())) return *x;
  return std::nullopt;
}

// The 40h reply that ends a write, if it does: one earlier in a burst may be
// overtaken by a later frame's command (a LOCATE behind it), so the mode
// bytes the model takes and an episode's end come only from the last.
std::optional<ExtendedStatusReply> last_extended_status(const std::vector<Frame>& device) {
  return device.empty() ? std::nullopt : extended_status(device.back());
}

// The mode a reply shows the device in (§3.17 byte 45), if it is a 40h reply.
std::optional<std::uint8_t> device_mode(const Frame& reply) {
  if (const auto x = extended_status(reply)) return x->mode;
  return std::nullopt;
}

// The §3.17 mode bytes of a 40h reply, as the model keeps them.
ModeState mode_state(const ExtendedStatusReply& x) { return ModeState{x.mode, x.state, x.last_mode, x.exit_status}; }

// Whether a command may move the antenna in any of its forms (the catalog's
// effects).
bool moves_antenna(std::uint8_t code) {
  const CommandInfo* info = find_command(code);
  return info && info->effects().moves_antenna;
}

// Whether `position` is at a limit of the axis (a move or jog there ends on it).
bool at_a_limit(const AxisProfile& a, double position) {
  return std::abs(position - a.min_deg) < 1e-6 || std::abs(position - a.max_deg) < 1e-6;
}

// Whether `position` lies within `window` of a limit or the stow position
// of the axis.
bool near_a_limit(const AxisProfile& a, double position, double window) {
  return std::abs(position - a.min_deg) <= window || std::abs(position - a.max_deg) <= window ||
         (a.has_stow_limit && std::abs(position - a.stow_deg) <= window);
}

// A §3.17 mode byte of `m` as describe_frame shows it ("0x21").
std::string mode_byte(const ModeState& m, std::string_view field) {
  const std::uint8_t b = field == "current mode" ? m.mode : field == "current state" ? m.state
                         : field == "last exited mode" ? m.last_mode : m.exit_status;
  return fmt::format("0x{:02x}", b);
}

// The §3.17 mode bytes.
constexpr std::size_t kNoAxis = static_cast<std::size_t>(-1);

bool is_mode_byte(std::string_view field) {
  return field == "current mode" || field == "current state" || field == "last exited mode" || field == "exit status";
}

// The model's reading of an axis in degrees, as its status block gives it.
std::optional<double> reading_of(const Controller& c, std::size_t axis) {
  const StatusBlock b = c.status_block();
  if (axis == 0) {
    if (b.azimuth.kind == fields::AzimuthReading::Kind::kError) return std::nullopt;
    return b.azimuth.tenths / 10.0;
  }
  const auto& t = axis == 1 ? b.elevation : b.polarization;
  if (!t) return std::nullopt;
  return *t / 10.0;
}

// §3.17 bytes 49-50 (ERRATA E-86, E-87): whether a reading of `tenths_deg`
// extended by its hundredths `digit` lies within `window` of `target`: the
// digit extends the magnitude (tenths truncated toward zero; a reading of
// 0.0 either way) or is added to it (tenths rounded down).
bool hundredths_within(double tenths_deg, std::optional<std::int32_t> digit, double target, double window) {
  if (!digit) return false;  // a blank on a mount with 0.01 deg feedback
  const double d = *digit / 100.0;
  if (std::abs(tenths_deg + d - target) <= window + 1e-9) return true;    // added (or a positive magnitude extended)
  return tenths_deg <= 0 && std::abs(tenths_deg - d - target) <= window + 1e-9;  // a negative magnitude extended
}

}  // namespace

// §3.7 'S', 'D', 'A' (ERRATA E-89, E-90): how a STOW, a DEPLOY or a search
// moves the antenna, in what order and for how long, the spec leaves to the
// controller; the model's is one reading.
bool all_at_rest(const Controller& c) {
  for (std::size_t a = 0; a < 3; ++a)
    if (by_axis(c.state(), a).motion != AxisState::Motion::kIdle) return false;
  return true;
}

bool moves_by_itself(std::uint8_t mode) {
  const auto name = meanings::mode_name(mode);
  return name == "STOW_MODE" || name == "DEPLOY_MODE" || name == "SPIRAL_REMOTE_MODE";
}

std::size_t comparable_reply_fields() {
  std::set<std::string> names;
  for (const CommandInfo& info : catalog())
    for (const ReplyFieldClass& c : reply_field_classes())
      if (c.reply == info.reply && c.cls != FieldClass::kDevice)
        names.insert(field_key(info.code, c.field));
  return names.size();
}

// How far to each side of the model's position a device's axis may stand
// when their readings agree (inside the display's 0.1 deg).
constexpr double kNudgesDeg[] = {0.03, -0.03, 0.08, -0.08};

// How long the mode bytes are taken from the device after a move that ends
// within the drift window on a line (Lockstep::step).
constexpr Duration kSettle = std::chrono::seconds(2);

// What a run whose reply has another form than the device's (or is
// missing) counts as, against runs that differ only in fields.
constexpr std::size_t kOtherReplyForm = 1000;

// How long after one frame of a write the model executes the next on a line.
constexpr Duration kBetweenFrames = std::chrono::milliseconds(1);

// One run of the model over a write: its replies and the rule of each NAK.
struct Lockstep::Run {
  std::unique_ptr<Bus> copy;  // null: the model itself
  Bus* bus = nullptr;
  std::vector<Frame> replies;
  std::vector<std::optional<std::string>> rules;  // per reply: the NAK rule
  std::size_t differences = 0;                    // fields that differ from the device's
};

Lockstep::Lockstep(const Profile& profile, TimePoint start) : profile_(profile) { rebuild(start); }

void Lockstep::rebuild(TimePoint now) {
  clock_ = std::make_unique<VirtualClock>();
  clock_->set(now);
  bus_ = std::make_unique<Bus>(std::vector<Profile>{profile_}, *clock_, FaultSet{}, Parity::kEvenBit7);
  bus_->set_transcript(false);
  pristine_clock_.set(now);
  pristine_ = std::make_unique<Bus>(std::vector<Profile>{profile_}, pristine_clock_, FaultSet{}, Parity::kEvenBit7);
  pristine_->set_transcript(false);
  splitter_ = std::make_unique<Receiver>(receiver_options(profile_, FaultSet{}, Parity::kEvenBit7));
  last_ = now;
  drifted_ = {};
  moved_on_line_ = {};
  settle_until_ = {};
  half_turn_ = false;
  at_limit_agreed_ = {};
  uncertainty_since_rest_ = Duration{0};
  auto_moving_ = {};
  arrived_at_ = {};
  settle_mode_ = {};
  position_unknown_ = {};
  device_led_ = stopped_out_ = handed_over_ = moving_when_stopped_ = model_was_led_ = false;
  locate_completed_ = false;
  undecided_.reset();
}

Controller& Lockstep::model() { return bus_->controller(0); }
const Controller& Lockstep::model() const { return bus_->controller(0); }

bool Lockstep::kept_as_before(const FuzzFrame& frame, std::size_t reply, std::string_view field, std::size_t occurrence,
                              const std::string& model_value, const std::string& device_value) {
  Bus fresh(*pristine_);
  Bytes out;
  fresh.receive(with_software_parity(frame.chars, frame.wrong_parity), out);
  Receiver rx(ReceiverOptions::master());
  ReplySink sink;
  rx.feed(out, sink);
  rx.finish(sink);
  if (reply >= sink.frames.size()) return false;
  const std::vector<Field> fields = value_fields(sink.frames[reply]);  // find_field points into it
  const std::string* v = find_field(fields, field, occurrence);
  return v && *v != model_value && *v == device_value;
}

// A count's five digits as describe_frame shows them (in double quotes).
static std::optional<std::uint32_t> count_value(std::string_view raw) {
  if (raw.size() >= 2 && raw.front() == '"' && raw.back() == '"') raw = raw.substr(1, raw.size() - 2);
  if (raw.empty()) return std::nullopt;
  std::uint32_t count = 0;
  for (const char c : raw) {
    if (c < '0' || c > '9') return std::nullopt;
    count = count * 10 + static_cast<std::uint32_t>(c - '0');
  }
  return count;
}

// A count at either end of its five digits stands for no one position: held
// there past it, or wrapped (§3.16 gives no rule; ERRATA E-85).
static bool count_at_an_end(std::string_view raw) {
  const auto count = count_value(raw);
  return count && (*count == 0 || *count == 99999);
}

std::optional<double> Lockstep::count_degrees(std::string_view raw) const {
  const auto count = count_value(raw);
  if (!count || count_at_an_end(raw) || profile_.counts_per_degree <= 0) return std::nullopt;
  return (static_cast<double>(*count) - profile_.count_offset) / profile_.counts_per_degree;
}

double Lockstep::drift_window(const AxisProfile& axis, Duration uncertainty) {
  const double seconds = std::chrono::duration<double>(uncertainty).count();
  return 2 * axis.fast_dps * seconds + axis.tolerance_deg + 0.1;
}

struct FrameEnds : ReceiverSink {
  std::vector<std::uint64_t> ends;  // stream offsets one past each frame
  void on_frame(const FrameView& f) override { ends.push_back(f.offset + f.bytes.size()); }
  void on_discard(const Discard&) override {}
};

std::vector<std::size_t> Lockstep::frame_cuts(const FuzzFrame& frame) {
  // The model's receiver: the sides of E-6 and E-8 it reads now decide
  // where a write's frames end.
  splitter_->reconfigure(receiver_options(model().profile(), FaultSet{}, Parity::kEvenBit7));
  const std::uint64_t base = splitter_->offset();
  FrameEnds ends;
  splitter_->feed(with_software_parity(frame.chars, frame.wrong_parity), ends);
  std::vector<std::size_t> cuts;
  for (std::uint64_t e : ends.ends)
    if (e > base && e - base < frame.chars.size()) cuts.push_back(static_cast<std::size_t>(e - base));
  return cuts;
}

Lockstep::Run Lockstep::run(const Bus& from, TimePoint at, const FuzzFrame& frame, bool in_place) {
  Run r;
  if (!in_place) {
    r.copy = std::make_unique<Bus>(from);
    r.bus = r.copy.get();
  } else {
    r.bus = bus_.get();
  }
  // One frame after the other: a controller executes a frame of a burst
  // after the one before it (§1 State 5), not at the same instant (a jog of
  // duration 0 has ended by the next frame).
  const Bytes wire = with_software_parity(frame.chars, frame.wrong_parity);
  Bytes out;
  std::size_t from_byte = 0;
  TimePoint t = at;
  for (std::size_t k = 0; k <= cuts_.size(); ++k) {
    const std::size_t to_byte = k < cuts_.size() ? cuts_[k] : wire.size();
    clock_->set(t);
    r.bus->tick();
    r.bus->receive(ByteView(wire).subspan(from_byte, to_byte - from_byte), out);
    from_byte = to_byte;
    t += spacing_;
  }
  Receiver rx(ReceiverOptions::master());
  ReplySink sink;
  rx.feed(out, sink);
  rx.finish(sink);
  r.replies = std::move(sink.frames);
  std::vector<std::string> rules = r.bus->take_nak_rules();
  std::size_t next = 0;
  for (const Frame& f : r.replies)
    r.rules.push_back(f.kind == FrameKind::kNak && next < rules.size() ? std::optional<std::string>(rules[next++])
                                                                         : std::nullopt);
  return r;
}

void Lockstep::take_positions(const std::vector<Frame>& device, const std::function<bool(std::size_t, double)>& take) {
  Controller& m = model();
  for (const Frame& dev : device) {
    if (form_of_reply(dev) != ReplyForm::kAck) continue;
    for (const Field& f : value_fields(dev)) {
      // An axis whose reading is '*' (an A/D error, §3.2 bytes 14-31,
      // E-42) shows where it is only in its pulse count (§3.16).
      const auto axis_of_count = f.name.ends_with(" count") ? axis_of(f.name, dev) : std::nullopt;
      if (axis_of_count && position_unknown_[*axis_of_count] &&
          motion_of(m, *axis_of_count) == AxisState::Motion::kIdle) {
        if (const auto dc = count_degrees(f.raw)) {
          by_axis(m.mutable_state(), *axis_of_count).position = *dc;
          position_unknown_[*axis_of_count] = false;
          drifted_[*axis_of_count] = true;
          ++coverage_.resyncs;
        }
        continue;
      }
      // ... or, at rest, in its limit bits (§3.2 bytes 32-34: 4 the upper
      // limit, 2 the lower) where it stands at one.
      const auto axis_of_limits = f.name.ends_with(" limits") ? axis_of(f.name, dev) : std::nullopt;
      if (axis_of_limits && position_unknown_[*axis_of_limits] && !device_moving(dev, *axis_of_limits) &&
          motion_of(m, *axis_of_limits) == AxisState::Motion::kIdle) {
        const unsigned long bits = hex_byte(f.raw) & 0x06;
        if (bits == 4 || bits == 2) {
          const AxisProfile& ap = axis_profile(*axis_of_limits);
          by_axis(m.mutable_state(), *axis_of_limits).position = bits == 4 ? ap.max_deg : ap.min_deg;
          position_unknown_[*axis_of_limits] = false;
          drifted_[*axis_of_limits] = true;
          ++coverage_.resyncs;
        }
        continue;
      }
      if (!is_position(f.name)) continue;
      const auto axis = axis_of(f.name, dev);
      if (!axis || motion_of(m, *axis) != AxisState::Motion::kIdle) continue;
      if (device_moving(dev, *axis)) continue;  // not at rest: nothing to take over
      bool heading = false;
      const auto dv = position_value(dev, f.name, &heading);
      if (!dv) continue;
      // The model's reading of the axis now (§3.2 bytes 14-31).
      const auto reading = reading_of(m, *axis);
      if (!reading) continue;
      const double distance = difference(*dv, *reading, heading);
      const long delta = std::lround(distance * 10);
      if (!take(*axis, distance) || delta == 0) continue;
      AxisState& s = by_axis(m.mutable_state(), *axis);
      s.position += delta / 10.0;
      drifted_[*axis] = true;
      ++coverage_.resyncs;
    }
  }
}

std::string Lockstep::adopt(const FuzzFrame& frame, TimePoint sent_at, const std::vector<Frame>& device) {
  const TimePoint at = std::max(sent_at, last_);
  cuts_ = frame_cuts(frame);
  spacing_ = Duration{0};
  run(*bus_, at, frame, true);
  last_ = at;
  clock_->set(last_);
  std::string taken;
  auto note = [&](std::string s) { taken += (taken.empty() ? "" : "; ") + s; };
  static constexpr const char* kAxes[] = {"azimuth", "elevation", "polarization"};
  take_positions(device, [&](std::size_t axis, double distance) {
    if (std::lround(distance * 10) != 0) note(std::string(kAxes[axis]) + " moved by " + fmt::format("{:.1f}", distance));
    return true;
  });
  for (const Frame& dev : device)
    if (const auto x = extended_status(dev)) {
      const ModeState mode = mode_state(*x);
      if (mode == model().state().mode) continue;
      note(fmt::format("mode {} (state 0x{:02x}, last exited {}, exit 0x{:02x})", meanings::mode_name(x->mode), x->state,
                       meanings::mode_name(x->last_mode), x->exit_status));
      model().mutable_state().mode = mode;
      ++coverage_.resyncs;
    }
  return taken;
}

// What one write's judgement carries from rule to rule.
struct Lockstep::Judging {
  const FuzzFrame& frame;
  TimePoint at;
  Duration uncertainty;
  ModeState mode_before;   // the model's before this write ran
  bool inexact = false;    // on a line, or an axis taken over from the device
  bool stopped_out = false;
  std::vector<Run>& runs;  // the nominal run first
  const std::vector<Frame>& device;
  bool take_modes = false;  // the device's mode bytes, after such a move
  std::optional<Verdict> finding;
  // The limit (a position) of each axis the device said it is at: it refused
  // a jog into it as the run that agrees with it did (§3.4), or its status
  // asserts it (§3.2 bytes 32-34).
  std::array<std::optional<double>, 3> limit_refused{};
  void report(FindingKind kind, std::string message) {
    if (!finding) finding = Verdict{kind, std::move(message)};
  }
};

// One ACK of the device and the runs that ACK it too, field by field.
struct Lockstep::AckJudging {
  const Frame& dev;
  std::size_t index;                // of the reply in the write's replies
  const CommandInfo& info;
  std::vector<Run*> same;           // the runs whose reply has the device's form
  std::vector<Field> dev_fields;
  std::vector<std::vector<Field>> model_fields;  // per run of `same`
  // Whether the device's position on each axis is one a model gives exactly.
  std::array<bool, 3> position_exact{true, true, true};
  const ControllerState& nominal() const { return same.front()->bus->controller(0).state(); }
};

struct Lockstep::Memory {
  std::unique_ptr<Bus> bus;
  TimePoint last;
  std::array<bool, 3> drifted, moved_on_line, at_limit_agreed, auto_moving;
  Duration uncertainty_since_rest;
  std::array<std::optional<double>, 3> arrived_at;
  std::array<double, 3> arrived_position;
  TimePoint settle_until;
  ModeState settle_mode;
  bool device_led, stopped_out, handed_over, model_was_led, moving_when_stopped, half_turn;
  LockstepCoverage coverage;
  std::array<bool, 3> position_unknown;
  TimePoint stopped_at;
  bool locate_completed;
};

Lockstep::Memory Lockstep::remember() const {
  return Memory{std::make_unique<Bus>(*bus_), last_, drifted_, moved_on_line_, at_limit_agreed_, auto_moving_,
                uncertainty_since_rest_, arrived_at_, arrived_position_, settle_until_, settle_mode_, device_led_,
                stopped_out_, handed_over_, model_was_led_, moving_when_stopped_, half_turn_,
                coverage_, position_unknown_, stopped_at_, locate_completed_};
}

void Lockstep::recall(const Memory& m) {
  bus_ = std::make_unique<Bus>(*m.bus);
  last_ = m.last;
  clock_->set(last_);
  drifted_ = m.drifted;
  moved_on_line_ = m.moved_on_line;
  at_limit_agreed_ = m.at_limit_agreed;
  auto_moving_ = m.auto_moving;
  uncertainty_since_rest_ = m.uncertainty_since_rest;
  arrived_at_ = m.arrived_at;
  arrived_position_ = m.arrived_position;
  settle_until_ = m.settle_until;
  settle_mode_ = m.settle_mode;
  device_led_ = m.device_led;
  stopped_out_ = m.stopped_out;
  handed_over_ = m.handed_over;
  model_was_led_ = m.model_was_led;
  moving_when_stopped_ = m.moving_when_stopped;
  half_turn_ = m.half_turn;
  coverage_ = m.coverage;
  position_unknown_ = m.position_unknown;
  stopped_at_ = m.stopped_at;
  locate_completed_ = m.locate_completed;
}

std::vector<std::string> Lockstep::open_readings() const {
  std::vector<std::string> ids;
  for (const ReadingPoint& p : reading_points())
    if (!side_pinned(profile_.readings, p.id)) ids.emplace_back(p.id);
  return ids;
}

std::vector<std::pair<std::string, ReadingSide>> Lockstep::unshown_flips(
    const ReadingPins& taken, const std::function<bool(const std::string&, ReadingSide)>& keep) const {
  std::vector<std::pair<std::string, ReadingSide>> flips;
  for (const std::string& id : open_readings()) {
    const ReadingSide side = sides_besides(id, side_taken(taken, id)).front();
    if (side_taken(taken, id) == side_taken(profile_.readings, id) && keep(id, side)) flips.emplace_back(id, side);
  }
  return flips;
}

void Lockstep::note_reading(std::vector<std::string> ids, const Verdict& explained) {
  std::string errata;
  for (const auto& id : ids) errata += (errata.empty() ? "" : "+") + id;
  const ReadingSide side = side_taken(model().profile().readings, ids.front());
  for (ReadingNote& n : notes_)
    if (n.errata == errata && n.side == side) {
      ++n.count;
      return;
    }
  notes_.push_back(ReadingNote{errata, side, 1, std::string(to_string(explained.kind)) + ": " + explained.message});
}

// A write whose replies the model does not give is judged again with the
// model on the other side of each open point of the spec (ERRATA class
// reading), one at a time, then of all of them at once: a side that
// explains the replies is the device's (a note), and the model keeps it.
std::optional<Verdict> Lockstep::step(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                                      const std::vector<Frame>& device) {
  const Receiver split_before = *splitter_;
  Memory before = remember();
  std::optional<Verdict> finding = judge_step(frame, sent_at, uncertainty, device, split_before, before);
  if (finding) {
    undecided_.reset();  // the session synchronizes the model after a finding
    return finding;
  }
  keep_undecided(std::move(before), split_before, frame, sent_at, uncertainty, device);
  return finding;
}

std::optional<Verdict> Lockstep::judge_step(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                                            const std::vector<Frame>& device, const Receiver& split_before,
                                            const Memory& before) {
  cuts_ = frame_cuts(frame);  // the model's receiver reads each write once a side
  const std::vector<std::string> open = open_readings();
  // The write cut again by the receiver of the sides the model takes now.
  auto recut = [&] {
    *splitter_ = split_before;
    cuts_ = frame_cuts(frame);
  };
  std::optional<Verdict> finding = judge_write(frame, sent_at, uncertainty, device);
  if (!finding) return finding;
  // The sides of a point besides the one the model takes.
  auto besides = [&](const std::string& id) {
    return sides_besides(id, side_taken(before.bus->controller(0).profile().readings, id));
  };
  auto try_sides = [&](const std::vector<std::pair<std::string, ReadingSide>>& flips) {
    recall(before);
    for (const auto& [id, side] : flips) model().set_reading(id, side);
    recut();
    return !judge_write(frame, sent_at, uncertainty, device);
  };
  // E-90 decides only when a search ends: its other side (over within a
  // second) can explain a device whose search has ended where the model's
  // runs (at rest, or out of the search mode), not one that goes on moving
  // (a stop it ignored), which the episode rules would otherwise leave to it.
  // E-94 decides only the order and pace of a LOCATE's movements, which the
  // device leads while it is open (device_leads): its other side would
  // redo the LOCATE and so excuse where it ends.
  auto plausible = [&](const std::string& id, ReadingSide side) {
    if (id == "E-94") return false;
    if (id != "E-90") return true;
    auto search = [](std::uint8_t mode) { return meanings::mode_name(mode) == "SPIRAL_REMOTE_MODE"; };
    bool ended = false, going_on = false;
    for (const Frame& dev : device) {
      if (shows_moving(dev) == false) ended = true;
      if (shows_moving(dev) == true) going_on = true;
      if (const auto mode = device_mode(dev)) (search(*mode) ? going_on : ended) = true;
    }
    return side == ReadingSide::kOther ? ended && !going_on : going_on;
  };
  for (const auto& id : open)
    for (const ReadingSide side : besides(id))
      if (plausible(id, side) && try_sides({{id, side}})) {
        note_reading({id}, *finding);
        return std::nullopt;
      }
  // Together: the points whose side the device has not shown yet (a side
  // taken earlier stays), each to its first other side.
  const auto unshown = unshown_flips(before.bus->controller(0).profile().readings, plausible);
  if (unshown.size() > 1 && try_sides(unshown)) {
    std::vector<std::string> unshown_ids;
    for (const auto& flip : unshown) unshown_ids.push_back(flip.first);
    note_reading(unshown_ids, *finding);
    return std::nullopt;
  }
  // §3.4: a jog NAKed on an axis whose position the model has lost (an A/D
  // error, out of a device-led episode) may be a jog into the limit the
  // device's axis stands at. Where the model with the axis at that limit
  // gives the device's replies, the axis is known from then on (as a limit
  // shown in a status block gives it back, take_positions).
  if (const auto lost = jogs_on_lost_axes(split_before, frame, device); !lost.empty()) {
    recall(before);
    for (const auto& [axis, limit] : lost) {
      // At rest there: a jog into a limit finds the axis standing at it.
      AxisState& at = by_axis(model().mutable_state(), axis);
      at.position = limit;
      at.motion = AxisState::Motion::kIdle;
      at.velocity = 0;
      if (!device_led_) position_unknown_[axis] = false;  // in an episode the end decides (keep_in_step)
      drifted_[axis] = true;
    }
    recut();
    if (!judge_write(frame, sent_at, uncertainty, device)) {
      ++coverage_.resyncs;
      return std::nullopt;
    }
  }
  if (undecided_ && undecided_explains(frame, sent_at, uncertainty, device, split_before, *finding))
    return std::nullopt;
  recall(before);
  recut();
  return judge_write(frame, sent_at, uncertainty, device);
}

struct Lockstep::Undecided {
  std::vector<std::string> errata;  // the points: "E-93", "E-52", "E-88", "E-82", "E-89"
  Memory before;                    // the model before the first write that decided one
  struct Write {
    Receiver split_before;
    FuzzFrame frame;
    TimePoint sent_at;
    Duration uncertainty;
    std::vector<Frame> device;
    ReadingPins sides;  // the sides the model judged it on (a note taken in it)
  };
  std::vector<Write> writes;  // that write and the ones judged since
};

Lockstep::~Lockstep() = default;

// At most this many writes are kept to judge again: a point the device has
// not shown by then is left to the model's side.
constexpr std::size_t kUndecidedWrites = 256;

void Lockstep::keep_undecided(Memory before, const Receiver& split_before, const FuzzFrame& frame, TimePoint sent_at,
                              Duration uncertainty, const std::vector<Frame>& device) {
  // A 40h the model agreed with has shown the mode bytes: decided (not in
  // an episode the device leads, where the model takes them from it).
  const bool mode_shown = last_extended_status(device) && !device_led_;
  if (mode_shown) {
    undecided_.reset();
    return;
  }
  // A point the profile leaves open (a side the model took earlier, with
  // others at once, may be the wrong one of three).
  auto open = [&](const char* id) { return !side_pinned(profile_.readings, id); };
  std::vector<std::string> decided;
  // ERRATA E-93: a LOCATE that completed in this write went to the mode of
  // the model's side; a device on the other side shows it only in a 40h
  // (and in the last exited mode after the next command that changes it).
  const ModeState& now = model().state().mode;
  if (open("E-93") && now != before.bus->controller(0).state().mode && left_completed_locate(now.last_mode, now.exit_status))
    decided.emplace_back("E-93");
  // ERRATA E-52: which commands take the controller to REMOTE_MODE; a
  // command the device took (an ACK, a poll aside) may have changed its mode
  // otherwise than the model's.
  const bool took_command = std::any_of(device.begin(), device.end(), [](const Frame& dev) {
    return form_of_reply(dev) == ReplyForm::kAck && !is_poll(dev.command);
  });
  if (open("E-52") && took_command) decided.emplace_back("E-52");
  // ERRATA E-88: the mode a Stop key sent remotely (48h, 36h 'K') leaves
  // REMOTE in.
  const bool took_key = std::any_of(device.begin(), device.end(), [](const Frame& dev) {
    return form_of_reply(dev) == ReplyForm::kAck && (dev.command == RemoteKeypress::kCode || dev.command == Misc::kCode);
  });
  if (open("E-88") && took_key) decided.emplace_back("E-88");
  // ERRATA E-82, E-89: the exit status of a LOCATE, STOW or DEPLOY left by
  // a stop or another mode's command in this write (the STOP_KEY or
  // MOVE_STOPPED entry, or MODE_CHANGED; and which movement's).
  const ModeState& was = before.bus->controller(0).state().mode;
  const std::string last = meanings::mode_name(now.last_mode);
  if (now != was && !left_completed_locate(now.last_mode, now.exit_status)) {
    if (open("E-82") && last == "LOCATE_MODE") decided.emplace_back("E-82");
    if (open("E-89") && (last == "STOW_MODE" || last == "DEPLOY_MODE")) decided.emplace_back("E-89");
  }

  Undecided::Write write{split_before, frame, sent_at, uncertainty, device, model().profile().readings};
  if (undecided_) {
    if (undecided_->writes.size() >= kUndecidedWrites) {
      undecided_.reset();
      return;
    }
    for (auto& id : decided)
      if (std::find(undecided_->errata.begin(), undecided_->errata.end(), id) == undecided_->errata.end())
        undecided_->errata.push_back(std::move(id));
    undecided_->writes.push_back(std::move(write));
    return;
  }
  if (decided.empty()) return;
  undecided_ = std::make_unique<Undecided>(Undecided{std::move(decided), std::move(before), {}});
  undecided_->writes.push_back(std::move(write));
}

bool Lockstep::undecided_explains(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                                  const std::vector<Frame>& device, const Receiver& split_before, const Verdict& finding) {
  // The points on other sides, from the model as it was before the first
  // write that decided one, through every write since: each point alone on
  // each of its other sides, then several together (a write that decides
  // two, a stop that leaves a LOCATE in another mode with another exit:
  // E-52 and E-82), fewest flipped first.
  const Undecided& u = *undecided_;
  const ReadingPins& taken = u.before.bus->controller(0).profile().readings;
  // Built from the last point to the first, so that, fewest first, the
  // points come in the order they were decided.
  std::vector<std::vector<std::pair<std::string, ReadingSide>>> choices{{}};
  for (auto it = u.errata.rbegin(); it != u.errata.rend(); ++it) {
    const std::string& id = *it;
    std::vector<std::vector<std::pair<std::string, ReadingSide>>> more;
    for (const auto& c : choices) {
      more.push_back(c);  // this point on the model's side
      for (const ReadingSide side : sides_besides(id, side_taken(taken, id))) {
        auto with = c;
        with.emplace_back(id, side);
        more.push_back(std::move(with));
      }
    }
    choices = std::move(more);
  }
  std::stable_sort(choices.begin(), choices.end(), [](const auto& x, const auto& y) { return x.size() < y.size(); });
  for (const auto& flips : choices) {
    if (flips.empty()) continue;
    recall(u.before);
    for (const auto& [id, side] : flips) model().set_reading(id, side);
    auto flipped = [&](std::string_view id) {
      return std::any_of(flips.begin(), flips.end(), [&](const auto& f) { return f.first == id; });
    };
    bool held = true;
    for (const Undecided::Write& w : u.writes) {
      // The other points on the sides the write was judged on (a note
      // taken in it flipped one before judging it, as step does).
      for (const ReadingPoint& p : reading_points())
        if (const ReadingSide want = side_taken(w.sides, p.id);
            !flipped(p.id) && side_taken(model().profile().readings, p.id) != want)
          model().set_reading(std::string(p.id), want);
      *splitter_ = w.split_before;
      cuts_ = frame_cuts(w.frame);
      if (judge_write(w.frame, w.sent_at, w.uncertainty, w.device)) {
        held = false;
        break;
      }
    }
    if (!held) continue;
    // This write on those sides, and with another open point flipped too
    // (its side shown in this write only).
    const Memory replayed = remember();
    std::vector<std::string> explained;
    for (const auto& f : flips) explained.push_back(f.first);
    // This write with `also` flipped too; what explained it is named.
    auto this_write = [&](const std::vector<std::pair<std::string, ReadingSide>>& also) {
      recall(replayed);
      for (const auto& [id, side] : also) model().set_reading(id, side);
      *splitter_ = split_before;
      cuts_ = frame_cuts(frame);
      if (judge_write(frame, sent_at, uncertainty, device)) return false;
      for (const auto& flip : also) explained.push_back(flip.first);
      return true;
    };
    bool holds = this_write({});
    const ReadingPins& replayed_sides = replayed.bus->controller(0).profile().readings;
    // E-90 and E-94 explain only what step's own rules let them (a search
    // that has ended; never where a LOCATE ends).
    auto may_flip = [&](const std::string& other) { return !flipped(other) && other != "E-90" && other != "E-94"; };
    for (const std::string& other : open_readings()) {
      if (holds) break;
      if (!may_flip(other)) continue;
      for (const ReadingSide s2 : sides_besides(other, side_taken(replayed_sides, other)))
        if ((holds = this_write({{other, s2}}))) break;
    }
    // Or with every open point the device has not shown a side of yet on
    // its first other side, as step tries them together (a 40h shows many).
    if (!holds) {
      const auto unshown = unshown_flips(replayed_sides, [&](const std::string& id, ReadingSide) { return may_flip(id); });
      holds = unshown.size() > 1 && this_write(unshown);
    }
    if (!holds) continue;
    undecided_.reset();  // `u` with it
    note_reading(explained, finding);
    return true;
  }
  return false;
}

std::vector<std::pair<std::size_t, double>> Lockstep::jogs_on_lost_axes(const Receiver& splitter, const FuzzFrame& frame,
                                                                         const std::vector<Frame>& device) const {
  std::vector<std::pair<std::size_t, double>> lost;
  const bool jog_naked = std::any_of(device.begin(), device.end(), [](const Frame& dev) {
    return dev.kind == FrameKind::kNak && (dev.command == Jog::kCode || dev.command == JogMinimal::kCode);
  });
  if (!jog_naked) return lost;
  Receiver rx = splitter;  // the write's frames as the model reads them
  ReplySink frames;
  rx.feed(with_software_parity(frame.chars, frame.wrong_parity), frames);
  for (const Frame& f : frames.frames) {
    const auto request = decode_request(f);
    if (!request) continue;
    const JogFields* jog = std::get_if<Jog>(&*request);
    if (!jog) jog = std::get_if<JogMinimal>(&*request);
    if (!jog || jog->direction == 'X') continue;
    // §3.4 directions: E/W azimuth, D/U elevation, O/L polarization; W, U
    // and L toward the upper limit.
    const char d = jog->direction;
    const std::size_t axis = d == 'E' || d == 'W' ? 0 : d == 'D' || d == 'U' ? 1 : 2;
    const AxisProfile& ap = axis_profile(axis);
    const double limit = d == 'W' || d == 'U' || d == 'L' ? ap.max_deg : ap.min_deg;
    // Lost: out of a device-led episode without a reading, or in one (the
    // device leads its motion) on an axis whose reading is '*' (E-42) or
    // that the model has within a display unit and the axis's tolerance of
    // the limit (a reading cut to its unit, E-76, says no more).
    const bool near_limit =
        device_led_ && std::abs(by_axis(model().state(), axis).position - limit) <= 0.1 + ap.tolerance_deg + 1e-9;
    if (!position_unknown_[axis] && !(device_led_ && !reading_of(model(), axis)) && !near_limit) continue;
    lost.emplace_back(axis, limit);
  }
  return lost;
}

std::optional<Verdict> Lockstep::judge_write(const FuzzFrame& frame, TimePoint sent_at, Duration uncertainty,
                                             const std::vector<Frame>& device) {
  if (uncertainty > Duration{0}) uncertainty = uncertainty_since_rest_ = std::max(uncertainty_since_rest_, uncertainty);
  const TimePoint at = std::max(sent_at, last_);
  // In-process the device executes a whole write at one instant, as the model.
  spacing_ = uncertainty > Duration{0} ? kBetweenFrames : Duration{0};
  const ModeState mode_before = model().state().mode;
  const std::uint32_t modes_entered_before = model().modes_entered();
  std::vector<Run> runs = runs_of(frame, at, uncertainty);
  last_ = at + spacing_ * static_cast<int>(cuts_.size());
  clock_->set(last_);

  // The model only roughly where the device is: on a line (timing), or an
  // axis taken over from the device's readings (to their tenths).
  Judging j{frame, at, uncertainty, mode_before, uncertainty > Duration{0} || drifted_[0] || drifted_[1] || drifted_[2],
            false, runs, device, false, std::nullopt, {}};
  const Controller& nominal = runs.front().bus->controller(0);
  note_settling(nominal, j);
  j.stopped_out = follow_device_led(nominal, mode_before, nominal.modes_entered() != modes_entered_before, device);

  // Answers vs silence: the framing oracle judges these first against the
  // reference receiver; here only what the model adds (a command it leaves
  // unanswered, none today).
  if (std::none_of(runs.begin(), runs.end(), [&](const Run& r) { return r.replies.size() == device.size(); })) {
    const Run& m = runs.front();
    if (device.size() > m.replies.size())
      j.report(FindingKind::kReplyToIgnored, std::to_string(device.size()) + " replies where the model gives " +
                                                 std::to_string(m.replies.size()) + "; the first: " + summary(device.front()));
    else
      j.report(FindingKind::kNoReply, "the model answers " + summary(m.replies[device.size()]) + "; the device is silent");
  }
  for (std::size_t i = 0; i < device.size() && !j.finding; ++i)
    if (!judge_reply(j, i)) break;

  if (uncertainty > Duration{0})
    for (std::size_t a = 0; a < 3; ++a)
      for (const Run& r : runs) moved_on_line_[a] = moved_on_line_[a] || motion_of(r.bus->controller(0), a) != AxisState::Motion::kIdle;

  // Keep the run the device agreed with most (the nominal one on a tie).
  std::size_t best = 0;
  for (std::size_t k = 1; k < runs.size(); ++k)
    if (runs[k].differences < runs[best].differences) best = k;
  if (runs[best].copy) bus_ = std::move(runs[best].copy);
  runs.clear();
  // The device's word on a limit holds until a status block (which judged
  // its limit bits, and whose own word note_limits_shown reads below) or a
  // command the device took that moves the antenna (§3.3, §3.4, §3.7,
  // §3.18): that may take its axis a hair off, even where the model's stays
  // at rest (a move to where it stands).
  for (const Frame& dev : device)
    if (form_of_reply(dev) == ReplyForm::kAck && (status_block(dev) || moves_antenna(dev.command))) at_limit_agreed_ = {};
  note_limits_shown(j, device);
  for (std::size_t a = 0; a < 3; ++a) {
    AxisState& ax = by_axis(model().mutable_state(), a);
    if (ax.motion != AxisState::Motion::kIdle) {
      at_limit_agreed_[a] = false;
    } else if (j.limit_refused[a] && std::abs(ax.position - *j.limit_refused[a]) <= drift_window(axis_profile(a), uncertainty)) {
      // The device has said where the axis is: at that limit. The model's
      // axis (a nudged run's, or taken to a tenth) stands exactly there.
      ax.position = *j.limit_refused[a];
      at_limit_agreed_[a] = true;
    }
  }
  note_arrivals();
  if (j.take_modes && !j.finding)
    if (const auto x = last_extended_status(device)) {
      model().mutable_state().mode = mode_state(*x);
      ++coverage_.resyncs;
    }
  if (!j.finding) keep_in_step(device, uncertainty);
  // Both at rest (the device's status says so): the positions are in step
  // again, and earlier timing no longer matters.
  const bool device_at_rest =
      std::any_of(device.begin(), device.end(), [](const Frame& dev) { return shows_moving(dev) == false; });
  if (all_at_rest(model()) && device_at_rest) uncertainty_since_rest_ = Duration{0};
  return std::move(j.finding);
}

std::vector<Lockstep::Run> Lockstep::runs_of(const FuzzFrame& frame, TimePoint at, Duration uncertainty) {
  // The later and the earlier model first (copies of the model as it is),
  // then the model itself at the nominal time: a controller only moves
  // forward in time (Controller::update).
  std::vector<Run> runs;
  if (uncertainty > Duration{0}) {
    runs.push_back(run(*bus_, at + uncertainty, frame));
    runs.push_back(run(*bus_, std::max(last_, at - uncertainty), frame));
    // An axis that has moved on a line stands where the device's stand
    // only to within what its readings resolve: a move to where the model
    // already is may move the device's a hair, either way (§3.2 shows
    // tenths). The model is also run with those axes a little to each side.
    // An axis the device has said is at a limit stands there in a write of
    // one frame, which is judged by that (its limit bits, a jog into it
    // NAKed: §3.2 bytes 32-34, §3.4); in a burst it is nudged too: a 0 ms
    // jog there (its frames run microseconds apart in a device, 1 ms apart
    // in the model) takes a device's axis a hair off where the model's
    // stays (random profiles over a pty gave JogIntoLimit findings).
  }
  // An axis taken over from the device's readings (to their tenths, after a
  // STOW, DEPLOY or search) that the model has at rest at a limit may stand a
  // hair short of it in the device, or the reverse (§3.2 bytes 32-34, §3.4):
  // nudged too, in-process as on a line, unless the device has said it is at
  // that limit.
  const bool one_frame = cuts_.empty();
  std::array<bool, 3> nudge_axis{};
  for (std::size_t a = 0; a < 3; ++a) {
    const AxisState& ax = by_axis(model().state(), a);
    nudge_axis[a] = (uncertainty > Duration{0} && moved_on_line_[a]) ||
                    (drifted_[a] && ax.motion == AxisState::Motion::kIdle && !at_limit_agreed_[a] &&
                     near_a_limit(axis_profile(a), ax.position, 0.1));
  }
  if (nudge_axis[0] || nudge_axis[1] || nudge_axis[2])
    for (const double nudge : kNudgesDeg) {
      Bus nudged(*bus_);
      // At the frame's time first: a jog that has run out by then (a 0 ms
      // one still pending after the write before) is at rest, and nudged.
      clock_->set(at);
      nudged.tick();
      ControllerState& st = nudged.controller(0).mutable_state();
      for (std::size_t a = 0; a < 3; ++a) {
        AxisState& ax = by_axis(st, a);
        if (nudge_axis[a] && ax.motion == AxisState::Motion::kIdle && !(one_frame && at_limit_agreed_[a])) ax.position += nudge;
      }
      runs.push_back(run(nudged, at, frame));
    }
  runs.insert(runs.begin(), run(*bus_, at, frame, true));
  return runs;
}

void Lockstep::note_settling(const Controller& nominal, const Judging& j) {
  // A move that ends within the drift window, the model inexact: where the
  // device's axis stands a hair from the model's, that move can end at once
  // in one and take a few milliseconds in the other, and the mode it ran in
  // (§3.17) end otherwise (finished, or stopped by the next command). For a
  // while after one the mode bytes are taken from the device, not judged.
  const ControllerState& st = nominal.state();
  if (j.inexact)
    for (std::size_t a = 0; a < 3; ++a) {
      const AxisState& ax = by_axis(st, a);
      if ((ax.motion == AxisState::Motion::kAutoMove || ax.motion == AxisState::Motion::kRemoteAutoMove) &&
          std::abs(ax.aim - ax.position) <= drift_window(axis_profile(a), j.uncertainty)) {
        settle_until_ = std::max(settle_until_, j.at + kSettle);
        settle_mode_ = st.mode;  // the mode while the move still runs
      }
    }
  // An azimuth target at the half turn (+-180 deg, as a LOCATE due south of
  // its site computes it): +180 and -180 are one bearing, and which one a
  // controller computes (and so which way it turns) is decided by less than
  // its readings show (§3.18 gives no rule). On a line the azimuth is not
  // compared while such a move runs, and the model takes the device's
  // azimuth once both are at rest.
  if (j.uncertainty > Duration{0} &&
      (st.az.motion == AxisState::Motion::kAutoMove || st.az.motion == AxisState::Motion::kRemoteAutoMove) &&
      std::abs(std::abs(st.az.target) - 180.0) <= drift_window(profile_.az, j.uncertainty))
    half_turn_ = true;
}

// ERRATA E-94: while the profile leaves it open, the order and pace of a
// LOCATE's movements are the device's as a STOW's are (§3.17 locate_states
// lists movements, not their order); it is judged by where it ends
// (locate_ended_alike) and how it exits (judge_locate_end, judge_stop_exit).
// A LOCATE held at rest (waiting for its site or data, E-59, or in a range
// error, E-81) is a held mode, not led.
bool Lockstep::locate_led() const { return !side_pinned(profile_.readings, "E-94"); }

enums::EnumReading Lockstep::profile_reading() const { return enums::EnumReading{profile_.restore_lost_locate_exit}; }

bool Lockstep::left_completed_locate(std::uint8_t last_mode, std::uint8_t exit_status) const {
  return meanings::mode_name(last_mode) == "LOCATE_MODE" &&
         exit_named(last_mode, exit_status, profile_reading()) == "LOCATE_FUNCTION_COMPLETED";
}

// ERRATA E-100: while TRACK peaks or searches the device moves the antenna
// on its own (the spec gives TRACK's submodes, not how far or how often a
// peaking or search operation moves it, nor when one submode follows
// another): its positions, motion bits, state and submode are the device's,
// as a STOW's are, unless the profile pins the reference side (TRACK holds
// the antenna still). Moves are still refused as the model's submode says
// (§3.4). A TRACK the model has idle (not peaking or searching) takes
// moves and stops, and is judged as any mode at rest.
bool Lockstep::track_led(const ModeState& ms) const {
  return side_pinned(profile_.readings, "E-100") != ReadingSide::kReference &&
         meanings::mode_name(ms.mode) == "TRACK_MODE" && model().track_peaks_or_searches();
}

bool Lockstep::device_leads_mode(std::uint8_t mode) const {
  return moves_by_itself(mode) || (locate_led() && meanings::mode_name(mode) == "LOCATE_MODE") ||
         track_led(ModeState{mode});
}

namespace {

// A LOCATE that runs: in LOCATE_MODE, neither waiting (for its site or data,
// E-59) nor in a range or parameter error (E-81), which hold it at rest.
bool locate_runs(const ModeState& ms) {
  if (meanings::mode_name(ms.mode) != "LOCATE_MODE") return false;
  const std::string state = meanings::state_name(ms.mode, ms.state);
  return state.find("WAITING") == std::string::npos && !state.ends_with("_ERROR");
}
}  // namespace

bool Lockstep::device_leads(const ModeState& ms) const {
  return moves_by_itself(ms.mode) || (locate_led() && locate_runs(ms)) || track_led(ms);
}

// A LOCATE the model and the device have both run to LOCATE_FUNCTION_COMPLETED
// and rest after (the device's 40h says so): its positions are the look
// angles the profile's site and the satellite give (§3.18), whatever the
// order of the movements: judged as any position at rest.
bool Lockstep::locate_ended_alike(const AckJudging& r) const {
  const ModeState& ms = r.nominal().mode;
  if (!locate_led() || handed_over_ || !left_completed_locate(ms.last_mode, ms.exit_status)) return false;
  for (std::size_t a = 0; a < 3; ++a)
    if (by_axis(r.nominal(), a).motion != AxisState::Motion::kIdle) return false;
  const auto x = extended_status(r.dev);
  return x && left_completed_locate(x->last_mode, x->exit_status) && !device_leads_mode(x->mode) &&
         shows_moving(r.dev) == false;
}

// How a LOCATE the device leads ends, whatever the order of its movements
// (E-94): not in an error state of LOCATE_MODE (§3.17 locate_states: a
// range or parameter error) where the model's LOCATE runs or has completed,
// nor left by an exit that is neither LOCATE_FUNCTION_COMPLETED nor a
// stop's (a stop or another command may end it, §3.17
// locate_exit_conditions). nullopt: it holds.
std::optional<std::string> Lockstep::judge_locate_end(const AckJudging& r, const ReplyField& f) const {
  if (!locate_led() || handed_over_ || stopped_out_ || (f.name != "current state" && f.name != "exit status"))
    return std::nullopt;
  const ControllerState& m = r.nominal();
  const bool model_running = locate_runs(m.mode);
  const bool model_completed = meanings::mode_name(m.mode.mode) != "LOCATE_MODE" &&
                               left_completed_locate(m.mode.last_mode, m.mode.exit_status);
  const auto x = extended_status(r.dev);
  if ((!model_running && !model_completed) || !x) return std::nullopt;
  std::string how;
  if (f.name == "current state" && meanings::mode_name(x->mode) == "LOCATE_MODE") {
    if (const std::string state = meanings::state_name(x->mode, x->state); state.ends_with("_ERROR")) how = state;
  } else if (f.name == "exit status" && meanings::mode_name(x->mode) != "LOCATE_MODE" &&
             meanings::mode_name(x->last_mode) == "LOCATE_MODE") {
    const std::string exit = exit_named(x->last_mode, x->exit_status, profile_reading());
    if (exit != "LOCATE_FUNCTION_COMPLETED" && !is_stop_exit(x->last_mode, x->exit_status, profile_reading())) how = exit;
  }
  if (how.empty()) return std::nullopt;
  return "field '" + f.name + "' (§3.17) is " + f.raw + " (" + how + "): the device's LOCATE ended so where the model's " +
         (model_running ? "runs" : "completed") +
         " (§3.18; the order of its movements is the device's, ERRATA E-94, not its end). Device: " + summary(r.dev) +
         " [" + fields_text(r.dev_fields) + "]; model: [" + fields_text(r.model_fields.front()) + "]";
}

// In a LOCATE the device leads (E-94) its states are its own, but not its
// mode: LOCATE_MODE while it runs, then MANUAL_MODE or REMOTE_MODE (E-52,
// E-93) or what the model's next command entered. Any other mode code (one
// naming a search, say) is judged.
bool Lockstep::mode_outside_locate(const AckJudging& r, const ReplyField& f) const {
  const ModeState& ms = r.nominal().mode;
  const auto x = extended_status(r.dev);
  if (f.name != "current mode" || !x || !locate_led() || moves_by_itself(ms.mode) || moves_by_itself(ms.last_mode))
    return false;
  const std::string mode = meanings::mode_name(x->mode);
  return x->mode != ms.mode && mode != "LOCATE_MODE" && mode != "MANUAL_MODE" && mode != "REMOTE_MODE";
}

// §3.2 byte 35: "The 'Y' field described above only contains meaningful
// data when TRACK mode is active" (ERRATA E-95, class text): outside TRACK
// its bit (0x08) is the device's, whatever the profile pins.
bool Lockstep::y_outside_track(const AckJudging& r, const ReplyField& f,
                               const std::vector<const std::string*>& values) const {
  if (f.name != "pol equipment" || r.nominal().track.active) return false;
  return std::any_of(values.begin(), values.end(),
                     [&](const std::string* v) { return v && ((hex_byte(*v) ^ hex_byte(f.raw)) & ~0x08ul) == 0; });
}

// §3.2 byte 40 while TRACK leads (E-100): the band BBB is the model's, the
// submode SSSS the device's, but one of the TRACK codes (0001-0110,
// 1000-1110), never 0000 "track mode not active".
bool Lockstep::track_submode_shown(const AckJudging& r, const ReplyField& f,
                                   const std::vector<const std::string*>& values) const {
  if (f.name != "track" || !track_led(r.nominal().mode)) return false;
  const unsigned long dev = hex_byte(f.raw);
  if (!fields::TrackByte::names_active_submode(static_cast<std::uint8_t>(dev))) return false;
  return std::any_of(values.begin(), values.end(), [&](const std::string* v) { return v && ((hex_byte(*v) ^ dev) & 0x70) == 0; });
}

// §3.17 bytes 49-50 on a mount without 0.01 deg feedback (ERRATA E-30):
// they follow no position ('0', or on the other side a blank or a stale
// digit).
namespace {
bool hundredths_without_feedback(const Profile& p, const ReplyField& f) {
  return !p.hundredths && f.name.ends_with(" hundredths");
}
}  // namespace

// Those bytes on the other side, which the model's blank shows it has
// taken: "something else", a blank or a stale digit of the device's, any
// digit. A letter or a control byte does not decode (the oracle's).
bool Lockstep::no_hundredths(const ReplyField& f, const std::vector<const std::string*>& values) const {
  if (!hundredths_without_feedback(profile_, f)) return false;
  const unsigned long dev = hex_byte(f.raw);
  return (dev == 0x20 || (dev >= 0x30 && dev <= 0x39)) &&
         std::any_of(values.begin(), values.end(), [](const std::string* v) { return v && hex_byte(*v) == 0x20; });
}

// An axis the device's own episode drove, at a speed the model does not
// know, ramps down after the stop (§3.2 bytes 36-38: movement in progress
// until it rests) for as long as its fast speed takes to stop at the
// profile's acceleration: moving until then is no finding.
bool Lockstep::ramping_down(std::size_t axis, std::uint8_t status, Duration uncertainty) const {
  const AxisProfile& ap = axis_profile(axis);
  if (!movement_in_progress(status) || !ap.accel_dps2 || *ap.accel_dps2 <= 0) return false;
  const auto ramp = std::chrono::duration<double>(ap.fast_dps / *ap.accel_dps2);
  constexpr Duration kMargin = std::chrono::milliseconds(100);  // the status's own exchange
  return clock_->now() - stopped_at_ <= std::chrono::duration_cast<Duration>(ramp) + uncertainty + kMargin;
}

// §3.2 byte 35 ZZZ names 'h' and 'v' beside 'H' and 'V' without saying when
// the lower case shows (ERRATA E-96): while E-96 is open, a device whose own
// status shows its feed moving may show the model's letter in either case.
bool Lockstep::lower_case_while_moving(const AckJudging& r, const ReplyField& f,
                                       const std::vector<const std::string*>& values) const {
  if (f.name != "pol equipment" || side_pinned(profile_.readings, "E-96")) return false;
  const auto st = status_block(r.dev);
  if (!st || !movement_in_progress(axis_status(*st, 2))) return false;
  const unsigned long dev = hex_byte(f.raw);
  // The letter codes are 000-011 ('H', 'h', 'V', 'v'): the case is bit 0;
  // 'Y' (0x08) is left to y_outside_track.
  const unsigned long mask = r.nominal().track.active ? ~0x01ul : ~0x09ul;
  return (dev & 0x07) <= 0x03 && std::any_of(values.begin(), values.end(), [&](const std::string* v) {
           return v && (hex_byte(*v) & 0x07) <= 0x03 && ((hex_byte(*v) ^ dev) & mask) == 0;
         });
}

bool Lockstep::follow_device_led(const Controller& nominal, const ModeState& before, bool modes_entered,
                                 const std::vector<Frame>& device) {
  // While the model or the device runs a STOW, a DEPLOY, a search or (E-94
  // open) a LOCATE's movements, the positions, motion bits and mode bytes
  // are the device's: not compared, and taken over once both are at rest
  // out of it (E-89, E-90, E-94). A stop still has to stop: after it the
  // model is at rest and compares again.
  const ModeState& ms = nominal.state().mode;
  if (device_leads(ms)) device_led_ = true;
  // A new STOW, DEPLOY, search or LOCATE takes the antenna: whatever ended
  // the one before (a hand-over, a stop) no longer holds.
  if (device_leads(ms) && !model_was_led_) handed_over_ = stopped_out_ = locate_completed_ = false;
  // One the model entered and left within this write (a burst that starts
  // and stops it): the device's too, the model in it as far as a stop goes.
  // It left it last: the mode bytes say so, or, stopped or taken over the
  // same way as the one before (a STOW taken over at once, E-89), that it
  // entered modes at all. One that completed as the one before did is the
  // model's (E-93 decides where it went).
  const bool through = before.mode != ms.last_mode && device_leads_mode(ms.last_mode) &&
                       (before.last_mode != ms.last_mode || before.exit_status != ms.exit_status ||
                        (modes_entered && is_stop_exit(ms.last_mode, ms.exit_status, profile_reading())));
  if (through) device_led_ = model_was_led_ = true;
  // The device in such a mode where the model is not: only where the model
  // has been in one (it left it a little earlier, or later); else the
  // device's mode byte is judged (a wrong mode code that names one made
  // every mode byte the device's for the rest of the episode).
  const bool model_has_been = model_was_led_ || device_leads_mode(ms.last_mode);
  // Not while the model's own LOCATE is held at rest (a range error, E-81):
  // a device that moves there is judged.
  const bool held = meanings::mode_name(ms.mode) == "LOCATE_MODE" && !locate_runs(ms);
  for (const Frame& dev : device)
    if (const auto mode = device_mode(dev); mode && device_leads_mode(*mode) && model_has_been && !held) device_led_ = true;
  // Where such a mode leaves the axes the model knows only to the tenths the
  // device's readings show: counts and hundredths are not compared after it.
  if (device_led_) drifted_ = {true, true, true};
  // Stopped out of one (a STOP_KEY, MOVE_STOPPED or MODE_CHANGED exit) and at
  // rest in the model: the device must be at rest too, so its motion bits are
  // compared again; its positions and mode bytes are still its own.
  // Left for a move of another command (§3.3, §3.18: MODE_CHANGED) rather
  // than stopped: no stop to judge; the new move is the device's too until
  // both are at rest.
  bool stopped_out = false;
  if (device_led_) {
    bool at_rest = true, driving = false;
    for (std::size_t a = 0; a < 3; ++a) {
      const AxisState::Motion m = motion_of(nominal, a);
      at_rest = at_rest && m == AxisState::Motion::kIdle;
      driving = driving || (m != AxisState::Motion::kIdle && m != AxisState::Motion::kStopping);
    }
    if (model_was_led_ && !device_leads(ms) && driving) handed_over_ = true;
    // The model's LOCATE has completed (E-94): what the device shows until
    // its own ends is not taken into the model (a MODE_CHANGED exit taken
    // would read as a stop), but judged at the end (judge_locate_end).
    if (!device_leads(ms) && left_completed_locate(ms.last_mode, ms.exit_status)) locate_completed_ = true;
    stopped_out = !handed_over_ && at_rest && !device_leads(ms) && device_leads_mode(ms.last_mode) &&
                  is_stop_exit(ms.last_mode, ms.exit_status, profile_reading());
  }
  model_was_led_ = device_leads(ms);
  // The write that stopped it: whether the device's last status before it
  // showed the device moving (then its exit must be a stop's too).
  if (stopped_out && !stopped_out_) {
    // Seen moving by a status in the write that stops it, just before the
    // stop: a STOW, DEPLOY or search may end by itself at any moment (E-89,
    // E-90), so a status of an earlier write says nothing of what the stop
    // found (the generator sends the two together).
    moving_when_stopped_ = device.size() > 1 && std::any_of(device.begin(), device.end() - 1, [](const Frame& dev) {
                             return shows_moving(dev) == true;
                           });
    stopped_at_ = clock_->now();
  }
  stopped_out_ = stopped_out;
  return stopped_out;
}

bool Lockstep::judge_reply(Judging& j, std::size_t i) {
  const Frame& dev = j.device[i];
  std::vector<Run*> with;
  for (Run& r : j.runs)
    if (i < r.replies.size()) with.push_back(&r);
  if (with.empty()) return false;
  const Run& nominal = *with.front();
  const ReplyForm dev_form = form_of_reply(dev);
  std::vector<Run*> same;
  for (Run* r : with)
    if (form_of_reply(r->replies[i]) == dev_form) same.push_back(r);
  // A run that answers otherwise (or not at all) agrees less than any that
  // answers alike, whatever their fields.
  for (Run& r : j.runs)
    if (std::find(same.begin(), same.end(), &r) == same.end()) r.differences += kOtherReplyForm;
  if (same.empty()) {
    const Frame& m = nominal.replies[i];
    const auto& rule = nominal.rules[i];
    std::string model = form_of_reply(m) == ReplyForm::kNak
                            ? "the model NAKs by rule " + (rule ? *rule : std::string("?")) +
                                  (rule ? " (§" + std::string(paragraph(*find_nak_rule(*rule))) + ": " +
                                              std::string(description(*find_nak_rule(*rule))) + ")"
                                        : std::string())
                            : "the model answers " + summary(m) + " [" + fields_text(value_fields(m)) + "]";
    const std::string dev_text = dev_form == ReplyForm::kNak       ? "device NAKed"
                                 : dev_form == ReplyForm::kOffline ? "device answered offline"
                                                                   : "device ACKed";
    j.report(dev_form == ReplyForm::kOffline || form_of_reply(m) == ReplyForm::kOffline ? FindingKind::kValue
                                                                                         : FindingKind::kNakRule,
             dev_text + " (" + summary(dev) + "); " + model);
    return false;
  }
  if (dev_form == ReplyForm::kNak) {
    const auto& rule = same.front()->rules[i];
    if (rule) coverage_.rules_fired.insert(*rule);
    // §3.4: the device refused a jog into a limit, as the model did, where a
    // run with the axis a hair off the limit takes it: only the limit
    // explains the NAK (a frame every run NAKs may be refused for another
    // reason too), so the device has the axis at that limit.
    if (rule && *rule == name(NakRule::kJogIntoLimit) && same.size() < with.size()) {
      const ControllerState& s = same.front()->bus->controller(0).state();
      for (std::size_t a = 0; a < 3; ++a) {
        const AxisState& ax = by_axis(s, a);
        const AxisProfile& ap = axis_profile(a);
        if (ax.motion != AxisState::Motion::kIdle) continue;
        if (ax.position <= ap.min_deg + 1e-6) j.limit_refused[a] = ap.min_deg;
        if (ax.position >= ap.max_deg - 1e-6) j.limit_refused[a] = ap.max_deg;
      }
    }
    return true;
  }
  if (dev_form == ReplyForm::kOffline) return true;
  // Both ACK: field by field.
  const CommandInfo* info = find_command(dev.command);
  if (!info) return true;
  AckJudging r{dev, i, *info, std::move(same), value_fields(dev), {}};
  for (Run* run : r.same) r.model_fields.push_back(value_fields(run->replies[i]));
  std::map<std::string, std::size_t> occurrences;
  for (const Field& f : r.dev_fields)
    if (!judge_field(j, r, f, occurrences[f.name]++)) return false;
  return true;
}

bool Lockstep::judge_field(Judging& j, AckJudging& r, const Field& f, std::size_t occurrence) {
  const ReplyFieldClass* cls = field_class(r.info.reply, f.name);
  if (!cls || cls->cls == FieldClass::kDevice) return true;  // the spec leaves it to the device
  coverage_.fields_compared.insert(field_key(r.dev.command, f.name));
  std::vector<const std::string*> values;
  for (std::size_t k = 0; k < r.same.size(); ++k) {
    const std::string* v = find_field(r.model_fields[k], f.name, occurrence);
    values.push_back(v);
    if (v && *v != f.raw) ++r.same[k]->differences;
  }
  auto report = [&](FindingKind kind, std::string message) {
    j.report(kind, std::move(message));
    j.finding->field = f.name;
    return false;
  };
  if (const auto judged = judge_arrival_hundredths(r, f)) {
    if (judged->empty()) return true;
    return report(FindingKind::kEffect, *judged);
  }
  if (std::any_of(values.begin(), values.end(), [&](const std::string* v) { return v && *v == f.raw; })) return true;
  if (y_outside_track(r, f, values) || lower_case_while_moving(r, f, values) || no_hundredths(f, values) ||
      track_submode_shown(r, f, values))
    return true;
  // The axis of a motion field; kNoAxis for any other (a plain index: GCC 12
  // reports an optional's value as maybe unset through this loop). Without
  // 0.01 deg feedback the hundredths bytes follow no position (E-30: '0', or
  // on the other side a blank or a stale digit): compared as they are,
  // wherever the axis is.
  const bool positional = !hundredths_without_feedback(profile_, f);
  const std::size_t axis =
      cls->cls == FieldClass::kMotion && positional ? axis_of(f.name, r.dev).value_or(kNoAxis) : kNoAxis;
  const bool has_axis = axis != kNoAxis;
  // A LOCATE that ended alike is judged where it ends: its azimuth and
  // elevation. It has no polarization target (§3.18 bytes 24-29 name none
  // the feed must reach), so the polarization stays the device's until the
  // episode's end takes it (keep_in_step), as an earlier STOW or search
  // left it (E-89: a STOW stopped before it moved the feed).
  const bool judged_at_locate_end = has_axis && axis != 2 && locate_ended_alike(r);
  if (device_led_ && (has_axis || is_mode_byte(f.name)) && !held_by_a_command(r, f) && !judged_at_locate_end &&
      !mode_outside_locate(r, f)) {
    // After the stop only whether it moves: its limits are where its own
    // positions put it.
    const bool motion_bits = has_axis && !is_position(f.name) && !is_fine_position(f.name) && !f.name.ends_with(" limits");
    if (!(motion_bits && j.stopped_out)) {
      if (const auto wrong_end = judge_locate_end(r, f)) return report(FindingKind::kEffect, *wrong_end);
      if (const auto wrong_exit = judge_stop_exit(j, r, f)) return report(FindingKind::kValue, *wrong_exit);
      // Taken over while it runs; once the model has stopped out or
      // completed its LOCATE, not (a device that goes on would hold the
      // model in the mode): the device's exit is taken when the episode
      // ends (keep_in_step).
      j.take_modes = j.take_modes || (is_mode_byte(f.name) && !j.stopped_out && !locate_completed_);
      return true;
    }
    // Whether it moves, which way and its alarms; the speed bit (0x10) is
    // that of the last leg the device ran (§3.2 bytes 36-38, E-89, E-90),
    // taken when the episode ends (keep_in_step).
    const auto dev_status = has_axis && f.name.ends_with(" status") ? status_block(r.dev) : std::nullopt;
    // A reply before the last of the write came before the stop (the
    // generator's "status and stop"); an axis at rest is what the stop asks,
    // whatever speed the model's ramp runs down from.
    if (dev_status && r.index + 1 < r.same.front()->replies.size()) return true;
    if (dev_status && (axis_status(*dev_status, axis) & 0x0F) == 0) return true;
    if (dev_status && ramping_down(axis, axis_status(*dev_status, axis), j.uncertainty)) return true;
    if (dev_status && std::any_of(r.same.begin(), r.same.end(), [&](const Run* run) {
          const auto model_status = status_block(run->replies[r.index]);
          return model_status && (axis_status(*model_status, axis) & 0x0F) == (axis_status(*dev_status, axis) & 0x0F);
        }))
      return true;
  }
  // An axis whose position the model lost (position_unknown_: out of a
  // device-led episode with no reading, E-42): whether it stands at a limit
  // and how long a move from there runs are the device's until it shows
  // where it is (take_positions: a count, or a limit it rests at).
  if (has_axis && position_unknown_[axis] && (f.name.ends_with(" limits") || f.name.ends_with(" status"))) return true;
  bool moving = false;
  if (has_axis)
    for (Run* run : r.same) moving |= motion_of(run->bus->controller(0), axis) != AxisState::Motion::kIdle;
  if (has_axis && is_position(f.name)) {
    r.position_exact[axis] = false;
    if (position_in_window(j, r, f, axis)) return true;
  }
  if (has_axis && axis == 0 && half_turn_) return true;
  // Within the settle time the device's mode bytes may be those the model
  // had while the move ran or before this write (it ends a little later
  // there) or now (earlier): one of these, not any.
  if (is_mode_byte(f.name) && j.inexact && j.at < settle_until_ &&
      (mode_byte(j.mode_before, f.name) == f.raw || mode_byte(settle_mode_, f.name) == f.raw)) {
    j.take_modes = true;
    return true;
  }
  if (has_axis && !is_position(f.name) && !is_fine_position(f.name) && !(device_led_ && j.stopped_out) &&
      motion_bits_unjudged(j, r, f, axis))
    return true;
  // Hundredths and counts resolve what a few milliseconds of timing move an
  // axis: compared only while the model is exact on that axis (in-process,
  // or on a line before the axis first moved). Inexact, a count is still a
  // position (§3.16: count_offset + deg x counts_per_degree), judged in the
  // axis's window as its reading is (one count more); a hundredths digit is
  // not (but after an arrival: judge_arrival_hundredths).
  if (has_axis && is_fine_position(f.name) && position_unknown_[axis]) return true;  // taken (keep_in_step)
  // A count past its five digits is the device's (ERRATA E-85): where the
  // device's or a run's count is at an end, not judged.
  if (has_axis && f.name.ends_with(" count") &&
      (count_at_an_end(f.raw) || std::any_of(values.begin(), values.end(), [](const std::string* v) { return v && count_at_an_end(*v); })))
    return true;
  if (has_axis && is_fine_position(f.name) &&
      (moving || drifted_[axis] || moved_on_line_[axis] || !r.position_exact[axis])) {
    const auto dc = f.name.ends_with(" count") ? count_degrees(f.raw) : std::nullopt;
    if (!dc) return true;
    const double w = drift_window(axis_profile(axis), j.uncertainty) + 1.0 / profile_.counts_per_degree;
    for (const std::string* v : values)
      if (const auto mc = v ? count_degrees(*v) : std::nullopt; mc && std::abs(*dc - *mc) <= w + 1e-9) return true;
  }
  // A difference: named, the model's reply beside the device's.
  const std::string model_value = values.front() ? *values.front() : std::string("(no such field)");
  // An effect: the device did not follow what a command did: a motion field
  // (a stop that does not stop, a move that ends elsewhere), or a field the
  // session's commands changed in the model (a controller fresh from the
  // profile reads otherwise) that the device still reads as that fresh
  // controller does (a write not read back, a mode not entered). A value:
  // any other difference (a wrong count, name, code or sign).
  const bool effect = cls->cls == FieldClass::kMotion || kept_as_before(j.frame, r.index, f.name, occurrence, model_value, f.raw);
  return report(effect ? FindingKind::kEffect : FindingKind::kValue,
                "field '" + f.name + "' (§" + std::string(cls->paragraph) + ", " + std::string(to_string(cls->cls)) + ": " +
                    std::string(cls->rests_on) + ") is " + f.raw + "; the model expects " + model_value +
                    (moving ? " (the axis moving: outside the motion window)" : "") + ". Device: " + summary(r.dev) +
                    " [" + fields_text(r.dev_fields) + "]; model: [" + fields_text(r.model_fields.front()) + "]");
}

std::optional<std::string> Lockstep::judge_arrival_hundredths(const AckJudging& r, const Field& f) const {
  // A hundredths digit on a line, after an auto move that arrived: the
  // reading it extends lies within the target's arrival window (E-86:
  // tolerance_deg less the display's 0.1, plus 0.01), the device at rest
  // too; judged before the runs' digits, whose tenths may differ from the
  // device's (a fluxgate heading is not judged here).
  const auto a = axis_of(f.name, r.dev);
  if (!a || !f.name.ends_with(" hundredths") || !(drifted_[*a] || moved_on_line_[*a])) return std::nullopt;
  const auto x = extended_status(r.dev);
  bool heading = false;
  const auto tenths = position_value(r.dev, *a == 0 ? "azimuth" : "elevation", &heading);
  // The axis still where it arrived (not moved since by a motion between
  // two writes, nor taken a tenth from the device's reading).
  const AxisState& ax = by_axis(r.nominal(), *a);
  if (!x || !tenths || heading || !profile_.hundredths || device_led_ || !arrived_at_[*a] ||
      ax.motion != AxisState::Motion::kIdle || std::abs(ax.position - arrived_position_[*a]) > 1e-6 || device_moving(r.dev, *a))
    return std::nullopt;
  const double target = *arrived_at_[*a];
  const double window = std::max(0.0, axis_profile(*a).tolerance_deg - 0.1) + 0.01;
  if (hundredths_within(*tenths, *a == 0 ? x->az_hundredths : x->el_hundredths, target, window)) return std::string();
  return fmt::format("field '{}' (§3.17 bytes 49-50, motion: the hundredths of the position) is {}: after an auto "
                     "move arrived at {:.2f} the reading {:.1f} extended by it lies outside the arrival window "
                     "{:.2f}-{:.2f} (ERRATA E-86, E-87). Device: {} [{}]; model: [{}]",
                     f.name, f.raw, target, *tenths, target - window, target + window, summary(r.dev),
                     fields_text(r.dev_fields), fields_text(r.model_fields.front()));
}

void Lockstep::note_limits_shown(Judging& j, const std::vector<Frame>& device) const {
  // §3.2 bytes 32-34: a device at rest whose status asserts a limit of an
  // axis says the axis is at that limit (a jog into it is then NAKed, §3.4),
  // as a refused jog does. Not within a STOW, DEPLOY or search episode,
  // whose positions are the device's.
  if (device_led_) return;
  for (const Frame& dev : device)
    if (const auto st = status_block(dev); st && form_of_reply(dev) == ReplyForm::kAck)
      for (std::size_t a = 0; a < 3; ++a) {
        const std::uint8_t bits = a == 0 ? st->az_limits : a == 1 ? st->el_limits : st->pol_limits;
        if (device_moving(dev, a) || (bits & 0x06) == 0 || (bits & 0x06) == 0x06) continue;
        j.limit_refused[a] = (bits & 0x04) ? axis_profile(a).max_deg : axis_profile(a).min_deg;
      }
}

bool Lockstep::held_by_a_command(const AckJudging& r, const ReplyField& f) const {
  // Within a STOW, DEPLOY or search episode the mode bytes are the device's,
  // but not a mode a command has entered and holds at rest (a LOCATE waiting
  // for its site, E-59; a remote move's mode): with the model's axes and the
  // device's at rest, the current mode and state are that command's. MANUAL
  // is not: a mode the device ran to its end leaves it there as a stop does.
  if (f.name != "current mode" && f.name != "current state") return false;
  const ControllerState& s = r.nominal();
  if (device_leads(s.mode) || meanings::mode_name(s.mode.mode) == "MANUAL_MODE") return false;
  for (std::size_t a = 0; a < 3; ++a)
    if (by_axis(s, a).motion != AxisState::Motion::kIdle || device_moving(r.dev, a)) return false;
  return true;
}

std::optional<std::string> Lockstep::judge_stop_exit(const Judging& j, const AckJudging& r, const Field& f) const {
  // How a STOW, DEPLOY or search ends is the device's, but not by what:
  // stopped while it moved, it exits by a stop, not as finished or without
  // a peak (E-90).
  if (f.name != "exit status" || !j.stopped_out || !moving_when_stopped_) return std::nullopt;
  const auto x = extended_status(r.dev);
  if (!x || x->last_mode != r.nominal().mode.last_mode || is_stop_exit(x->last_mode, x->exit_status, profile_reading()))
    return std::nullopt;
  return "field 'exit status' (§3.17, state: how the last mode ended) is " + f.raw + " (" +
         exit_named(x->last_mode, x->exit_status, profile_reading()) + ") after a stop that found the device moving in " +
         std::string(meanings::mode_name(x->last_mode)) +
         "; a stop ends it with a STOP_KEY, MOVE_STOPPED or MODE_CHANGED entry (§3.7, ERRATA E-90). Device: " +
         summary(r.dev) + " [" + fields_text(r.dev_fields) + "]; model: [" + fields_text(r.model_fields.front()) + "]";
}

bool Lockstep::position_in_window(const Judging& j, const AckJudging& r, const Field& f, std::size_t axis) const {
  // A window from the motion model: every run's reading, widened by the
  // drift the exchange's timing and the arrival tolerance allow.
  bool heading = false;
  const auto dv = position_value(r.dev, f.name, &heading);
  const auto nv = position_value(r.same.front()->replies[r.index], f.name);
  if (!dv || !nv) return false;
  double lo = 0, hi = 0;
  for (const Run* run : r.same)
    if (auto v = position_value(run->replies[r.index], f.name)) {
      const double d = difference(*v, *nv, heading);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  const double w = drift_window(axis_profile(axis), j.uncertainty);
  const double d = difference(*dv, *nv, heading);
  return d >= lo - w - 1e-9 && d <= hi + w + 1e-9;
}

bool Lockstep::motion_bits_unjudged(const Judging& j, const AckJudging& r, const Field& f, std::size_t axis) const {
  // Inexact, an axis whose readings agree may stand a little apart in the
  // model and the device (the display resolves 0.1 deg): a move that ends
  // within the drift window can start, end or turn differently in each. Its
  // status and limit bits are then not compared; a device that goes on
  // moving shows in its positions, beyond the window (§3.2). Not after a
  // stop out of a STOW, DEPLOY or search: there the motion bits are all that
  // is judged, and the earlier and later runs give the line's timing.
  const AxisProfile& ap = axis_profile(axis);
  const AxisState& ax = by_axis(r.nominal(), axis);
  // The model's state is the one after the whole write: of a reply before
  // the last of a burst it says nothing (a later frame of the burst may have
  // started, ended or turned the motion), so those bits are left on a line.
  if (j.inexact && r.index + 1 < r.same.front()->replies.size()) return true;
  // A motion that reaches a limit (or the stow position) in its direction
  // within the window ends there as an auto move at its aim does: a jog
  // into a limit a few milliseconds earlier in the device.
  const double window = drift_window(ap, j.uncertainty);
  const double to_limit = ax.direction > 0   ? ap.max_deg - ax.position
                          : ax.direction < 0 ? ax.position - ap.min_deg
                                             : window + 1;
  const bool to_stow = ap.has_stow_limit && ax.direction != 0 && (ap.stow_deg - ax.position) * ax.direction >= 0 &&
                       std::abs(ap.stow_deg - ax.position) <= window;
  const bool short_move = ax.motion == AxisState::Motion::kIdle || ax.motion == AxisState::Motion::kStopping ||
                          ((ax.motion == AxisState::Motion::kAutoMove || ax.motion == AxisState::Motion::kRemoteAutoMove) &&
                           std::abs(ax.aim - ax.position) <= window) ||
                          to_limit <= window || to_stow;
  const bool limit_bits = f.name.ends_with(" limits");
  const bool agreed_limit = limit_bits && at_limit_agreed_[axis] && ax.motion == AxisState::Motion::kIdle && at_a_limit(ap, ax.position);
  if (j.inexact && short_move && !agreed_limit) return true;
  // An axis a hair from a limit or the stow position in the model may be at
  // it in the device, or the reverse (§3.2 bytes 32-34): judged only where
  // the device agreed it is at the limit.
  return limit_bits && !agreed_limit && near_a_limit(ap, ax.position, window);
}

void Lockstep::keep_in_step(const std::vector<Frame>& device, Duration uncertainty) {
  // An axis at rest in the model whose reading the device gives within the
  // drift window takes the device's reading (a move arriving elsewhere
  // within its tolerance, a stop a few milliseconds apart: §3.2).
  Controller& m = model();
  // A 40h reply showing every axis at rest: the episode's end.
  const bool device_at_rest = last_extended_status(device) && shows_moving(device.back()) == false;
  take_positions(device, [&](std::size_t axis, double distance) {
    // Out of a STOW, DEPLOY, search or LOCATE, at rest; where a LOCATE the
    // model completed ends is judged by the 40h that shows its end
    // (locate_ended_alike), so it is taken only from that one.
    if (device_led_ && !device_leads(m.state().mode)) return !locate_completed_ || device_at_rest;
    if (device_led_) return false;
    if (axis == 0 && half_turn_) {
      half_turn_ = false;  // both at rest: the device's azimuth, whatever it is
      return true;
    }
    return std::abs(distance) <= drift_window(axis_profile(axis), uncertainty);
  });
  // Judged again once the model is out of such a mode and at rest, and the
  // device's extended status shows every axis at rest.
  if (!device_led_ || device_leads(m.state().mode)) return;
  // A 40h reply: its positions taken above and its mode bytes with them.
  if (!all_at_rest(m) || !device_at_rest) return;
  device_led_ = false;
  for (std::size_t a = 0; a < 3; ++a) position_unknown_[a] = !reading_of(m, a);
  stopped_out_ = handed_over_ = moving_when_stopped_ = locate_completed_ = false;
  if (const auto x = last_extended_status(device)) {  // how the device says it ended (judged above)
    m.mutable_state().mode = mode_state(*x);
    ++coverage_.resyncs;
    // The speed of each axis's last leg (§3.2 bytes 36-38, bit 0x10), or
    // on E-98's other side the speed it is configured for: what the bit
    // shows on the side the model takes.
    const bool configured = side_taken(m.profile().readings, "E-98") == ReadingSide::kOther;
    for (std::size_t a = 0; a < 3; ++a) {
      AxisState& ax = by_axis(m.mutable_state(), a);
      (configured ? ax.configured_fast : ax.fast) = (axis_status(x->status, a) & 0x10) != 0;
    }
  }
}

const AxisProfile& Lockstep::axis_profile(std::size_t axis) const {
  return by_axis(profile_, axis);
}

// Before the device's positions are taken over (they move the model's a
// tenth): an axis idle exactly at the aim of the §3.3 auto move it ran has
// arrived at that move's target. Not a LOCATE's: its target is the
// controller's own computation (§3.18), which the model reads one way.
void Lockstep::note_arrivals() {
  const ControllerState& s = model().state();
  for (std::size_t a = 0; a < 3; ++a) {
    const AxisState& ax = by_axis(s, a);
    if (ax.motion == AxisState::Motion::kRemoteAutoMove) {
      auto_moving_[a] = true;
      arrived_at_[a].reset();
    } else if (ax.motion == AxisState::Motion::kIdle) {
      // The move's target now: a later move within the deadband of where the
      // axis stood ended at once (ControllerState's aim) and set its own.
      if (auto_moving_[a] && std::abs(ax.position - ax.aim) < 1e-6) {
        arrived_at_[a] = ax.target;
        arrived_position_[a] = ax.position;
      }
      auto_moving_[a] = false;
    } else {
      auto_moving_[a] = false;
      arrived_at_[a].reset();
    }
  }
}

}  // namespace sabus::harness::live_fuzz
