// RapidCheck generators: random valid values for every field type, and random
// messages made by walking a message's layout with them.
#pragma once

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <string>

#include "sabus/protocol/codec.hpp"

namespace sabus::gen {

inline std::int32_t int_in(std::int32_t lo, std::int32_t hi) { return *rc::gen::inRange(lo, hi + 1); }

// Printable text of at most n characters with no trailing blank.
inline std::string text(std::size_t n) {
  const auto len = static_cast<std::size_t>(*rc::gen::inRange<int>(0, static_cast<int>(n) + 1));
  std::string s;
  for (std::size_t i = 0; i < len; ++i) s += static_cast<char>(*rc::gen::inRange(0x20, 0x80));
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// Largest magnitudes that fit a width with a sign or a decimal point.
inline std::int32_t pow10(std::size_t n) {
  std::int32_t p = 1;
  for (std::size_t i = 0; i < n; ++i) p *= 10;
  return p;
}

// One overload per field type, producing a value that encodes and decodes back.
inline std::string value(const fields::Text& c) { return text(c.width); }
inline fields::Unit value(const fields::Fill&) { return {}; }
inline std::string value(const fields::Reserved& c) {
  if (*rc::gen::inRange(0, 4) != 0) return "";
  std::string s;
  for (std::size_t i = 0; i < c.width; ++i) s += static_cast<char>(*rc::gen::inRange(0x20, 0x80));
  if (s == std::string(c.width, static_cast<char>(c.ch))) return "";
  return s;
}
inline std::uint32_t value(const fields::Digits& c) {
  return static_cast<std::uint32_t>(int_in(0, pow10(c.width) - 1));
}
inline std::int32_t value(const fields::SignedDigits& c) {
  return int_in(-(pow10(c.width - 1) - 1), pow10(c.width) - 1);
}
inline std::optional<std::int32_t> value(const fields::ZeroPaddedDecimal& c) {
  if (c.blank_allowed && *rc::gen::inRange(0, 5) == 0) return std::nullopt;
  return int_in(0, pow10(c.width - 1) - 1);
}
inline std::optional<std::int32_t> value(const fields::Position&) {
  if (*rc::gen::inRange(0, 8) == 0) return std::nullopt;
  return int_in(-9999, 99999);
}
inline fields::AzimuthReading value(const fields::Azimuth&) {
  using K = fields::AzimuthReading::Kind;
  switch (*rc::gen::inRange(0, 3)) {
    case 0: return {K::kError, 0, 0};
    case 1: return {K::kHeading, int_in(0, 9999), *rc::gen::element('M', 'T')};
    default: return {K::kPosition, int_in(-9999, 99999), 0};
  }
}
inline std::optional<std::int32_t> value(const fields::RightDecimal& c) {
  if (c.blank_allowed && *rc::gen::inRange(0, 5) == 0) return std::nullopt;
  const std::size_t digits = c.width - (c.decimals ? 1 : 0);
  return int_in(-(pow10(digits - 1) - 1), pow10(digits) - 1);
}
inline std::optional<std::int32_t> value(const fields::LeftDecimal& c) {
  if (c.blank_allowed && *rc::gen::inRange(0, 5) == 0) return std::nullopt;
  const std::size_t digits = c.width - (c.decimals ? 1 : 0);
  return int_in(-(pow10(digits - 1) - 1), pow10(digits) - 1);
}
inline std::uint8_t value(const fields::Bits& c) {
  return static_cast<std::uint8_t>(*rc::gen::inRange(0, 256) & c.mask);
}
inline std::uint8_t value(const fields::TrackByte&) {
  return static_cast<std::uint8_t>(int_in(1, 7) << 4 | int_in(0, 15));
}
inline char value(const fields::Choice& c) {
  return c.items[static_cast<std::size_t>(*rc::gen::inRange<int>(0, static_cast<int>(c.items.size())))].ch;
}
inline char value(const fields::AnyChar&) { return static_cast<char>(*rc::gen::inRange(0x20, 0x80)); }
inline std::optional<std::uint8_t> value(const fields::SlotIndex&) {
  if (*rc::gen::inRange(0, 5) == 0) return std::nullopt;
  return static_cast<std::uint8_t>(int_in(0, 99));
}
inline fields::PresetRef value(const fields::PresetIndex&) {
  return {*rc::gen::arbitrary<bool>(), static_cast<std::uint8_t>(int_in(0, 99))};
}
inline std::uint8_t value(const fields::EnumByte&) { return static_cast<std::uint8_t>(int_in(0x20, 0x7F)); }
inline std::optional<std::int32_t> value(const fields::NavAngle& c) {
  if (*rc::gen::inRange(0, 5) == 0) return std::nullopt;
  const std::int32_t max = (c.width == 6 ? 99 : 999) * 60 + 59;
  return int_in(-max, max);
}
inline std::string value(const fields::Version&) {
  std::string s = "0.00";
  s[0] = static_cast<char>('0' + int_in(0, 9));
  s[2] = static_cast<char>('0' + int_in(0, 9));
  s[3] = static_cast<char>('0' + int_in(0, 9));
  return s;
}
inline std::string value(const fields::Opaque&) {
  std::string s = text(40);
  return s;
}

struct RandomFill {
  template <class C, class T, class... M>
  void operator()(std::string_view, const C& c, T& member, M&&...) {
    member = value(c);
  }
};

template <class T>
T random_message() {
  T m{};
  T::layout(m, RandomFill{});
  return m;
}

inline AutoMove random_auto_move() {
  switch (*rc::gen::inRange(0, 5)) {
    case 0: return {random_message<AutoMoveStored>()};
    case 1: return {random_message<AutoMoveAzEl>()};
    case 2: return {random_message<AutoMoveCounts>()};
    case 3: return {random_message<AutoMoveAxis>()};
    default: return {random_message<AutoMovePol>()};
  }
}

template <class T>
T random_request() {
  if constexpr (std::is_same_v<T, AutoMove>) return random_auto_move();
  else return random_message<T>();
}

}  // namespace sabus::gen
