// The structure-aware mutator of the frame-level fuzz targets
// (fuzz_support.hpp mutate_stream). Kept apart from fuzz_support.cpp because
// it needs libFuzzer's LLVMFuzzerMutate (replay_main.cpp has a stand-in).
#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <cstdio>
#include <random>
#include <set>

#include "fuzz_support.hpp"
#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/codec.hpp"
#include "sabus/protocol/structured.hpp"

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace sabus::fuzz {

namespace {

// The mutator reads and repairs the whole stream on every call, so it works
// eight bytes a step (a word of the stream; bit 7 of each byte ignored).
constexpr std::uint64_t kLow = 0x0101010101010101ULL, kHigh = 0x80 * kLow, kChars = 0x7F * kLow;

std::uint64_t word_at(const std::uint8_t* p) {
  std::uint64_t w;
  std::memcpy(&w, p, 8);
  return w;
}

// Bit 7 of each byte of the result: whether the byte's 7 bits are `c`. Exact
// (no carry between bytes): the bytes of t are below 80h.
std::uint64_t bytes_equal(std::uint64_t chars, std::uint8_t c) {
  const std::uint64_t t = chars ^ (c * kLow);
  return ~(t + kChars) & kHigh;
}

// Even parity in bit 7 of every 7-bit character (with_even_parity, a table).
constexpr std::array<std::uint8_t, 128> kWithParity = [] {
  std::array<std::uint8_t, 128> t{};
  for (unsigned c = 0; c < 128; ++c) t[c] = with_even_parity(static_cast<std::uint8_t>(c));
  return t;
}();

// A frame in the stream: its start byte, its ETX (npos if none) and the end
// of the segment (the next start byte, or the end). The byte after ETX is the
// check byte even when it is 02h (READING-NOTES 7), so it never starts a segment.
struct Segment {
  std::size_t begin, etx, end;
};
constexpr std::size_t npos = static_cast<std::size_t>(-1);

// Calls visit(segment) for every segment of the stream in order, until it
// returns false. One pass over the stream, eight bytes a step: each word's
// start bytes and ETX found at once, then taken in order (a segment is
// visited when the next start byte, or the end, closes it). visit may change
// the bytes of the segment it is given up to its check byte (seal), not the
// bytes after them; a visit that inserts or erases bytes must stop the walk.
template <class Visit>
void walk_segments(const Bytes& b, Visit&& visit) {
  const std::size_t n = b.size();
  Segment s{npos, npos, n};
  std::size_t skip = 0;  // a mark before this is the check byte after an ETX
  // A start byte or an ETX at p: false when the walk stops.
  auto mark = [&](std::size_t p, bool start) {
    if (p < skip) return true;
    if (start) {
      if (s.begin != npos) {
        s.end = p;
        if (!visit(static_cast<const Segment&>(s))) return false;
      }
      s = {p, npos, n};
    } else if (s.begin != npos && s.etx == npos) {
      s.etx = p;
      skip = p + 2;
    }
    return true;
  };
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    const std::uint64_t c = word_at(b.data() + i) & kChars;
    const std::uint64_t starts = bytes_equal(c, STX) | bytes_equal(c, ACK) | bytes_equal(c, NAK);
    for (std::uint64_t marks = starts | bytes_equal(c, ETX); marks != 0; marks &= marks - 1) {
      const auto bit = static_cast<unsigned>(std::countr_zero(marks));
      if (!mark(i + bit / 8, (starts >> bit) & 1)) return;
    }
  }
  for (; i < n; ++i) {
    const std::uint8_t c = b[i] & 0x7F;
    if ((c == STX || c == ACK || c == NAK || c == ETX) && !mark(i, c != ETX)) return;
  }
  if (s.begin != npos) visit(static_cast<const Segment&>(s));
}

// Fills `out` (reused between calls: the mutator runs once per execution).
void segments(const Bytes& b, std::vector<Segment>& out) {
  out.clear();
  walk_segments(b, [&](const Segment& s) {
    out.push_back(s);
    return true;
  });
}

// Makes b[begin .. etx + 1] a frame that passes the checks: 7-bit characters
// (with even parity in bit 7 on the wire) and the check byte after ETX.
void seal(Bytes& b, std::size_t begin, std::size_t etx, LrcRule rule, bool wire) {
  std::uint8_t* p = b.data();
  std::uint64_t x8 = 0;  // XOR of the words: each byte of it, of one byte lane
  std::size_t i = begin;
  for (; i + 8 <= etx + 1; i += 8) {
    std::uint64_t c = word_at(p + i) & kChars;
    x8 ^= c;
    if (wire) {
      std::uint64_t odd = c ^ (c >> 4);  // bit 0 of each byte: the parity of its 7 bits
      odd ^= odd >> 2;
      odd ^= odd >> 1;
      c |= (odd & kLow) << 7;
    }
    std::memcpy(p + i, &c, 8);
  }
  x8 ^= x8 >> 32;
  x8 ^= x8 >> 16;
  x8 ^= x8 >> 8;
  auto x = static_cast<std::uint8_t>(x8);
  for (; i <= etx; ++i) {
    const std::uint8_t c = p[i] & 0x7F;
    x ^= c;
    p[i] = wire ? kWithParity[c] : c;
  }
  if (rule == LrcRule::kFromAddress) x ^= p[begin] & 0x7F;  // byte 0 is not covered
  p[etx + 1] = wire ? kWithParity[x] : x;
}

// One encoded request (7-bit characters, address '2') of every catalog
// command in every form, with the codecs' default field values.
const std::vector<Bytes>& templates() {
  static const std::vector<Bytes> all = [] {
    std::vector<Bytes> v;
    for (const auto& info : catalog()) {
      for (const auto& form : info.forms) {
        auto r = build_request(info, form.id, {});
        if (r) {
          v.push_back(encode_request(r.value(), '2'));
        } else {
          Frame f{FrameKind::kCommand, '2', info.code, Bytes(info.request_data_length().value_or(0), '0')};
          v.push_back(encode_frame(f));
        }
      }
    }
    return v;
  }();
  return all;
}

}  // namespace

