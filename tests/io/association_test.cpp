#include "sgslam/io/association.h"

#include <gtest/gtest.h>

namespace sgslam {
namespace {

constexpr Timestamp kMs = 1'000'000;

TEST(AssociateByTime, GreedyByDifferenceNotNearestPerItem) {
  // 100's nearest is 108, but 109-108 (1 ms) is taken first, so 100 pairs with 118.
  const std::vector<Timestamp> first = {100 * kMs, 109 * kMs};
  const std::vector<Timestamp> second = {108 * kMs, 118 * kMs};
  const auto m = AssociateByTime(first, second, 20 * kMs);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], (std::pair<std::size_t, std::size_t>(0, 1)));
  EXPECT_EQ(m[1], (std::pair<std::size_t, std::size_t>(1, 0)));
}

TEST(AssociateByTime, RespectsStrictWindowAndUsesEachOnce) {
  const std::vector<Timestamp> first = {0, 10 * kMs, 40 * kMs};
  const std::vector<Timestamp> second = {5 * kMs, 60 * kMs};
  const auto m = AssociateByTime(first, second, 20 * kMs);
  ASSERT_EQ(m.size(), 1u);  // 40 <-> 60 is exactly 20 ms: not < 20 ms
  EXPECT_EQ(m[0].second, 0u);
  EXPECT_EQ(m[0].first, 0u);  // tie 5 ms/5 ms: the smaller first timestamp wins, as in Python's tuple sort
}

TEST(AssociateByTime, OffsetShiftsSecond) {
  const std::vector<Timestamp> first = {1000 * kMs};
  const std::vector<Timestamp> second = {500 * kMs};
  EXPECT_TRUE(AssociateByTime(first, second, 20 * kMs).empty());
  EXPECT_EQ(AssociateByTime(first, second, 20 * kMs, 495 * kMs).size(), 1u);
}

}  // namespace
}  // namespace sgslam
