#include "sabus/harness/line_faults.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace sabus::harness {
namespace {

struct KindName {
  LineFaultKind kind;
  std::string_view name;
};
constexpr std::array<KindName, 4> kKindNames = {{
    {LineFaultKind::kFlip, "flip"},
    {LineFaultKind::kDrop, "drop"},
    {LineFaultKind::kInsert, "insert"},
    {LineFaultKind::kOutage, "outage"},
}};

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

}  // namespace

std::optional<LineFaultSpec> parse_line_faults(std::string_view text, std::string& error) {
  LineFaultSpec spec;
  const std::size_t comma = text.find(',');
  const std::string_view rate = trim(text.substr(0, comma));
  // strtod for the exponent forms ("1e-3"); the whole field must be the number.
  const std::string rate_text(rate);
  char* end = nullptr;
  spec.rate = rate_text.empty() ? NAN : std::strtod(rate_text.c_str(), &end);
  if (rate_text.empty() || end != rate_text.c_str() + rate_text.size() || !std::isfinite(spec.rate) || spec.rate < 0 ||
      spec.rate > 0.5) {
    error = fmt::format("line faults \"{}\": the rate \"{}\" is not a number from 0 to 0.5 (a byte error rate: 1e-3)",
                        text, rate);
    return std::nullopt;
  }
  if (comma == std::string_view::npos) return spec;
  spec.kinds = 0;
  std::string_view rest = text.substr(comma + 1);
  while (true) {
    const std::size_t next = rest.find(',');
    const std::string_view name = trim(rest.substr(0, next));
    const auto it = std::find_if(kKindNames.begin(), kKindNames.end(), [&](const KindName& k) { return k.name == name; });
    if (it == kKindNames.end()) {
      error = fmt::format("line faults \"{}\": unknown kind \"{}\" (flip, drop, insert, outage)", text, name);
      return std::nullopt;
    }
    spec.kinds |= static_cast<unsigned>(it->kind);
    if (next == std::string_view::npos) break;
    rest = rest.substr(next + 1);
  }
  return spec;
}

std::string describe(const LineFaultSpec& spec) {
  std::string kinds;
  for (const auto& k : kKindNames)
    if (spec.kinds & static_cast<unsigned>(k.kind)) kinds += (kinds.empty() ? "" : ", ") + std::string(k.name);
  return fmt::format("byte error rate {:g} ({}), seed {}", spec.rate, kinds, spec.seed);
}

std::string describe(const LineFaultTally& t) {
  return fmt::format("{} faults in {} bytes ({} flipped, {} dropped, {} inserted, {} outages)", t.total(), t.bytes, t.flips,
                     t.drops, t.inserts, t.outages);
}

LineFaultInjector::LineFaultInjector(LineFaultSpec spec) : spec_(spec), rng_(spec.seed) {
  if ((spec_.kinds & kAllLineFaultKinds) == 0) spec_.kinds = kAllLineFaultKinds;
}

LineFaultKind LineFaultInjector::pick_kind() {
  std::array<LineFaultKind, 4> enabled{};
  std::size_t n = 0;
  for (const auto& k : kKindNames)
    if (spec_.kinds & static_cast<unsigned>(k.kind)) enabled[n++] = k.kind;
  return enabled[std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_)];
}

Bytes LineFaultInjector::pass(ByteView wire) {
  Bytes out;
  out.reserve(wire.size() + 2);
  std::bernoulli_distribution hit(spec_.rate);
  std::size_t lost = 0;  // bytes an outage still swallows
  for (const std::uint8_t b : wire) {
    ++tally_.bytes;
    if (lost > 0) {
      --lost;
      continue;
    }
    if (spec_.rate <= 0 || !hit(rng_)) {
      out.push_back(b);
      continue;
    }
    switch (pick_kind()) {
      case LineFaultKind::kFlip:
        ++tally_.flips;
        out.push_back(static_cast<std::uint8_t>(b ^ (1u << std::uniform_int_distribution<int>(0, 7)(rng_))));
        break;
      case LineFaultKind::kDrop: ++tally_.drops; break;
      case LineFaultKind::kInsert:
        ++tally_.inserts;
        out.push_back(b);
        out.push_back(static_cast<std::uint8_t>(std::uniform_int_distribution<int>(0, 255)(rng_)));
        break;
      case LineFaultKind::kOutage:
        ++tally_.outages;
        lost = std::uniform_int_distribution<std::size_t>(0, kOutageBytes - 1)(rng_);
        break;
    }
  }
  return out;
}

}  // namespace sabus::harness