const Bytes& field_bytes() {
  static const Bytes all = [] {
    std::set<std::uint8_t> s = {ETX, STX, 0x30, 0x31, 0x6F, 0x70, '2', ' ', '+', '-', '.', '*', 0x7F, 0x40};
    for (const auto& info : catalog()) {
      s.insert(info.code);
      for (const auto& form : info.forms)
        for (char c : form.selectors) s.insert(static_cast<std::uint8_t>(c));
    }
    for (const auto& t : dictionary_tokens())
      if (t.bytes.size() == 1) s.insert(t.bytes[0]);
    for (int d = '0'; d <= '9'; ++d) s.insert(static_cast<std::uint8_t>(d));
    return Bytes(s.begin(), s.end());
  }();
  return all;
}

namespace {

// What one mutation works on: the header knobs, the byte stream and its
// frames as found before the mutation, and the random source every choice
// comes from (one draw per choice, in a fixed order, so a seed gives one
// mutation).
struct Mutation {
  std::minstd_rand& rng;
  Bytes& head;
  Bytes& b;
  std::vector<Segment>& found;  // reused storage for segs()
  const Bytes& tokens;
  const std::vector<Bytes>& tmpl;
  std::size_t max_size;
  bool have_segs = false;

  std::size_t pick(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); }
  // The frames of the stream, found when a mutation first needs them (most
  // mutations of a short stream never do).
  const std::vector<Segment>& segs() {
    if (!have_segs) segments(b, found);
    have_segs = true;
    return found;
  }
  const Segment& some_segment() { return segs()[pick(segs().size())]; }
  // The address of the first frame that has one, else '2'.
  std::uint8_t address() {
    for (const auto& s : segs())
      if (s.begin + 1 < b.size()) return b[s.begin + 1] & 0x7F;
    return '2';
  }
};

// Each mutation below returns false when it does not apply to the stream;
// a whole request is inserted instead (insert_request).

