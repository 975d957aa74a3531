// The structure-aware mutator of the frame-level fuzz targets
// (fuzz_support.hpp mutate_stream). Kept apart from fuzz_support.cpp because
// it needs libFuzzer's LLVMFuzzerMutate (replay_main.cpp has a stand-in).
#include <algorithm>
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

bool is_start(std::uint8_t b) {
  const std::uint8_t c = b & 0x7F;
  return c == STX || c == ACK || c == NAK;
}

// A frame in the stream: its start byte, its ETX (npos if none) and the end
// of the segment (the next start byte, or the end). The byte after ETX is the
// check byte even when it is 02h (READING-NOTES 7), so it never starts a segment.
struct Segment {
  std::size_t begin, etx, end;
};
constexpr std::size_t npos = static_cast<std::size_t>(-1);

// Fills `out` (reused between calls: the mutator runs once per execution).
void segments(const Bytes& b, std::vector<Segment>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < b.size() && !is_start(b[i])) ++i;
  while (i < b.size()) {
    Segment s{i, npos, b.size()};
    std::size_t j = i + 1;
    while (j < b.size() && (b[j] & 0x7F) != ETX && !is_start(b[j])) ++j;
    if (j < b.size() && (b[j] & 0x7F) == ETX) {
      s.etx = j;
      j += 2;  // ETX and the check byte
    }
    while (j < b.size() && !is_start(b[j])) ++j;
    s.end = std::min(j, b.size());
    out.push_back(s);
    i = s.end;
  }
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
  const std::vector<Segment>& segs;
  const Bytes& tokens;
  const std::vector<Bytes>& tmpl;
  std::size_t max_size;

  std::size_t pick(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); }
  const Segment& some_segment() { return segs[pick(segs.size())]; }
  // The address of the first frame that has one, else '2'.
  std::uint8_t address() const {
    for (const auto& s : segs)
      if (s.begin + 1 < b.size()) return b[s.begin + 1] & 0x7F;
    return '2';
  }
  Bytes some_template() {
    Bytes t = tmpl[pick(tmpl.size())];
    if (pick(8) != 0) t[1] = address();
    else t[1] = tokens[pick(tokens.size())];
    return t;
  }
};

// Each mutation below returns false when it does not apply to the stream;
// a whole request is inserted instead (insert_request).

// libFuzzer's byte-level mutation of the stream; repaired one time in two.
void byte_level(Mutation& m, bool& repair) {
  Bytes buf = m.b;
  buf.resize(std::max<std::size_t>(m.max_size - m.head.size(), 1));
  buf.resize(LLVMFuzzerMutate(buf.data(), m.b.size(), buf.size()));
  m.b = std::move(buf);
  repair = m.pick(2) == 0;
}

// A field byte (address, command, or a data byte) to a meaningful value.
bool set_field_byte(Mutation& m) {
  if (m.segs.empty()) return false;
  const Segment& s = m.some_segment();
  const std::size_t last = s.etx != npos ? s.etx : s.end;
  if (last <= s.begin + 1) return false;
  m.b[s.begin + 1 + m.pick(last - s.begin - 1)] = m.tokens[m.pick(m.tokens.size())];
  return true;
}

// A digit one up or down.
bool step_digit(Mutation& m) {
  std::vector<std::size_t> digits;
  for (std::size_t i = 0; i < m.b.size(); ++i)
    if ((m.b[i] & 0x7F) >= '0' && (m.b[i] & 0x7F) <= '9') digits.push_back(i);
  if (digits.empty()) return false;
  std::uint8_t& d = m.b[digits[m.pick(digits.size())]];
  const std::uint8_t c = d & 0x7F;
  d = static_cast<std::uint8_t>(m.pick(2) ? (c == '9' ? '0' : c + 1) : (c == '0' ? '9' : c - 1));
  return true;
}

// A whole request of any command and form, before a frame or at the end.
void insert_request(Mutation& m) {
  const Bytes t = m.some_template();
  std::size_t at = m.b.size();
  if (!m.segs.empty() && m.pick(2)) at = m.some_segment().begin;
  m.b.insert(m.b.begin() + static_cast<std::ptrdiff_t>(at), t.begin(), t.end());
}

bool delete_frame(Mutation& m) {
  if (m.segs.size() < 2) return false;
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
  if (m.segs.empty()) return false;
  const Segment& s = m.some_segment();
  if (m.segs.size() >= 2 && m.pick(2)) {
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
  if (m.segs.empty()) return false;
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
  if (m.segs.empty()) return false;
  const Segment& s = m.some_segment();
  const Bytes t = m.tmpl[m.pick(m.tmpl.size())];
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
// carries it.
void repair_frames(Mutation& m, const StreamFormat& format, std::vector<Segment>& again) {
  Bytes& b = m.b;
  const bool wire = format.wire && format.wire(m.head.data());
  const LrcRule rule = format.lrc_rule ? format.lrc_rule(m.head.data()) : LrcRule::kFromByte0;
  segments(b, again);
  for (const Segment& s : again) {
    std::size_t etx = s.etx;
    if (etx == npos) {
      if (m.pick(2)) continue;
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(s.end), {ETX, 0});
      // Segments after this one moved: repair only this one and stop.
      etx = s.end;
    } else if (etx + 1 >= b.size()) {
      b.push_back(0);
    }
    for (std::size_t i = s.begin; i <= etx; ++i) b[i] &= 0x7F;
    b[etx + 1] = lrc(ByteView(b).subspan(s.begin, etx + 1 - s.begin), rule);
    if (wire)
      for (std::size_t i = s.begin; i <= etx + 1; ++i) b[i] = with_even_parity(b[i]);
    if (s.etx == npos) break;
  }
}

}  // namespace

std::size_t mutate_stream(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed,
                          const StreamFormat& format) {
  std::minstd_rand rng(seed);
  const std::size_t h = format.header;
  if (max_size <= h) return LLVMFuzzerMutate(data, size, max_size);
  // Reused buffers: no allocation per call once they have grown.
  thread_local Bytes head, b, out;
  thread_local std::vector<Segment> segs, again;
  head.assign(data, data + std::min(size, h));
  head.resize(h, 0);
  b.assign(data + std::min(size, h), data + size);
  segments(b, segs);
  Mutation m{rng, head, b, segs, field_bytes(), templates(), max_size};

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
  if (repair) repair_frames(m, format, again);

  out.assign(head.begin(), head.end());
  out.insert(out.end(), b.begin(), b.end());
  if (out.size() > max_size) out.resize(max_size);
  std::copy(out.begin(), out.end(), data);
  return out.size();
}

}  // namespace sabus::fuzz
