// The live fuzzer's generator and its safety gate: frames from the catalog
// and the structured builder, damaged with the runner's modifiers.
#include <algorithm>

#include "sabus/harness/live_fuzz.hpp"
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
      while (a == options_.address) a = static_cast<std::uint8_t>(uniform(kMinAddress, kMaxAddress));
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
      Bytes cut_frame(g.begin(), g.begin() + static_cast<std::ptrdiff_t>(cut));
      f.insert(f.begin(), cut_frame.begin(), cut_frame.end());
      break;
    }
    case Mutation::kBurst: {
      for (std::size_t k = uniform(1, 2); k > 0; --k) {
        Bytes g = pick_base();
        f.insert(f.end(), g.begin(), g.end());
      }
      break;
    }
    case Mutation::kCount: break;
  }
  if (!(mod == Modifiers{})) f = apply_modifiers(std::move(f), mod);
  out.chars = std::move(f);
  return out;
}

FuzzFrame Generator::next() {
  // Damage more often than not; a valid frame now and then keeps the device
  // in a state worth damaging frames against.
  static constexpr unsigned kWeights[] = {3, 4, 2, 2, 2, 2, 2, 2, 1, 2, 2, 1, 1, 1};
  static_assert(std::size(kWeights) == static_cast<std::size_t>(Mutation::kCount));
  std::discrete_distribution<unsigned> which(std::begin(kWeights), std::end(kWeights));
  for (;;) {
    FuzzFrame f = make(static_cast<Mutation>(which(rng_)));
    if (is_safe_to_send(f.chars, options_.allow_motion, options_.allow_destructive)) return f;
  }
}

}  // namespace sabus::harness::live_fuzz
