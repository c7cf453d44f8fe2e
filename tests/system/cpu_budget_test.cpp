// The CPU budget's controller (system/cpu_budget.h) on made-up CPU times: it
// throttles one level per window over the budget, up to kMaxLevel, releases one per
// window well under it, judges by camera time (not wall time), and never moves
// without a budget.
#include <gtest/gtest.h>

#include "sgslam/system/cpu_budget.h"

namespace sgslam {
namespace {

constexpr Timestamp kFrame = kNsPerSecond / 30;  // a 30 Hz camera

// Feeds `windows` windows of frames using `cores` cores each; returns the level after
// every window. cpu is the running CPU total (s) and t the camera time, carried on.
std::vector<int> Feed(CpuBudget& budget, double cores, int windows, Timestamp& t, double& cpu) {
  std::vector<int> levels;
  for (int w = 0; w < windows; ++w) {
    for (int f = 0; f < CpuBudget::kWindow; ++f) {
      t += kFrame;
      cpu += cores * ToSeconds(kFrame);
      budget.Update(t, cpu);
    }
    levels.push_back(budget.level());
  }
  return levels;
}

TEST(CpuBudget, ThrottlesOneLevelPerWindowOverTheBudgetUpToTheTop) {
  CpuBudget budget(1.0);
  Timestamp t = 0;
  double cpu = 0;
  budget.Update(t, cpu);  // the first frame opens the first window
  EXPECT_EQ(Feed(budget, 1.6, 6, t, cpu), (std::vector<int>{1, 2, 3, 4, 4, 4}));
  EXPECT_EQ(budget.max_level_reached(), CpuBudget::kMaxLevel);
  EXPECT_EQ(budget.windows(), 6);
  EXPECT_EQ(budget.windows_over(), 6);
  ASSERT_TRUE(budget.last_usage());
  EXPECT_NEAR(*budget.last_usage(), 1.6, 1e-6);
}

TEST(CpuBudget, ReleasesWellUnderTheBudgetAndHoldsBetween) {
  CpuBudget budget(1.0);
  Timestamp t = 0;
  double cpu = 0;
  budget.Update(t, cpu);
  Feed(budget, 2.0, 3, t, cpu);  // level 3
  // Between kLower of the budget and the budget: held.
  EXPECT_EQ(Feed(budget, 0.9, 2, t, cpu), (std::vector<int>{3, 3}));
  // Under kLower: one level a window, down to 0 and no further.
  EXPECT_EQ(Feed(budget, 0.5, 5, t, cpu), (std::vector<int>{2, 1, 0, 0, 0}));
  EXPECT_EQ(budget.max_level_reached(), 3);
}

TEST(CpuBudget, JudgesByCameraTimeNotByHowFastFramesCame) {
  // A dataset read as fast as possible: 30 frames of camera time (1 s) processed
  // with 0.8 s of CPU is 0.8 cores at the camera's rate, whatever the wall time.
  CpuBudget budget(1.0);
  Timestamp t = 0;
  double cpu = 0;
  budget.Update(t, cpu);
  EXPECT_EQ(Feed(budget, 0.8, 3, t, cpu), (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(budget.windows_over(), 0);
}

TEST(CpuBudget, WithoutABudgetNothingMoves) {
  CpuBudget budget(0.0);
  EXPECT_FALSE(budget.enabled());
  Timestamp t = 0;
  double cpu = 0;
  EXPECT_EQ(Feed(budget, 5.0, 3, t, cpu), (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(budget.windows(), 0);
  EXPECT_FALSE(budget.last_usage());
}

TEST(CpuBudget, TimestampsThatDoNotAdvanceGiveNoVerdict) {
  CpuBudget budget(1.0);
  double cpu = 0;
  for (int f = 0; f < 3 * CpuBudget::kWindow; ++f) budget.Update(0, cpu += 1.0);
  EXPECT_EQ(budget.level(), 0);
  EXPECT_EQ(budget.windows(), 0);
}

TEST(CpuBudget, ProcessCpuTimeAdvancesWithWork) {
  const double before = ProcessCpuSeconds();
  volatile double x = 0;
  for (int i = 0; i < 20'000'000; ++i) x = x + i * 1e-9;
  EXPECT_GT(ProcessCpuSeconds(), before);
}

}  // namespace
}  // namespace sgslam
