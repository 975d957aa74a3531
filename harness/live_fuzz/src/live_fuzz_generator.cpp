// The live fuzzer's generator and its safety gate: frames from the catalog
// and the structured builder, damaged with the runner's modifiers.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/look_angles.hpp"
#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::harness::live_fuzz {
namespace {

constexpr bool is_start_byte(std::uint8_t b) { return b == STX || b == ACK || b == NAK; }

// The end of the write before and this one, as the line carries them.
Bytes joined(ByteView before, ByteView chars) {
  Bytes all(before.begin(), before.end());
  all.insert(all.end(), chars.begin(), chars.end());
  return all;
}

// Where frames start in `all`: a start byte, an address byte (§1: 31h-6Fh)
// and a command byte after it, as the vector lint reads frames.
std::vector<std::size_t> frame_starts(ByteView all) {
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i + 2 < all.size(); ++i)
    if (is_start_byte(all[i] & 0x7F) && is_valid_address(all[i + 1] & 0x7F)) starts.push_back(i);
  return starts;
}

// What a command frame can do on a bench (READING-NOTES 26): the form its
// selector byte chooses when the byte is there, or any form of the command.
Effects effects_at(ByteView bytes, std::size_t start, const CommandInfo& info) {
  if (info.form_selector_offset && start + *info.form_selector_offset < bytes.size())
    if (const FormInfo* f = info.form_for_selector(bytes[start + *info.form_selector_offset])) return f->effects;
  return info.effects();
}

bool allowed(const Effects& e, bool allow_motion, bool allow_destructive) {
  return (!e.moves_antenna || allow_motion) && (!e.changes_stored_data || allow_destructive);
}

Bytes with_byte(Bytes f, std::size_t at, std::uint8_t b) {
  f[at] = b;
  return f;
}

// `f` with the 4 digits at `at` set to `value`.
Bytes with_digits(Bytes f, std::size_t at, std::size_t value) {
  for (std::size_t k = 4; k-- > 0; value /= 10) f[at + k] = static_cast<std::uint8_t>('0' + value % 10);
  return f;
}

Bytes relrc(Bytes f) {
  if (f.size() >= 2) f.back() = lrc(ByteView(f).first(f.size() - 1));
  return f;
}

// Characters at the edges of the fields' ranges: digits, signs, blanks, the
// first and last printable characters, letters no field takes (§1 Data Format).
constexpr std::uint8_t kInteresting[] = {' ', '0', '1', '9', '-', '+', '.', '/', ':', '@', 'A', 'Z', 'a', 'z', 0x7F, '~'};

// A stored write and the read that shows it (§3.10/§3.11, §3.12/§3.13,
// §3.20/§3.21, §3.23/§3.22 and §3.6, §3.19/§3.6): `index` when the read takes the
// write's slot index (data bytes 3-4).
struct ReadBack {
  std::uint8_t write, read;
  bool index;
};
constexpr ReadBack kReadBacks[] = {
    {0x39, 0x3A, true}, {0x3B, 0x3C, true}, {0x43, 0x44, true}, {0x46, 0x45, false}, {0x42, 0x35, false},
    {0x46, 0x35, false}};  // §3.23 NOTE: a navigation write deletes the STORE list

// The stops of a motion (§3.4 'X', §3.7 'K' with the Stop key, §3.25 the
// Stop key): the command and its data.
struct Stop {
  std::uint8_t code;
  std::string_view data;
};
constexpr Stop kStops[] = {{0x33, "XS0000"}, {0x36, "KA"}, {0x48, "A"}};

// What a motion sequence runs before its stop (Generator::motions_stopped_'s
// rows): a legal move, a jog, a search, a STOW, a DEPLOY, a LOCATE, any
// motion frame.
enum class MotionKind : std::size_t { kLegalMove, kJog, kSearch, kStow, kDeploy, kLocate, kAnyMotion };
constexpr std::string_view kMotionKindNames[] = {"legal move", "jog", "search", "STOW", "DEPLOY", "LOCATE", "any motion frame"};
constexpr std::string_view kStopNames[] = {"33h X", "36h K A", "48h A"};
// What an arrival aims at (Generator::arrival's goals, in order).
constexpr std::string_view kArrivalGoalNames[] = {"azimuth limit", "elevation limit", "polarization limit",
                                                  "negative target", "2C hundredths", "LOCATE"};

// A table of scores read as one row after the other.
template <typename Row, std::size_t N>
std::vector<double> joined_scores(const std::array<Row, N>& rows) {
  std::vector<double> out;
  for (const Row& r : rows) out.insert(out.end(), r.begin(), r.end());
  return out;
}

// Slot indexes and counts at the edges of the lists (§3.6 1-50, §3.10 1-20,
// §3.12 1-10, §3.20 1-20) and of a field's width.
constexpr std::string_view kIndexes[] = {"00", "01", "02", "09", "10", "11", "19", "20", "21",
                                         "49", "50", "51", "99", "  ", " 1", "1 "};
