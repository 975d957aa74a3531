// Profile expressions in vectors (vectors/README.md, "Profile expressions"):
// a value written as "{expr}" in a send's field, a matcher, a wait or a raw
// template is computed from the device's profile and the values the vector
// captured, so that a vector rests on what the profile says, never on the
// values of one shipped profile. "{home(az)}", "{jog_ms(el, S)}",
// "{$az0 + 1.5}", "{first_empty(presets)}". Text outside the braces is kept;
// "{{" and "}}" are literal braces.
//
// An expression can be unavailable on a profile (no empty preset slot, an
// axis too short for the jog asked for): the vector is then skipped with the
// capability it lacks. The functions are one table (expressions.cpp,
// kFunctions), the motion physics is motion.hpp.
#pragma once

#include <chrono>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "sabus/harness/profile.hpp"

namespace sabus::harness {

struct ExprContext {
  const Profile& profile;
  // The values the vector captured so far; null in a static check (lint,
  // coverage), where each capture reads as "0".
  const std::map<std::string, std::string>* captures = nullptr;
  std::chrono::milliseconds pace{0};  // RunOptions::pace, for pace_ms()
};

struct Expansion {
  enum class Kind : std::uint8_t {
    kValue,        // `text` is the expanded text
    kUnavailable,  // `text` is the capability the profile lacks
    kError,        // `text` is what is wrong with the expression or its use
  };
  Kind kind = Kind::kValue;
  std::string text;
  bool ok() const { return kind == Kind::kValue; }
};

// Whether the text holds a "{…}" placeholder.
bool has_placeholder(std::string_view text);
// The template that expands to `text` as it is: each brace doubled. For
// text a writer takes from elsewhere (a recorded reply's field text).
std::string literal_template(std::string_view text);
// Expands every placeholder of `text`.
Expansion expand_template(std::string_view text, const ExprContext& cx);
// A text that must expand to one number ("{home(az)}" or "12.5").
struct Number {
  Expansion::Kind kind = Expansion::Kind::kValue;
  double value = 0;
  std::string text;  // the reason or the error when not a value
};
Number expand_number(std::string_view text, const ExprContext& cx);

// A number a step uses as a count (milliseconds, a slot index, an address
// byte), its fraction dropped: `value` when it is finite and within lo..hi,
// else `error` says why. An expression can give any number, and converting a
// double outside an integer's range is undefined behaviour.
struct Count {
  long long value = 0;
  std::optional<std::string> error;
};
Count count_in(double value, long long lo, long long hi);

// Load-time check of a text with placeholders: the syntax, the functions and
// their argument counts, and the captures it reads, each of which must be in
// `captured` (values captured by earlier steps). The error, or nullopt.
std::optional<std::string> check_template(std::string_view text, const std::set<std::string>& captured);
// The names ("$az0") of the captures a template reads.
std::set<std::string> template_captures(std::string_view text);

// A number as a field or matcher value: integers without a decimal point,
// others with the digits they need (at most 6): 30, -2.5, 12.25.
std::string format_number(double x);

// The function table, for `sabus vectors functions` and the README:
// name, arguments and what it gives.
struct ExprFunction {
  std::string_view name;
  std::string_view arguments;
  std::string_view description;
};
std::vector<ExprFunction> expression_functions();

// The indexes of a stored list the profile fills, in order: "presets",
// "tles", "signposts" (their slots, §3.10, §3.12, §3.20) or "store" (the
// STORE list's entries 1..n, §3.6). nullopt for another name. A vector's
// `each_slot` runs its steps once for each (vectors/README.md).
std::optional<std::vector<int>> filled_slots(const Profile& profile, std::string_view list);
// What one entry of such a list is called ("preset satellite", "TLE",
// "signpost", "STORE entry"); nullopt for a name that is not a list.
std::optional<std::string_view> slot_what(std::string_view list);
// The names of the lists, for messages: "presets, tles, signposts or store".
std::string slot_list_names();

}  // namespace sabus::harness
