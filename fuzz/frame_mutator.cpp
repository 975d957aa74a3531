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

std::size_t mutate_stream(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed,
                          const StreamFormat& format) {
  std::minstd_rand rng(seed);
  auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); };
  const std::size_t h = format.header;
  if (max_size <= h) return LLVMFuzzerMutate(data, size, max_size);
  // Reused buffers: no allocation per call once they have grown.
  thread_local Bytes head, b, out;
  thread_local std::vector<Segment> segs, again;
  head.assign(data, data + std::min(size, h));
  head.resize(h, 0);
  b.assign(data + std::min(size, h), data + size);
  const Bytes& tokens = field_bytes();
  const auto& tmpl = templates();

  segments(b, segs);
  auto address = [&]() -> std::uint8_t {
    for (const auto& s : segs)
      if (s.begin + 1 < b.size()) return b[s.begin + 1] & 0x7F;
    return '2';
  };
  auto some_template = [&] {
    Bytes t = tmpl[pick(tmpl.size())];
    if (pick(8) != 0) t[1] = address();
    else t[1] = tokens[pick(tokens.size())];
    return t;
  };

  bool repair = pick(8) != 0;
  switch (pick(10)) {
    case 0: {  // libFuzzer's byte-level mutation of the stream
      Bytes buf = b;
      buf.resize(std::max<std::size_t>(max_size - h, 1));
      buf.resize(LLVMFuzzerMutate(buf.data(), b.size(), buf.size()));
      b = std::move(buf);
      repair = pick(2) == 0;
      break;
    }
    case 1:
    case 2: {  // a field byte: address, command, or a data byte, to a meaningful value
      if (segs.empty()) goto insert;
      const Segment& s = segs[pick(segs.size())];
      const std::size_t last = s.etx != npos ? s.etx : s.end;
      if (last <= s.begin + 1) goto insert;
      b[s.begin + 1 + pick(last - s.begin - 1)] = tokens[pick(tokens.size())];
      break;
    }
    case 3: {  // a digit one up or down
      std::vector<std::size_t> digits;
      for (std::size_t i = 0; i < b.size(); ++i)
        if ((b[i] & 0x7F) >= '0' && (b[i] & 0x7F) <= '9') digits.push_back(i);
      if (digits.empty()) goto insert;
      std::uint8_t& d = b[digits[pick(digits.size())]];
      const std::uint8_t c = d & 0x7F;
      d = static_cast<std::uint8_t>(pick(2) ? (c == '9' ? '0' : c + 1) : (c == '0' ? '9' : c - 1));
      break;
    }
    case 4:
    insert: {  // a whole request of any command and form
      const Bytes t = some_template();
      std::size_t at = b.size();
      if (!segs.empty() && pick(2)) at = segs[pick(segs.size())].begin;
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), t.begin(), t.end());
      break;
    }
    case 5: {  // delete a frame
      if (segs.size() < 2) goto insert;
      const Segment& s = segs[pick(segs.size())];
      b.erase(b.begin() + static_cast<std::ptrdiff_t>(s.begin), b.begin() + static_cast<std::ptrdiff_t>(s.end));
      break;
    }
    case 6: {  // duplicate or swap frames
      if (segs.empty()) goto insert;
      const Segment& s = segs[pick(segs.size())];
      Bytes copy(b.begin() + static_cast<std::ptrdiff_t>(s.begin), b.begin() + static_cast<std::ptrdiff_t>(s.end));
      if (segs.size() >= 2 && pick(2)) {
        const Segment& o = segs[pick(segs.size())];
        if (o.begin != s.begin) {
          Bytes other(b.begin() + static_cast<std::ptrdiff_t>(o.begin), b.begin() + static_cast<std::ptrdiff_t>(o.end));
          const Segment& first = s.begin < o.begin ? s : o;
          const Segment& second = s.begin < o.begin ? o : s;
          Bytes out(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(first.begin));
          const Bytes& a2 = s.begin < o.begin ? other : copy;
          const Bytes& b2 = s.begin < o.begin ? copy : other;
          out.insert(out.end(), a2.begin(), a2.end());
          out.insert(out.end(), b.begin() + static_cast<std::ptrdiff_t>(first.end),
                     b.begin() + static_cast<std::ptrdiff_t>(second.begin));
          out.insert(out.end(), b2.begin(), b2.end());
          out.insert(out.end(), b.begin() + static_cast<std::ptrdiff_t>(second.end), b.end());
          b = std::move(out);
          break;
        }
      }
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(s.end), copy.begin(), copy.end());
      break;
    }
    case 7: {  // one data byte more or less: a length the command does not have
      if (segs.empty()) goto insert;
      const Segment& s = segs[pick(segs.size())];
      const std::size_t last = s.etx != npos ? s.etx : s.end;
      if (last <= s.begin + 3 || pick(2)) {
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(std::min(last, b.size())), tokens[pick(tokens.size())]);
      } else {
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(s.begin + 3 + pick(last - s.begin - 3)));
      }
      break;
    }
    case 8: {  // splice: a run of data bytes from a request template over a frame's data
      if (segs.empty()) goto insert;
      const Segment& s = segs[pick(segs.size())];
      const Bytes t = tmpl[pick(tmpl.size())];
      const std::size_t last = s.etx != npos ? s.etx : s.end;
      if (last <= s.begin + 3 || t.size() <= 5) goto insert;
      const std::size_t from = 3 + pick(t.size() - 5);
      const std::size_t to = s.begin + 3 + pick(last - s.begin - 3);
      const std::size_t n = std::min({1 + pick(12), t.size() - 2 - from, last - to});
      std::copy_n(t.begin() + static_cast<std::ptrdiff_t>(from), n, b.begin() + static_cast<std::ptrdiff_t>(to));
      break;
    }
    default: {  // a knob of the header
      if (h == 0) goto insert;
      head[pick(h)] = static_cast<std::uint8_t>(rng());
      break;
    }
  }

  if (repair) {
    const bool wire = format.wire && format.wire(head.data());
    const LrcRule rule = format.lrc_rule ? format.lrc_rule(head.data()) : LrcRule::kFromByte0;
    segments(b, again);
    for (const Segment& s : again) {
      std::size_t etx = s.etx;
      if (etx == npos) {
        if (pick(2)) continue;
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

  out.assign(head.begin(), head.end());
  out.insert(out.end(), b.begin(), b.end());
  if (out.size() > max_size) out.resize(max_size);
  std::copy(out.begin(), out.end(), data);
  return out.size();
}

}  // namespace sabus::fuzz