// Numbers at the axes' and angles' edges, signed, with tenths and hundredths.
constexpr std::string_view kNumbers[] = {"0",     "-0",     "0.0",   "-0.1",   "0.1",   "1.23",  "-2.57", "89.9",
                                         "90.0",  "90.1",   "-90.0", "-90.1",  "179.9", "180.0", "180.1", "-180.0",
                                         "-180.1", "359.9", "360.0", "999.9", "-999.9", "9999",  "1",     "-1"};

// An arrival sequence (Generator::arrival) aims no farther from where the
// model stands than its axis covers in this long at fast speed (a limit a
// little farther), waits for
// the model to be at rest this long, and gives up after this long.
constexpr double kReachSeconds = 4.0;
constexpr std::size_t kMotionsPerArrival = 3;
// How long after a motion's stop its last status is asked.
constexpr std::chrono::milliseconds kStopSettles{400};
constexpr double kLimitReachSeconds = 15.0;  // a limit: this far
constexpr Duration kRestFor = std::chrono::milliseconds(300);
constexpr Duration kArrivalLimit = std::chrono::seconds(30);
// §3.23 NOTE: a navigation write deletes the STORE list, which the reads
// and counts of §3.6 need entries in: for this long from the session's start
// (the model's clock) no write carries a 46h frame.
constexpr Duration kStoreKeptFor = std::chrono::seconds(15);
constexpr std::uint8_t kDeletesStore = 0x46;

// Whether `chars`, after `before`, carries a frame of `command` (a start
// byte, an address byte and the command, as is_safe_to_send reads frames).
bool carries_command(ByteView chars, ByteView before, std::uint8_t command) {
  const Bytes all = joined(before, chars);
  for (const std::size_t i : frame_starts(all))
    if ((all[i + 2] & 0x7F) == command) return true;
  return false;
}

// While it waits, a status poll every this many writes.
constexpr std::size_t kPollEvery = 10;

std::string fixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

// A target on one axis and whether it is a limit (+1 the clockwise/up end of
// the range, -1 the other, 0 none).
struct Target {
  double deg;
  int limit;
};

}  // namespace

bool is_safe_to_send(ByteView chars, bool allow_motion, bool allow_destructive, ByteView before, std::string* why) {
  const Bytes all = joined(before, chars);
  for (const std::size_t i : frame_starts(all)) {
    const CommandInfo* info = find_command(all[i + 2] & 0x7F);
    if (!info) continue;
    const Effects e = effects_at(all, i, *info);
    if (!allowed(e, allow_motion, allow_destructive)) {
      if (why)
        *why = std::string(info->key) + " (" + describe_byte(info->code) + ") " +
               (e.moves_antenna ? "can move the antenna (--allow-motion)" : "changes stored data (--allow-destructive)");
      return false;
    }
  }
  return true;
}

std::string_view to_string(Mutation m) {
  switch (m) {
#define SABUS_X(id, name) \
  case Mutation::id: return name;
    SABUS_LIVE_FUZZ_MUTATIONS(SABUS_X)
#undef SABUS_X
    case Mutation::kCount: break;
  }
  return "?";
}

std::vector<Bytes> base_frames(const GeneratorOptions& o) {
  std::vector<Bytes> out;
  for (const CommandInfo& info : catalog()) {
    for (const FormInfo& form : info.forms) {
      if (!allowed(form.effects, o.allow_motion, o.allow_destructive)) continue;
      auto request = build_request(info, form.id, {});
      if (!request) continue;  // a length the spec leaves TBD (3Dh)
      Bytes f = encode_request(request.value(), o.address);
      if (is_safe_to_send(f, o.allow_motion, o.allow_destructive)) out.push_back(std::move(f));
    }
  }
  return out;
}

Generator::Generator(GeneratorOptions options, std::uint64_t seed)
    : options_(options), bases_(base_frames(options)), rng_(seed) {}

template <typename Scores, typename Available>
std::size_t Generator::least_covered(const Scores& scores, Available available) {
  std::vector<std::size_t> open;
  for (std::size_t k = 0; k < std::size(scores); ++k)
    if (available(k)) open.push_back(k);
  if (open.empty()) return 0;
  if (std::uniform_int_distribution<int>(0, 3)(rng_) > 0) {
    const auto low = scores[*std::min_element(open.begin(), open.end(), [&](std::size_t a, std::size_t b) { return scores[a] < scores[b]; })];
    std::erase_if(open, [&](std::size_t k) { return scores[k] != low; });
  }
  return open[std::uniform_int_distribution<std::size_t>(0, open.size() - 1)(rng_)];
}

Bytes Generator::pick_base() { return bases_[std::uniform_int_distribution<std::size_t>(0, bases_.size() - 1)(rng_)]; }

std::uint8_t Generator::pick(std::initializer_list<std::uint8_t> bytes) {
  return *(bytes.begin() + std::uniform_int_distribution<std::size_t>(0, bytes.size() - 1)(rng_));
}