// libFuzzer's byte-level mutation of the stream; repaired one time in two.
void byte_level(Mutation& m, bool& repair) {
  const std::size_t n = m.b.size();
  m.b.resize(std::max<std::size_t>(m.max_size - m.head.size(), 1));
  m.b.resize(LLVMFuzzerMutate(m.b.data(), n, m.b.size()));
  repair = m.pick(2) == 0;
}

// A field byte (address, command, or a data byte) to a meaningful value.
bool set_field_byte(Mutation& m) {
  if (m.segs().empty()) return false;
  const Segment& s = m.some_segment();
  const std::size_t last = s.etx != npos ? s.etx : s.end;
  if (last <= s.begin + 1) return false;
  m.b[s.begin + 1 + m.pick(last - s.begin - 1)] = m.tokens[m.pick(m.tokens.size())];
  return true;
}

// A digit one up or down.
bool step_digit(Mutation& m) {
  auto is_digit = [](std::uint8_t b) { return (b & 0x7F) >= '0' && (b & 0x7F) <= '9'; };
  const auto digits = static_cast<std::size_t>(std::count_if(m.b.begin(), m.b.end(), is_digit));
  if (digits == 0) return false;
  std::size_t k = m.pick(digits);  // the k-th digit
  std::uint8_t& d = *std::find_if(m.b.begin(), m.b.end(), [&](std::uint8_t b) { return is_digit(b) && k-- == 0; });
  const std::uint8_t c = d & 0x7F;
  d = static_cast<std::uint8_t>(m.pick(2) ? (c == '9' ? '0' : c + 1) : (c == '0' ? '9' : c - 1));
  return true;
}

// A whole request of any command and form, to the stream's address (one
// time in eight a field value), before a frame or at the end.
void insert_request(Mutation& m) {
  const Bytes& t = m.tmpl[m.pick(m.tmpl.size())];
  const std::uint8_t address = m.pick(8) != 0 ? m.address() : m.tokens[m.pick(m.tokens.size())];
  std::size_t at = m.b.size();
  if (!m.segs().empty() && m.pick(2)) at = m.some_segment().begin;
  m.b.insert(m.b.begin() + static_cast<std::ptrdiff_t>(at), t.begin(), t.end());
  m.b[at + 1] = address;
}

bool delete_frame(Mutation& m) {
  if (m.segs().size() < 2) return false;
  const Segment& s = m.some_segment();
  m.b.erase(m.b.begin() + static_cast<std::ptrdiff_t>(s.begin), m.b.begin() + static_cast<std::ptrdiff_t>(s.end));
  return true;
}

// The stream with frames s and o (o after s) in each other's place.
Bytes swapped(const Bytes& b, const Segment& first, const Segment& second) {
  auto at = [&](std::size_t i) { return b.begin() + static_cast<std::ptrdiff_t>(i); };
  Bytes out(b.begin(), at(first.begin));
  out.insert(out.end(), at(second.begin), at(second.end));
  out.insert(out.end(), at(first.end), at(second.begin));
  out.insert(out.end(), at(first.begin), at(first.end));
  out.insert(out.end(), at(second.end), b.end());
  return out;
}

// A frame duplicated after itself, or two frames swapped.
bool duplicate_or_swap(Mutation& m) {
  if (m.segs().empty()) return false;
  const Segment& s = m.some_segment();
  if (m.segs().size() >= 2 && m.pick(2)) {
    const Segment& o = m.some_segment();
    if (o.begin != s.begin) {
      m.b = s.begin < o.begin ? swapped(m.b, s, o) : swapped(m.b, o, s);
      return true;
    }
  }
  const Bytes copy(m.b.begin() + static_cast<std::ptrdiff_t>(s.begin), m.b.begin() + static_cast<std::ptrdiff_t>(s.end));
  m.b.insert(m.b.begin() + static_cast<std::ptrdiff_t>(s.end), copy.begin(), copy.end());
  return true;
}

// One data byte more or less: a length the command does not have.
bool change_length(Mutation& m) {
  if (m.segs().empty()) return false;
  const Segment& s = m.some_segment();
  const std::size_t last = s.etx != npos ? s.etx : s.end;
  if (last <= s.begin + 3 || m.pick(2)) {
    m.b.insert(m.b.begin() + static_cast<std::ptrdiff_t>(std::min(last, m.b.size())), m.tokens[m.pick(m.tokens.size())]);
  } else {
    m.b.erase(m.b.begin() + static_cast<std::ptrdiff_t>(s.begin + 3 + m.pick(last - s.begin - 3)));
  }
  return true;
}

