#include "sabus/protocol/codec.hpp"

#include <algorithm>
#include <cstdio>
#include <type_traits>
#include <utility>

#include "sabus/protocol/receiver.hpp"

namespace sabus {
namespace {

// A field's width on the wire; an Opaque field of width 0 takes the rest.
template <class C, class T>
std::size_t width_for_encode(const C& c, const T& value) {
  if constexpr (std::is_same_v<C, fields::Opaque>) {
    if (c.width == 0) return value.size();
  }
  (void)value;
  return c.width;
}
template <class C>
std::size_t width_for_decode(const C& c, std::size_t remaining) {
  if constexpr (std::is_same_v<C, fields::Opaque>) {
    if (c.width == 0) return remaining;
  }
  (void)remaining;
  return c.width;
}

struct Measurer {
  std::size_t size = 0;
  template <class C, class T, class... M>
  void operator()(std::string_view, const C& c, const T& value, M&&...) {
    size += width_for_encode(c, value);
  }
};

struct Encoder {
  fields::Out out;
  std::size_t pos = 0;
  template <class C, class T, class... M>
  void operator()(std::string_view, const C& c, const T& value, M&&...) {
    const std::size_t w = width_for_encode(c, value);
    c.encode(value, out.subspan(pos, w));
    pos += w;
  }
};

struct Decoder {
  ByteView in;
  std::size_t pos = 0;
  std::optional<DecodeError> error;
  template <class C, class T, class... M>
  void operator()(std::string_view name, const C& c, T& value, M&&...) {
    if (error) return;
    const std::size_t w = width_for_decode(c, in.size() - pos);
    if (pos + w > in.size()) {
      error = DecodeError{kFrameDataStart + in.size(), std::string(name), std::to_string(w) + " more byte(s)", "ETX"};
      return;
    }
    if (auto e = c.decode(in.subspan(pos, w), value)) {
      // A field may report the position just past its last byte ("a digit"
      // after "-"): name the last byte instead.
      const std::size_t at = pos + std::min(e->index, w - 1);
      error = DecodeError{kFrameDataStart + at, std::string(name), e->expected, describe_byte(in[at])};
    }
    pos += w;
  }
};

std::string raw_text(ByteView b) {
  if (b.size() == 1) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "0x%02x", b[0]);
    return buf;
  }
  std::string s = "\"";
  for (auto c : b) {
    if (c >= 0x20 && c < 0x7F) {
      s += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      s += buf;
    }
  }
  return s + "\"";
}

struct Describer {
  ByteView in;
  std::vector<FieldDescription>& out;
  std::optional<DecodeError>& error;
  std::size_t pos = 0;
  bool truncated = false;  // the data ended inside a field: later fields are not described
  template <class C, class T, class... M>
  void operator()(std::string_view name, const C& c, T& value, M&&... meaning) {
    if (truncated) return;
    const std::size_t remaining = in.size() - pos;
    const std::size_t w = width_for_decode(c, remaining);
    if (w > remaining) {
      truncated = true;
      const std::string want = std::to_string(w) + " byte(s) for " + std::string(name);
      if (!error) error = DecodeError{kFrameDataStart + in.size(), std::string(name), want, "ETX"};
      if (remaining > 0)
        out.push_back({kFrameDataStart + pos, kFrameDataStart + in.size() - 1, std::string(name), raw_text(in.subspan(pos)),
                       "invalid: the data ends here, expected " + want, false, fields::KindOf<C>::value});
      return;
    }
    if (w == 0) return;
    ByteView slice = in.subspan(pos, w);
    FieldDescription d{kFrameDataStart + pos, kFrameDataStart + pos + w - 1, std::string(name), raw_text(slice), "", true,
                       fields::KindOf<C>::value};
    if (auto e = c.decode(slice, value)) {
      const std::size_t at = std::min(e->index, w - 1);  // see Decoder
      d.ok = false;
      d.meaning = "invalid: expected " + e->expected;
      if (w > 1) d.meaning += " at byte " + std::to_string(kFrameDataStart + pos + at);
      if (!error) error = DecodeError{kFrameDataStart + pos + at, std::string(name), e->expected, describe_byte(slice[at])};
    } else if constexpr (sizeof...(M) > 0) {
      d.meaning = (meaning(value), ...);
    } else {
      d.meaning = c.meaning(value);
    }
    out.push_back(std::move(d));
    pos += w;
  }
};

