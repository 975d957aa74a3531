// The sweep's closing "skips by cause" line (tools/sabus/skip_causes.hpp):
// causes that differ only in their numbers are one group, the ten largest
// groups are printed, and the rest is counted.
#include "skip_causes.hpp"

#include <gtest/gtest.h>

#include <string>

namespace sabus::cli {
namespace {

TEST(SkipCauses, NumbersBecomeEllipses) {
  EXPECT_EQ(cause_wording("needs TLE 10 filled in the profile (a slot cannot be emptied)"),
            "needs TLE … filled in the profile (a slot cannot be emptied)");
  EXPECT_EQ(cause_wording("needs azimuth -12.5 to 30 within the range"), "needs azimuth … to … within the range");
  EXPECT_EQ(cause_wording("requires bus_peers: 55"), "requires bus_peers: …");
  EXPECT_EQ(cause_wording("address 0x32 busy"), "address … busy");
  // Words that hold digits after a letter keep them; keys without numbers stay.
  EXPECT_EQ(cause_wording("requires remote_enabled"), "requires remote_enabled");
  EXPECT_EQ(cause_wording("needs rfc2217"), "needs rfc2217");
}

TEST(SkipCauses, OneGroupPerWording) {
  const std::map<std::string, std::size_t> skips = {
      {"needs TLE 1 filled in the profile", 3}, {"needs TLE 10 filled in the profile", 4}, {"requires track.active", 5}};
  EXPECT_EQ(skip_causes_line(skips), "7 needs TLE … filled in the profile; 5 requires track.active");
}

TEST(SkipCauses, TopTenThenTheRestCounted) {
  std::map<std::string, std::size_t> skips;
  // Fourteen wordings (letters, not numbers, tell them apart), counts 100..113,
  // each split over three numbers.
  for (int k = 0; k < 14; ++k)
    for (int n = 0; n < 3; ++n)
      skips["requires key_" + std::string(1, static_cast<char>('a' + k)) + " at " + std::to_string(n)] =
          static_cast<std::size_t>(k == 0 && n == 0 ? 100 - 2 : (n == 0 ? 100 + k - 2 : 1));
  const std::string line = skip_causes_line(skips);
  // The largest first: key_n (113), and ten groups, then four more.
  EXPECT_EQ(line.rfind("113 requires key_n at …; 112 requires key_m at …", 0), 0u) << line;
  EXPECT_NE(line.find("; 104 requires key_e at …; and 4 more causes (406 vector runs)"), std::string::npos) << line;
  EXPECT_EQ(line.find("key_d"), std::string::npos) << line;
  EXPECT_LT(line.size(), 400u);
}

TEST(SkipCauses, EqualCountsByWordingAndOneMoreSaidSingular) {
  const std::map<std::string, std::size_t> skips = {{"b 1", 1}, {"a 2", 1}, {"c 3", 1}};
  EXPECT_EQ(skip_causes_line(skips, 2), "1 a …; 1 b …; and 1 more cause (1 vector run)");
}

}  // namespace
}  // namespace sabus::cli
