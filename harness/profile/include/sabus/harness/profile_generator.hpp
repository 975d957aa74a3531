// Random legal device profiles: the controllers a sweep runs the whole suite
// against, so that the suite judges any legal RC3000 and not only the
// shipped profiles. Every profile loads (to_yaml, then load_profile_text, reads
// it back equal) and every key is drawn within its documented range
// (vectors/profiles/README.md), with these narrower draws:
//   - speeds 0.1 to 50 deg/s per axis (log-uniform), slow <= fast;
//   - acceleration none or 0.5 to 500 deg/s^2 (log-uniform);
//   - reply turnaround up to kRandomMaxTurnaroundMs;
//   - the locate index range is one of E-22's two readings, 1-20 or 0-19;
//   - stored satellites lie inside the axis ranges; TLE lines carry a right
//     checksum digit; ephemeris only on presets 1-10 (E-51); a preset is
//     dual band only with band C/Ku;
//   - the nullable fields of presets and signposts always hold a value: a
//     blank field there is a reply the protocol's decoders reject (§3.11,
//     §3.21 give ranges, not blanks), so no legal controller sends one.
// Deterministic per seed on every platform: its own mt19937_64 and its own
// mapping of the engine's numbers to ranges, no global state.
#pragma once

#include <cstdint>

#include "sabus/harness/profile.hpp"

namespace sabus::harness {

inline constexpr double kRandomMaxTurnaroundMs = 1000.0;

// The profile of seed `seed`, named "random-<seed>".
Profile random_profile(std::uint64_t seed);

// Changes `p` to hold only what a controller on `sides` can hold (ERRATA
// E-23 other-2: no signpost of priority 0); random_profile applies its own
// pins, a sweep against a controller on other sides applies those.
void hold_only_what_sides_allow(Profile& p, const ReadingPins& sides);

}  // namespace sabus::harness
