// The emulated noisy line (line_faults.hpp): its option text, failing paths
// first, and what it does to bytes.
#include "sabus/harness/line_faults.hpp"

#include <gtest/gtest.h>

namespace sabus::harness {
namespace {

TEST(LineFaultSpecText, BadTextIsRefusedWithWhatIsWrong) {
  std::string error;
  for (const char* bad : {"", "x", "1e-3x", "-0.1", "0.6", "nan", "inf", ",flip"}) {
    error.clear();
    EXPECT_FALSE(parse_line_faults(bad, error)) << bad;
    EXPECT_NE(error.find("is not a number from 0 to 0.5"), std::string::npos) << bad << ": " << error;
  }
  EXPECT_FALSE(parse_line_faults("1e-3,flip,bend", error));
  EXPECT_EQ(error, "line faults \"1e-3,flip,bend\": unknown kind \"bend\" (flip, drop, insert, outage)");
  EXPECT_FALSE(parse_line_faults("1e-3,", error));
  EXPECT_NE(error.find("unknown kind \"\""), std::string::npos) << error;
}

TEST(LineFaultSpecText, RateAndKinds) {
  std::string error;
  const auto all = parse_line_faults("1e-3", error);
  ASSERT_TRUE(all) << error;
  EXPECT_DOUBLE_EQ(all->rate, 0.001);
  EXPECT_EQ(all->kinds, kAllLineFaultKinds);
  const auto two = parse_line_faults("0.01, flip ,outage", error);
  ASSERT_TRUE(two) << error;
  EXPECT_EQ(two->kinds, static_cast<unsigned>(LineFaultKind::kFlip) | static_cast<unsigned>(LineFaultKind::kOutage));
  EXPECT_EQ(describe(*two), "byte error rate 0.01 (flip, outage), seed 1");
}

Bytes bytes_of(std::size_t n) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(i * 7);
  return b;
}

TEST(LineFaultInjector, RateZeroPassesEveryByte) {
  LineFaultInjector line({0, kAllLineFaultKinds, 9});
  const Bytes in = bytes_of(10000);
  EXPECT_EQ(line.pass(in), in);
  EXPECT_EQ(line.tally().total(), 0u);
  EXPECT_EQ(line.tally().bytes, 10000u);
}

TEST(LineFaultInjector, TheSameSeedMakesTheSameFaults) {
  const Bytes in = bytes_of(5000);
  LineFaultInjector a({0.01, kAllLineFaultKinds, 5}), b({0.01, kAllLineFaultKinds, 5}), c({0.01, kAllLineFaultKinds, 6});
  const Bytes out_a = a.pass(in);
  EXPECT_EQ(out_a, b.pass(in));
  EXPECT_NE(out_a, c.pass(in));
}

TEST(LineFaultInjector, EachKindDoesWhatItSays) {
  const Bytes in = bytes_of(20000);
  LineFaultInjector flip({0.01, static_cast<unsigned>(LineFaultKind::kFlip), 1});
  const Bytes flipped = flip.pass(in);
  ASSERT_EQ(flipped.size(), in.size());
  std::size_t one_bit = 0;
  for (std::size_t i = 0; i < in.size(); ++i)
    if (flipped[i] != in[i]) one_bit += __builtin_popcount(flipped[i] ^ in[i]) == 1;
  EXPECT_EQ(one_bit, flip.tally().flips) << "each flip inverts one bit: a parity error";
  EXPECT_GT(flip.tally().flips, 100u);
  EXPECT_LT(flip.tally().flips, 300u);

  LineFaultInjector drop({0.01, static_cast<unsigned>(LineFaultKind::kDrop), 1});
  const std::size_t after_drops = drop.pass(in).size();
  EXPECT_GT(drop.tally().drops, 100u);
  EXPECT_EQ(after_drops, in.size() - drop.tally().drops);
  LineFaultInjector insert({0.01, static_cast<unsigned>(LineFaultKind::kInsert), 1});
  const std::size_t after_inserts = insert.pass(in).size();
  EXPECT_GT(insert.tally().inserts, 100u);
  EXPECT_EQ(after_inserts, in.size() + insert.tally().inserts);
  LineFaultInjector outage({0.01, static_cast<unsigned>(LineFaultKind::kOutage), 1});
  const std::size_t left = outage.pass(in).size();
  EXPECT_LE(left, in.size() - outage.tally().outages);
  EXPECT_GE(left, in.size() - outage.tally().outages * kOutageBytes);
  EXPECT_EQ(describe(outage.tally()).find(std::to_string(outage.tally().total()) + " faults in 20000 bytes"), 0u);
}

}  // namespace
}  // namespace sabus::harness
