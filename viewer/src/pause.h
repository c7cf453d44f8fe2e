// The page's pause and single step. The run's thread asks MayGo() before each
// frame; while it says no, the thread waits on wake_fd() (with the stop signals:
// apps/stop_signals.h), which Resume() and Step() make readable.
#pragma once

#include <atomic>
#include <mutex>

namespace sgslam::viewer {

class PauseControl {
 public:
  PauseControl();
  ~PauseControl();
  PauseControl(const PauseControl&) = delete;
  PauseControl& operator=(const PauseControl&) = delete;

  void Pause();
  void Resume();
  void Step();  // one frame, then paused again
  bool paused() const { return paused_.load(); }

  // True: process the next frame now (not paused, or a step was asked for, which
  // this takes). Clears the wake-up.
  bool MayGo();
  int wake_fd() const { return fd_; }

 private:
  void Wake();

  int fd_ = -1;  // eventfd
  std::atomic<bool> paused_{false};
  std::mutex mutex_;
  int steps_ = 0;
};

}  // namespace sgslam::viewer
