#include "sabus/protocol/structured.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <set>

namespace sabus {
namespace {

using namespace fields;
using ParseError = std::optional<std::string>;

std::string trim(std::string_view s) {
  const auto a = s.find_first_not_of(' ');
  if (a == std::string_view::npos) return "";
  const auto b = s.find_last_not_of(' ');
  return std::string(s.substr(a, b - a + 1));
}

bool parse_int(std::string_view s, long long& out) {
  int base = 10;
  bool negative = false;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    negative = s[0] == '-';
    s.remove_prefix(1);
  }
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    base = 16;
    s.remove_prefix(2);
  }
  // from_chars takes a sign of its own: "--5" and "0x-5" are not numbers.
  if (s.empty() || s[0] == '-' || s[0] == '+') return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out, base);
  if (ec != std::errc{} || p != s.data() + s.size()) return false;
  if (negative) out = -out;
  return true;
}

// "-152.5" with 1 decimal -> -1525; at most `decimals` digits after the point.
bool parse_scaled(std::string_view s, int decimals, std::int32_t& out) {
  const std::string t = trim(s);
  const auto dot = t.find('.');
  std::string digits = t;
  int frac = 0;
  if (dot != std::string::npos) {
    frac = static_cast<int>(t.size() - dot - 1);
    if (frac > decimals || frac == 0) return false;
    digits = t.substr(0, dot) + t.substr(dot + 1);
  }
  long long v = 0;
  if (!parse_int(digits, v)) return false;
  // In range before each step, so a long digit string cannot overflow.
  for (;; ++frac) {
    if (v < INT32_MIN || v > INT32_MAX) return false;
    if (frac == decimals) break;
    v *= 10;
  }
  out = static_cast<std::int32_t>(v);
  return true;
}

bool printable_text(std::string_view s, std::size_t width) {
  return s.size() <= width && std::all_of(s.begin(), s.end(), [](char c) { return is_printable(static_cast<std::uint8_t>(c)); });
}

// A single character, or its code as 0xNN (for key codes such as 3Ah).
bool parse_char(std::string_view s, char& out) {
  if (s.size() == 1) {
    out = s[0];
    return true;
  }
  long long v = 0;
  if (s.size() > 2 && parse_int(s, v) && v >= 0 && v <= 0x7F) {
    out = static_cast<char>(v);
    return true;
  }
  return false;
}