FuzzFrame Generator::make(Mutation m) {
  FuzzFrame out;
  out.what = std::string(to_string(m));
  Bytes f = pick_base();
  const std::size_t data = f.size() - kFrameOverhead;  // data bytes between the command and ETX
  Modifiers mod;
  switch (m) {
    case Mutation::kValid: break;
    case Mutation::kFieldValue: {
      if (data == 0) {
        out.what = "valid";
        break;
      }
      const std::size_t n = uniform(1, std::min<std::size_t>(2, data));
      for (std::size_t k = 0; k < n; ++k)
        f[3 + uniform(0, data - 1)] = kInteresting[uniform(0, std::size(kInteresting) - 1)];
      f = relrc(std::move(f));
      break;
    }
    case Mutation::kExtraData: mod.extra_data_bytes = uniform(1, 3); break;
    case Mutation::kMissingData:
      if (data == 0) {
        mod.extra_data_bytes = 1;
        out.what = std::string(to_string(Mutation::kExtraData));
        break;
      }
      f.erase(f.begin() + 3, f.begin() + 3 + static_cast<std::ptrdiff_t>(uniform(1, data)));
      f = relrc(std::move(f));
      break;
    case Mutation::kTruncated: mod.truncate = uniform(1, f.size() - 2); break;
    case Mutation::kBadLrc: mod.lrc_xor = static_cast<std::uint8_t>(uniform(1, 0x7F)); break;
    case Mutation::kParityFlip:
      if (!options_.parity_errors) return make(Mutation::kBadLrc);
      out.wrong_parity.push_back(uniform(0, f.size() - 1));
      break;
    case Mutation::kForeignAddress: {
      std::uint8_t a = options_.address;
      while (a == options_.address || std::find(options_.peers.begin(), options_.peers.end(), a) != options_.peers.end())
        a = static_cast<std::uint8_t>(uniform(kMinAddress, kMaxAddress));
      mod.address = a;
      break;
    }
    case Mutation::kInvalidAddress:
      mod.address = uniform(0, 1) ? static_cast<std::uint8_t>(uniform(0x20, kMinAddress - 1))
                                  : static_cast<std::uint8_t>(uniform(kMaxAddress + 1, 0x7F));
      break;
    case Mutation::kControlInBody: {
      std::uint8_t c = STX;
      while (c == STX || c == ETX) c = static_cast<std::uint8_t>(uniform(0, 0x1F));
      f.insert(f.begin() + static_cast<std::ptrdiff_t>(uniform(3, f.size() - 2)), c);
      f = relrc(std::move(f));
      break;
    }
    case Mutation::kUnknownCommand: {
      const std::uint8_t c = uniform(0, 1) ? static_cast<std::uint8_t>(uniform(0x20, kFirstCommand - 1))
                                           : static_cast<std::uint8_t>(uniform(kLastCommand + 1, 0x7F));
      mod.replace.emplace_back(2, c);
      f = apply_modifiers(std::move(f), mod);
      mod = {};
      f = relrc(std::move(f));
      break;
    }
    case Mutation::kJunkPrefix: {
      Bytes junk;
      for (std::size_t k = uniform(1, 4); k > 0; --k) junk.push_back(pick({ETX, ACK, NAK, 0x00, ' ', '2', 0x7F, '0'}));
      f.insert(f.begin(), junk.begin(), junk.end());
      break;
    }
    case Mutation::kStxRestart: {
      // A frame cut short by the STX of the next (§1 State 3, E-7), or an
      // STX where the address belongs (§1 State 2 c).
      Bytes g = pick_base();
      const std::size_t cut = uniform(1, g.size() - 2);
      g.resize(cut);
      f.insert(f.begin(), g.begin(), g.end());
      break;
    }
    case Mutation::kBurst: {
      for (std::size_t k = uniform(1, 2); k > 0; --k) {
        Bytes g = pick_base();
        f.insert(f.end(), g.begin(), g.end());
      }
      break;
    }
    case Mutation::kBoundary:
      f = boundary(pick_boundary_base());
      break;
    case Mutation::kSequence: return sequence();
    case Mutation::kCount: break;
  }
  if (!(mod == Modifiers{})) f = apply_modifiers(std::move(f), mod);
  out.chars = std::move(f);
  return out;
}

FuzzFrame Generator::sequence() {
  // Half stored data (a write and its read, or a read a third of the time):
  // they take no time, a motion or an arrival seconds.
  const bool stored = !options_.allow_motion || uniform(0, 1) == 0;
  // An arrival after every three motions with their stops: an arrival
  // takes seconds, and a motion sequence waits while one runs.
  if (!stored && options_.allow_motion && !arriving_ && motions_since_arrival_ >= kMotionsPerArrival) {
    // From rest: a motion still running (a DEPLOY a damaged frame began)
    // is stopped first, and the status and extended status show where it
    // ended; the arrival comes with a later sequence. One begun inside such
    // a mode would be the device's to run until both were at rest, its
    // target unjudged (a LOCATE the device failed went unseen so).
    if (const Controller* c = model_ ? model_().controller : nullptr;
        c && (!all_at_rest(*c) || moves_by_itself(c->state().mode.mode))) {
      queued_.push_back({command(0x31), {}, "status after the stop"});
      queued_.push_back({command(0x40), {}, "extended status after the stop"});
      return {command(0x33, "XS0000"), {}, "sequence: stop before an arrival"};
    }
    if (auto a = arrival()) {
      motions_since_arrival_ = 0;
      return *a;
    }
  }
  if (stored) return options_.allow_destructive && uniform(0, 2) > 0 ? stored_sequence() : stored_read();
  ++motions_since_arrival_;
  return motion_sequence();
}