// Splice: a run of data bytes from a request template over a frame's data.
bool splice_template(Mutation& m) {
  if (m.segs().empty()) return false;
  const Segment& s = m.some_segment();
  const Bytes& t = m.tmpl[m.pick(m.tmpl.size())];
  const std::size_t last = s.etx != npos ? s.etx : s.end;
  if (last <= s.begin + 3 || t.size() <= 5) return false;
  const std::size_t from = 3 + m.pick(t.size() - 5);
  const std::size_t to = s.begin + 3 + m.pick(last - s.begin - 3);
  const std::size_t n = std::min({1 + m.pick(12), t.size() - 2 - from, last - to});
  std::copy_n(t.begin() + static_cast<std::ptrdiff_t>(from), n, m.b.begin() + static_cast<std::ptrdiff_t>(to));
  return true;
}

// A knob of the header.
bool set_knob(Mutation& m) {
  if (m.head.empty()) return false;
  m.head[m.pick(m.head.size())] = static_cast<std::uint8_t>(m.rng());
  return true;
}

// Gives every frame an ETX (one missing ETX is added, one time in two), its
// check byte under the target's LRC rule, and even parity when the stream
// carries it. Frame by frame as they are found: a repair writes only its own
// frame's bytes, never the ones the next frame is found in.
void repair_frames(Mutation& m, const StreamFormat& format) {
  Bytes& b = m.b;
  const bool wire = format.wire && format.wire(m.head.data());
  const LrcRule rule = format.lrc_rule ? format.lrc_rule(m.head.data()) : LrcRule::kFromByte0;
  walk_segments(b, [&](const Segment& s) {
    if (s.etx == npos) {
      if (m.pick(2)) return true;
      // The frames after this one move: repair only this one and stop.
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(s.end), {ETX, 0});
      seal(b, s.begin, s.end, rule, wire);
      return false;
    }
    const bool last = s.etx + 1 >= b.size();
    if (last) b.push_back(0);  // its check byte
    seal(b, s.begin, s.etx, rule, wire);
    return !last;
  });
}

}  // namespace

std::size_t mutate_stream(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed,
                          const StreamFormat& format) {
  std::minstd_rand rng(seed);
  const std::size_t h = format.header;
  if (max_size <= h) return LLVMFuzzerMutate(data, size, max_size);
  // Reused buffers: no allocation per call once they have grown (the mutator
  // runs once per execution, and its cost is part of every execution's).
  struct Scratch {
    Bytes head, b;
    std::vector<Segment> segs;
  };
  thread_local Scratch scratch;
  Bytes& head = scratch.head;
  Bytes& b = scratch.b;
  head.assign(data, data + std::min(size, h));
  head.resize(h, 0);
  b.assign(data + std::min(size, h), data + size);
  Mutation m{rng, head, b, scratch.segs, field_bytes(), templates(), max_size};

  bool repair = m.pick(8) != 0;
  bool applied = true;
  switch (m.pick(10)) {
    case 0: byte_level(m, repair); break;
    case 1:
    case 2: applied = set_field_byte(m); break;
    case 3: applied = step_digit(m); break;
    case 4: applied = false; break;
    case 5: applied = delete_frame(m); break;
    case 6: applied = duplicate_or_swap(m); break;
    case 7: applied = change_length(m); break;
    case 8: applied = splice_template(m); break;
    default: applied = set_knob(m); break;
  }
  if (!applied) insert_request(m);
  if (repair) repair_frames(m, format);
  if (format.draw) format.draw(head.data(), static_cast<std::uint32_t>(rng()));

  const std::size_t n = std::min(h + b.size(), max_size);
  std::copy(head.begin(), head.end(), data);
  std::copy_n(b.begin(), n - h, data + h);
  return n;
}

}  // namespace sabus::fuzz
