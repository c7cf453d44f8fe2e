// A one-line progress bar on a terminal (stderr); silent when stderr is not a tty.
#pragma once

#include <cstddef>

namespace sgslam::app {

class ProgressBar {
 public:
  // unit: what is counted ("frames"); rate: per second, shown when > 0.
  explicit ProgressBar(std::size_t total, const char* unit = "frames");
  ~ProgressBar();
  void Update(std::size_t done, double rate);

 private:
  std::size_t total_;
  const char* unit_;
  bool enabled_;
  int last_percent_ = -1;
};

}  // namespace sgslam::app