FuzzFrame Generator::stored_sequence() {
  // A write (at a boundary half the time), then the read that shows it.
  const ReadBack& rb = kReadBacks[uniform(0, std::size(kReadBacks) - 1)];
  const auto writes = bases_where([&](const Bytes& b) { return b[2] == rb.write; });
  if (writes.empty()) return make(Mutation::kBoundary);
  Bytes f = *writes[uniform(0, writes.size() - 1)];
  if (uniform(0, 1)) f = boundary(std::move(f));
  const std::string index = rb.index && f.size() > 5 ? std::string(f.begin() + 3, f.begin() + 5)
                            : rb.read == 0x35 ? std::string(kIndexes[uniform(1, 3)])
                                              : std::string();
  queued_.push_back({command(rb.read, index), {}, "read back"});
  return {std::move(f), {}, "sequence: stored write"};
}

FuzzFrame Generator::stored_read() {
  // A read of a stored list at any index it has, or one past its end (§3.6
  // 35h, §3.11 3Ah, §3.13 3Ch, §3.21 44h): an entry in the middle of a list
  // as often as its ends. A read changes nothing, so one may go out while
  // an arrival waits.
  if (!model_) return make(Mutation::kBoundary);
  const ControllerState& s = model_().controller->state();
  struct List {
    std::uint8_t read;
    std::size_t size;
  };
  const List lists[] = {{0x35, s.store.size()}, {0x3A, s.presets.size()}, {0x3C, s.tles.size()}, {0x44, s.signposts.size()}};
  const List& list = lists[uniform(0, std::size(lists) - 1)];
  char index[8];
  std::snprintf(index, sizeof index, "%02zu", uniform(1, list.size + 1));
  return {command(list.read, index), {}, "sequence: read of a stored list"};
}

