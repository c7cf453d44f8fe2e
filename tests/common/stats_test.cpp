#include "sgslam/common/stats.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace sgslam {
namespace {

TEST(Stats, MedianAndPercentile) {
  EXPECT_EQ(Median({3, 1, 2}), 2);
  EXPECT_EQ(Percentile({4, 1, 3, 2, 5}, 1.0), 5);
  EXPECT_EQ(Percentile({4, 1, 3, 2, 5}, 0.0), 1);
}

// The resident memory follows memory touched and freed; the peak keeps the most.
TEST(Stats, ResidentMemoryFollowsWhatIsTouched) {
  const double before = RssMiB();
  ASSERT_GT(before, 0);
  double during = 0;
  {
    std::vector<char> block(64u << 20);
    std::memset(block.data(), 1, block.size());
    during = RssMiB();
    EXPECT_GT(during, before + 48) << "64 MiB touched";
  }
  EXPECT_GE(PeakRssMiB(), during - 1);
}

}  // namespace
}  // namespace sgslam