ParseError parse(const Text& c, std::string_view s, std::string& v) {
  if (!printable_text(s, c.width)) return "printable text of at most " + std::to_string(c.width) + " characters";
  v = std::string(s);
  while (!v.empty() && v.back() == ' ') v.pop_back();
  return std::nullopt;
}
ParseError parse(const Fill&, std::string_view, Unit&) { return "nothing: this field is fixed by the spec"; }
ParseError parse(const Reserved& c, std::string_view s, std::string& v) {
  if (!printable_text(s, c.width)) return "printable text of at most " + std::to_string(c.width) + " characters";
  v = std::string(s);
  return std::nullopt;
}
ParseError parse(const Digits& c, std::string_view s, std::uint32_t& v) {
  long long x = 0;
  long long max = 1;
  for (std::size_t i = 0; i < c.width; ++i) max *= 10;
  if (!parse_int(trim(s), x) || x < 0 || x >= max) return "a whole number 0-" + std::to_string(max - 1);
  v = static_cast<std::uint32_t>(x);
  return std::nullopt;
}
ParseError parse(const SignedDigits& c, std::string_view s, std::int32_t& v) {
  if (!parse_scaled(s, c.decimals, v))
    return "a number with at most " + std::to_string(c.decimals) + " decimal(s), e.g. -152.5";
  return std::nullopt;
}
ParseError parse_optional_scaled(std::string_view s, int decimals, std::optional<std::int32_t>& v) {
  if (trim(s).empty()) {
    v.reset();
    return std::nullopt;
  }
  std::int32_t x = 0;
  if (!parse_scaled(s, decimals, x)) return "a number with at most " + std::to_string(decimals) + " decimal(s), or blank";
  v = x;
  return std::nullopt;
}
ParseError parse(const ZeroPaddedDecimal& c, std::string_view s, std::optional<std::int32_t>& v) {
  return parse_optional_scaled(s, c.decimals, v);
}
ParseError parse(const LeftDecimal& c, std::string_view s, std::optional<std::int32_t>& v) {
  return parse_optional_scaled(s, c.decimals, v);
}
ParseError parse(const Bits& c, std::string_view s, std::uint8_t& v) {
  long long x = 0;
  if (!parse_int(trim(s), x) || x < 0 || (x & ~static_cast<long long>(c.mask)) != 0)
    return "the data bits, a number within mask " + std::to_string(c.mask);
  v = static_cast<std::uint8_t>(x);
  return std::nullopt;
}
ParseError parse(const Choice& c, std::string_view s, char& v) {
  char ch = 0;
  if (!parse_char(s, ch)) return "one of " + c.allowed();
  v = ch;  // not checked against the set: a vector may send a wrong value on purpose
  return std::nullopt;
}
ParseError parse(const AnyChar&, std::string_view s, char& v) {
  if (!parse_char(s, v)) return "one character, or its code as 0xNN";
  return std::nullopt;
}
ParseError parse(const PresetIndex&, std::string_view s, PresetRef& v) {
  // "preset 5" (A=1) or "data" / "data 0" (A=0).
  const std::string t = trim(s);
  const bool preset = t.rfind("preset", 0) == 0;
  if (!preset && t.rfind("data", 0) != 0) return "\"preset N\" or \"data\"";
  long long x = 0;
  const std::string rest = trim(t.substr(preset ? 6 : 4));
  if (!rest.empty() && (!parse_int(rest, x) || x < 0 || x > 99)) return "an index 0-99 after preset/data";
  v = {preset, static_cast<std::uint8_t>(x)};
  return std::nullopt;
}
ParseError parse(const Opaque&, std::string_view s, std::string& v) {
  if (!printable_text(s, 200)) return "printable text";
  v = std::string(s);
  return std::nullopt;
}

// A number the field's wire format can carry: its codec writes it and reads
// back the same value. The codecs write a fixed width and drop what does not
// fit (azimuth "-1000" in 2A's six characters, in hundredths, went out as
// "-00000", which reads as 0). A value out of the spec's range but within the width (azimuth
// 999.0) is still sent: vectors do that on purpose.
template <class C>
bool carried(const C& c, const typename C::value_type& v) {
  std::array<std::uint8_t, 32> wire{};
  if (c.width > wire.size()) return false;
  c.encode(v, Out(wire.data(), c.width));
  typename C::value_type back{};
  return !c.decode(ByteView(wire.data(), c.width), back) && back == v;
}
template <class C>
constexpr bool kNumeric = std::is_same_v<C, SignedDigits> || std::is_same_v<C, ZeroPaddedDecimal> ||
                          std::is_same_v<C, LeftDecimal>;

// Assigns named values to a layout's members.
struct Assign {
  const std::map<std::string, std::string>& values;
  std::set<std::string> used;
  std::optional<std::string> error;
  template <class C, class T, class... M>
  void operator()(std::string_view name, const C& c, T& member, M&&...) {
    auto it = values.find(std::string(name));
    if (it == values.end() || error) return;
    used.insert(it->first);
    if (auto e = parse(c, it->second, member)) {
      error = "field \"" + it->first + "\": expected " + *e + ", got \"" + it->second + "\"";
    } else if constexpr (kNumeric<C>) {
      if (!carried(c, member))
        error = "field \"" + it->first + "\": \"" + it->second + "\" does not fit its " + std::to_string(c.width) +
                " characters on the wire";
    }
  }
};

struct Names {
  std::vector<std::string>& out;
  template <class C, class T, class... M>
  void operator()(std::string_view name, const C&, T&, M&&...) {
    if (std::find(out.begin(), out.end(), name) == out.end()) out.emplace_back(name);
  }
};

