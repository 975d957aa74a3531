// The live fuzzer's generator and its safety gate: frames from the catalog
// and the structured builder, damaged with the runner's modifiers.
#include <algorithm>
#include <set>

#include "sabus/harness/live_fuzz.hpp"
#include "sabus/harness/nak_rules.hpp"
#include "sabus/harness/runner.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

namespace sabus::harness::live_fuzz {
namespace {

constexpr bool is_start_byte(std::uint8_t b) { return b == STX || b == ACK || b == NAK; }

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

Bytes relrc(Bytes f) {
  if (f.size() >= 2) f.back() = lrc(ByteView(f).first(f.size() - 1));
  return f;
}

// Characters at the edges of the fields' ranges: digits, signs, blanks, the
// first and last printable characters, letters no field takes (§1 Data Format).
constexpr std::uint8_t kInteresting[] = {' ', '0', '1', '9', '-', '+', '.', '/', ':', '@', 'A', 'Z', 'a', 'z', 0x7F, '~'};

// A stored write and the read that shows it (§3.10/§3.11, §3.12/§3.13,
// §3.20/§3.21, §3.23/§3.22, §3.19/§3.6): `index` when the read takes the
// write's slot index (data bytes 3-4).
struct ReadBack {
  std::uint8_t write, read;
  bool index;
};
constexpr ReadBack kReadBacks[] = {
    {0x39, 0x3A, true}, {0x3B, 0x3C, true}, {0x43, 0x44, true}, {0x46, 0x45, false}, {0x42, 0x35, false}};

// The stops of a motion (§3.4 'X', §3.7 'K' with the Stop key, §3.25 the
// Stop key): the command and its data.
struct Stop {
  std::uint8_t code;
  std::string_view data;
};
constexpr Stop kStops[] = {{0x33, "XS0000"}, {0x36, "KA"}, {0x48, "A"}};

// Slot indexes and counts at the edges of the lists (§3.6 1-50, §3.10 1-20,
// §3.12 1-10, §3.20 1-20) and of a field's width.
constexpr std::string_view kIndexes[] = {"00", "01", "02", "09", "10", "11", "19", "20", "21",
                                         "49", "50", "51", "99", "  ", " 1", "1 "};
// Numbers at the axes' and angles' edges, signed, with tenths and hundredths.
constexpr std::string_view kNumbers[] = {"0",     "-0",     "0.0",   "-0.1",   "0.1",   "1.23",  "-2.57", "89.9",
                                         "90.0",  "90.1",   "-90.0", "-90.1",  "179.9", "180.0", "180.1", "-180.0",
                                         "-180.1", "359.9", "360.0", "999.9", "-999.9", "9999",  "1",     "-1"};

}  // namespace

bool is_safe_to_send(ByteView chars, bool allow_motion, bool allow_destructive, ByteView before, std::string* why) {
  Bytes all(before.begin(), before.end());
  all.insert(all.end(), chars.begin(), chars.end());
  // A start byte, an address byte (§1: 31h-6Fh), a command byte: a frame as
  // the vector lint reads one.
  for (std::size_t i = 0; i + 2 < all.size(); ++i) {
    if (!is_start_byte(all[i] & 0x7F) || !is_valid_address(all[i + 1] & 0x7F)) continue;
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

Bytes Generator::pick_base() { return bases_[std::uniform_int_distribution<std::size_t>(0, bases_.size() - 1)(rng_)]; }

std::uint8_t Generator::pick(std::initializer_list<std::uint8_t> bytes) {
  return *(bytes.begin() + std::uniform_int_distribution<std::size_t>(0, bytes.size() - 1)(rng_));
}

FuzzFrame Generator::make(Mutation m) {
  auto uniform = [&](std::size_t lo, std::size_t hi) { return std::uniform_int_distribution<std::size_t>(lo, hi)(rng_); };
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
    case Mutation::kSequence: {
      auto frame = [&](std::uint8_t code, std::string_view data) {
        return encode_frame({FrameKind::kCommand, options_.address, code, Bytes(data.begin(), data.end())});
      };
      auto with_code = [&](auto keep) {
        std::vector<const Bytes*> out;
        for (const Bytes& b : bases_)
          if (keep(b)) out.push_back(&b);
        return out;
      };
      const bool stored = options_.allow_destructive && (!options_.allow_motion || uniform(0, 1) == 0);
      if (stored) {
        // A write (at a boundary half the time), then the read that shows it.
        const ReadBack& rb = kReadBacks[uniform(0, std::size(kReadBacks) - 1)];
        const auto writes = with_code([&](const Bytes& b) { return b[2] == rb.write; });
        if (writes.empty()) return make(Mutation::kBoundary);
        f = *writes[uniform(0, writes.size() - 1)];
        if (uniform(0, 1)) f = boundary(std::move(f));
        const std::string index = rb.index && f.size() > 5 ? std::string(f.begin() + 3, f.begin() + 5)
                                  : rb.read == 0x35 ? std::string(kIndexes[uniform(1, 3)])
                                                    : std::string();
        queued_.push_back({frame(rb.read, index), {}, "read back"});
        out.what = "sequence: stored write";
      } else if (options_.allow_motion) {
        // A motion, a status or two while it runs, a stop of one kind, and
        // what the controller says after it.
        const auto moves = with_code([&](const Bytes& b) {
          const CommandInfo* info = find_command(b[2]);
          return info && effects_at(b, 0, *info).moves_antenna;
        });
        if (moves.empty()) return make(Mutation::kBoundary);
        f = *moves[uniform(0, moves.size() - 1)];
        if (uniform(0, 2) == 0) f = boundary(std::move(f));
        for (std::size_t k = uniform(0, 2); k > 0; --k) queued_.push_back({frame(0x31, ""), {}, "status while moving"});
        const Stop& stop = kStops[uniform(0, std::size(kStops) - 1)];
        queued_.push_back({frame(stop.code, stop.data), {}, "stop"});
        queued_.push_back({frame(0x31, ""), {}, "status after the stop"});
        queued_.push_back({frame(0x40, ""), {}, "extended status after the stop"});
        out.what = "sequence: motion";
      } else {
        return make(Mutation::kBoundary);
      }
      break;
    }
    case Mutation::kCount: break;
  }
  if (!(mod == Modifiers{})) f = apply_modifiers(std::move(f), mod);
  out.chars = std::move(f);
  return out;
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
  auto uniform = [&](std::size_t lo, std::size_t hi) { return std::uniform_int_distribution<std::size_t>(lo, hi)(rng_); };
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
      tail_.assign(w.chars.end() - static_cast<std::ptrdiff_t>(std::min<std::size_t>(4, w.chars.size())), w.chars.end());
      return true;
    };
    if (!queued_.empty()) {
      FuzzFrame q = std::move(queued_.front());
      queued_.pop_front();
      if (safe(q)) return q;
      continue;
    }
    FuzzFrame f = make(static_cast<Mutation>(which(rng_)));
    if (safe(f)) return f;
  }
}

}  // namespace sabus::harness::live_fuzz