FuzzFrame Generator::motion_sequence() {
  // A motion, a status or two while it runs, a stop of one kind, and
  // what the controller says after it.
  const auto moves = bases_where([&](const Bytes& b) {
    const CommandInfo* info = find_command(b[2]);
    return info && effects_at(b, 0, *info).moves_antenna;
  });
  if (moves.empty()) return make(Mutation::kBoundary);
  // A legal move (runs a while when stopped), a jog, a mode that
  // moves by itself (a search §3.7 'A' 'E' or 'F', a STOW 'S', a
  // DEPLOY 'D', a LOCATE §3.18), any motion frame at a boundary or as
  // it is; stopped by one of kStops: the pair least covered so far.
  auto pick_move = [&](auto keep) {
    std::vector<const Bytes*> some;
    for (const Bytes* b : moves)
      if (keep(*b)) some.push_back(b);
    return some.empty() ? *moves[uniform(0, moves.size() - 1)] : *some[uniform(0, some.size() - 1)];
  };
  const auto is_jog = [](const Bytes& b) { return b.size() == 11 && (b[2] == 0x33 || b[2] == 0x47) && b[3] != 'X'; };
  static_assert(std::size(kStops) == kStopKinds && std::size(kStopNames) == kStopKinds &&
                std::size(kMotionKindNames) == kMotionKinds && std::size(kArrivalGoalNames) == kArrivalGoals);
  const std::size_t pair = least_covered(joined_scores(motions_stopped_), [](std::size_t) { return true; });
  const auto kind = static_cast<MotionKind>(pair / kStopKinds);
  stop_pending_ = {pair / kStopKinds, pair % kStopKinds};
  const auto legal = kind == MotionKind::kLegalMove ? legal_move(nullptr, {.auto_move_only = true})
                     : kind == MotionKind::kLocate  ? legal_move(nullptr, {.form = 'L'})
                                                    : std::nullopt;
  const char mode_form = kind == MotionKind::kStow ? 'S' : kind == MotionKind::kDeploy ? 'D' : 'A';
  Bytes f;
  if (legal) f = *legal;
  else if (kind == MotionKind::kJog) f = pick_move(is_jog);
  else if (kind == MotionKind::kSearch || kind == MotionKind::kStow || kind == MotionKind::kDeploy)
    f = pick_move([mode_form](const Bytes& b) { return b.size() > 5 && b[2] == 0x36 && b[3] == mode_form; });
  else f = *moves[uniform(0, moves.size() - 1)];
  if (kind == MotionKind::kAnyMotion && uniform(0, 1) == 0) f = boundary(std::move(f));
  else if (f.size() > 5 && f[2] == 0x36 && f[3] == 'A') f = relrc(with_byte(std::move(f), 4, pick({'E', 'F'})));  // §3.7 a search
  else if (f.size() > 5 && f[2] == 0x36 && (f[3] == 'S' || f[3] == 'D')) f = relrc(with_byte(std::move(f), 4, f[3]));  // 'SS', 'DD'
  else if (is_jog(f)) {
    // A jog that lasts (§3.4: 4 digits of milliseconds), and three times in
    // four one about another axis after it, which ends the first.
    static constexpr std::string_view kDirections = "EWDUOL";  // two per axis: az, el, pol
    f = relrc(with_digits(std::move(f), 5, uniform(1000, 4000)));
    const std::size_t axis = kDirections.find(static_cast<char>(f[3])) / 2;
    if (axis < 3 && uniform(0, 3) > 0) {
      const std::size_t other = (axis + uniform(1, 2)) % 3;
      Bytes g = relrc(with_byte(f, 3, static_cast<std::uint8_t>(kDirections[other * 2 + uniform(0, 1)])));
      queued_.push_back({command(0x31), {}, "status while jogging", std::chrono::milliseconds(uniform(100, 500))});
      queued_.push_back({std::move(g), {}, "jog about another axis"});
    }
  }
  // The first poll after a while: the motion has begun when it is
  // stopped (a STOW, DEPLOY or search is judged by how it stops).
  for (std::size_t k = uniform(1, 2), first = 1; k > 0; --k, first = 0)
    queued_.push_back({command(0x31), {}, "status while moving", std::chrono::milliseconds(first ? uniform(200, 800) : 0)});
  // The stop goes out with a status just before it, in one write: what the
  // stop found (moving or not) is what that status shows (a STOW, DEPLOY or
  // search may end by itself at any moment, E-89, E-90).
  const Stop& stop = kStops[stop_pending_->second];
  Bytes with_status = command(0x31);
  const Bytes stop_frame = command(stop.code, stop.data);
  with_status.insert(with_status.end(), stop_frame.begin(), stop_frame.end());
  queued_.push_back({std::move(with_status), {}, "status and stop"});
  queued_.push_back({command(0x31), {}, "status after the stop"});
  queued_.push_back({command(0x40), {}, "extended status after the stop"});
  // A device that goes on after a stop shows it in its positions once they
  // are beyond the timing's window (a status right after the stop may still
  // see a legal device ramping down): a status a while later.
  queued_.push_back({command(0x31), {}, "status once the stop has settled", kStopSettles});
  return {std::move(f), {}, "sequence: motion (" + std::string(kMotionKindNames[stop_pending_->first]) + ", stopped by " +
             std::string(kStopNames[stop_pending_->second]) + ")"};
}

std::vector<const Bytes*> Generator::bases_where(const std::function<bool(const Bytes&)>& keep) const {
  std::vector<const Bytes*> out;
  for (const Bytes& b : bases_)
    if (keep(b)) out.push_back(&b);
  return out;
}

Bytes Generator::command(std::uint8_t code, std::string_view data) const {
  return encode_frame({FrameKind::kCommand, options_.address, code, Bytes(data.begin(), data.end())});
}

std::size_t Generator::uniform(std::size_t lo, std::size_t hi) {
  return std::uniform_int_distribution<std::size_t>(lo, hi)(rng_);
}

