// What the field codecs of fields.cpp and fields_numeric.cpp share (not part
// of the protocol library's API).
#pragma once

#include <algorithm>
#include <string>
#include <string_view>

#include "sabus/protocol/fields.hpp"

namespace sabus::fields::internal {

inline bool is_digit(std::uint8_t c) { return c >= '0' && c <= '9'; }

inline FieldError error_at(std::size_t i, std::string expected) { return FieldError{i, std::move(expected)}; }

// Writes `text` right- or left-justified into `out`, padded with `pad`.
inline void put_justified(std::string_view text, Out out, bool right, std::uint8_t pad) {
  const std::size_t n = std::min(text.size(), out.size());
  const std::size_t lead = right ? out.size() - n : 0;
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = pad;
  for (std::size_t i = 0; i < n; ++i) out[lead + i] = static_cast<std::uint8_t>(text[i]);
}

}  // namespace sabus::fields::internal
