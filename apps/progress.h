// A one-line progress bar on a terminal (stderr); silent when stderr is not a tty.
#pragma once

#include <cstddef>

namespace sgslam::app {

class ProgressBar {
 public:
  explicit ProgressBar(std::size_t total);
  ~ProgressBar();
  void Update(std::size_t done, double fps);

 private:
  std::size_t total_;
  bool enabled_;
  int last_percent_ = -1;
};

}  // namespace sgslam::app