std::optional<FuzzFrame> Generator::arrival() {
  if (!model_ || !options_.profile) return std::nullopt;
  // Aimed at: each limit, negative targets in the counts' form (§3.3 2B
  // below the offset) or else 2A's, 2C's hundredths, a LOCATE
  // (kArrivalGoalNames).
  const Profile& p = *options_.profile;
  const bool counts = p.az_sensor == AzSensor::kPulse || p.az_sensor == AzSensor::kResolver;
  struct Goal {
    Aim aim;
    bool available;
  };
  const std::array<Goal, kArrivalGoals> goals = {{{{'A', 0, false}, true},
                                                  {{'A', 1, false}, true},
                                                  {{'P', 2, false}, p.pol_type != PolType::kCircular},
                                                  {{counts ? 'B' : 'A', -1, true}, p.az.min_deg < 0 || p.el.min_deg < 0},
                                                  {{'C', -1, true}, p.hundredths},
                                                  {{'L', -1, false}, true}}};
  // The first arrival is a LOCATE: its geometry has the most rules of any
  // aim, and a limit may take a slow mount a quarter of a minute (three
  // limits first left a minute without one). While no site is known, a
  // LOCATE waits for one (E-59): a state only this part of a session shows
  // (a navigation write may give a site later).
  constexpr std::size_t kLocateGoal = 5;
  static_assert(kArrivalGoalNames[kLocateGoal] == "LOCATE");
  const std::size_t goal = arrivals_aimed_[kLocateGoal] == 0
                               ? kLocateGoal
                               : least_covered(arrivals_aimed_, [&](std::size_t k) { return goals[k].available; });
  const Aim aim = goals[goal].aim;
  std::array<int, 3> limits{};
  aim_met_ = true;
  const auto move = legal_move(&limits, aim);
  if (!move) return std::nullopt;
  // A limit too far or no negative position within reach this time: a step
  // toward it, and the aim counts a quarter.
  // A LOCATE counts half: its geometry (site, heading, hemispheres, range,
  // E-59 to E-82) has the most rules of any aim, so it comes twice as often.
  arrivals_aimed_[goal] += (aim_met_ ? 1.0 : 0.25) * (goal == kLocateGoal ? 0.5 : 1.0);
  arriving_ = true;
  arrival_start_ = model_().now;
  at_rest_since_.reset();
  writes_since_poll_ = 0;
  // Once at rest: what the controller says, then a jog further into a
  // limit the move ended at (§3.4: NAKed while the limit is asserted).
  // The mode the move entered (§3.17), before a write of the wait changes it.
  queued_.push_back({command(0x40), {}, "extended status as the move begins"});
  after_arrival_ = {{command(0x31), {}, "status after the arrival"}, {command(0x40), {}, "extended status after the arrival"}};
  static constexpr std::string_view kIntoLimit[3][2] = {{"ES0500", "WS0500"}, {"DS0500", "US0500"}, {"OS0500", "LS0500"}};
  // The aimed limit always; another one the move ends at half the time.
  for (std::size_t a = 0; a < 3; ++a)
    if (limits[a] != 0 && (static_cast<int>(a) == aim.limit_axis || (aim.limit_axis < 0 && uniform(0, 1) == 0))) {
      after_arrival_.push_back({command(0x33, kIntoLimit[a][limits[a] > 0 ? 1 : 0]), {}, "jog into the limit"});
      after_arrival_.push_back({command(0x31), {}, "status after the jog"});
      break;
    }
  return FuzzFrame{*move, {}, "sequence: arrival (" + std::string(kArrivalGoalNames[goal]) + ")"};
}

std::optional<Bytes> Generator::legal_move(std::array<int, 3>* limits_out, Aim aim) {
  if (!model_ || !options_.profile) return std::nullopt;
  const Profile& p = *options_.profile;
  const ModelView view = model_();
  const Controller& m = *view.controller;
  auto real = [&](double lo, double hi) { return lo >= hi ? lo : std::uniform_real_distribution<double>(lo, hi)(rng_); };
  // Within reach of where the model stands; a limit one time in four, a
  // negative position one time in four where the reach has one (§3.3's
  // signed forms), rounded to what the form carries.
  auto target = [&](std::size_t a, double step) -> Target {
    const AxisProfile& ap = by_axis(p, a);
    const double from = by_axis(m.state(), a).position, reach = ap.fast_dps * kReachSeconds;
    const double lo = std::max(ap.min_deg, from - reach), hi = std::min(ap.max_deg, from + reach);
    const std::size_t r = static_cast<int>(a) == aim.limit_axis ? 0 : aim.negative ? 1 : uniform(0, 3);
    if (r == 0) {  // the nearer limit, or a step toward it where it is far
      const int toward = ap.max_deg - from <= from - ap.min_deg ? +1 : -1;
      const double edge = toward > 0 ? ap.max_deg : ap.min_deg;
      if (std::abs(edge - from) <= ap.fast_dps * kLimitReachSeconds) return {edge, toward};
      if (static_cast<int>(a) == aim.limit_axis) aim_met_ = false;
      return {std::round((from + toward * reach) / step) * step, 0};
    }
    if (r == 1 && lo >= -step && ap.min_deg < -step && aim.negative) {  // a step toward the negatives
      aim_met_ = false;
      return {std::round(std::max(ap.min_deg, from - reach) / step) * step, 0};
    }
    const double t = r == 1 && lo < -step ? real(lo, std::min(hi, -step)) : real(lo, hi);
    return {std::clamp(std::round(t / step) * step, ap.min_deg, ap.max_deg), 0};
  };
  // The forms this profile takes (§3.3: 2B needs count sensors, 2C the
  // hundredths, 3 a linear feed; §3.18 a site, which it may lack: then the
  // LOCATE waits for it, E-59).
  std::vector<char> forms = {'A', 'L'};
  if (p.az_sensor == AzSensor::kPulse || p.az_sensor == AzSensor::kResolver) forms.push_back('B');
  if (p.hundredths) forms.push_back('C');
  if (p.pol_type != PolType::kCircular) forms.push_back('P');
  if (aim.auto_move_only) std::erase(forms, 'L');
  const char form = aim.form ? aim.form : forms[uniform(0, forms.size() - 1)];
  std::map<std::string, std::string> fields;
  std::string_view form_id;
  std::uint8_t code = 0x32;
  std::array<int, 3> limits{};
  auto counts = [&](double deg) { return std::to_string(p.count_offset + std::lround(deg * p.counts_per_degree)); };
  switch (form) {
    case 'A': case 'B': {
      const Target az = target(0, 0.1), el = target(1, 0.1);
      limits = {az.limit, el.limit, 0};
      form_id = form == 'A' ? "2A" : "2B";
      if (form == 'A') fields = {{"azimuth", fixed(az.deg, 1)}, {"elevation", fixed(el.deg, 1)}};
      else fields = {{"azimuth count", counts(az.deg)}, {"elevation count", counts(el.deg)}};
      break;
    }
    case 'C': {
      const std::size_t a = uniform(0, 1);
      const Target t = target(a, 0.01);
      limits[a] = t.limit;
      form_id = "2C";
      fields = {{"axis", a == 0 ? "A" : "E"}, {"target", fixed(t.deg, 2)}};
      break;
    }
    case 'P': {
      const Target t = target(2, 0.1);
      limits[2] = t.limit;
      form_id = "3";
      fields = {{"pol target", fixed(t.deg, 1)}};
      break;
    }
    default: {
      // A satellite whose look angles the model's axes reach within a few
      // seconds, where the site is known; any longitude otherwise.
      code = 0x41;
      form_id = "data";
      double longitude = real(-180.0, 180.0);
      const look::SiteOf site = look::site_of(m.state().navigation, p.az_sensor, p.fluxgate_heading);
      if (site.site) {
        // Seconds to get there at fast speed (the slower axis).
        auto seconds_to = [&](double lon) -> std::optional<double> {
          const look::Pointing aim = look::pointing(*site.site, lon);
          const auto az = look::azimuth_position(p.az, aim.azimuth_deg, m.state().az.position);
          if (!az || aim.elevation_deg < p.el.min_deg || aim.elevation_deg > p.el.max_deg) return std::nullopt;
          return std::max(std::abs(*az - m.state().az.position) / p.az.fast_dps,
                          std::abs(aim.elevation_deg - m.state().el.position) / p.el.fast_dps);
        };
        std::vector<double> near;
        std::optional<double> nearest, best;
        for (double lon = -180.0; lon <= 180.0; lon += 0.5)
          if (const auto t = seconds_to(lon)) {
            if (*t <= kReachSeconds) near.push_back(lon);
            if (!best || *t < *best) best = t, nearest = lon;
          }
        if (!near.empty()) longitude = near[uniform(0, near.size() - 1)];
        else if (nearest) longitude = *nearest;  // none that near: the nearest the axes reach
      }
      fields = {{"sat name", "FUZZ LOC"}, {"longitude", fixed(longitude, 1)}, {"inclination", "0"}, {"band", "1"},
                {"pol offset", "0.0"}, {"receive polarization", "N"}, {"position update", "A"}};
    }
  }
  auto request = build_request(*find_command(code), form_id, fields);
  if (!request) return std::nullopt;
  if (limits_out) *limits_out = limits;
  return encode_request(request.value(), options_.address);
}

