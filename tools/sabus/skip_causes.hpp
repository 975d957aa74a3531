// The closing "skips by cause" line of `sabus vectors sweep` (sweep.cpp):
// each random profile words its causes with its own numbers ("needs TLE 10
// filled in the profile", "needs TLE 3 ..."), so over many profiles the line
// ran to thousands of characters. Causes are grouped by their wording, every
// number replaced by "…", and the ten largest groups are printed with a
// count of the rest.
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace sabus::cli {

// A cause's wording: every number (decimal, signed, hexadecimal) as "…".
std::string cause_wording(const std::string& cause);

// "548917 requires remote_enabled; 306813 needs TLE … filled in the profile;
// …; and 12 more causes (4711 vector runs)": the groups by count, largest
// first (equal counts by wording), at most `top` of them.
std::string skip_causes_line(const std::map<std::string, std::size_t>& skips, std::size_t top = 10);

}  // namespace sabus::cli
