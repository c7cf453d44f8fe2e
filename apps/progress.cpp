#include "progress.h"

#include <unistd.h>

#include <cstdio>
#include <string>

namespace sgslam::app {

ProgressBar::ProgressBar(std::size_t total, const char* unit)
    : total_(total), unit_(unit), enabled_(isatty(STDERR_FILENO) != 0 && total > 0) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && last_percent_ >= 0) std::fputc('\n', stderr);
}

void ProgressBar::Update(std::size_t done, double rate) {
  if (!enabled_) return;
  const int percent = static_cast<int>(100 * done / total_);
  if (percent == last_percent_ && done != total_) return;
  last_percent_ = percent;
  constexpr int kWidth = 40;
  const int filled = kWidth * percent / 100;
  std::string bar(filled, '=');
  bar.resize(kWidth, ' ');
  if (rate > 0) {
    std::fprintf(stderr, "\r[%s] %3d%% %zu/%zu %s %5.1f/s", bar.c_str(), percent, done, total_, unit_, rate);
  } else {
    std::fprintf(stderr, "\r[%s] %3d%% %zu/%zu %s", bar.c_str(), percent, done, total_, unit_);
  }
  std::fflush(stderr);
}

}  // namespace sgslam::app