std::optional<FuzzFrame> Generator::while_arriving() {
  if (!arriving_) return std::nullopt;
  const ModelView view = model_();
  const bool at_rest = all_at_rest(*view.controller) && !view.device_led;
  if (!at_rest) at_rest_since_.reset();
  else if (!at_rest_since_) at_rest_since_ = view.now;
  if ((at_rest_since_ && view.now - *at_rest_since_ >= kRestFor) || view.now - arrival_start_ >= kArrivalLimit) {
    arriving_ = false;
    queued_.insert(queued_.end(), after_arrival_.begin(), after_arrival_.end());
    after_arrival_.clear();
    return std::nullopt;
  }
  if (++writes_since_poll_ >= kPollEvery) {
    writes_since_poll_ = 0;
    // The extended status while the device leads: its mode bytes end the
    // episode, and a LOCATE's end is judged by it.
    return FuzzFrame{command(view.device_led ? 0x40 : 0x31), {}, "status while arriving"};
  }
  // Anything that cannot move the antenna (nor start another sequence);
  // while the device leads (a LOCATE), nothing that stores either: a 42h or
  // 46h would leave the LOCATE before its end is judged.
  const bool stores = options_.allow_destructive && !view.device_led;
  for (;;) {
    const auto m = static_cast<Mutation>(std::uniform_int_distribution<unsigned>(0, static_cast<unsigned>(Mutation::kCount) - 1)(rng_));
    FuzzFrame f = m == Mutation::kSequence ? stored_read() : make(m);
    if (is_safe_to_send(f.chars, false, stores, tail_)) return f;
  }
}

Bytes Generator::pick_boundary_base() {
  // The commands of the rules the device has not fired yet, three times in
  // four (a rule of §3 itself belongs to every command).
  if (fired_ && std::uniform_int_distribution<int>(0, 3)(rng_) > 0) {
    std::set<std::string_view> paragraphs;
    for (NakRule r : all_nak_rules())
      if (!fired_->count(std::string(name(r))) && paragraph(r) != "3") paragraphs.insert(paragraph(r));
    std::vector<const Bytes*> wanted;
    for (const Bytes& b : bases_)
      if (const CommandInfo* info = find_command(b[2]); info && paragraphs.count(info->paragraph)) wanted.push_back(&b);
    if (!wanted.empty()) return *wanted[std::uniform_int_distribution<std::size_t>(0, wanted.size() - 1)(rng_)];
  }
  return pick_base();
}