template <class T>
Bytes encode_layout(const T& m) {
  Measurer measure;
  T::layout(m, measure);
  Bytes out(measure.size);
  Encoder enc{out, 0};
  T::layout(m, enc);
  return out;
}

template <class T>
Expected<T> decode_layout(ByteView data) {
  T m{};
  Decoder dec{data, 0, std::nullopt};
  T::layout(m, dec);
  if (dec.error) return *dec.error;
  if (dec.pos != data.size())
    return DecodeError{kFrameDataStart + dec.pos, "data", "ETX after " + std::to_string(dec.pos) + " data bytes",
                       std::to_string(data.size()) + " data bytes"};
  return m;
}

// ---- auto move: byte 3 selects the form (§3.3; READING-NOTES 13, 31) -------
// The SignedDigits fields of one layout, by their place in the data.
struct SignedSpans {
  std::vector<DataSpan>& out;
  std::size_t pos = 0;
  template <class C, class T, class... M>
  void operator()(std::string_view, const C& c, T&, M&&...) {
    const std::size_t w = width_for_decode(c, 0);  // the forms' fields all have fixed widths
    if constexpr (std::is_same_v<C, fields::SignedDigits>) out.push_back({pos, w});
    pos += w;
  }
};

// The LeftDecimal fields with a decimal digit whose text has no '.'.
struct WholeDecimals {
  ByteView data;
  std::vector<DataSpan>& out;
  std::size_t pos = 0;
  template <class C, class T, class... M>
  void operator()(std::string_view, const C& c, T&, M&&...) {
    const std::size_t w = width_for_decode(c, data.size() - std::min(pos, data.size()));
    if constexpr (std::is_same_v<C, fields::LeftDecimal>) {
      if (c.decimals > 0 && pos + w <= data.size()) {
        const ByteView text = data.subspan(pos, w);
        const bool blank = std::all_of(text.begin(), text.end(), [](std::uint8_t b) { return b == ' '; });
        if (!blank && std::find(text.begin(), text.end(), '.') == text.end()) out.push_back({pos, w});
      }
    }
    pos += w;
  }
};

}  // namespace

std::vector<DataSpan> decimals_without_point(const Request& request, ByteView data) {
  std::vector<DataSpan> spans;
  std::visit(
      [&]<class T>(const T& m) {
        if constexpr (requires(T& t, WholeDecimals& v) { T::layout(t, v); }) {
          T copy = m;  // layout takes its message by reference
          WholeDecimals walk{data, spans};
          T::layout(copy, walk);
        }
      },
      request);
  return spans;
}

std::vector<DataSpan> auto_move_signed_targets(std::uint8_t form_byte) {
  std::vector<DataSpan> spans;
  SignedSpans collect{spans};
  auto walk = [&]<class Form>(Form form) { Form::layout(form, collect); };
  switch (form_byte) {
    case ' ': walk(AutoMoveAzEl{}); break;
    case 'A':
    case 'E': walk(AutoMoveAxis{}); break;
    case 'P': walk(AutoMovePol{}); break;
    default: break;  // forms 1 and 2B have no signed field
  }
  return spans;
}

std::optional<TargetSpelling> spelling_of(ByteView t) {
  const auto minus = std::find(t.begin(), t.end(), '-');
  if (minus == t.end()) return std::nullopt;
  auto digit = [](std::uint8_t c) { return c >= '0' && c <= '9'; };
  const bool digits_after = std::all_of(minus + 1, t.end(), digit);
  if (minus == t.begin()) {
    if (t.size() > 1 && t[1] == '0' && digits_after) return TargetSpelling::kSignFirst;
    return std::nullopt;
  }
  if (digits_after && minus + 1 != t.end() && std::all_of(t.begin(), minus, [](std::uint8_t c) { return c == '0'; }))
    return TargetSpelling::kZerosFirst;
  return std::nullopt;
}

namespace {
// Each signed target of 32h `data` the data holds whole.
template <class T, class F>
void for_each_target(std::span<T> data, F&& f) {
  if (data.empty()) return;
  for (const DataSpan& t : auto_move_signed_targets(data[0]))
    if (t.first + t.width <= data.size()) f(data.subspan(t.first, t.width));
}
}  // namespace

