#include "sgslam/common/time.h"

#include <gtest/gtest.h>

namespace sgslam {
namespace {

TEST(Timestamp, ParsesDecimalSecondsExactly) {
  EXPECT_EQ(ParseTimestamp("1305031229.528748"), 1305031229528748000LL);
  EXPECT_EQ(ParseTimestamp("1305031229.5287481234"), 1305031229528748123LL);  // beyond ns: truncated
  EXPECT_EQ(ParseTimestamp("12"), 12 * kNsPerSecond);
  EXPECT_EQ(ParseTimestamp("-0.5"), -kNsPerSecond / 2);
  EXPECT_EQ(ParseTimestamp(".25"), kNsPerSecond / 4);
}

TEST(Timestamp, RejectsGarbage) {
  for (const char* bad : {"", "abc", "1.2.3", "1e9", "12x", ".", "-"}) EXPECT_FALSE(ParseTimestamp(bad)) << bad;
  // Beyond the nanosecond type's range (9999999999.5 came out as -8446744074.2).
  for (const char* bad : {"9999999999.5", "-9999999999.5", "4000000000.000000001", "99999999999"}) {
    EXPECT_FALSE(ParseTimestamp(bad)) << bad;
  }
  EXPECT_EQ(ParseTimestamp("4000000000"), 4'000'000'000 * kNsPerSecond);
}

TEST(Timestamp, FormatsWithMicroseconds) {
  EXPECT_EQ(FormatTimestamp(1305031229528748000LL), "1305031229.528748");
  EXPECT_EQ(FormatTimestamp(1305031229528748600LL), "1305031229.528749");  // rounded
  EXPECT_EQ(FormatTimestamp(-kNsPerSecond / 2), "-0.500000");
  EXPECT_EQ(*ParseTimestamp(FormatTimestamp(1234567890123456000LL)), 1234567890123456000LL);
}

}  // namespace
}  // namespace sgslam