Bytes Generator::boundary(Bytes f) {
  std::vector<FieldDescription> data;
  for (FieldDescription& fd : describe_frame(f).fields)
    if (fd.kind != fields::Kind::kHeader && fd.kind != fields::Kind::kUndescribed && fd.first >= 3 && fd.last + 2 < f.size())
      data.push_back(std::move(fd));
  if (data.empty()) return f;
  const FieldDescription& fd = data[uniform(0, data.size() - 1)];
  const std::size_t width = fd.last - fd.first + 1;
  std::string text;
  using K = fields::Kind;
  switch (fd.kind) {
    case K::kSlotIndex:
    case K::kPresetIndex:
    case K::kDigits:
      if (width == 2) text = kIndexes[uniform(0, std::size(kIndexes) - 1)];
      else if (uniform(0, 2) == 0) text = std::string(width, '0');
      else if (uniform(0, 1) == 0) text = std::string(width, '9');
      else text = std::string(width - 1, '0') + "1";
      break;
    case K::kText:
      if (!options_.names.empty() && uniform(0, 2) > 0) text = options_.names[uniform(0, options_.names.size() - 1)];
      else text = uniform(0, 1) ? "" : "NO SUCH";
      break;
    case K::kPosition:
    case K::kAzimuth:
    case K::kSignedDigits:
    case K::kLeftDecimal:
    case K::kRightDecimal:
    case K::kZeroPaddedDecimal:
    case K::kNavAngle: {
      const std::string n(kNumbers[uniform(0, std::size(kNumbers) - 1)]);
      if (n.size() > width) text = n.substr(0, width);
      else if (uniform(0, 1)) text = std::string(width - n.size(), uniform(0, 3) ? ' ' : '0') + n;  // right-justified
      else text = n;                                                                            // left-justified
      if (uniform(0, 7) == 0) text = "";                                                        // blanks
      break;
    }
    default:
      // A choice, a selector, a bit field: capitals (the choice sets of
      // §3) most often, then digits, then any printable character.
      for (std::size_t k = 0; k < width; ++k) {
        const std::size_t r = uniform(0, 9);
        text += static_cast<char>(r < 6 ? 'A' + uniform(0, 25) : r < 8 ? '0' + uniform(0, 9) : uniform(0x20, 0x7E));
      }
  }
  text.resize(width, ' ');
  std::copy(text.begin(), text.end(), f.begin() + static_cast<std::ptrdiff_t>(fd.first));
  return relrc(std::move(f));
}

FuzzFrame Generator::next() {
  // Damage more often than not; a valid frame now and then keeps the device
  // in a state worth damaging frames against.
  // Well-framed values at the rules' edges as often as all damage together
  // (the lockstep oracle judges them), sequences now and then.
  static constexpr unsigned kWeights[] = {3, 4, 2, 2, 2, 2, 2, 2, 1, 2, 2, 1, 1, 1, 12, 3};
  static_assert(std::size(kWeights) == static_cast<std::size_t>(Mutation::kCount));
  std::discrete_distribution<unsigned> which(std::begin(kWeights), std::end(kWeights));
  for (;;) {
    // Safe with the end of the write before it too: a frame cut short there
    // and completed here is a frame on the line (the session's gate reads
    // them alike, so it never has to refuse one of these).
    auto safe = [&](const FuzzFrame& w) {
      if (!is_safe_to_send(w.chars, options_.allow_motion, options_.allow_destructive, tail_)) return false;
      if (model_) {
        const TimePoint now = model_().now;
        if (!session_start_) session_start_ = now;
        if (now - *session_start_ < kStoreKeptFor && carries_command(w.chars, tail_, kDeletesStore)) return false;
      }
      tail_.assign(w.chars.end() - static_cast<std::ptrdiff_t>(std::min<std::size_t>(4, w.chars.size())), w.chars.end());
      return true;
    };
    if (!queued_.empty()) {
      FuzzFrame q = std::move(queued_.front());
      queued_.pop_front();
      if (!safe(q)) continue;
      if (q.what == "status and stop" && stop_pending_) {
        const bool moving = !model_ || !all_at_rest(*model_().controller);
        motions_stopped_[stop_pending_->first][stop_pending_->second] += moving ? 1.0 : 1.0 / 3;
        stop_pending_.reset();
      }
      return q;
    }
    if (auto w = while_arriving()) {
      if (safe(*w)) return *w;
      continue;
    }
    if (!queued_.empty()) continue;  // the arrival's last writes
    FuzzFrame f = make(static_cast<Mutation>(which(rng_)));
    if (safe(f)) return f;
  }
}

}  // namespace sabus::harness::live_fuzz
