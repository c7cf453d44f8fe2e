// The pages' pause and single step. The run's thread asks MayGo() before each
// frame; while it says no, the thread waits on wake_fd() (with the stop signals:
// apps/stop_signals.h), which every change that may let it go makes readable.
//
// A pause belongs to the page that asked for it (a pause or a step), and ends with
// it: the run is paused while at least one page holds a pause. "resume", from any
// page, ends every hold (every page shows the one run, paused or not); a page that
// closes ends its own (a page that paused and went away must not hold the run
// forever).
#pragma once

#include <cstdint>
#include <mutex>
#include <set>

namespace sgslam::viewer {

class PauseControl {
 public:
  using Holder = std::uint64_t;  // a page's connection (Source::Control's page)

  PauseControl();
  ~PauseControl();
  PauseControl(const PauseControl&) = delete;
  PauseControl& operator=(const PauseControl&) = delete;

  void Pause(Holder page);
  void Step(Holder page);  // one frame, then paused again, page holding the pause
  void Resume();           // every hold ends
  // page's hold (if it has one) ends. True when that let the run go on.
  bool Release(Holder page);
  bool paused() const;

  // True: process the next frame now (no hold, or a step was asked for, which
  // this takes). Clears the wake-up.
  bool MayGo();
  int wake_fd() const { return fd_; }

 private:
  void Wake();
  void Unpause();  // mutex_ held: no holds, no steps left

  int fd_ = -1;  // eventfd
  mutable std::mutex mutex_;
  std::set<Holder> holders_;
  int steps_ = 0;  // steps asked for and not taken; only while paused
};

}  // namespace sgslam::viewer