bool auto_move_spells(ByteView data, TargetSpelling spelling) {
  bool found = false;
  for_each_target(data, [&](ByteView t) { found = found || spelling_of(t) == spelling; });
  return found;
}

bool respell_target(std::span<std::uint8_t> t, TargetSpelling to) {
  const auto now = spelling_of(t);
  if (!now || *now == to) return false;
  const auto minus = std::find(t.begin(), t.end(), '-');
  if (to == TargetSpelling::kSignFirst) {
    std::rotate(t.begin(), minus, minus + 1);  // "00-50" -> "-0050"
  } else {
    // "-0050" -> "00-50": the sign moves right up to the digits without
    // their padding, zeros fill its place.
    const auto digits = std::find_if(t.begin() + 1, t.end() - 1, [](std::uint8_t c) { return c != '0'; });
    std::fill(t.begin(), digits - 1, '0');
    *(digits - 1) = '-';
  }
  return true;
}

bool respell_auto_move(Bytes& data, TargetSpelling to) {
  bool changed = false;
  for_each_target(std::span<std::uint8_t>(data), [&](std::span<std::uint8_t> t) { changed = respell_target(t, to) || changed; });
  return changed;
}

namespace {

Bytes encode_auto_move(const AutoMove& a) {
  return std::visit([](const auto& form) { return encode_layout(form); }, a.form);
}

template <class Form>
Expected<AutoMove> decode_form(ByteView data) {
  auto r = decode_layout<Form>(data);
  if (!r) return r.error();
  return AutoMove{std::move(r).value()};
}

Expected<AutoMove> decode_auto_move(ByteView data) {
  switch (data[0]) {
    case ' ': {
      // Two right-justified numbers are form 2A; anything else is a name
      // (form 1). Whether a name that parses as numbers is stored is the
      // controller's decision (READING-NOTES 31).
      if (auto two_a = decode_form<AutoMoveAzEl>(data)) return two_a;
      return decode_form<AutoMoveStored>(data);
    }
    case 'H':
    case 'V': return decode_form<AutoMoveStored>(data);
    case 'C': return decode_form<AutoMoveCounts>(data);
    case 'A':
    case 'E': return decode_form<AutoMoveAxis>(data);
    case 'P': return decode_form<AutoMovePol>(data);
    default:
      return DecodeError{3, "polarization", "one of ' ', 'H', 'V', 'C', 'A', 'E', 'P' (§3.3 byte 3)",
                         describe_byte(data[0])};
  }
}

template <class T>
Bytes encode_request_alt(const T& m) {
  if constexpr (std::is_same_v<T, AutoMove>) return encode_auto_move(m);
  else return encode_layout(m);
}

template <class T>
Expected<Request> decode_request_alt(ByteView data) {
  if constexpr (std::is_same_v<T, AutoMove>) {
    auto r = decode_auto_move(data);
    if (!r) return r.error();
    return Request{std::move(r).value()};
  } else {
    auto r = decode_layout<T>(data);
    if (!r) return r.error();
    return Request{std::move(r).value()};
  }
}

template <std::size_t... I>
Expected<Request> decode_request_by_code(std::uint8_t code, ByteView data, std::index_sequence<I...>) {
  std::optional<Expected<Request>> r;
  (void)((std::variant_alternative_t<I, Request>::kCode == code
              ? (r.emplace(decode_request_alt<std::variant_alternative_t<I, Request>>(data)), true)
              : false) ||
         ...);
  if (!r) return DecodeError{2, "command", "a command code 30h-48h", describe_byte(code)};
  return *std::move(r);
}

template <class T>
concept HasReplyKind = requires { T::kKind; };

template <std::size_t... I>
Expected<Reply> decode_reply_by_kind(ReplyKind kind, ByteView data, std::index_sequence<I...>) {
  std::optional<Expected<Reply>> r;
  auto try_one = [&]<class T>(std::type_identity<T>) {
    if constexpr (HasReplyKind<T>) {
      if (T::kKind != kind) return false;
      auto d = decode_layout<T>(data);
      if (d) r.emplace(Reply{std::move(d).value()});
      else r.emplace(d.error());
      return true;
    }
    return false;
  };
  (void)(try_one(std::type_identity<std::variant_alternative_t<I, Reply>>{}) || ...);
  if (!r) return DecodeError{2, "command", "a command with a reply layout", ""};
  return *std::move(r);
}

template <class T, std::size_t... I>
void describe_by_kind(ReplyKind kind, Describer& d, std::index_sequence<I...>) {
  auto try_one = [&]<class R>(std::type_identity<R>) {
    if constexpr (HasReplyKind<R>) {
      if (R::kKind != kind) return false;
      R m{};
      R::layout(m, d);
      return true;
    }
    return false;
  };
  (void)(try_one(std::type_identity<std::variant_alternative_t<I, T>>{}) || ...);
}

template <std::size_t... I>
void describe_request_by_code(std::uint8_t code, Describer& d, std::index_sequence<I...>) {
  auto try_one = [&]<class R>(std::type_identity<R>) {
    if (R::kCode != code) return false;
    if constexpr (std::is_same_v<R, AutoMove>) {
      // Describe the form that decodes (or the form byte 3 selects).
      auto decoded = decode_auto_move(d.in);
      AutoMove m = decoded ? decoded.value() : AutoMove{};
      if (!decoded) {
        switch (d.in[0]) {
          case 'C': m.form = AutoMoveCounts{}; break;
          case 'A':
          case 'E': m.form = AutoMoveAxis{}; break;
          case 'P': m.form = AutoMovePol{}; break;
          case ' ': m.form = AutoMoveAzEl{}; break;
          default: m.form = AutoMoveStored{}; break;
        }
      }
      std::visit([&](auto& form) { std::decay_t<decltype(form)>::layout(form, d); }, m.form);
    } else {
      R m{};
      R::layout(m, d);
    }
    return true;
  };
  (void)(try_one(std::type_identity<std::variant_alternative_t<I, Request>>{}) || ...);
}

DecodeError length_error(const CommandInfo& info, std::size_t got, std::size_t want, bool reply) {
  return DecodeError{got > want ? want - 2 : got - 2, "length",
                     std::to_string(want) + " bytes for a " + std::string(reply ? "reply to " : "") +
                         std::string(info.name) + " (§" + std::string(info.paragraph) + ")",
                     std::to_string(got) + " bytes"};
}

std::string address_text(std::uint8_t a) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "0x%02x '%c' (%u)", a, a >= 0x20 && a < 0x7F ? a : '?', a);
  return buf;
}

