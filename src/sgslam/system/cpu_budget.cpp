#include "sgslam/system/cpu_budget.h"

#include <time.h>

#include <algorithm>

namespace sgslam {

int CpuBudget::Update(Timestamp t, double cpu_seconds) {
  if (!enabled()) return level_;
  if (frames_ == 0) {
    window_t_ = t, window_cpu_ = cpu_seconds;
  }
  if (++frames_ <= kWindow) return level_;
  const double span = ToSeconds(t - window_t_);
  if (span > 0) {  // a stream without increasing timestamps gives no verdict
    const double usage = (cpu_seconds - window_cpu_) / span;
    last_usage_ = usage;
    ++windows_;
    if (usage > cores_) {
      ++windows_over_;
      level_ = std::min(level_ + 1, kMaxLevel);
    } else if (usage < kLower * cores_) {
      level_ = std::max(level_ - 1, 0);
    }
    max_level_ = std::max(max_level_, level_);
  }
  frames_ = 1;
  window_t_ = t, window_cpu_ = cpu_seconds;
  return level_;
}

double ProcessCpuSeconds() {
  timespec ts{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0.0;
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace sgslam