template <class T>
Expected<Request> assign_layout(T m, const std::map<std::string, std::string>& fields, const CommandInfo& info,
                                std::string_view form) {
  Assign a{fields, {}, std::nullopt};
  T::layout(m, a);
  if (a.error) return DecodeError{0, "fields", *a.error, ""};
  for (const auto& [name, value] : fields) {
    if (a.used.count(name)) continue;
    std::string known;
    for (const auto& n : request_field_names(info, form)) known += (known.empty() ? "" : ", ") + n;
    return DecodeError{0, "fields", "a field of " + std::string(info.name) + (form.empty() ? "" : " form " + std::string(form)) +
                                         " (" + known + ")",
                       "\"" + name + "\""};
  }
  if constexpr (std::is_same_v<T, AutoMoveStored> || std::is_same_v<T, AutoMoveAzEl> ||
                std::is_same_v<T, AutoMoveCounts> || std::is_same_v<T, AutoMoveAxis> || std::is_same_v<T, AutoMovePol>)
    return Request{AutoMove{std::move(m)}};
  else
    return Request{std::move(m)};
}

template <class T>
T with_selector(std::string_view form) {
  T m{};
  const char sel = form.empty() ? 0 : form[0];
  if constexpr (std::is_base_of_v<JogFields, T>) {
    if (sel) m.direction = sel;
  } else if constexpr (std::is_same_v<T, PolPreset>) {
    if (sel) m.pol = sel;
  } else if constexpr (std::is_same_v<T, Misc>) {
    if (sel) m.sub = sel;
  } else if constexpr (std::is_same_v<T, RemoteLocate> || std::is_same_v<T, RemoteStore>) {
    m.preset.preset = form == "preset";
  } else if constexpr (std::is_same_v<T, AutoMoveAxis>) {
    m.axis = 'A';
  }
  return m;
}

// Calls f(default message) for the request type of `info` in `form`.
template <class F>
auto with_request_type(const CommandInfo& info, std::string_view form, F&& f) -> decltype(f(StatusPoll{})) {
  if (info.code == AutoMove::kCode) {
    if (form == "1") return f(AutoMoveStored{});
    if (form == "2A") return f(AutoMoveAzEl{});
    if (form == "2B") return f(AutoMoveCounts{});
    if (form == "2C") return f(AutoMoveAxis{});
    return f(AutoMovePol{});
  }
  std::optional<decltype(f(StatusPoll{}))> out;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    auto one = [&]<class T>(std::type_identity<T>) {
      if constexpr (!std::is_same_v<T, AutoMove>) {
        if (T::kCode != info.code) return false;
        out.emplace(f(with_selector<T>(form)));
        return true;
      }
      return false;
    };
    (void)(one(std::type_identity<std::variant_alternative_t<I, Request>>{}) || ...);
  }(std::make_index_sequence<std::variant_size_v<Request>>{});
  return *std::move(out);
}

}  // namespace

Expected<Request> build_request(const CommandInfo& info, std::string_view form,
                                const std::map<std::string, std::string>& fields) {
  if (info.forms.size() > 1 && !info.form_by_id(form)) {
    std::string ids;
    for (const auto& f : info.forms) ids += (ids.empty() ? "" : ", ") + std::string(f.id);
    return DecodeError{0, "form", "a form of " + std::string(info.name) + ": " + ids, "\"" + std::string(form) + "\""};
  }
  return with_request_type(info, form, [&](auto m) { return assign_layout(std::move(m), fields, info, form); });
}

std::vector<std::string> request_field_names(const CommandInfo& info, std::string_view form) {
  std::vector<std::string> names;
  with_request_type(info, form, [&](auto m) {
    Names n{names};
    decltype(m)::layout(m, n);
    return 0;
  });
  return names;
}

std::vector<std::string> reply_field_names(const CommandInfo& info) {
  std::vector<std::string> names = {"start", "address", "command"};
  Names n{names};
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    auto one = [&]<class T>(std::type_identity<T>) {
      if constexpr (requires { T::kKind; }) {
        if (T::kKind != info.reply) return;
        T m{};
        T::layout(m, n);
        if constexpr (requires { m.index = std::nullopt; }) {  // the empty-slot form
          m.index = std::nullopt;
          T::layout(m, n);
        }
      }
    };
    (one(std::type_identity<std::variant_alternative_t<I, Reply>>{}), ...);
  }(std::make_index_sequence<std::variant_size_v<Reply>>{});
  names.push_back("offline");
  names.push_back("ETX");
  names.push_back("check byte");
  return names;
}

}  // namespace sabus