// Byte 0 of the command frame a slave's receiver last began in `b`, complete
// or not: the last frame it reports, or the last run it discards that begins
// with STX (bad LRC, another address, cut short, ...). So the frame is the
// one the last STX begins (READING-NOTES 7: an STX restarts reception in
// state 2 or 3), except that an STX where the check byte belongs is the
// check byte (state 4). nullopt: no STX begins a frame.
class LastCommandFrame final : public ReceiverSink {
 public:
  explicit LastCommandFrame(ByteView bytes) : bytes_(bytes) {}
  void on_frame(const FrameView& f) override { start_ = static_cast<std::size_t>(f.offset); }
  void on_discard(const Discard& d) override {
    if (d.reason != DiscardReason::kUnknown && d.offset < bytes_.size() && bytes_[d.offset] == STX)
      start_ = static_cast<std::size_t>(d.offset);
  }
  std::optional<std::size_t> start() const { return start_; }

 private:
  ByteView bytes_;
  std::optional<std::size_t> start_;
};

std::optional<std::size_t> command_frame_start(ByteView b) {
  ReceiverOptions options = ReceiverOptions::slave_any_address();
  options.parity = Parity::kNone;  // 7-bit characters, as a vector's send is written
  Receiver receiver(options);
  LastCommandFrame last(b);
  receiver.feed(b, last);
  receiver.finish(last);
  return last.start();
}

}  // namespace

std::string_view AutoMove::form_id() const {
  return std::visit([](const auto& f) { return std::decay_t<decltype(f)>::kForm; }, form);
}

std::uint8_t command_code(const Request& r) {
  return std::visit([](const auto& m) { return std::decay_t<decltype(m)>::kCode; }, r);
}

