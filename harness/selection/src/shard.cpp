// --shard K/N: stable slices of a selection, by a hash of each vector's id
// (or each sweep profile's seed), so that a CI matrix or a rack of benches
// splits one run and every vector runs on exactly one of them.
#include <charconv>
#include <fmt/format.h>

#include "sabus/harness/selection.hpp"

namespace sabus::harness {

namespace {

constexpr std::uint32_t kMaxShards = 10000;

// FNV-1a, 64 bits: the same slice for the same id on every machine and build
// (std::hash is neither).
std::uint64_t fnv1a(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

std::optional<std::uint32_t> whole_number(std::string_view text) {
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

}  // namespace

std::optional<Shard> parse_shard(std::string_view text, std::string& error, std::string_view option) {
  const auto slash = text.find('/');
  const auto k = slash == std::string_view::npos ? std::nullopt : whole_number(text.substr(0, slash));
  const auto n = slash == std::string_view::npos ? std::nullopt : whole_number(text.substr(slash + 1));
  if (!k || !n) {
    error = fmt::format("{} {}: give K/N, the K-th of N slices (1/4, 2/4, 3/4, 4/4)", option, text);
    return std::nullopt;
  }
  if (*n < 1 || *n > kMaxShards) {
    error = fmt::format("{} {}: N must be between 1 and {}", option, text, kMaxShards);
    return std::nullopt;
  }
  if (*k < 1 || *k > *n) {
    error = fmt::format("{} {}: K must be between 1 and N ({})", option, text, *n);
    return std::nullopt;
  }
  return Shard{*k, *n};
}

bool in_shard(const Shard& shard, std::string_view key) { return fnv1a(key) % shard.count + 1 == shard.index; }

}  // namespace sabus::harness