std::string_view form_of(const Request& r) {
  const CommandInfo* info = find_command(command_code(r));
  return std::visit(
      [&](const auto& m) -> std::string_view {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, AutoMove>) return m.form_id();
        else if constexpr (std::is_base_of_v<JogFields, T>) return info->form_for_selector(m.direction)->id;
        else if constexpr (std::is_same_v<T, PolPreset>) return info->form_for_selector(m.pol)->id;
        else if constexpr (std::is_same_v<T, Misc>) return info->form_for_selector(m.sub)->id;
        else if constexpr (std::is_same_v<T, RemoteLocate> || std::is_same_v<T, RemoteStore>)
          return m.preset.preset ? "preset" : "data";
        else return info->forms.front().id;
      },
      r);
}

CommandForm classify_command(ByteView b) {
  CommandForm out;
  const std::optional<std::size_t> start = command_frame_start(b);
  if (!start || *start + 2 >= b.size()) return out;
  out.info = find_command(b[*start + 2]);
  if (!out.info) return out;
  if (out.info->forms.size() == 1) {
    out.form = &out.info->forms.front();
    return out;
  }
  if (auto frame = decode_frame(ByteView(b).subspan(*start)); frame) {
    if (auto request = decode_request(frame.value()); request) {
      out.form = out.info->form_by_id(form_of(request.value()));
      return out;
    }
  }
  if (out.info->form_selector_offset) {
    const std::size_t at = *start + *out.info->form_selector_offset;
    if (at < b.size()) out.form = out.info->form_for_selector(b[at]);
  }
  return out;
}

Bytes encode_request_data(const Request& r) {
  return std::visit([](const auto& m) { return encode_request_alt(m); }, r);
}

Frame request_frame(const Request& r, std::uint8_t address) {
  return Frame{FrameKind::kCommand, address, command_code(r), encode_request_data(r)};
}

Bytes encode_request(const Request& r, std::uint8_t address) { return encode_frame(request_frame(r, address)); }

Expected<Request> decode_request(const Frame& f) {
  if (f.kind != FrameKind::kCommand) return DecodeError{0, "start", "STX (a command frame)", describe_byte(start_byte(f.kind))};
  const CommandInfo* info = find_command(f.command);
  if (!info) return DecodeError{2, "command", "a command code 30h-48h (§3 Command Set)", describe_byte(f.command)};
  const std::size_t length = f.data.size() + kFrameOverhead;
  if (info->request_length && length != *info->request_length)
    return length_error(*info, length, *info->request_length, false);
  if (!info->request_length && f.data.size() < 2)
    return DecodeError{kFrameDataStart, "index", "a 2-digit index", "ETX"};
  return decode_request_by_code(f.command, f.data, std::make_index_sequence<std::variant_size_v<Request>>{});
}

Expected<Frame> reply_frame(const Reply& reply, std::uint8_t address, std::uint8_t command) {
  const CommandInfo* info = find_command(command);
  return std::visit(
      [&](const auto& m) -> Expected<Frame> {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, NakReply>) {
          return nak_reply(address, command);
        } else if constexpr (std::is_same_v<T, OfflineReply>) {
          return offline_reply(address, command);
        } else {
          if (!info || info->reply != T::kKind)
            return DecodeError{2, "command",
                               "a command whose reply is " + std::string(to_string(T::kKind)),
                               describe_byte(command)};
          return Frame{FrameKind::kAck, address, command, encode_layout(m)};
        }
      },
      reply);
}

Expected<Bytes> encode_reply(const Reply& reply, std::uint8_t address, std::uint8_t command) {
  auto f = reply_frame(reply, address, command);
  if (!f) return f.error();
  return encode_frame(f.value());
}

Expected<Reply> decode_reply(const Frame& f) {
  if (f.kind == FrameKind::kCommand) return DecodeError{0, "start", "ACK or NAK (a reply frame)", describe_byte(STX)};
  if (f.kind == FrameKind::kNak) {
    if (!f.data.empty())
      return DecodeError{kFrameDataStart, "ETX", "ETX after the command byte (§3 NAK Reply: NAK A CC ETX LRC)",
                         describe_byte(f.data[0])};
    return Reply{NakReply{}};
  }
  if (is_offline_reply(f)) return Reply{OfflineReply{}};
  const CommandInfo* info = find_command(f.command);
  if (!info) return DecodeError{2, "command", "a command code 30h-48h (§3 Command Set)", describe_byte(f.command)};
  const std::size_t length = f.data.size() + kFrameOverhead;
  if (info->reply_length && length != *info->reply_length) return length_error(*info, length, *info->reply_length, true);
  return decode_reply_by_kind(info->reply, f.data, std::make_index_sequence<std::variant_size_v<Reply>>{});
}

std::string FieldDescription::line() const {
  char range[32];
  if (first == last) std::snprintf(range, sizeof range, "byte %zu", first);
  else std::snprintf(range, sizeof range, "bytes %zu-%zu", first, last);
  char buf[512];
  std::snprintf(buf, sizeof buf, "%-13s %-22s %-14s %s%s", range, name.c_str(), raw.c_str(), ok ? "" : "!! ",
                meaning.c_str());
  return buf;
}

FrameDescription describe_frame(ByteView b) {
  FrameDescription out;
  auto add = [&](std::size_t first, std::size_t last, std::string name, std::string meaning, bool ok = true,
                 fields::Kind kind = fields::Kind::kHeader) {
    out.fields.push_back({first, last, std::move(name), raw_text(b.subspan(first, last - first + 1)),
                          std::move(meaning), ok, kind});
  };
  auto frame = decode_frame(b);
  if (!frame) out.error = frame.error();
  if (b.size() < 5) {
    out.summary = "short frame of " + std::to_string(b.size()) + " bytes";
    for (std::size_t i = 0; i < b.size(); ++i) add(i, i, "byte", describe_byte(b[i]), false, fields::Kind::kUndescribed);
    return out;
  }
  const std::uint8_t start = b[0];
  const bool is_command = start == STX;
  const std::size_t etx = b.size() - 2;
  const CommandInfo* info = find_command(b[2]);

  add(0, 0, "start",
      start == STX   ? "STX: command"
      : start == ACK ? "ACK: command acknowledged"
      : start == NAK ? "NAK: command not acknowledged"
                     : "not STX, ACK or NAK",
      start == STX || start == ACK || start == NAK);
  add(1, 1, "address", address_text(b[1]), is_valid_address(b[1]));
  add(2, 2, "command",
      info ? std::string(info->name) + " (§" + std::string(info->paragraph) + ")" : "unknown command code",
      info != nullptr);

  std::string kind_text = is_command ? "command" : start == ACK ? "ACK" : "NAK";
  char code[8];
  std::snprintf(code, sizeof code, "%02Xh", b[2]);
  out.summary = kind_text + " " + code + " " + (info ? std::string(info->name) : "(unknown)") +
                (is_command ? " to " : " from ") + address_text(b[1]);

  ByteView data = b.subspan(kFrameDataStart, etx - kFrameDataStart);
  std::optional<DecodeError> field_error;
  Describer d{data, out.fields, field_error, 0, false};
  bool described = false;
  if (start == NAK) {
    out.summary += ", NAK reply";
  } else if (start == ACK && data.size() == 1 && data[0] == kOfflineMarker) {
    add(3, 3, "offline", "'F': remote control disabled (§3 Online/Offline Reply)");
    out.summary += ", offline reply";
    described = true;
  } else if (info) {
    const auto want = is_command ? info->request_length : info->reply_length;
    const std::size_t got = b.size();
    if (want && *want != got) {
      if (!out.error) out.error = length_error(*info, got, *want, !is_command);
      out.summary += ", wrong length";
    } else if (is_command) {
      describe_request_by_code(b[2], d, std::make_index_sequence<std::variant_size_v<Request>>{});
      described = true;
    } else {
      describe_by_kind<Reply>(info->reply, d, std::make_index_sequence<std::variant_size_v<Reply>>{});
      out.summary += ", " + std::string(to_string(info->reply)) + " reply";
      described = true;
    }
  }
  if (!described && !data.empty() && !(start == ACK && data.size() == 1 && data[0] == kOfflineMarker))
    add(kFrameDataStart, etx - 1, "data", std::to_string(data.size()) + " byte(s) not described", false,
        fields::Kind::kUndescribed);
  if (field_error && !out.error) out.error = field_error;

  add(etx, etx, "ETX", b[etx] == ETX ? "end of text" : "expected ETX", b[etx] == ETX);
  const std::uint8_t want_lrc = lrc(b.first(b.size() - 1));
  add(b.size() - 1, b.size() - 1, "check byte",
      b.back() == want_lrc ? "LRC ok" : "bad LRC, expected " + describe_byte(want_lrc), b.back() == want_lrc);
  return out;
}

}  // namespace sabus
